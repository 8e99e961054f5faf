// How much of a step runs in parallel, and what 2 threads gain: the scenes of
// bench/scenes.hpp (box_pile, sphere_pile, ...) stepped three ways.
//
//   bench_step_threads [--scene NAME] [--steps N] [--threads N] [--quick] [--p-only] [--one-thread-only]
//
// --p-only: the timing run alone (to profile the step as p sees it);
// --one-thread-only: one run with threads = 1 (the inline task system), for
// instruction counts under callgrind. Both print the final state's hash.
//
// 1. On a timing wrapper around the inline task system (one thread): the
//    calling thread's CPU time inside parallelFor calls over its CPU time in
//    World::step is the parallel fraction p. Thread CPU time, not wall time,
//    so the figure holds on a machine shared with other work. Amdahl's bound
//    for N threads is 1 / ((1 - p) + p / N).
// 2. On the built-in pool with 1 thread and with N threads (default 2): wall
//    ms per step (median, mean) and the speed-up; those need idle cores, so
//    the load average is printed with them.
// 3. The final state of every run is hashed: the runs must agree to the bit.
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <numeric>
#include <string>
#include <vector>

#include "fulcrum/fulcrum.hpp"
#include "fulcrum/task_system.hpp"
#include "scenes.hpp"

namespace {

double threadCpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// The inline task system, timing the CPU spent inside parallelFor. It claims
// two workers (and runs every range on the calling thread as worker 0, which
// the contract allows): the contact solver runs its loops inline, outside
// parallelFor, when workerCount() is 1, so a count of 1 would hide its
// parallel part from p.
class TimingTaskSystem final : public fulcrum::TaskSystem {
public:
    double parallelSeconds = 0;
    std::uint64_t calls = 0;
    std::uint32_t workerCount() const noexcept override { return 2; }
    void parallelFor(std::uint32_t count, std::uint32_t, fulcrum::RangeFn fn) override {
        if (count == 0) return;
        ++calls;
        const double t0 = threadCpuSeconds();
        fn(0, count, 0);
        parallelSeconds += threadCpuSeconds() - t0;
    }
};

fulcrum::World build(const bench::SceneSpec& scene, int threads) {
    fulcrum::WorldDef def;
    def.sleeping = scene.sleeping;
    def.threads = threads;
    fulcrum::World world(def);
    const auto real = [](double v) { return static_cast<fulcrum::Real>(v); };
    const auto vec = [&](bench::V3 v) { return fulcrum::Vec3{real(v.x), real(v.y), real(v.z)}; };
    for (const bench::BodySpec& b : scene.bodies) {
        fulcrum::BodyDef d;
        d.type = b.isStatic ? fulcrum::BodyType::Static : fulcrum::BodyType::Dynamic;
        switch (b.kind) {
            case bench::BodySpec::Kind::Sphere: d.shape = fulcrum::Shape::sphere(real(b.half.x)); break;
            case bench::BodySpec::Kind::Capsule:
                d.shape = fulcrum::Shape::capsule(real(b.half.x), real(b.half.y));
                break;
            case bench::BodySpec::Kind::Box: d.shape = fulcrum::Shape::box(vec(b.half)); break;
        }
        if (!b.isStatic) d.mass = real(b.mass);
        d.position = vec(b.position);
        d.orientation = fulcrum::Quat{real(b.orientation.w), real(b.orientation.x), real(b.orientation.y),
                                      real(b.orientation.z)};
        d.linearVelocity = vec(b.linearVelocity);
        d.angularVelocity = vec(b.angularVelocity);
        d.friction = real(scene.friction);
        world.createBody(d);
    }
    return world;
}

std::uint64_t hashState(const fulcrum::World& world) {
    std::uint64_t h = 14695981039346656037ull;
    const auto add = [&](float v) {
        std::uint32_t bits = 0;
        std::memcpy(&bits, &v, sizeof bits);
        h = (h ^ bits) * 1099511628211ull;
    };
    for (const fulcrum::BodyId id : world.bodies()) {
        const fulcrum::Vec3 p = world.position(id), v = world.linearVelocity(id);
        const fulcrum::Quat q = world.orientation(id);
        for (const float x : {p.x, p.y, p.z, v.x, v.y, v.z, q.w, q.x, q.y, q.z}) add(x);
    }
    return h;
}

struct Timing {
    std::vector<double> stepMs;
    double cpuSeconds = 0;  // calling thread
    std::uint64_t hash = 0;
};

Timing run(const bench::SceneSpec& scene, int steps, int threads, fulcrum::TaskSystem* tasks) {
    fulcrum::World world = build(scene, threads);
    if (tasks != nullptr) world.setTaskSystem(tasks);
    Timing t;
    t.stepMs.reserve(static_cast<std::size_t>(steps));
    for (int i = 0; i < steps; ++i) {
        const double c0 = threadCpuSeconds();
        const auto t0 = std::chrono::steady_clock::now();
        world.step(static_cast<fulcrum::Real>(scene.dt));
        const auto t1 = std::chrono::steady_clock::now();
        t.cpuSeconds += threadCpuSeconds() - c0;
        t.stepMs.push_back(std::chrono::duration<double, std::milli>(t1 - t0).count());
    }
    t.hash = hashState(world);
    return t;
}

double median(std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
    return v[v.size() / 2];
}
double mean(const std::vector<double>& v) { return std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size()); }

double loadAverage() {
    double load = -1;
    if (std::FILE* f = std::fopen("/proc/loadavg", "r")) {
        if (std::fscanf(f, "%lf", &load) != 1) load = -1;
        std::fclose(f);
    }
    return load;
}

}  // namespace

int main(int argc, char** argv) {
    std::string only;
    int steps = 0, threads = 2;
    bool quick = false, pOnly = false, oneThreadOnly = false;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--scene") == 0 && i + 1 < argc) only = argv[++i];
        else if (std::strcmp(argv[i], "--steps") == 0 && i + 1 < argc) steps = std::atoi(argv[++i]);
        else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) threads = std::max(2, std::atoi(argv[++i]));
        else if (std::strcmp(argv[i], "--quick") == 0) quick = true;
        else if (std::strcmp(argv[i], "--p-only") == 0) pOnly = true;
        else if (std::strcmp(argv[i], "--one-thread-only") == 0) oneThreadOnly = true;
        else {
            std::fprintf(stderr, "usage: %s [--scene NAME] [--steps N] [--threads N] [--quick] [--p-only] [--one-thread-only]\n", argv[0]);
            return 2;
        }
    }
    std::printf("| scene | steps | parallel fraction p | Amdahl bound, %d threads | 1 thread ms (median/mean) | %d threads ms "
                "(median/mean) | speed-up (mean) | load | bit-identical | state hash |\n",
                threads, threads);
    std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
    for (const bench::SceneSpec& scene : bench::allScenes(quick)) {
        if (!only.empty() && scene.name.rfind(only, 0) != 0) continue;
        const int n = steps > 0 ? steps : scene.steps;
        if (oneThreadOnly) {
            const Timing one = run(scene, n, 1, nullptr);
            std::printf("| %s | %d | | | %.3f / %.3f | | | | | %016llx |\n", scene.name.c_str(), n, median(one.stepMs),
                        mean(one.stepMs), static_cast<unsigned long long>(one.hash));
            continue;
        }
        TimingTaskSystem timing;
        const Timing serial = run(scene, n, 1, &timing);
        const double p = timing.parallelSeconds / serial.cpuSeconds;
        const double bound = 1 / ((1 - p) + p / threads);
        if (pOnly) {  // the one-thread run alone (for profiling its serial part)
            std::printf("| %s | %d | %.3f (%llu calls) | %.2f | | | | | | %016llx |\n", scene.name.c_str(), n, p,
                        static_cast<unsigned long long>(timing.calls), bound, static_cast<unsigned long long>(serial.hash));
            continue;
        }
        const double load0 = loadAverage();
        const Timing one = run(scene, n, 1, nullptr);
        const Timing many = run(scene, n, threads, nullptr);
        const double load1 = loadAverage();
        std::printf("| %s | %d | %.3f (%llu calls) | %.2f | %.3f / %.3f | %.3f / %.3f | %.2f | %.1f-%.1f | %s | %016llx |\n",
                    scene.name.c_str(), n, p, static_cast<unsigned long long>(timing.calls), bound, median(one.stepMs),
                    mean(one.stepMs), median(many.stepMs), mean(many.stepMs), mean(one.stepMs) / mean(many.stepMs),
                    std::min(load0, load1), std::max(load0, load1),
                    serial.hash == one.hash && one.hash == many.hash ? "yes" : "NO", static_cast<unsigned long long>(serial.hash));
        std::fflush(stdout);
    }
    return 0;
}
