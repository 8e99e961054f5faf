// The geometric half of continuous collision (src/collision/swept_impact.cpp)
// against analytic stops: a sphere dropped on a plane, a mesh and a box (the
// stop is stopGap above the surface, never past it), a box sliding on a floor
// it touches (no stop) or pressed into it (stops sinkAllowance deeper), a bar
// turning into a wall (stops where its end reaches the wall, by the angle).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

#include "collision/epa.hpp"
#include "collision/gjk.hpp"
#include "collision/support.hpp"
#include "collision/swept_impact.hpp"
#include "fulcrum/error.hpp"

using namespace fulcrum;
using namespace fulcrum::detail;

namespace {

Sweep still(const Transform& x) { return {x, Vec3::zero(), Vec3::zero(), Vec3::zero()}; }

Sweep moving(const Vec3& start, const Vec3& displacement, const Vec3& turn = Vec3::zero()) {
    return {{start, {}}, Vec3::zero(), displacement, turn};
}

// The fraction at which a sphere of radius r falling from height y0 by `drop`
// is stopGap above the surface y = 0.
Real sphereStop(Real y0, Real r, Real drop, const ImpactRules& rules) { return (y0 - r - rules.stopGap) / drop; }

TEST(SweptImpact, SphereDroppedThroughPlaneMeshAndBoxStopsAboveEach) {
    const ImpactRules rules;
    const Shape ball = Shape::sphere(Real(0.1));
    const Sweep fall = moving({0, 1, 0}, {0, -3, 0});
    const Real expected = sphereStop(1, Real(0.1), 3, rules);

    const std::vector<Vec3> vertices = {{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}};
    const std::vector<std::array<std::uint32_t, 3>> triangles = {{0, 2, 1}, {0, 3, 2}};
    const Shape surfaces[] = {Shape::plane({0, 1, 0}, 0), Shape::mesh(vertices, triangles), Shape::box({5, Real(0.01), 5})};
    const Transform places[] = {Transform{}, Transform{}, Transform{{0, -Real(0.01), 0}, {}}};
    for (int k = 0; k < 3; ++k) {
        const SweptImpact r = sweptImpact(ball, fall, surfaces[k], still(places[k]), rules);
        ASSERT_TRUE(r.hit) << k;
        // Never past the stop gap; within the tolerance above it.
        EXPECT_LE(r.time, expected + Real(1e-5)) << k;
        EXPECT_GE(r.time, expected - rules.tolerance / 3) << k;
    }
}

TEST(SweptImpact, BoxTouchingAFloorSlidesAlongItButSinksOnlyItsAllowance) {
    ImpactRules rules;
    rules.sinkAllowance = Real(0.05);
    const Shape box = Shape::box(Vec3::splat(Real(0.5)));
    const Shape floor = Shape::plane({0, 1, 0}, 0);
    // 2 mm into the floor at the start.
    const Vec3 start{0, Real(0.498), 0};
    EXPECT_FALSE(sweptImpact(box, moving(start, {4, 0, 0}), floor, still({}), rules).hit);
    const SweptImpact into = sweptImpact(box, moving(start, {0, -1, 0}), floor, still({}), rules);
    ASSERT_TRUE(into.hit);
    // Stops at 2 mm + the allowance deep (within the tolerance short of it).
    const Real depth = Real(0.002) + into.time * 1;
    EXPECT_LE(depth, Real(0.002) + rules.sinkAllowance + Real(1e-5));
    EXPECT_GE(depth, Real(0.002) + rules.sinkAllowance - rules.tolerance);
}

TEST(SweptImpact, BarTurningIntoAWallStopsWhereItsEndReachesIt) {
    const ImpactRules rules;
    // A capsule along y, turning about z by one radian (its upper end towards
    // +x), beside a wall whose face is x = 0.3: the end's sphere reaches the
    // face at 0.475 sin(phi) + 0.025 = 0.3.
    const Shape bar = Shape::capsule(Real(0.025), Real(0.475));
    const Shape wall = Shape::box({Real(0.02), 2, 2});
    const SweptImpact r = sweptImpact(bar, moving(Vec3::zero(), Vec3::zero(), {0, 0, -1}), wall, still({{Real(0.32), 0, 0}, {}}), rules);
    ASSERT_TRUE(r.hit);
    const Real contact = std::asin(Real(0.275) / Real(0.475));
    // The stop is stopGap short of the face: its angle is a little less.
    const Real stopGapAngle = rules.stopGap / (Real(0.475) * std::cos(contact));
    EXPECT_LE(r.time, contact - stopGapAngle + Real(1e-4));
    EXPECT_GE(r.time, contact - stopGapAngle - 2 * rules.tolerance / (Real(0.475) * std::cos(contact)));
    // Translating the same bar past the wall without turning meets nothing.
    EXPECT_FALSE(sweptImpact(bar, moving(Vec3::zero(), {0, 0, 3}), wall, still({{Real(0.32), 0, 0}, {}}), rules).hit);
}

TEST(SweptImpact, CompoundPiecesAndMovingMeshes) {
    const ImpactRules rules;
    // A compound whose far child reaches the floor first.
    const std::vector<CompoundChild> children = {{Shape::sphere(Real(0.1)), Transform{}},
                                                 {Shape::sphere(Real(0.1)), Transform{{0, -1, 0}, {}}}};
    const Shape pair = Shape::compound(children);
    const SweptImpact r = sweptImpact(pair, moving({0, 3, 0}, {0, -3, 0}), Shape::plane({0, 1, 0}, 0), still({}), rules);
    ASSERT_TRUE(r.hit);
    EXPECT_NEAR(r.time, sphereStop(2, Real(0.1), 3, rules), rules.tolerance);
    // A mesh must be still: a clear fulcrum::Error, not a wrong answer.
    const std::vector<Vec3> vertices = {{-1, 0, -1}, {1, 0, -1}, {0, 0, 1}};
    const std::vector<std::array<std::uint32_t, 3>> triangles = {{0, 2, 1}};
    EXPECT_THROW(sweptImpact(Shape::sphere(1), moving({0, 3, 0}, {0, -3, 0}), Shape::mesh(vertices, triangles),
                             moving(Vec3::zero(), {0, 1, 0}), rules),
                 Error);
}

// sweptBounds must hold every pose of the sweep (the continuous phase culls
// triangles and pieces by it), and for a turning piece far from the centre it
// should box that piece's own path: the sphere of its distance around the
// centre met every triangle under a tumbling tree. Poses sampled along
// Sweep::at over [0, 1] for random boxes, offsets, moves and turns below 3 rad.
TEST(SweptImpact, SweptBoundsHoldEveryPoseAndBoxATurningPieceByItsPath) {
    std::uint32_t seed = 12345;
    const auto uniform = [&seed](Real lo, Real hi) {
        seed = seed * 1664525u + 1013904223u;
        return lo + (hi - lo) * Real(seed >> 8) / Real(1u << 24);
    };
    for (int trial = 0; trial < 300; ++trial) {
        const Shape box = Shape::box({uniform(Real(0.1), 1), uniform(Real(0.1), 1), uniform(Real(0.1), 1)});
        Sweep sweep;
        sweep.start = {{uniform(-5, 5), uniform(-5, 5), uniform(-5, 5)},
                       normalize(Quat(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)))};
        sweep.localCenter = {uniform(-20, 20), uniform(-20, 20), uniform(-20, 20)};  // a child far from the centre of mass
        sweep.linearVelocity = {uniform(-3, 3), uniform(-3, 3), uniform(-3, 3)};
        const Vec3 axis = normalize(Vec3{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)});
        sweep.angularVelocity = axis * uniform(Real(0.01), Real(2.9));
        const AABB bound = sweptBounds(box, sweep);
        for (int k = 0; k <= 64; ++k) {
            const AABB at = box.bounds(sweep.at(Real(k) / 64));
            for (std::size_t i = 0; i < 3; ++i) {
                ASSERT_LE(bound.min[i], at.min[i] + Real(1e-4)) << "trial " << trial << " t " << k;
                ASSERT_GE(bound.max[i], at.max[i] - Real(1e-4)) << "trial " << trial << " t " << k;
            }
        }
    }
    // A 1 m cube 25 m from the centre turning by 0.05 rad while the centre
    // stays: its path is 1.25 m long, the old sphere bound 52 m across.
    Sweep turn;
    turn.start = Transform{};
    turn.localCenter = {0, -25, 0};
    turn.linearVelocity = Vec3::zero();
    turn.angularVelocity = {0, 0, Real(0.05)};
    const AABB b = sweptBounds(Shape::box({Real(0.5), Real(0.5), Real(0.5)}), turn);
    EXPECT_LT(b.max.x - b.min.x, Real(2.5));
    EXPECT_LT(b.max.y - b.min.y, Real(1.2));
}

}  // namespace

// A toppling "tree" (ten boxes stacked on its foot, as bench/mesh_scenes.hpp's
// trees are hulls) turning 0.2 rad about its foot in one step, its top piece
// swinging through a thin wall of two triangles at x = 1.5: the stop is where
// the top piece's outer corner comes within stopGap of the wall (never past
// it), with the pieces that barely move skipped (rules.pieceThickness, as the
// continuous phase does) or not.
TEST(SweptImpact, TopplingTreeStopsAtAThinWallWithOrWithoutItsSlowPieces) {
    std::vector<CompoundChild> pieces;
    for (int k = 0; k < 10; ++k) pieces.push_back({Shape::box({Real(0.1), Real(0.5), Real(0.1)}), Transform{{0, Real(k) + Real(0.5), 0}, {}}});
    const Shape tree = Shape::compound(pieces);
    const Vec3 centre{0, 5, 0};
    const Real angle = Real(0.2);
    const Quat q1 = Quat::fromAxisAngle({0, 0, 1}, -angle);  // the top towards +x
    const Sweep topple = sweepBetween(centre, Quat{}, rotate(q1, centre), q1, centre);
    const std::vector<Vec3> vertices = {{Real(1.5), -1, -2}, {Real(1.5), 20, -2}, {Real(1.5), 20, 2}, {Real(1.5), -1, 2}};
    const std::vector<std::array<std::uint32_t, 3>> triangles = {{0, 1, 2}, {0, 2, 3}};
    const Shape wall = Shape::mesh(vertices, triangles);
    // The top piece's outer corner (0.1, 10, z) along the sweep.
    const auto cornerX = [&](Real t) { return transformPoint(topple.at(t), Vec3{Real(0.1), 10, 0}).x; };
    ImpactRules rules;
    const SweptImpact all = sweptImpact(tree, topple, wall, still({}), rules);
    rules.pieceThickness = [](const Shape&) { return Real(0.7); };  // skips the lowest piece, sweeps the top
    rules.slowPieceFraction = Real(0.5);
    const SweptImpact gated = sweptImpact(tree, topple, wall, still({}), rules);
    for (const SweptImpact& r : {all, gated}) {
        ASSERT_TRUE(r.hit);
        EXPECT_LE(cornerX(r.time), Real(1.5) - rules.stopGap + Real(1e-4));
        EXPECT_GE(cornerX(r.time), Real(1.5) - rules.stopGap - rules.tolerance - Real(1e-4));
        EXPECT_LT(r.advances, 40u);
    }
    EXPECT_EQ(all.time, gated.time);
}

// Only the spin across the normal closes a gap (branch hsccd): a bar
// spinning fast about the wall's normal while it flies at the wall is
// stopped where its translation alone puts it stopGap from the wall, in a
// few distance evaluations (the bound |w| r took one per few millimetres:
// 40 rad of spin times 0.5 m of reach against 3 m of approach).
TEST(SweptImpact, SpinAboutTheNormalDoesNotSlowTheAdvance) {
    const ImpactRules rules;
    const Shape bar = Shape::box({Real(0.5), Real(0.125), Real(0.125)});
    const Shape wall = Shape::box({Real(0.2), 50, 50});
    // Face at x = 2.8; the bar's long axis is x, about which it turns, so its
    // extent along x stays 0.5: it reaches the face when its centre is at 2.3.
    const Sweep throwIn = moving(Vec3::zero(), {3, 0, 0}, {40, 0, 0});
    const SweptImpact r = sweptImpact(bar, throwIn, wall, still({{3, 0, 0}, {}}), rules);
    ASSERT_TRUE(r.hit);
    const Real expected = (Real(2.3) - rules.stopGap) / 3;
    EXPECT_LE(r.time, expected + Real(1e-5));
    EXPECT_GE(r.time, expected - rules.tolerance / 3);
    EXPECT_LE(r.advances, 8u);
}

namespace {

// The signed distance of two full shapes (negative: the overlap's depth).
Real signedDistance(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb) {
    const ConvexShape ca = makeConvex(a, xa), cb = makeConvex(b, xb);
    const GjkResult g = gjkDistance(ca, cb, false);
    if (!g.overlap && g.distance > Real(1e-6)) return g.distance - ca.radius - cb.radius;
    const PenetrationResult p = epaPenetration(ca, cb);
    return p.valid ? -p.depth : 0;
}

}  // namespace

// Random throws of spinning sphere, box and capsule pieces at a thin wall
// and at a box, sphere and capsule (the kinds whose point depth the
// continuous phase reads to confirm a path goes on in): the stop is never
// past stopGap (dense samples of the sweep before it keep the gap), lies
// within the tolerance of it, and a sweep that takes the piece more than
// passDepth (plus a margin for the sampling) in is always stopped. Margins
// (0.2 mm on the gaps, 2 mm on the sampled depth) hold the checks apart from
// rounding, so they do not depend on the compiler's bits.
TEST(SweptImpact, SpinningThrowsStopBeforeTheTargetAndNeverPassIt) {
    std::uint32_t seed = 2024;
    const auto uniform = [&seed](Real lo, Real hi) {
        seed = seed * 1664525u + 1013904223u;
        return lo + (hi - lo) * Real(seed >> 8) / Real(1u << 24);
    };
    const ImpactRules rules;
    const Shape movers[] = {Shape::box({Real(0.5), Real(0.125), Real(0.125)}), Shape::capsule(Real(0.125), Real(0.5)),
                            Shape::sphere(Real(0.3)), Shape::box({Real(0.25), Real(0.5), Real(0.5)})};
    const Shape targets[] = {Shape::box({Real(0.2), 3, 3}), Shape::sphere(Real(1.5)), Shape::capsule(Real(0.8), 2)};
    int hits = 0, deepPasses = 0;
    for (int trial = 0; trial < 180; ++trial) {
        const Shape& a = movers[trial % 4];
        const Shape& b = targets[(trial / 4) % 3];
        Sweep s;
        s.start = {{uniform(-Real(3.5), -Real(2.5)), uniform(-1, 1), uniform(-1, 1)},
                   normalize(Quat(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)))};
        s.localCenter = Vec3::zero();
        s.linearVelocity = {uniform(3, 6), uniform(-1, 1), uniform(-1, 1)};
        s.angularVelocity = normalize(Vec3{uniform(-1, 1), uniform(-1, 1), uniform(-1, 1)}) * uniform(0, 8);
        const Transform xb{};
        if (signedDistance(a, s.start, b, xb) <= rules.touchBand + Real(0.01)) continue;  // apart at the start only
        const SweptImpact r = sweptImpact(a, s, b, still(xb), rules);
        constexpr int kSamples = 2000;
        Real deepest = 0;
        for (int k = 0; k <= kSamples; ++k) {
            const Real t = Real(k) / kSamples;
            const Real d = signedDistance(a, s.at(t), b, xb);
            if (r.hit && t < r.time) {
                ASSERT_GE(d, rules.stopGap - Real(2e-4)) << "trial " << trial << " t " << t;
            }
            deepest = std::min(deepest, d);
        }
        if (r.hit) {
            ++hits;
            const Real atStop = signedDistance(a, s.at(r.time), b, xb);
            EXPECT_GE(atStop, rules.stopGap - Real(2e-4)) << "trial " << trial;
            EXPECT_LE(atStop, rules.stopGap + rules.tolerance + Real(2e-4)) << "trial " << trial;
        }
        if (deepest < -rules.passDepth - Real(0.002)) {
            ++deepPasses;
            EXPECT_TRUE(r.hit) << "trial " << trial << " went " << -deepest << " in";
        }
    }
    // The throws meet their targets and go on in: the checks above ran.
    EXPECT_GE(hits, 40);
    EXPECT_GE(deepPasses, 40);
}

// A box flying head-on at a sphere, a capsule and a (thin) box stops
// stopGap short when its path goes more than passDepth in (confirmed at one
// later pose or, when that pose is past the step, by advancing), and not at
// all when the path ends less than passDepth in.
TEST(SweptImpact, PathEndingJustInsideIsNotStoppedOneGoingOnIs) {
    const ImpactRules rules;
    const Shape cube = Shape::box(Vec3::splat(Real(0.25)));
    const Shape targets[] = {Shape::sphere(Real(0.5)), Shape::capsule(Real(0.5), 1), Shape::box({Real(0.5), 1, 1})};
    for (int k = 0; k < 3; ++k) {
        // Each target's surface facing -x is at x = -0.5 (the capsule lies along y).
        for (const Real endDepth : {Real(0.005), Real(0.015), Real(0.2)}) {
            // The cube starts with its +x face at -2.5, 2 from the surface, and moves `travel` along x.
            const Real travel = 2 + endDepth;
            const Sweep s = moving({-Real(2.75), 0, 0}, {travel, 0, 0});
            const SweptImpact r = sweptImpact(cube, s, targets[k], still({}), rules);
            if (endDepth < rules.passDepth) {
                EXPECT_FALSE(r.hit) << k << " " << endDepth;
                continue;
            }
            ASSERT_TRUE(r.hit) << k << " " << endDepth;
            const Real expected = (2 - rules.stopGap) / travel;
            EXPECT_LE(r.time, expected + Real(1e-5)) << k << " " << endDepth;
            EXPECT_GE(r.time, expected - rules.tolerance / travel) << k << " " << endDepth;
        }
    }
}
