// How much of a step runs in parallel, and what 2 threads gain: the scenes of
// bench/scenes.hpp (box_pile, sphere_pile, ...) stepped three ways.
//
//   bench_step_threads [--scene NAME] [--steps N] [--threads N] [--quick] [--p-only] [--one-thread-only] [--phases] [--rounds R]
//                      [--windows W] [--phase-steps A-B]
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
// --phases: after each scene, where the time went on 1 and on N threads
//    (World::lastStepProfile summed over the run): ms per step of each phase
//    and its speed-up, to see which phase keeps the step from scaling.
// --rounds R: the 1- and N-thread runs R times each, alternating; each step's
//    time and each phase's sum is the fastest of its R (the machine's noise
//    only ever adds time).
// --windows W: the mean step time on 1 and N threads over each W steps (a
//    pile's fall, collapse and rest scale differently).
// --phase-steps A-B: --phases summed over steps A to B only (box_pile's
//    ~950-body tail, steps 150-249, scales worst of its phases).
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
            case bench::BodySpec::Kind::Hull: {
                std::vector<fulcrum::Vec3> points;
                for (const bench::V3& p : scene.hullPoints) points.push_back(vec(p));
                d.shape = fulcrum::Shape::convexHull(points);
                break;
            }
            case bench::BodySpec::Kind::SharedCompound: break;  // the mesh scenes' (not among the scenes run here)
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

// StepProfile's times, in pipeline order, then the total.
struct Phase {
    const char* name;
    double fulcrum::StepProfile::*field;
};
constexpr Phase kPhases[] = {
    {"collide", &fulcrum::StepProfile::collide},       {"prepare", &fulcrum::StepProfile::prepare},
    {"solve", &fulcrum::StepProfile::solve},           {"store", &fulcrum::StepProfile::store},
    {"continuous", &fulcrum::StepProfile::continuous}, {"particles", &fulcrum::StepProfile::particles},
    {"sleep", &fulcrum::StepProfile::sleep},           {"finish", &fulcrum::StepProfile::finish},
    {"total", &fulcrum::StepProfile::total},
};

struct Timing {
    std::vector<double> stepMs;
    fulcrum::StepProfile phases;  // summed over the steps
    double cpuSeconds = 0;  // calling thread
    std::uint64_t hash = 0;
};

int gPhaseFirst = 0, gPhaseLast = -1;  // --phase-steps; last < 0: every step
bool inPhaseSteps(int step) { return step >= gPhaseFirst && (gPhaseLast < 0 || step <= gPhaseLast); }

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
        if (!inPhaseSteps(i)) continue;
        const fulcrum::StepProfile p = world.lastStepProfile();
        for (const Phase& phase : kPhases) t.phases.*(phase.field) += p.*(phase.field);
    }
    t.hash = hashState(world);
    return t;
}

// Keeps the faster of each step time and each phase sum (the same scene and steps).
void keepFastest(Timing& best, const Timing& t) {
    for (std::size_t k = 0; k < best.stepMs.size(); ++k) best.stepMs[k] = std::min(best.stepMs[k], t.stepMs[k]);
    for (const Phase& phase : kPhases) best.phases.*(phase.field) = std::min(best.phases.*(phase.field), t.phases.*(phase.field));
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

void printWindows(const Timing& one, const Timing& many, int threads, int window) {
    std::printf("\n| steps | 1 thread ms/step | %d threads ms/step | speed-up |\n|---|---|---|---|\n", threads);
    const std::size_t n = one.stepMs.size(), w = static_cast<std::size_t>(window);
    for (std::size_t first = 0; first < n; first += w) {
        const std::size_t last = std::min(n, first + w);
        double a = 0, b = 0;
        for (std::size_t k = first; k < last; ++k) {
            a += one.stepMs[k];
            b += many.stepMs[k];
        }
        const auto count = static_cast<double>(last - first);
        std::printf("| %zu-%zu | %.3f | %.3f | %.2f |\n", first, last - 1, a / count, b / count, a / b);
    }
    std::printf("\n");
}

void printPhases(const Timing& one, const Timing& many, int threads, int steps) {
    const auto& a = one.phases;
    const auto& b = many.phases;
    int counted = 0;
    for (int i = 0; i < steps; ++i) counted += inPhaseSteps(i) ? 1 : 0;
    const double n = std::max(1, counted);
    if (counted != steps) std::printf("\nPhases over steps %d-%d:\n", gPhaseFirst, gPhaseFirst + counted - 1);
    std::printf("\n| phase | 1 thread ms/step | %d threads ms/step | speed-up |\n|---|---|---|---|\n", threads);
    for (const Phase& phase : kPhases) {
        const double x = a.*(phase.field), y = b.*(phase.field);
        std::printf("| %s | %.4f | %.4f | %.2f |\n", phase.name, x / n, y / n, y > 0 ? x / y : 0.0);
    }
    std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
    std::string only;
    int steps = 0, threads = 2, rounds = 1, window = 0;
    bool quick = false, pOnly = false, oneThreadOnly = false, phases = false;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--scene") == 0 && i + 1 < argc) only = argv[++i];
        else if (std::strcmp(argv[i], "--steps") == 0 && i + 1 < argc) steps = std::atoi(argv[++i]);
        else if (std::strcmp(argv[i], "--threads") == 0 && i + 1 < argc) threads = std::max(2, std::atoi(argv[++i]));
        else if (std::strcmp(argv[i], "--quick") == 0) quick = true;
        else if (std::strcmp(argv[i], "--p-only") == 0) pOnly = true;
        else if (std::strcmp(argv[i], "--one-thread-only") == 0) oneThreadOnly = true;
        else if (std::strcmp(argv[i], "--phases") == 0) phases = true;
        else if (std::strcmp(argv[i], "--windows") == 0 && i + 1 < argc) window = std::max(1, std::atoi(argv[++i]));
        else if (std::strcmp(argv[i], "--rounds") == 0 && i + 1 < argc) rounds = std::max(1, std::atoi(argv[++i]));
        else if (std::strcmp(argv[i], "--phase-steps") == 0 && i + 1 < argc) {
            phases = true;
            if (std::sscanf(argv[++i], "%d-%d", &gPhaseFirst, &gPhaseLast) != 2 || gPhaseFirst < 0 || gPhaseLast < gPhaseFirst) {
                std::fprintf(stderr, "--phase-steps wants A-B with 0 <= A <= B, got '%s'\n", argv[i]);
                return 2;
            }
        } else {
            std::fprintf(stderr, "usage: %s [--scene NAME] [--steps N] [--threads N] [--quick] [--p-only] [--one-thread-only] [--phases] [--rounds R] [--windows W] [--phase-steps A-B]\n", argv[0]);
            return 2;
        }
    }
    std::printf("| scene | steps | parallel fraction p | Amdahl bound, %d threads | 1 thread ms (median/mean) | %d threads ms "
                "(median/mean) | speed-up (mean) | load | bit-identical | state hash |\n",
                threads, threads);
    std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
    for (const bench::LazyScene& lazy : bench::allScenes(quick)) {
        if (!only.empty() && lazy.name.rfind(only, 0) != 0) continue;
        const bench::SceneSpec scene = lazy.build();
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
        Timing one = run(scene, n, 1, nullptr);
        Timing many = run(scene, n, threads, nullptr);
        bool sameBits = one.hash == many.hash;
        for (int r = 1; r < rounds; ++r) {
            const Timing again1 = run(scene, n, 1, nullptr);
            const Timing againN = run(scene, n, threads, nullptr);
            sameBits = sameBits && again1.hash == one.hash && againN.hash == one.hash;
            keepFastest(one, again1);
            keepFastest(many, againN);
        }
        const double load1 = loadAverage();
        std::printf("| %s | %d | %.3f (%llu calls) | %.2f | %.3f / %.3f | %.3f / %.3f | %.2f | %.1f-%.1f | %s | %016llx |\n",
                    scene.name.c_str(), n, p, static_cast<unsigned long long>(timing.calls), bound, median(one.stepMs),
                    mean(one.stepMs), median(many.stepMs), mean(many.stepMs), mean(one.stepMs) / mean(many.stepMs),
                    std::min(load0, load1), std::max(load0, load1),
                    serial.hash == one.hash && sameBits ? "yes" : "NO", static_cast<unsigned long long>(serial.hash));
        if (phases) printPhases(one, many, threads, n);
        if (window > 0) printWindows(one, many, threads, window);
        std::fflush(stdout);
    }
    return 0;
}
