// The `cloth` benchmark scene (bench/scenes.hpp; docs/benchmarks.md): 64 x 64
// particles spaced 0.05 m (a 3.15 m square, 0.01 kg each) with structural,
// shear and bend constraints, held horizontal at y = 3 and dropped onto a
// static sphere (radius 0.8, centre (0, 1, 0)) above the ground plane y = 0;
// 600 steps of 1/60 s, one thread.
//
// Reports median and mean ms per step and the quality metric: mean and max
// structural stretch at the end, deepest penetration into the sphere.
// Run: build-bench/bench/bench_cloth  (configure with -DFULCRUM_BUILD_BENCH=ON)
// Optional arguments after the benchmark flags: --substeps=N --iterations=N --steps=N (600; fewer for callgrind)
// --lanes=4|1 (the distance kernel's SIMD width: 8 with AVX2 by default, detected at run time)
// Counters: median_ms / mean_ms (wall per step), cpu_ms (thread CPU per step), quality.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <ctime>
#include <cstring>
#include <vector>

#include "particles/particle_builders.hpp"
#include "particles/particle_metrics.hpp"
#include "particles/particle_world.hpp"
#include "particles/shape_query_adapter.hpp"
#include "particles/xpbd_distance.hpp"
#include "../tests/particles/rigid_test_world.hpp"

namespace {

using namespace fulcrum;

int gSubsteps = ParticleWorldSettings{}.substeps;
int gIterations = ParticleWorldSettings{}.iterations;
int gSteps = 600;

// CPU time of this thread: the machine is shared, so wall time includes waiting for a core.
double threadCpuMs() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

void clothScene(benchmark::State& state) {
    for (auto _ : state) {
        state.PauseTiming();
        ParticleWorldSettings settings;
        settings.substeps = gSubsteps;
        settings.iterations = gIterations;
        ParticleWorld world(settings);
        test_support::TestRigidWorld rigid;
        const Vec3 sphereCenter{0, 1, 0};
        const Real sphereRadius = Real(0.8);
        const std::uint32_t sphere = rigid.addStatic(Shape::sphere(sphereRadius), {sphereCenter, {}});
        rigid.addStatic(Shape::plane({0, 1, 0}, 0));
        ClothDef def;
        def.name = "cloth";
        def.size = {64, 64};
        def.spacing = Real(0.05);
        def.particleMass = Real(0.01);
        def.radius = Real(0.02);
        def.origin = {Real(-1.575), 3, Real(-1.575)};
        def.bendCompliance = Real(0.1);  // m/N: drapes (0 would make a stiff plate)
        const ParticleSystemId id = world.addCloth(def, &rigid);
        std::vector<double> ms;
        ms.reserve(static_cast<std::size_t>(gSteps));
        state.ResumeTiming();
        const double cpu0 = threadCpuMs();
        for (int stepIndex = 0; stepIndex < gSteps; ++stepIndex) {
            const auto t0 = std::chrono::steady_clock::now();
            world.step(Real(1) / 60, &rigid);
            const auto t1 = std::chrono::steady_clock::now();
            ms.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
        }
        const double cpuMs = (threadCpuMs() - cpu0) / static_cast<double>(gSteps);
        state.PauseTiming();
        const ParticleSystem& s = world.system(id);
        const StretchStats stretch = structuralStretch(s);
        Real deepest = 0;  // into the sphere only
        for (std::size_t i = 0; i < s.particleCount(); ++i) {
            deepest = std::max(deepest, s.radius[i] - (distance(s.position[i], sphereCenter) - sphereRadius));
        }
        (void)sphere;
        double mean = 0;
        for (double v : ms) mean += v;
        mean /= static_cast<double>(ms.size());
        std::vector<double> sorted = ms;
        const auto middle = sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2);
        std::nth_element(sorted.begin(), middle, sorted.end());
        state.counters["median_ms"] = *middle;
        state.counters["cpu_ms"] = cpuMs;
        state.counters["mean_ms"] = mean;
        state.counters["max_stretch"] = stretch.max;
        state.counters["mean_stretch"] = stretch.mean;
        state.counters["sphere_penetration_m"] = deepest;
        state.counters["substeps"] = gSubsteps;
        state.counters["iterations"] = gIterations;
        state.counters["lanes"] = detail::distanceSimdLanes();
        state.ResumeTiming();
    }
}
BENCHMARK(clothScene)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
    std::vector<char*> rest;
    for (int i = 0; i < argc; ++i) {
        if (std::strncmp(argv[i], "--substeps=", 11) == 0) gSubsteps = std::atoi(argv[i] + 11);
        else if (std::strncmp(argv[i], "--iterations=", 13) == 0) gIterations = std::atoi(argv[i] + 13);
        else if (std::strncmp(argv[i], "--steps=", 8) == 0) gSteps = std::max(1, std::atoi(argv[i] + 8));
        else if (std::strncmp(argv[i], "--lanes=", 8) == 0) detail::setDistanceSimdLanes(std::atoi(argv[i] + 8));
        else rest.push_back(argv[i]);
    }
    int restCount = static_cast<int>(rest.size());
    benchmark::Initialize(&restCount, rest.data());
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
