// Jolt's HighSpeed scene (bench/churn_scenes.hpp) in Fulcrum, stepped with
// the deepest reported overlap printed every `every` steps: its depth, the
// pair's shapes, speeds and closing speed along the normal, and whether a
// fresh look at the pair (the bodies' fat boxes, their distance) agrees.
//   build-bench/bench/bench_high_speed_probe [COUNT] [STEPS] [EVERY] [THREADS] [WARM]
// and for the instruction counts of steps WARM + 1 .. STEPS:
//   valgrind --tool=callgrind --toggle-collect='measuredStep(*)' build-bench/bench/bench_high_speed_probe 5000 230 1000 1 200
// It also counts the pairs created overlapping (the scene draws positions
// at random in a 90 m cube, as Jolt's does), which stay in the report until
// the solver has pushed them apart. Not a test. With FULCRUM_PROBE_PROFILE=1
// in the environment it also prints the scene's construction time and each
// phase of World::lastStepProfile summed over the steps (wall clock, a
// diagnostic: the figures move with the machine's load); with
// FULCRUM_PROBE_SUBSTEPS=N it runs the scene at N sub-steps.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "churn_scenes.hpp"
#include "collision/narrow_phase.hpp"
#include "fulcrum/fulcrum.hpp"
#include "fulcrum_world.hpp"

using namespace fulcrum;

// The steps after WARM: callgrind's --toggle-collect='measuredStep(*)' counts only them.
[[gnu::noinline]] void measuredStep(World& world, Real dt) { world.step(dt); }

int main(int argc, char** argv) {
    const int count = argc > 1 ? std::atoi(argv[1]) : 5000;
    const int steps = argc > 2 ? std::atoi(argv[2]) : 500;
    const int every = argc > 3 ? std::atoi(argv[3]) : 50;
    const int threads = argc > 4 ? std::atoi(argv[4]) : 1;
    const int warm = argc > 5 ? std::atoi(argv[5]) : 0;
    if (count <= 0 || steps <= 0 || every <= 0 || threads <= 0) {
        std::fprintf(stderr, "usage: %s [COUNT] [STEPS] [EVERY] [THREADS] [WARM] (WARM: steps callgrind does not count)\n", argv[0]);
        return 2;
    }
    const bool profile = std::getenv("FULCRUM_PROBE_PROFILE") != nullptr;
    const auto built0 = std::chrono::steady_clock::now();
    bench::SceneSpec scene = bench::joltHighSpeed(count, steps);
    // FULCRUM_PROBE_SUBSTEPS=N: the scene at N sub-steps (the benchmark's is 2), for comparing the split.
    if (const char* sub = std::getenv("FULCRUM_PROBE_SUBSTEPS"); sub != nullptr && std::atoi(sub) > 0) scene.substeps = std::atoi(sub);
    bench::FulcrumWorld built = bench::buildFulcrumWorld(scene, threads);
    const double buildMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - built0).count();
    StepProfile sum;
    World& world = *built.world;
    const auto kindOf = [&](BodyId id) -> std::string {
        for (std::size_t i = 0; i < built.bodies.size(); ++i) {
            if (built.bodies[i] != id) continue;
            const bench::BodySpec& b = scene.bodies[i];
            if (b.isStatic) return "wall";
            if (!b.parts.empty()) return "compound";
            return b.kind == bench::BodySpec::Kind::Sphere ? "sphere" : "box";
        }
        return "?";
    };
    const auto report = [&](int step) {
        const std::vector<ContactReport> now = world.contacts();
        const ContactReport* worst = nullptr;
        int deep = 0, freshDeep = 0, freshWall = 0;
        Real deepestFresh = 0, deepestWall = 0;
        ManifoldBuffer buffer;
        for (const ContactReport& r : now) {
            if (r.depth > Real(0.05)) ++deep;
            if (worst == nullptr || r.depth > worst->depth) worst = &r;
            // The pair's overlap at the final poses, from a fresh narrow phase.
            collide(world.shape(r.bodyA), world.transform(r.bodyA), world.shape(r.bodyB), world.transform(r.bodyB), 0, buffer);
            Real fresh = 0;
            for (std::size_t m = 0; m < buffer.size(); ++m) fresh = std::max(fresh, buffer[m].maxDepth());
            if (fresh > Real(0.05)) {
                ++freshDeep;
                if (kindOf(r.bodyA) == "wall" || kindOf(r.bodyB) == "wall") ++freshWall;
            }
            deepestFresh = std::max(deepestFresh, fresh);
            if (kindOf(r.bodyA) == "wall" || kindOf(r.bodyB) == "wall") deepestWall = std::max(deepestWall, fresh);
        }
        int awake = 0;
        for (const BodyId id : built.bodies)
            if (world.isAwake(id)) ++awake;
        std::printf("step %4d: %zu contacts, %d reported deeper than 5 cm, %d at the final poses (%d with a wall, the deepest into a wall %.4f m; deepest %.4f m), %d awake",
                    step, now.size(), deep, freshDeep, freshWall, double(deepestWall), double(deepestFresh), awake);
        if (worst != nullptr) {
            const Vec3 va = world.linearVelocity(worst->bodyA), vb = world.linearVelocity(worst->bodyB);
            std::printf("; deepest reported %.4f m: %s-%s, speeds %.2f, %.2f m/s, closing %.2f m/s, spins %.1f, %.1f rad/s, at (%.1f %.1f %.1f)",
                        double(worst->depth), kindOf(worst->bodyA).c_str(), kindOf(worst->bodyB).c_str(), double(length(va)),
                        double(length(vb)), double(dot(va - vb, worst->normal)), double(length(world.angularVelocity(worst->bodyA))),
                        double(length(world.angularVelocity(worst->bodyB))), double(world.position(worst->bodyB).x),
                        double(world.position(worst->bodyB).y), double(world.position(worst->bodyB).z));
        }
        std::printf("\n");
    };
    report(0);
    for (int i = 0; i < steps; ++i) {
        if (i < warm) {
            world.step(static_cast<Real>(scene.dt));
        } else {
            measuredStep(world, static_cast<Real>(scene.dt));
        }
        if (profile) {
            const StepProfile p = world.lastStepProfile();
            sum.total += p.total;
            sum.collide += p.collide;
            sum.prepare += p.prepare;
            sum.solve += p.solve;
            sum.store += p.store;
            sum.continuous += p.continuous;
            sum.sleep += p.sleep;
            sum.finish += p.finish;
        }
        if ((i + 1) % every == 0 || i < 3) report(i + 1);
    }
    if (profile) {
        std::printf("construction %.1f ms; %d steps %.1f ms: collide %.1f, prepare %.1f, solve %.1f, store %.1f, "
                    "continuous %.1f, sleep %.1f, finish %.1f\n",
                    buildMs, steps, sum.total, sum.collide, sum.prepare, sum.solve, sum.store, sum.continuous, sum.sleep,
                    sum.finish);
    }
    return 0;
}
