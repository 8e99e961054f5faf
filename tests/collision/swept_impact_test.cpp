// The geometric half of continuous collision (src/collision/swept_impact.cpp)
// against analytic stops: a sphere dropped on a plane, a mesh and a box (the
// stop is stopGap above the surface, never past it), a box sliding on a floor
// it touches (no stop) or pressed into it (stops sinkAllowance deeper), a bar
// turning into a wall (stops where its end reaches the wall, by the angle).
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

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
