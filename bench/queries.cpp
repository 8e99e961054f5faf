// World queries over a world of 10,000 bodies (spheres, boxes, capsules; a
// third static) scattered in a 100 m cube, after one step: ray casts (closest
// and all hits), sphere and box overlaps, shape casts, and the stray-body
// rebuild that the first query after each step pays (docs/queries.md, "Costs").
#include <benchmark/benchmark.h>

#include <random>
#include <vector>

#include <fulcrum/fulcrum.hpp>

#include "world/world_access.hpp"

namespace {

using namespace fulcrum;

World& sharedWorld() {
    static World world = [] {
        World w{WorldDef{.gravity = {0, 0, 0}}};
        std::mt19937 rng(3);
        std::uniform_real_distribution<float> pos(-50, 50), size(Real(0.2), Real(1)), vel(-2, 2);
        for (int i = 0; i < 10000; ++i) {
            BodyDef def;
            def.type = i % 3 == 0 ? BodyType::Static : BodyType::Dynamic;
            def.shape = i % 3 == 0 ? Shape::box({size(rng), size(rng), size(rng)})
                                   : (i % 3 == 1 ? Shape::sphere(size(rng)) : Shape::capsule(size(rng), size(rng)));
            def.position = {pos(rng), pos(rng), pos(rng)};
            if (def.type == BodyType::Dynamic) def.linearVelocity = {vel(rng), vel(rng), vel(rng)};
            w.createBody(def);
        }
        w.step(Real(1) / 60);
        return w;
    }();
    return world;
}

struct Probe {
    Vec3 origin, direction;
};

std::vector<Probe> probes() {
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> pos(-50, 50);
    std::normal_distribution<float> g(0, 1);
    std::vector<Probe> out(1024);
    for (Probe& p : out) p = {{pos(rng), pos(rng), pos(rng)}, normalize(Vec3{g(rng), g(rng), g(rng)})};
    return out;
}

void BM_CastRayClosest20m(benchmark::State& state) {
    const World& world = sharedWorld();
    const std::vector<Probe> ps = probes();
    std::size_t i = 0, hits = 0;
    for (auto _ : state) {
        const Probe& p = ps[i++ & 1023];
        hits += world.castRay({p.origin, p.direction * 20}).has_value();
    }
    state.counters["hit_rate"] = static_cast<double>(hits) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_CastRayClosest20m);

void BM_CastRayAll20m(benchmark::State& state) {
    const World& world = sharedWorld();
    const std::vector<Probe> ps = probes();
    std::vector<RayCastHit> out;
    std::size_t i = 0, hits = 0;
    for (auto _ : state) {
        const Probe& p = ps[i++ & 1023];
        world.castRayAll({p.origin, p.direction * 20}, out);
        hits += out.size();
    }
    state.counters["hits_per_ray"] = static_cast<double>(hits) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_CastRayAll20m);

void BM_OverlapSphere2m(benchmark::State& state) {
    const World& world = sharedWorld();
    const std::vector<Probe> ps = probes();
    std::vector<BodyId> out;
    std::size_t i = 0, hits = 0;
    for (auto _ : state) {
        world.overlapSphere(ps[i++ & 1023].origin, 2, out);
        hits += out.size();
    }
    state.counters["bodies_found"] = static_cast<double>(hits) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_OverlapSphere2m);

void BM_OverlapBox2m(benchmark::State& state) {
    const World& world = sharedWorld();
    const std::vector<Probe> ps = probes();
    std::vector<BodyId> out;
    std::size_t i = 0;
    for (auto _ : state) {
        const Probe& p = ps[i++ & 1023];
        world.overlapBox(p.origin, {2, 1, 2}, Quat::fromAxisAngle(p.direction, 1), out);
        benchmark::DoNotOptimize(out.data());
    }
}
BENCHMARK(BM_OverlapBox2m);

void BM_CastSphere10m(benchmark::State& state) {
    const World& world = sharedWorld();
    const std::vector<Probe> ps = probes();
    const Shape ball = Shape::sphere(Real(0.5));
    std::size_t i = 0, hits = 0;
    for (auto _ : state) {
        const Probe& p = ps[i++ & 1023];
        hits += world.castShape(ball, {p.origin, {}}, p.direction * 10).has_value();
    }
    state.counters["hit_rate"] = static_cast<double>(hits) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_CastSphere10m);

// The first query after a step rebuilds the stray list (one pass over the
// 6,667 moving bodies). Measured as: a fresh stamp each iteration.
void BM_StrayRebuild10k(benchmark::State& state) {
    World& world = sharedWorld();
    for (auto _ : state) {
        detail::implOf(world).strayBodies.invalidate();
        benchmark::DoNotOptimize(world.overlapSphere({0, 0, 0}, Real(0.1)));
    }
}
BENCHMARK(BM_StrayRebuild10k);

}  // namespace

BENCHMARK_MAIN();
