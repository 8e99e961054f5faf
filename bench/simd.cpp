// SIMD benchmark: the toy contact-row solve of tests/simd/contact_rows.hpp
// (gather bodies, one sequential-impulse row each, scatter back), scalar vs
// 4-wide (SSE2) vs 8-wide (AVX2), plus the portable 4-lane fallback.
//
//   cmake -S . -B build-bench -DCMAKE_BUILD_TYPE=Release -DFULCRUM_BUILD_BENCH=ON
//   cmake --build build-bench -j2 --target bench_simd          # scalar, portable, SSE2
//   cmake -S . -B build-bench-avx2 -DCMAKE_BUILD_TYPE=Release -DFULCRUM_BUILD_BENCH=ON -DCMAKE_CXX_FLAGS="-mavx2 -mfma -ffp-contract=off"
//   cmake --build build-bench-avx2 -j2 --target bench_simd     # adds AVX2
//   build-bench-avx2/bench/bench_simd --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// Each iteration is one pass over all rows; items/s counts rows. Before timing,
// every variant's result is checked bit-identical to the scalar one (the
// benchmark aborts otherwise), so the figures compare equal work.
// Rows: bodies ~ rows / 2 (a random contact graph), in colours of 8 rows with
// distinct bodies. Both a cache-resident size and a larger one.
//
// BM_SceneSimdPaths: the real solver's 4-lane (SSE2) and 8-lane (AVX2) paths
// side by side on the benchmark scenes (bench/scenes.hpp), one thread: two
// worlds built alike, stepped alternately (the order swapped every step), each
// step timed on its own, so the shared machine's noise falls on both paths
// alike. Counters: sse2_ms and avx2_ms per step (means), avx2/sse2 their ratio.
// The two worlds must stay bit-identical (checked at the end; aborts if not).
// Needs a CPU with AVX2 (skipped otherwise).
//   build/bench/bench_simd --benchmark_filter=Scene
#include <benchmark/benchmark.h>

#include <bit>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "../tests/simd/contact_rows.hpp"
#include "fulcrum/fulcrum.hpp"
#include "scenes.hpp"
#include "world/world_access.hpp"

namespace fulcrum::test {
namespace {

constexpr std::size_t kColour = 8;

RowScene scene(std::size_t rows) { return makeRowScene(std::max<std::size_t>(rows / 2, 2 * kColour), rows, kColour, 1); }

// One pass of the wide kernel must give the scalar bodies, bit for bit.
template <class P, void (*Kernel)(SolverBody*, RowBundle<P>*, std::size_t)>
void verifyAgainstScalar(std::size_t rows) {
    RowScene reference = scene(rows);
    std::vector<SolverBody> bodies = reference.bodies;
    std::vector<RowBundle<P>> bundles = bundleRows<P>(reference.rows);
    solveRowsScalar(reference.bodies.data(), reference.rows.data(), reference.rows.size());
    Kernel(bodies.data(), bundles.data(), bundles.size());
    for (std::size_t k = 0; k < bodies.size(); ++k)
        for (int c = 0; c < 3; ++c)
            if (std::bit_cast<std::uint32_t>(bodies[k].v[c]) != std::bit_cast<std::uint32_t>(reference.bodies[k].v[c]) ||
                std::bit_cast<std::uint32_t>(bodies[k].w[c]) != std::bit_cast<std::uint32_t>(reference.bodies[k].w[c])) {
                std::fprintf(stderr, "wide kernel (%d lanes) differs from scalar at body %zu\n", P::kLanes, k);
                std::abort();
            }
}

void BM_SolveRowsScalar(benchmark::State& state) {
    RowScene s = scene(std::size_t(state.range(0)));
    for (auto _ : state) {
        solveRowsScalar(s.bodies.data(), s.rows.data(), s.rows.size());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * state.range(0));
}

template <class P, void (*Kernel)(SolverBody*, RowBundle<P>*, std::size_t)>
void solveWide(benchmark::State& state) {
    verifyAgainstScalar<P, Kernel>(std::size_t(state.range(0)));
    RowScene s = scene(std::size_t(state.range(0)));
    std::vector<RowBundle<P>> bundles = bundleRows<P>(s.rows);
    for (auto _ : state) {
        Kernel(s.bodies.data(), bundles.data(), bundles.size());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * state.range(0));
}

// Transposed gathers of whole bodies (the kernel to use) and field-by-field gathers.
template <class P>
void BM_SolveRowsWide(benchmark::State& state) {
    solveWide<P, solveRowsWide<P>>(state);
}
template <class P>
void BM_SolveRowsWideByField(benchmark::State& state) {
    solveWide<P, solveRowsWideByField<P>>(state);
}

BENCHMARK(BM_SolveRowsScalar)->Arg(1024)->Arg(65536);
BENCHMARK(BM_SolveRowsWide<simd::PortablePolicy<4>>)->Arg(1024)->Arg(65536);
#if FULCRUM_SIMD_HAS_SSE2
BENCHMARK(BM_SolveRowsWide<simd::Sse2Policy>)->Arg(1024)->Arg(65536);
BENCHMARK(BM_SolveRowsWideByField<simd::Sse2Policy>)->Arg(1024)->Arg(65536);
#endif
#if FULCRUM_SIMD_HAS_AVX2
BENCHMARK(BM_SolveRowsWide<simd::Avx2Policy>)->Arg(1024)->Arg(65536);
BENCHMARK(BM_SolveRowsWideByField<simd::Avx2Policy>)->Arg(1024)->Arg(65536);
#endif

// A scene of boxes and spheres (bench/scenes.hpp), as bench_benchmark_scenes builds it.
std::unique_ptr<World> buildScene(const bench::SceneSpec& scene, std::vector<BodyId>& ids) {
    WorldDef def;
    def.sleeping = scene.sleeping;
    def.threads = 1;
    def.gravity = {static_cast<Real>(scene.gravity.x), static_cast<Real>(scene.gravity.y),
                   static_cast<Real>(scene.gravity.z)};
    auto world = std::make_unique<World>(def);
    for (const bench::BodySpec& b : scene.bodies) {
        BodyDef d;
        d.type = b.isStatic ? BodyType::Static : BodyType::Dynamic;
        const Vec3 half{static_cast<Real>(b.half.x), static_cast<Real>(b.half.y), static_cast<Real>(b.half.z)};
        d.shape = b.kind == bench::BodySpec::Kind::Sphere ? Shape::sphere(half.x) : Shape::box(half);
        if (!b.isStatic) d.mass = static_cast<Real>(b.mass);
        d.position = {static_cast<Real>(b.position.x), static_cast<Real>(b.position.y), static_cast<Real>(b.position.z)};
        d.orientation = {static_cast<Real>(b.orientation.w), static_cast<Real>(b.orientation.x),
                         static_cast<Real>(b.orientation.y), static_cast<Real>(b.orientation.z)};
        d.friction = static_cast<Real>(scene.friction);
        ids.push_back(world->createBody(d));
    }
    return world;
}

bench::SceneSpec sceneOf(int which) {
    switch (which) {
        case 0: return bench::pyramid("pyramid_large", 60, 0);
        case 1: return bench::pile("box_pile", bench::BodySpec::Kind::Box, 20, 10, 20, 1.5, 0);
        default: return bench::pile("sphere_pile", bench::BodySpec::Kind::Sphere, 25, 16, 25, 1.2, 0);
    }
}

void BM_SceneSimdPaths(benchmark::State& state) {
    if (!detail::avx2Available()) {
        state.SkipWithError("this CPU has no AVX2");
        return;
    }
    const bench::SceneSpec scene = sceneOf(static_cast<int>(state.range(0)));
    state.SetLabel(scene.name);
    std::vector<BodyId> idsA, idsB;
    std::unique_ptr<World> sse2 = buildScene(scene, idsA), avx2 = buildScene(scene, idsB);
    detail::implOf(*sse2).contactSolver.setSimdPath(detail::SimdPath::Sse2);
    detail::implOf(*avx2).contactSolver.setSimdPath(detail::SimdPath::Avx2);
    const Real dt = static_cast<Real>(scene.dt);
    for (std::int64_t i = 0; i < state.range(1); ++i) sse2->step(dt), avx2->step(dt);  // untimed
    double sse2Seconds = 0, avx2Seconds = 0;
    const auto timedStep = [dt](World& world) {
        const auto start = std::chrono::steady_clock::now();
        world.step(dt);
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    bool sse2First = true;
    for (auto _ : state) {
        if (sse2First) {
            sse2Seconds += timedStep(*sse2);
            avx2Seconds += timedStep(*avx2);
        } else {
            avx2Seconds += timedStep(*avx2);
            sse2Seconds += timedStep(*sse2);
        }
        sse2First = !sse2First;
    }
    for (std::size_t i = 0; i < idsA.size(); ++i) {
        if (!(sse2->position(idsA[i]) == avx2->position(idsB[i]))) {
            std::fprintf(stderr, "%s: the 4- and 8-lane worlds differ at body %zu\n", scene.name.c_str(), i);
            std::abort();
        }
    }
    const double steps = static_cast<double>(state.iterations());
    state.counters["sse2_ms"] = 1e3 * sse2Seconds / steps;
    state.counters["avx2_ms"] = 1e3 * avx2Seconds / steps;
    state.counters["avx2/sse2"] = avx2Seconds / sse2Seconds;
}
// Args: the scene (0 pyramid_large, 1,830 boxes; 1 box_pile, 4,000 boxes;
// 2 sphere_pile, 10,000 spheres) and the untimed steps first; iterations: the timed steps.
BENCHMARK(BM_SceneSimdPaths)->Args({0, 0})->Iterations(300)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SceneSimdPaths)->Args({1, 0})->Iterations(120)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SceneSimdPaths)->Args({1, 120})->Iterations(120)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SceneSimdPaths)->Args({2, 0})->Iterations(150)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace fulcrum::test

BENCHMARK_MAIN();
