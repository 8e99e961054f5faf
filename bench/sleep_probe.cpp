// When a pile falls asleep (the step after which no body is awake, and the
// awake body-steps in all), with ContactSolver's push-out of grown overlaps on
// or off (off: main's bits), and with tiny perturbations: every dynamic body's
// spawn position moved by up to SHIFT m per axis (SEED >= 0: each body its
// own offset; SEED < 0: one offset for all, so a pile's identical towers stay
// identical), and gravity moved by GRAVITY_ULPS ulps. docs/benchmarks.md,
// `pile9`, "Round nine", 5: box_pile's sleep is a draw, not a lean.
//   bench_sleep_probe SCENE STEPS PUSHOUT SHIFT SEED GRAVITY_ULPS [TRACE]
// (SCENE: bench/scenes.hpp, full or quick size; TRACE > 0: the awake count
// every TRACE steps.)
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <vector>

#include "fulcrum/fulcrum.hpp"
#include "fulcrum_world.hpp"
#include "world/world_impl.hpp"

using namespace fulcrum;

static double hashUnit(std::uint64_t x) {
    x += 0x9E3779B97F4A7C15ull; x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull; x = (x ^ (x >> 27)) * 0x94D049BB133111EBull; x ^= x >> 31;
    return double(x >> 11) / double(1ull << 53) * 2.0 - 1.0;
}

int main(int argc, char** argv) {
    if (argc < 7) {
        std::fprintf(stderr, "usage: %s SCENE STEPS PUSHOUT(0|1) SHIFT SEED GRAVITY_ULPS [TRACE]\n", argv[0]);
        return 2;
    }
    const std::string name = argv[1];
    const int steps = std::atoi(argv[2]);
    const bool pushOut = std::atoi(argv[3]) != 0;
    const double shift = std::atof(argv[4]);
    const int seed = std::atoi(argv[5]);
    const int gulps = std::atoi(argv[6]);
    const int trace = argc > 7 ? std::atoi(argv[7]) : 0;
    std::vector<bench::LazyScene> scenes = bench::allScenes(true);
    for (bench::LazyScene& s : bench::allScenes(false)) scenes.push_back(std::move(s));
    if (std::optional<bench::SceneSpec> found = bench::buildNamed(scenes, name)) {
        bench::SceneSpec& scene = *found;
        int moved = 0;
        for (std::size_t i = 0; i < scene.bodies.size(); ++i) {
            bench::BodySpec& b = scene.bodies[i];
            if (b.isStatic || shift == 0) continue;
            // seed < 0: one offset for every body (the towers stay alike).
            const std::uint64_t k = seed < 0 ? std::uint64_t(-seed) * 7919ull : seed * 1000003ull + i * 3;
            b.position.x += shift * hashUnit(k + 0);
            b.position.y += shift * hashUnit(k + 1);
            b.position.z += shift * hashUnit(k + 2);
            ++moved;
        }
        bench::FulcrumWorld built = bench::buildFulcrumWorld(scene, 1);
        World& world = *built.world;
        if (gulps != 0) {
            Vec3 g = bench::toFulcrum(scene.gravity);
            for (int k = 0; k < std::abs(gulps); ++k) g.y = std::nextafter(g.y, gulps > 0 ? Real(1e30) : Real(-1e30));
            world.setGravity(g);
        }
        world.setPushOutGrownOverlaps(pushOut);
        std::vector<BodyId> dyn;
        for (std::size_t i = 0; i < scene.bodies.size(); ++i) if (!scene.bodies[i].isStatic) dyn.push_back(built.bodies[i]);
        long long awakeSteps = 0;
        int lastAwake = -1;
        for (int i = 0; i < steps; ++i) {
            world.step(static_cast<Real>(scene.dt));
            int awake = 0;
            for (BodyId id : dyn) awake += world.isAwake(id) ? 1 : 0;
            awakeSteps += awake;
            if (awake > 0) lastAwake = i;
            if (trace > 0 && i % trace == 0) std::printf("  step %d awake %d\n", i, awake);
        }
        double checksum = 0;
        for (BodyId id : built.bodies) { const Vec3 p = world.position(id); checksum += double(p.x) + double(p.y) + double(p.z); }
        std::printf("%s pushOut %d shift %g seed %d gulps %d (bodies moved %d): asleep after step %d, awake body-steps %lld, checksum %.9g\n",
                    name.c_str(), int(pushOut), shift, seed, gulps, moved, lastAwake + 1, awakeSteps, checksum);
        return 0;
    }
    std::fprintf(stderr, "no scene\n");
    return 2;
}
