// Box3D's convex_pile (bench/box3d_scenes.hpp) in Fulcrum, stepped for
// instruction counts, its deepest overlap and a check of the reported contacts:
// `warm` steps first, then `measured` steps timed (and, under callgrind with
// --instr-atstart=no, the only steps counted). After the run every reported
// manifold is compared with a fresh narrow phase at the bodies' final poses.
//   build/release/bench/bench_convex_pile_probe 8 8 80 0 500 [threads] [every]
// With `every` > 0 the deepest reported overlap is printed every that many
// measured steps (outside the timed and counted part).
//   valgrind --tool=callgrind --instr-atstart=no build/release/bench/bench_convex_pile_probe 8 8 10 200 10
// PROBE_EXACT=K: at each print, the K deepest reported contacts are checked
// against a fresh narrow phase at the bodies' poses and the exact separation
// of the two hulls (exact_hull_depth.hpp), and the deepest pair's poses are
// printed in hexadecimal floats (to rebuild it in a test).
// The checksum (sum of the final heights) lets two builds be checked for the
// same results; it is not a test.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <type_traits>
#include <vector>

#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#else
#define CALLGRIND_START_INSTRUMENTATION
#define CALLGRIND_STOP_INSTRUMENTATION
#endif

#include "box3d_scenes.hpp"
#include "exact_hull_depth.hpp"
#include "collision/narrow_phase.hpp"
#include "collision/support.hpp"
#include "fulcrum/fulcrum.hpp"

namespace {

// The k deepest reported hull-hull contacts: the report's depth, a fresh
// manifold's at the current poses, the overlap along the fresh normal (support
// functions) and the exact penetration depth.
void checkExact(const fulcrum::World& world, const std::vector<fulcrum::ContactReport>& reports, int k) {
    fulcrum::ManifoldBuffer buffer;
    struct Row {
        std::size_t report;
        double fresh;
        int points;
        fulcrum::Vec3 normal;
    };
    std::vector<Row> rows;
    for (std::size_t i = 0; i < reports.size(); ++i) {
        const fulcrum::ContactReport& r = reports[i];
        const fulcrum::Shape& sa = world.shape(r.bodyA);
        const fulcrum::Shape& sb = world.shape(r.bodyB);
        if (sa.type() != fulcrum::ShapeType::ConvexHull || sb.type() != fulcrum::ShapeType::ConvexHull) continue;
        fulcrum::collide(sa, world.transform(r.bodyA), sb, world.transform(r.bodyB), 1, buffer);
        if (buffer.size() == 1) rows.push_back({i, double(buffer[0].maxDepth()), int(buffer[0].pointCount), buffer[0].normal});
    }
    // The k deepest by the report and the k deepest by the fresh manifold.
    std::vector<Row> picked;
    std::sort(rows.begin(), rows.end(), [&](const Row& x, const Row& y) { return reports[x.report].depth > reports[y.report].depth; });
    picked.insert(picked.end(), rows.begin(), rows.begin() + std::min<std::ptrdiff_t>(k, std::ptrdiff_t(rows.size())));
    std::sort(rows.begin(), rows.end(), [](const Row& x, const Row& y) { return x.fresh > y.fresh; });
    picked.insert(picked.end(), rows.begin(), rows.begin() + std::min<std::ptrdiff_t>(k, std::ptrdiff_t(rows.size())));
    double worstOver = -1e300, worstUnder = -1e300;
    for (std::size_t i = 0; i < picked.size(); ++i) {
        const Row& row = picked[i];
        const fulcrum::ContactReport& r = reports[row.report];
        const fulcrum::Shape& sa = world.shape(r.bodyA);
        const fulcrum::Shape& sb = world.shape(r.bodyB);
        const fulcrum::Transform xa = world.transform(r.bodyA), xb = world.transform(r.bodyB);
        const fulcrum::detail::ConvexShape ca = fulcrum::detail::makeConvex(sa, xa);
        const fulcrum::detail::ConvexShape cb = fulcrum::detail::makeConvex(sb, xb);
        const fulcrum::Vec3 n = row.normal;
        const double alongFresh = -double(fulcrum::dot(cb.support(-n) - ca.support(n), n));
        const bench::ExactSeparation e = bench::exactHullSeparation(sa.hull(), xa, sb.hull(), xb);
        const double exact = -e.separation;
        worstOver = std::max(worstOver, row.fresh - exact);
        worstUnder = std::max(worstUnder, exact - row.fresh);
        std::printf("  %s pair %u-%u: reported %.4f  fresh %.4f (%d points, overlap along its normal %.4f)  exact %.4f  "
                    "speeds %.2f %.2f\n",
                    i < std::size_t(k) ? "by report" : "by fresh ", r.bodyA.index, r.bodyB.index, double(r.depth), row.fresh,
                    row.points, alongFresh, exact, double(length(world.linearVelocity(r.bodyA))),
                    double(length(world.linearVelocity(r.bodyB))));
        if (i == 0 || i == std::size_t(k)) {
            std::printf("    poses: A p {%a, %a, %a} q {%a, %a, %a, %a}  B p {%a, %a, %a} q {%a, %a, %a, %a}\n", double(xa.p.x),
                        double(xa.p.y), double(xa.p.z), double(xa.q.w), double(xa.q.x), double(xa.q.y), double(xa.q.z),
                        double(xb.p.x), double(xb.p.y), double(xb.p.z), double(xb.q.w), double(xb.q.x), double(xb.q.y),
                        double(xb.q.z));
        }
    }
    std::printf("  fresh manifold vs exact over these: deeper by at most %.4f m, shallower by at most %.4f m\n", worstOver,
                worstUnder);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 6) {
        std::fprintf(stderr, "usage: %s NX NZ LAYERS WARM_STEPS MEASURED_STEPS [THREADS]\n", argv[0]);
        return 2;
    }
    const int nx = std::atoi(argv[1]), nz = std::atoi(argv[2]), layers = std::atoi(argv[3]);
    const int warm = std::atoi(argv[4]), measured = std::atoi(argv[5]);
    const int threads = argc > 6 ? std::atoi(argv[6]) : 1;
    const int every = argc > 7 ? std::atoi(argv[7]) : 0;
    const int exactChecks = std::getenv("PROBE_EXACT") != nullptr ? std::atoi(std::getenv("PROBE_EXACT")) : 0;
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
    // Experiments on the solver's settings (not Box3D's scene): PROBE_SUBSTEPS,
    // PROBE_HERTZ (contactHertz), PROBE_PUSH (contactPushMaxVelocity),
    // PROBE_MARGIN (speculativeMargin), PROBE_DAMPING (contactDampingRatio),
    // PROBE_PUSH_OUT (pushOutGrownOverlaps).
    const auto setting = [](const char* name, auto& value) {
        if (const char* text = std::getenv(name)) value = static_cast<std::remove_reference_t<decltype(value)>>(std::atof(text));
    };
    setting("PROBE_SUBSTEPS", def.substeps);
    setting("PROBE_HERTZ", def.contactHertz);
    setting("PROBE_PUSH", def.contactPushMaxVelocity);
    setting("PROBE_MARGIN", def.speculativeMargin);
    setting("PROBE_DAMPING", def.contactDampingRatio);
    setting("PROBE_PUSH_OUT", def.pushOutGrownOverlaps);  // 1: WorldDef::pushOutGrownOverlaps on
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
    // PROBE_DT_DIVIDE=k: k times shorter steps (the narrow phase k times as often;
    // with PROBE_SUBSTEPS the sub-step length can be kept).
    const double dtDivide = std::getenv("PROBE_DT_DIVIDE") != nullptr ? std::atof(std::getenv("PROBE_DT_DIVIDE")) : 1.0;
    const Real dt = real(scene.dt / dtDivide);
    for (int i = 0; i < warm; ++i) world.step(dt);
    double ms = 0;
    fulcrum::StepProfile phases;  // summed over the measured steps
    for (int i = 0; i < measured; ++i) {
        CALLGRIND_START_INSTRUMENTATION;
        const auto t0 = std::chrono::steady_clock::now();
        world.step(dt);
        ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
        CALLGRIND_STOP_INSTRUMENTATION;
        const fulcrum::StepProfile& p = world.lastStepProfile();
        phases.total += p.total, phases.collide += p.collide, phases.prepare += p.prepare, phases.solve += p.solve;
        phases.store += p.store, phases.continuous += p.continuous, phases.sleep += p.sleep;
        if (every > 0 && (i + 1) % every == 0) {
            Real deepest = 0;
            std::size_t count = 0;
            const fulcrum::ContactReport* worst = nullptr;
            const std::vector<fulcrum::ContactReport> now = world.contacts();
            for (const fulcrum::ContactReport& r : now) {
                if (r.depth > deepest) worst = &r;
                deepest = std::max(deepest, r.depth);
                ++count;
            }
            std::printf("step %d: deepest reported %.4f m, %zu contacts, %.3f ms/step so far", warm + i + 1,
                        double(deepest), count, ms / (i + 1));
            if (worst != nullptr) {
                // The deepest pair: how fast its bodies move and close along the normal, and how high it is.
                const Vec3 va = world.linearVelocity(worst->bodyA), vb = world.linearVelocity(worst->bodyB);
                std::printf("; its pair at y %.1f m, speeds %.2f and %.2f m/s, closing %.2f m/s, spins %.2f and %.2f rad/s",
                            double(world.position(worst->bodyB).y), double(length(va)), double(length(vb)),
                            double(dot(va - vb, worst->normal)), double(length(world.angularVelocity(worst->bodyA))),
                            double(length(world.angularVelocity(worst->bodyB))));
            }
            std::printf("\n");
            if (exactChecks > 0) checkExact(world, now, exactChecks);
        }
    }

    double heights = 0;
    int awake = 0;
    for (const fulcrum::BodyId id : ids) {
        heights += static_cast<double>(world.position(id).y);
        if (world.isAwake(id)) ++awake;
    }
    // Every reported manifold against a fresh narrow phase at the final poses.
    // A report's depth is the solver's first-order estimate at the step's end
    // and its normal the one of the step's start (a tumbling 2 m hull turns a
    // few degrees in a step: its separation along that normal moves by
    // centimetres), so only gross errors count as mismatches (the defect of
    // issue 27 was 300 m): a depth off by 5 cm, or a normal separating the
    // shapes (support functions) 50 cm less than the fresh one. The worst
    // values are printed; tests/contacts/persistent_manifold_test.cpp checks
    // the manifolds themselves at their own poses, tightly.
    Real deepestReported = 0, deepestFresh = 0, worstDepthError = 0, worstSeparationLoss = 0;
    int mismatches = 0;
    fulcrum::ManifoldBuffer buffer;
    const std::vector<fulcrum::ContactReport> reports = world.contacts();
    for (const fulcrum::ContactReport& r : reports) {
        deepestReported = std::max(deepestReported, r.depth);
        const fulcrum::Transform xa = world.transform(r.bodyA), xb = world.transform(r.bodyB);
        fulcrum::collide(world.shape(r.bodyA), xa, world.shape(r.bodyB), xb, 1, buffer);
        Real fresh = -1, loss = 0;
        if (buffer.size() == 1) {
            const fulcrum::Manifold& m = buffer[0];
            fresh = m.maxDepth();
            const fulcrum::detail::ConvexShape ca = fulcrum::detail::makeConvex(world.shape(r.bodyA), xa);
            const fulcrum::detail::ConvexShape cb = fulcrum::detail::makeConvex(world.shape(r.bodyB), xb);
            const auto separation = [&](const Vec3& n) { return fulcrum::dot(cb.support(-n) - ca.support(n), n); };
            loss = separation(m.normal) - separation(r.normal);
        }
        deepestFresh = std::max(deepestFresh, fresh);
        const Real depthError = std::fabs(fresh - r.depth);
        worstDepthError = std::max(worstDepthError, depthError);
        worstSeparationLoss = std::max(worstSeparationLoss, loss);
        if (depthError > Real(0.05) || loss > Real(0.5)) {
            if (++mismatches <= 10) {
                const Vec3 pa = world.position(r.bodyA), pb = world.position(r.bodyB);
                std::printf("mismatch: bodies %u-%u at (%.3f %.3f %.3f) (%.3f %.3f %.3f): reported depth %.4f normal (%.3f %.3f %.3f) "
                            "%zu points; fresh depth %.4f, separation lost along the reported normal %.4f m\n",
                            r.bodyA.index, r.bodyB.index, double(pa.x), double(pa.y), double(pa.z), double(pb.x), double(pb.y),
                            double(pb.z), double(r.depth), double(r.normal.x), double(r.normal.y), double(r.normal.z),
                            r.points.size(), double(fresh), double(loss));
            }
        }
    }
    if (exactChecks > 0) checkExact(world, reports, exactChecks);
    std::printf("%s: %zu bodies, %d steps, %d threads\n", scene.name.c_str(), ids.size(), warm + measured, threads);
    std::printf("ms/step %.3f  awake %d  checksum %.9g\n", ms / measured, awake, heights);
    std::printf("pairs held after the last collide %u, contact constraints %u\n", world.lastStepProfile().contactPairs,
                world.lastStepProfile().contactConstraints);
    std::printf("phases, share of the step: collide %.1f %%, prepare %.1f %%, solve %.1f %%, store %.1f %%, continuous %.1f %%, "
                "sleep %.1f %%\n",
                100 * phases.collide / phases.total, 100 * phases.prepare / phases.total, 100 * phases.solve / phases.total,
                100 * phases.store / phases.total, 100 * phases.continuous / phases.total, 100 * phases.sleep / phases.total);
    std::printf("contacts %zu  deepest reported %.4f m  deepest fresh %.4f m  mismatches %d  worst depth error %.4g m  "
                "worst separation lost %.4g m\n",
                reports.size(), double(deepestReported), double(deepestFresh), mismatches, double(worstDepthError),
                double(worstSeparationLoss));
    return 0;
}
