// Box3D's convex_pile (bench/box3d_scenes.hpp) in Fulcrum, stepped for
// instruction counts, its deepest overlap and a check of the reported contacts:
// `warm` steps first, then `measured` steps timed (and, under callgrind with
// --instr-atstart=no, the only steps counted). After the run every reported
// manifold is compared with a fresh narrow phase at the bodies' final poses.
//   build/release/bench/bench_convex_pile_probe 8 8 80 0 500 [threads]
//   valgrind --tool=callgrind --instr-atstart=no build/release/bench/bench_convex_pile_probe 8 8 10 200 10
// The checksum (sum of the final heights) lets two builds be checked for the
// same results; it is not a test.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <vector>

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#else
#define CALLGRIND_START_INSTRUMENTATION
#define CALLGRIND_STOP_INSTRUMENTATION
#endif

#include "box3d_scenes.hpp"
#include "collision/narrow_phase.hpp"
#include "fulcrum/fulcrum.hpp"

int main(int argc, char** argv) {
    if (argc < 6) {
        std::fprintf(stderr, "usage: %s NX NZ LAYERS WARM_STEPS MEASURED_STEPS [THREADS]\n", argv[0]);
        return 2;
    }
    const int nx = std::atoi(argv[1]), nz = std::atoi(argv[2]), layers = std::atoi(argv[3]);
    const int warm = std::atoi(argv[4]), measured = std::atoi(argv[5]);
    const int threads = argc > 6 ? std::atoi(argv[6]) : 1;
    if (nx <= 0 || nz <= 0 || layers <= 0 || warm < 0 || measured <= 0 || threads <= 0) {
        std::fprintf(stderr, "convex_pile_probe: sizes, measured steps and threads must be positive\n");
        return 2;
    }
    const bench::HullPileSpec scene = bench::convexPile(nx, nz, layers);
    using fulcrum::Real;
    using fulcrum::Vec3;
    const auto real = [](double v) { return static_cast<Real>(v); };
    const auto vec = [&](bench::V3 v) { return Vec3{real(v.x), real(v.y), real(v.z)}; };

    fulcrum::WorldDef def;
    def.threads = threads;
    def.substeps = scene.substeps;
    def.sleeping = scene.sleeping;
    def.gravity = vec(scene.gravity);
    fulcrum::World world(def);
    fulcrum::BodyDef ground;
    ground.type = fulcrum::BodyType::Static;
    ground.shape = fulcrum::Shape::box(vec(scene.groundHalf));
    ground.position = vec(scene.groundPosition);
    ground.friction = real(scene.friction);
    world.createBody(ground);
    std::vector<Vec3> points;
    for (const bench::V3& p : scene.hullPoints) points.push_back(vec(p));
    const fulcrum::Shape hull = fulcrum::Shape::convexHull(points);
    std::vector<fulcrum::BodyId> ids;
    for (const bench::V3& p : scene.positions) {
        fulcrum::BodyDef d;
        d.shape = hull;
        d.density = real(scene.density);
        d.friction = real(scene.friction);
        d.restitution = real(scene.restitution);
        d.position = vec(p);
        ids.push_back(world.createBody(d));
    }
    const Real dt = real(scene.dt);
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
    // Every reported manifold against a fresh narrow phase at the final poses.
    Real deepestReported = 0, deepestFresh = 0, worstDepthError = 0, worstNormalError = 0;
    int mismatches = 0;
    fulcrum::ManifoldBuffer buffer;
    const std::vector<fulcrum::ContactReport> reports = world.contacts();
    for (const fulcrum::ContactReport& r : reports) {
        deepestReported = std::max(deepestReported, r.depth);
        fulcrum::collide(world.shape(r.bodyA), world.transform(r.bodyA), world.shape(r.bodyB), world.transform(r.bodyB),
                         def.speculativeMargin, buffer);
        Real fresh = -1, cosine = -1;
        for (const fulcrum::Manifold& m : buffer) {
            if (m.pointCount == 0) continue;
            fresh = std::max(fresh, m.maxDepth());
            cosine = std::max(cosine, fulcrum::dot(m.normal, r.normal));
        }
        deepestFresh = std::max(deepestFresh, fresh);
        const Real depthError = std::fabs(fresh - r.depth), normalError = 1 - cosine;
        worstDepthError = std::max(worstDepthError, depthError);
        worstNormalError = std::max(worstNormalError, normalError);
        if (depthError > Real(0.01) || normalError > Real(0.01)) {
            if (++mismatches <= 10) {
                const Vec3 pa = world.position(r.bodyA), pb = world.position(r.bodyB);
                std::printf("mismatch: bodies %u-%u at (%.3f %.3f %.3f) (%.3f %.3f %.3f): reported depth %.4f normal (%.3f %.3f %.3f) "
                            "%zu points; fresh depth %.4f, normal cosine %.4f\n",
                            r.bodyA.index, r.bodyB.index, double(pa.x), double(pa.y), double(pa.z), double(pb.x), double(pb.y),
                            double(pb.z), double(r.depth), double(r.normal.x), double(r.normal.y), double(r.normal.z),
                            r.points.size(), double(fresh), double(cosine));
                const fulcrum::Transform xb = world.transform(r.bodyB);
                std::printf("  pose B: p %a %a %a q %a %a %a %a\n", double(xb.p.x), double(xb.p.y), double(xb.p.z),
                            double(xb.q.w), double(xb.q.x), double(xb.q.y), double(xb.q.z));
            }
        }
    }
    std::printf("%s: %zu bodies, %d steps, %d threads\n", scene.name.c_str(), ids.size(), warm + measured, threads);
    std::printf("ms/step %.3f  awake %d  checksum %.9g\n", ms / measured, awake, heights);
    std::printf("contacts %zu  deepest reported %.4f m  deepest fresh %.4f m  mismatches %d  worst depth error %.4g m  "
                "worst 1-cos %.4g\n",
                reports.size(), double(deepestReported), double(deepestFresh), mismatches, double(worstDepthError),
                double(worstNormalError));
    return 0;
}
