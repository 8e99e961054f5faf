// Broad-phase benchmarks (Google Benchmark).
//
//   cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DFULCRUM_BUILD_BENCH=ON
//   cmake --build build-bench -j2 --target bench_broadphase
//   build-bench/bench/bench_broadphase --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
//
// BM_StepBoxes: one broad-phase step of N dynamic boxes flying around a closed
//   volume (random velocities up to 4 m/s, 60 Hz) above a static ground of
//   2,500 tiles: move every proxy, find new pairs, end separated pairs (the
//   caller's side of the contract, included because it is part of the cost).
//   Counters: live pairs, new pairs per step, proxies reinserted per step, and
//   the moving tree's internal area relative to a fresh binned-SAH build of
//   the same boxes after all the motion (tree quality over time).
// BM_Insert / BM_Rebuild: building a tree of N random boxes incrementally or
//   top-down, with the resulting internal area (quality) as a counter.
// BM_RayCastClosest: closest-hit rays through the static ground and boxes.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <random>
#include <vector>

#include "collision/broad_phase.hpp"

namespace fulcrum {
namespace {

struct Body {
    ProxyId proxy;
    Vec3 center, half, velocity;
};

class BoxScene {
public:
    BoxScene(int count, Real displacementScale, DynamicTreeConfig::Search search = DynamicTreeConfig::Search::Greedy)
        : bp_(config(displacementScale, search)), rng_(42) {
        // Ground: 50 x 50 tiles of 2 m, the top at y = 0.
        for (int i = 0; i < 50; ++i)
            for (int k = 0; k < 50; ++k) {
                const Vec3 c{Real(-50 + 2 * i + 1), Real(-0.5), Real(-50 + 2 * k + 1)};
                bp_.createProxy(AABB::fromCenterHalf(c, {1, Real(0.5), 1}), BodyType::Static, {}, 0);
            }
        bp_.rebuildStaticTree();
        // Volume scaled so the density (and pairs per box) is the same for every count:
        // 10,000 boxes fill 100 x 20 x 100 m.
        const Real scale = std::cbrt(static_cast<Real>(count) / 10000);
        lo_ = Vec3{-50, 0, -50} * scale;
        hi_ = Vec3{50, 20, 50} * scale;
        std::uniform_real_distribution<Real> u(0, 1);
        for (int i = 0; i < count; ++i) {
            Body b;
            b.half = Vec3{Real(0.25) + Real(0.5) * u(rng_), Real(0.25) + Real(0.5) * u(rng_), Real(0.25) + Real(0.5) * u(rng_)};
            b.center = lo_ + mul(hi_ - lo_, Vec3{u(rng_), u(rng_), u(rng_)});
            b.velocity = Vec3{u(rng_) - Real(0.5), u(rng_) - Real(0.5), u(rng_) - Real(0.5)} * Real(8);
            b.proxy = bp_.createProxy(AABB::fromCenterHalf(b.center, b.half), BodyType::Dynamic, {}, static_cast<std::uint32_t>(i));
            bodies_.push_back(b);
        }
        pairs_.reserve(static_cast<std::size_t>(count) * 8);
    }

    // One step; returns the number of new pairs.
    std::size_t step() {
        const Real dt = Real(1) / 60;
        reinserted_ = 0;
        for (Body& b : bodies_) {
            const Vec3 d = b.velocity * dt;
            b.center += d;
            for (std::size_t i = 0; i < 3; ++i) {
                if ((b.center[i] < lo_[i] && b.velocity[i] < 0) || (b.center[i] > hi_[i] && b.velocity[i] > 0)) {
                    b.velocity[i] = -b.velocity[i];
                }
            }
            reinserted_ += bp_.moveProxy(b.proxy, AABB::fromCenterHalf(b.center, b.half), d) ? 1u : 0u;
        }
        const std::span<const ProxyPair> fresh = bp_.updatePairs();
        pairs_.insert(pairs_.end(), fresh.begin(), fresh.end());
        std::erase_if(pairs_, [&](const ProxyPair& p) { return !bp_.testOverlap(p.a, p.b); });
        return fresh.size();
    }

    std::size_t livePairs() const { return pairs_.size(); }
    std::size_t reinserted() const { return reinserted_; }
    double movingTreeQuality() const {
        DynamicTree copy = bp_.movingTree();
        const double incremental = copy.internalSurfaceArea();
        copy.rebuild();
        return incremental / copy.internalSurfaceArea();
    }
    const BroadPhase& broadPhase() const { return bp_; }

private:
    static BroadPhaseConfig config(Real displacementScale, DynamicTreeConfig::Search search) {
        BroadPhaseConfig c;
        c.movingTree.displacementScale = displacementScale;
        c.movingTree.search = search;
        c.staticTree.search = search;
        return c;
    }
    BroadPhase bp_;
    std::mt19937 rng_;
    Vec3 lo_, hi_;
    std::vector<Body> bodies_;
    std::vector<ProxyPair> pairs_;
    std::size_t reinserted_ = 0;
};

void BM_StepBoxes(benchmark::State& state) {
    const auto count = static_cast<int>(state.range(0));
    const Real displacementScale = static_cast<Real>(state.range(1)) / 2;
    BoxScene scene(count, displacementScale, static_cast<DynamicTreeConfig::Search>(state.range(2)));
    for (int i = 0; i < 120; ++i) scene.step();  // reach a steady state (2 s of motion)
    std::size_t fresh = 0, reinserted = 0, live = 0;
    for (auto _ : state) {
        fresh += scene.step();
        reinserted += scene.reinserted();
        live += scene.livePairs();
    }
    const auto steps = static_cast<double>(state.iterations());
    state.counters["live_pairs"] = static_cast<double>(live) / steps;
    state.counters["new_pairs"] = static_cast<double>(fresh) / steps;
    state.counters["reinserted"] = static_cast<double>(reinserted) / steps;
    state.counters["live_pairs_per_s"] = benchmark::Counter(static_cast<double>(live), benchmark::Counter::kIsRate);
    state.counters["tree_area_vs_rebuild"] = scene.movingTreeQuality();
    state.counters["tree_height"] = scene.broadPhase().movingTree().height();
}
// Args: body count, 2 x displacementScale (0 = margin only, 2 = one step ahead,
// 4 = two steps), sibling search (0 = greedy, 1 = branch and bound).
BENCHMARK(BM_StepBoxes)
    ->Args({10000, 0, 0})->Args({10000, 2, 0})->Args({10000, 4, 0})->Args({10000, 2, 1})->Args({1000, 2, 0})
    ->Unit(benchmark::kMillisecond);

std::vector<AABB> randomBoxes(int count, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<Real> u(0, 1);
    const Real extent = 50 * std::cbrt(static_cast<Real>(count) / 10000);
    std::vector<AABB> boxes;
    for (int i = 0; i < count; ++i) {
        const Vec3 c = Vec3{u(rng), u(rng), u(rng)} * (2 * extent) - Vec3::splat(extent);
        const Vec3 h = Vec3{u(rng), u(rng), u(rng)} * Real(0.9) + Vec3::splat(Real(0.1));
        boxes.push_back(AABB::fromCenterHalf(c, h));
    }
    return boxes;
}

void BM_Insert(benchmark::State& state) {
    const std::vector<AABB> boxes = randomBoxes(static_cast<int>(state.range(0)), 7);
    double area = 0;
    int height = 0;
    DynamicTreeConfig config;
    config.search = static_cast<DynamicTreeConfig::Search>(state.range(1));
    for (auto _ : state) {
        DynamicTree tree(config);
        for (std::size_t i = 0; i < boxes.size(); ++i) tree.createProxy(boxes[i], static_cast<std::uint32_t>(i));
        area = tree.internalSurfaceArea();
        height = tree.height();
        benchmark::DoNotOptimize(tree.root());
    }
    DynamicTree reference;
    for (const AABB& b : boxes) reference.createProxy(b, 0);
    reference.rebuild();
    state.counters["area_vs_rebuild"] = area / reference.internalSurfaceArea();
    state.counters["height"] = height;
    state.counters["ns_per_insert"] = benchmark::Counter(static_cast<double>(boxes.size()),
                                                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}
// Args: box count, sibling search (0 = greedy, 1 = branch and bound).
BENCHMARK(BM_Insert)->ArgsProduct({{1000, 10000, 100000}, {0, 1}})->Unit(benchmark::kMillisecond);

void BM_Rebuild(benchmark::State& state) {
    const std::vector<AABB> boxes = randomBoxes(static_cast<int>(state.range(0)), 7);
    DynamicTree tree;
    for (std::size_t i = 0; i < boxes.size(); ++i) tree.createProxy(boxes[i], static_cast<std::uint32_t>(i));
    for (auto _ : state) {
        tree.rebuild();
        benchmark::DoNotOptimize(tree.root());
    }
    state.counters["height"] = tree.height();
}
BENCHMARK(BM_Rebuild)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

void BM_RayCastClosest(benchmark::State& state) {
    BoxScene scene(10000, 1);
    for (int i = 0; i < 60; ++i) scene.step();
    const BroadPhase& bp = scene.broadPhase();
    std::mt19937 rng(3);
    std::uniform_real_distribution<Real> u(-50, 50);
    std::vector<RayCastInput> rays;
    for (int i = 0; i < 1000; ++i) rays.push_back({{u(rng), 40, u(rng)}, {u(rng) * Real(0.2), -60, u(rng) * Real(0.2)}, 1});
    std::size_t hits = 0;
    for (auto _ : state) {
        for (const RayCastInput& ray : rays) {
            const RaySlab slab(ray);
            ProxyId best = kNullProxy;
            bp.rayCast(ray, [&](const RayCastInput& in, ProxyId id, std::uint32_t) {
                const Real t = slab.entry(bp.fatAABB(id), in.maxFraction);
                if (t < 0) return Real(-1);
                best = id;
                return t;
            });
            hits += best != kNullProxy ? 1u : 0u;
        }
    }
    benchmark::DoNotOptimize(hits);
    state.counters["rays_per_s"] = benchmark::Counter(static_cast<double>(rays.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_RayCastClosest)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace fulcrum

BENCHMARK_MAIN();
