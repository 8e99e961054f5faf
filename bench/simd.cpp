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
#include <benchmark/benchmark.h>

#include <bit>
#include <cstdio>
#include <cstdlib>

#include "../tests/simd/contact_rows.hpp"

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

}  // namespace
}  // namespace fulcrum::test

BENCHMARK_MAIN();
