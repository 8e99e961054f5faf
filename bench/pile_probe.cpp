// A pile of bench/scenes.hpp stepped for instruction counts and quick timings:
// `warm` steps first, then `measured` steps timed (and, under callgrind with
// --instr-atstart=no, the only steps counted). docs/solver.md's sphere-pile
// figures come from
//   valgrind --tool=callgrind --instr-atstart=no build/bench/bench_pile_probe sphere 10 6 10 150 30
//   build/bench/bench_pile_probe sphere 25 16 25 60 30 [threads]
// The checksum (sum of the final heights) lets two builds be checked for the
// same results; it is not a test.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#else
#define CALLGRIND_START_INSTRUMENTATION
#define CALLGRIND_STOP_INSTRUMENTATION
#endif

#include "fulcrum/fulcrum.hpp"
#include "scenes.hpp"

int main(int argc, char** argv) {
    if (argc < 7) {
        std::fprintf(stderr, "usage: %s sphere|box NX NY NZ WARM_STEPS MEASURED_STEPS [THREADS]\n", argv[0]);
        return 2;
    }
    const bool spheres = std::strcmp(argv[1], "sphere") == 0;
    const int nx = std::atoi(argv[2]), ny = std::atoi(argv[3]), nz = std::atoi(argv[4]);
    const int warm = std::atoi(argv[5]), measured = std::atoi(argv[6]);
    const int threads = argc > 7 ? std::atoi(argv[7]) : 1;
    if (nx <= 0 || ny <= 0 || nz <= 0 || warm < 0 || measured <= 0 || threads <= 0) {
        std::fprintf(stderr, "pile_probe: sizes, measured steps and threads must be positive\n");
        return 2;
    }
    const bench::SceneSpec scene = bench::pile(spheres ? "sphere_pile" : "box_pile",
                                               spheres ? bench::BodySpec::Kind::Sphere : bench::BodySpec::Kind::Box,
                                               nx, ny, nz, spheres ? 1.2 : 1.5, warm + measured);
    fulcrum::WorldDef def;
    def.threads = threads;
    fulcrum::World world(def);
    const auto real = [](double v) { return static_cast<fulcrum::Real>(v); };
    const auto vec = [&](bench::V3 v) { return fulcrum::Vec3{real(v.x), real(v.y), real(v.z)}; };
    std::vector<fulcrum::BodyId> ids;
    for (const bench::BodySpec& b : scene.bodies) {
        fulcrum::BodyDef d;
        d.type = b.isStatic ? fulcrum::BodyType::Static : fulcrum::BodyType::Dynamic;
        d.shape = b.kind == bench::BodySpec::Kind::Sphere ? fulcrum::Shape::sphere(real(b.half.x))
                                                           : fulcrum::Shape::box(vec(b.half));
        if (!b.isStatic) d.mass = 1;
        d.position = vec(b.position);
        d.friction = real(scene.friction);
        ids.push_back(world.createBody(d));
    }
    const fulcrum::Real dt = fulcrum::Real(1) / 60;
    for (int i = 0; i < warm; ++i) world.step(dt);
    CALLGRIND_START_INSTRUMENTATION;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < measured; ++i) world.step(dt);
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    CALLGRIND_STOP_INSTRUMENTATION;
    double heights = 0;
    int awake = 0;
    for (const fulcrum::BodyId id : ids) {
        heights += static_cast<double>(world.position(id).y);
        if (world.isAwake(id)) ++awake;
    }
    std::printf("ms/step %.3f  awake %d  checksum %.9g\n", ms / measured, awake, heights);
    return 0;
}
