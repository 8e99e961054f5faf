// A fixed number of steps of one benchmark scene (bench/scenes.hpp, the quick
// sizes), on one thread, with no timing: for callgrind, whose instruction
// counts are repeatable on a loaded machine where clocks are not. Compares
// builds, e.g. float against FULCRUM_DOUBLE (docs/double-precision.md):
//   valgrind --tool=callgrind --toggle-collect='fulcrum::World::step(*)'
//       build/release/bench/bench_step_count pyramid20 60
// Prints the scene, the steps and a checksum of the final positions (so the
// two builds' runs can be told apart from a broken one). Box3D's scenes
// (bench/box3d_scenes.hpp) and Jolt's run at their full sizes, e.g. joint_grid,
// trees25, convex_vs_mesh, and the mesh scenes at their small sizes too
// (trees100(10), convex_vs_mesh(7x7)); the churn scenes
// (bench/churn_scenes.hpp) at their full or quick sizes, their script's
// creations and destructions inside the counted step (callgrind:
// --toggle-collect='scriptAndStep(*)' counts them with the step).
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "fulcrum/fulcrum.hpp"
#include "box3d_scenes.hpp"
#include "churn_scenes.hpp"
#include "fulcrum_world.hpp"

using namespace fulcrum;

// One step with the script's events before it: callgrind's
// --toggle-collect='scriptAndStep(*)' counts both.
[[gnu::noinline]] void scriptAndStep(bench::FulcrumScript& script, World& world, int step, Real dt) {
    script.beforeStep(step);
    world.step(dt);
}

// The steps from FIRST_MEASURED on (the optional third argument) run through
// this instead: callgrind's --toggle-collect='measuredStep(*)' counts a slice
// of a long run (the full scenes' later steps, where their bodies rest on each
// other) without the first steps' falls.
[[gnu::noinline]] void measuredStep(bench::FulcrumScript& script, World& world, int step, Real dt) {
    scriptAndStep(script, world, step, dt);
}

int main(int argc, char** argv) {
    if (argc != 3 && argc != 4) {
        std::fprintf(stderr, "usage: %s SCENE STEPS [FIRST_MEASURED]   (SCENE: a name from bench/scenes.hpp, quick sizes, or bench/box3d_scenes.hpp)\n", argv[0]);
        return 2;
    }
    const std::string name = argv[1];
    const int steps = std::atoi(argv[2]);
    const int firstMeasured = argc == 4 ? std::atoi(argv[3]) : steps;
    // Every scene by name, only the one asked for built.
    std::vector<bench::LazyScene> scenes = bench::allScenes(true);
    const auto append = [&scenes](std::vector<bench::LazyScene> more) {
        for (bench::LazyScene& scene : more) scenes.push_back(std::move(scene));
    };
    append(bench::box3dScenes(false));
    append(bench::joltScenes(false));
    // The mesh scenes' small sizes too (trees100(10), convex_vs_mesh(7x7), ...): callgrind runs them in minutes.
    append(bench::box3dMeshScenes(true));
    append(bench::joltMeshScenes(true));
    // The churn scenes by name: full size, or the quick sizes (e.g. rain(4x2)).
    append(bench::churnScenes(false));
    append(bench::churnScenes(true));
    // A middle size of the washer for callgrind: 1728 cubes, where the cube pairs weigh as at full size.
    scenes.push_back(bench::lazyScene<bench::washer, bench::washerName>(12, 300));
    if (const std::optional<bench::SceneSpec> found = bench::buildNamed(scenes, name)) {
        const bench::SceneSpec& scene = *found;
        bench::FulcrumWorld built = bench::buildFulcrumWorld(scene, 1);
        World& world = *built.world;
        bench::pushOutFromEnvironment(world);
        std::vector<BodyId> ids = built.bodies;
        bench::FulcrumScript script(scene, built);
        for (int i = 0; i < steps; ++i) {
            bench::driveKinematics(built, scene, i);
            if (i >= firstMeasured) {
                measuredStep(script, world, i, static_cast<Real>(scene.dt));
            } else {
                scriptAndStep(script, world, i, static_cast<Real>(scene.dt));
            }
        }
        for (const BodyId id : script.liveBodies()) ids.push_back(id);
        double checksum = 0;
        for (const BodyId id : ids) {
            const Vec3 p = world.position(id);
            checksum += double(p.x) + double(p.y) + double(p.z);
        }
        std::printf("%s: %d steps, sizeof(Real) %zu, position checksum %.9g\n", name.c_str(), steps, sizeof(Real), checksum);
        return 0;
    }
    std::fprintf(stderr, "no scene named '%s'\n", name.c_str());
    return 2;
}
