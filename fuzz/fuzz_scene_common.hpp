#pragma once
// Shared by the scene-reading fuzz targets: what a fuzzed scene may cost
// before it is built and stepped, and the build-and-step itself.
//
// The fuzzer hunts crashes, hangs and sanitizer reports, not scenes that are
// legal but big: a cloth of 1000 x 1000 or 1000 sub-steps of 1000 iterations
// is a fine scene that takes seconds, and would be reported as a timeout or
// an out-of-memory. So a scene over these budgets is still parsed (and saved
// and parsed again) but not built; the budgets are far above what the fuzzer
// needs to reach every code path.
#include <cstddef>
#include <cstdlib>
#include <cstdio>

#include "fulcrum/error.hpp"
#include "fulcrum/scene.hpp"
#include "fulcrum/world.hpp"

namespace fulcrum::fuzz {

inline std::size_t shapeCost(const ShapeDesc& s) {
    std::size_t cost = 1 + s.points.size() + s.vertices.size() + 4 * s.triangles.size();
    for (const ShapeDesc::Child& c : s.children) cost += shapeCost(c.shape);
    return cost;
}

inline bool withinBudget(const Scene& scene) {
    std::size_t cost = 0;
    for (const SceneBody& b : scene.bodies) cost += shapeCost(b.shape);
    for (const SceneRope& r : scene.ropes) cost += static_cast<std::size_t>(r.def.segments) + 1;
    for (const SceneCloth& c : scene.cloths) cost += static_cast<std::size_t>(c.def.size[0]) * static_cast<std::size_t>(c.def.size[1]);
    cost += scene.joints.size() + scene.springs.size();
    const long long solverWork = static_cast<long long>(scene.world.substeps) * scene.world.solverIterations;
    return cost <= 4000 && solverWork <= 256;
}

// Builds the scene (one thread: the fuzzer runs one input at a time, and a
// pool per input would be most of the run) and steps it up to three times.
// Errors the engine reports are the expected outcome of bad input.
inline void buildAndStep(Scene scene) {
    if (!withinBudget(scene)) return;
    scene.world.threads = 1;
    try {
        World world = buildWorld(scene);
        const int steps = scene.steps < 3 ? scene.steps : 3;
        for (int i = 0; i < steps; ++i) world.step(scene.dt);
    } catch (const Error&) {
    }
}

// A save of a parsed scene must parse again to the same scene.
inline void checkRoundTrip(const Scene& scene) {
    const std::string saved = sceneToJson(scene);
    Scene again;
    try {
        again = parseScene(saved, "<saved>");
    } catch (const Error& e) {
        std::fprintf(stderr, "a saved scene does not load again: %s\n--- saved:\n%s\n", e.what(), saved.c_str());
        std::abort();
    }
    if (!(again == scene)) {
        std::fprintf(stderr, "a saved scene loads as a different scene\n--- saved:\n%s\n", saved.c_str());
        std::abort();
    }
}

}  // namespace fulcrum::fuzz
