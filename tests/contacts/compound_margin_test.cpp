// The speculative margin of a spinning compound, child by child
// (SpeculativeReach, src/collision/narrow_phase.hpp): a point at distance r
// from the centre of mass approaches by at most |v| dt + |w| r dt in a step,
// so each child of a compound looks for contacts only that far (its r: the
// farthest corner of its bounds from the centre of mass), not as far as the
// whole body's extent. The near-centre children of a long spinning body get a
// small margin, its far ends a large one, and the far ends still never pass
// through a thin wall.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "collision/manifold.hpp"
#include "collision/narrow_phase.hpp"
#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

constexpr int kRodChildren = 21;  // unit cubes along x, centres at x = -10 ... 10
constexpr Real kHalf = Real(0.5);

// A rod of unit cubes along x, its centre (and centre of mass) at its origin.
Shape rod() {
    std::vector<CompoundChild> children;
    for (int i = 0; i < kRodChildren; ++i) {
        children.push_back({Shape::box(Vec3::splat(kHalf)), Transform{{Real(i - kRodChildren / 2), 0, 0}, Quat{}}});
    }
    return Shape::compound(children);
}

// The distance from the rod's centre to child i's farthest corner.
Real childReach(int i) {
    const Real x = std::fabs(Real(i - kRodChildren / 2)) + kHalf;
    return std::sqrt(x * x + 2 * kHalf * kHalf);
}

// Which children of the rod have a manifold against `plate` (a static shape at
// xPlate) with the given reach.
std::vector<bool> childrenInContact(const Shape& plate, const Transform& xPlate, const SpeculativeReach& reach,
                                    ManifoldBuffer& out) {
    collide(rod(), Transform{}, plate, xPlate, reach, out);
    std::vector<bool> hit(kRodChildren, false);
    for (const Manifold& m : out) {
        EXPECT_LT(m.childA, std::uint32_t(kRodChildren));
        if (m.childA < std::uint32_t(kRodChildren) && m.pointCount > 0) hit[m.childA] = true;
    }
    return hit;
}

// A rod spinning about z at 1 rad/s, 10 cm above a static plate (a thin box,
// or a two-triangle mesh): with dt = 1/60 and a 2 cm base margin, a child
// reaches the plate within a step when 0.02 + r / 60 >= 0.1, r >= 4.8 m: the
// children 5 or more from the centre (r = 5.55 m and up), not those within 4
// (r <= 4.56 m: 4 mm short). The whole rod's extent (10.52 m) would give
// every child the 0.195 m margin.
TEST(CompoundMargin, EachChildLooksOnlyAsFarAsItCanMoveInAStep) {
    const Real gap = Real(0.1), spin = 1, dt = Real(1) / 60, base = Real(0.02);
    SpeculativeReach reach;
    reach.base = base;
    reach.spinA = spin;
    reach.dt = dt;
    reach.extentA = std::sqrt(Real(10.5) * Real(10.5) + 2 * kHalf * kHalf);  // as World computes it (local box corner)
    const Real plateTop = -kHalf - gap;
    const Shape box = Shape::box({30, Real(0.05), 5});
    const std::array<Vec3, 4> corners = {Vec3{-30, plateTop, -5}, Vec3{30, plateTop, -5}, Vec3{30, plateTop, 5},
                                         Vec3{-30, plateTop, 5}};
    const std::array<std::array<std::uint32_t, 3>, 2> triangles = {{{0, 2, 1}, {0, 3, 2}}};
    const Shape mesh = Shape::mesh(corners, triangles);
    ManifoldBuffer out;
    for (const bool asMesh : {false, true}) {
        SCOPED_TRACE(asMesh ? "mesh plate" : "box plate");
        const Shape& plate = asMesh ? mesh : box;
        const Transform xPlate = asMesh ? Transform{} : Transform{{0, plateTop - Real(0.05), 0}, Quat{}};
        const std::vector<bool> hit = childrenInContact(plate, xPlate, reach, out);
        for (int i = 0; i < kRodChildren; ++i) {
            const Real margin = base + spin * childReach(i) * dt;
            ASSERT_GT(std::fabs(margin - gap), Real(0.003)) << "child " << i << " too near the threshold to test";
            EXPECT_EQ(hit[i], margin >= gap) << "child " << i << ", its margin " << margin;
        }
        // Every point reported within its own child's margin.
        for (const Manifold& m : out) {
            for (std::uint32_t k = 0; k < m.pointCount; ++k) {
                EXPECT_GE(m.points[k].depth, -(base + spin * childReach(int(m.childA)) * dt) - Real(1e-4));
            }
        }
        // With no spin only the base margin: no child is within 2 cm.
        SpeculativeReach still = reach;
        still.spinA = 0;
        const std::vector<bool> none = childrenInContact(plate, xPlate, still, out);
        EXPECT_EQ(std::count(none.begin(), none.end(), true), 0);
        // The one margin of the whole extent reaches every child.
        collide(rod(), Transform{}, plate, xPlate, reach.margin(reach.extentA, 0), out);
        std::vector<bool> all(kRodChildren, false);
        for (const Manifold& m : out) all[m.childA] = all[m.childA] || m.pointCount > 0;
        EXPECT_EQ(std::count(all.begin(), all.end(), true), kRodChildren);
    }
}

// A pair without compounds keeps the one margin of the whole bodies, bit for bit.
TEST(CompoundMargin, PairsWithoutCompoundsKeepTheWholeBodysMargin) {
    SpeculativeReach reach;
    reach.base = Real(0.02);
    reach.linear = Real(1.3);
    reach.spinA = Real(2.1);
    reach.spinB = Real(0.7);
    reach.dt = Real(1) / 60;
    reach.extentA = Real(0.9);
    reach.extentB = Real(0.6);
    const Shape a = Shape::box({Real(0.5), Real(0.3), Real(0.4)}), b = Shape::capsule(Real(0.3), Real(0.2));
    const Transform xa{{0, 0, 0}, Quat{}};
    const Transform xb{{Real(0.2), Real(0.85), Real(0.1)}, Quat::fromAxisAngle(normalize(Vec3{1, 2, 0}), Real(0.3))};
    ManifoldBuffer withReach, withMargin;
    collide(a, xa, b, xb, reach, withReach);
    collide(a, xa, b, xb, reach.margin(reach.extentA, reach.extentB), withMargin);
    ASSERT_EQ(withReach.size(), withMargin.size());
    ASSERT_GT(withReach.size(), 0u);
    for (std::size_t i = 0; i < withReach.size(); ++i) {
        ASSERT_EQ(withReach[i].pointCount, withMargin[i].pointCount);
        for (std::uint32_t k = 0; k < withReach[i].pointCount; ++k) {
            EXPECT_EQ(withReach[i].points[k].depth, withMargin[i].points[k].depth);
            EXPECT_EQ(withReach[i].points[k].position.x, withMargin[i].points[k].position.x);
        }
    }
}

// A 21 m rod spinning at 6 rad/s in zero gravity, starting along y, its far
// ends moving at 63 m/s (1.05 m a step), swept into a wall 50 times thinner
// than that (a zero-thickness one-sided triangle mesh at x = 7 facing the rod,
// or a 2 cm box) with continuous collision off: only the far children's
// speculative contacts can stop them, and they do (their margin counts their
// own r, 10.5 m, in full: the same as the whole body's). The end cube's
// trailing corner, which the step's manifold did not hold when it was taken,
// overlaps the wall by 15 cm for a step (as with the whole extent's margin
// before children had their own: the linear approach of a turning body's
// points); no cube gets halfway through, none passes it.
TEST(CompoundMargin, SpinningRodsFarEndNeverPassesThroughAThinWall) {
    for (const bool asMesh : {true, false}) {
        SCOPED_TRACE(asMesh ? "mesh wall" : "2 cm box wall");
        WorldDef def;
        def.gravity = {0, 0, 0};
        def.sleeping = false;
        def.continuousCollision = false;
        World world(def);
        const Real wallX = 7;
        BodyDef wall;
        wall.type = BodyType::Static;
        if (asMesh) {
            const std::array<Vec3, 4> corners = {Vec3{wallX, -20, -5}, Vec3{wallX, 20, -5}, Vec3{wallX, 20, 5},
                                                 Vec3{wallX, -20, 5}};
            // Wound so the face normal is -x, towards the rod.
            const std::array<std::array<std::uint32_t, 3>, 2> triangles = {{{0, 2, 1}, {0, 3, 2}}};
            wall.shape = Shape::mesh(corners, triangles);
        } else {
            wall.shape = Shape::box({Real(0.01), 20, 5});
            wall.position = {wallX + Real(0.01), 0, 0};
        }
        world.createBody(wall);
        BodyDef r;
        r.shape = rod();
        r.mass = 21;
        r.orientation = Quat::fromAxisAngle({0, 0, 1}, Real(1.5707963));  // along y, clear of the wall
        r.angularVelocity = {0, 0, 6};
        const BodyId body = world.createBody(r);
        Real deepest = 0, farthestCentre = -100;
        bool touched = false;
        for (int step = 0; step < 120; ++step) {
            world.step(kDt);
            const Transform x = world.transform(body);
            for (int i = 0; i < kRodChildren; ++i) {
                farthestCentre = std::max(farthestCentre, transformPoint(x, {Real(i - kRodChildren / 2), 0, 0}).x);
                for (int c = 0; c < 8; ++c) {
                    const Vec3 local{Real(i - kRodChildren / 2) + ((c & 1) ? kHalf : -kHalf), (c & 2) ? kHalf : -kHalf,
                                     (c & 4) ? kHalf : -kHalf};
                    const Vec3 p = transformPoint(x, local);
                    deepest = std::max(deepest, p.x - wallX);
                }
            }
            touched = touched || world.contacts().size() > 0;
        }
        EXPECT_TRUE(touched);
        EXPECT_LT(deepest, kHalf) << "a corner went " << deepest << " m behind the wall";
        EXPECT_LT(farthestCentre, wallX - kHalf) << "a cube's centre reached the wall";
    }
}

// The same rod rolling about its own length (x) at 1 rad/s, 10 cm above the
// plates: no point of it moves by more than |w| times its distance from the
// x axis, at most a cube's half diagonal (0.87 m), so with the spin's axis
// given no child looks for the plate (0.02 + 0.87 / 60 = 0.034 m < 0.1 m),
// where the farthest corner's r alone (up to 10.5 m) gave the outer children
// a contact. Spun about y instead, the axis changes nothing: every child's
// margin is its farthest corner's, as above.
TEST(CompoundMargin, RodRollingAboutItsLengthLooksOnlyAsFarAsItsGirthTurns) {
    const Real gap = Real(0.1), dt = Real(1) / 60, base = Real(0.02);
    SpeculativeReach reach;
    reach.base = base;
    reach.spinA = 1;
    reach.dt = dt;
    reach.extentA = std::sqrt(Real(10.5) * Real(10.5) + 2 * kHalf * kHalf);
    const Real plateTop = -kHalf - gap;
    const std::array<Vec3, 4> corners = {Vec3{-30, plateTop, -5}, Vec3{30, plateTop, -5}, Vec3{30, plateTop, 5},
                                         Vec3{-30, plateTop, 5}};
    const std::array<std::array<std::uint32_t, 3>, 2> triangles = {{{0, 2, 1}, {0, 3, 2}}};
    const Shape mesh = Shape::mesh(corners, triangles);
    const Shape box = Shape::box({30, Real(0.05), 5});
    ManifoldBuffer out;
    for (const bool asMesh : {false, true}) {
        SCOPED_TRACE(asMesh ? "mesh plate" : "box plate");
        const Shape& plate = asMesh ? mesh : box;
        const Transform xPlate = asMesh ? Transform{} : Transform{{0, plateTop - Real(0.05), 0}, Quat{}};
        SpeculativeReach rolling = reach;
        rolling.axisA = {1, 0, 0};
        const std::vector<bool> none = childrenInContact(plate, xPlate, rolling, out);
        EXPECT_EQ(std::count(none.begin(), none.end(), true), 0);
        // Without the axis: the farthest corners, the children 5 or more from the centre.
        const std::vector<bool> unknown = childrenInContact(plate, xPlate, reach, out);
        EXPECT_EQ(std::count(unknown.begin(), unknown.end(), true), 12);
        // About y, the axis through the rod's middle across it: the same children as without the axis.
        SpeculativeReach yawing = reach;
        yawing.axisA = {0, 1, 0};
        EXPECT_EQ(childrenInContact(plate, xPlate, yawing, out), unknown);
    }
}

// The contact manager bounds an awake compound's children once a step
// (compoundChildReaches) and hands them to every pair of the body: the same
// manifolds, bit for bit, as the narrow phase bounding them per pair, and the
// union of the children's bounds is the body's bounds.
TEST(CompoundMargin, ChildBoundsKnownOnceGiveTheSameManifolds) {
    const Shape r = rod();
    const Transform xr{{Real(0.3), Real(0.2), Real(-0.1)}, Quat::fromAxisAngle(normalize(Vec3{Real(0.2), Real(0.1), 1}), Real(0.4))};
    SpeculativeReach reach;
    reach.base = Real(0.02);
    reach.linear = Real(0.7);
    reach.spinA = Real(1.5);
    reach.dt = Real(1) / 60;
    reach.centreA = xr.p;
    reach.extentA = std::sqrt(Real(10.5) * Real(10.5) + 2 * kHalf * kHalf);
    std::vector<ChildReach> known(kRodChildren);
    const AABB all = compoundChildReaches(r, xr, reach.centreA, reach.extentA, reach.axisA, known.data());
    const AABB whole = r.bounds(xr);
    EXPECT_EQ(all.min.x, whole.min.x);
    EXPECT_EQ(all.min.y, whole.min.y);
    EXPECT_EQ(all.max.z, whole.max.z);
    const Shape cube = Shape::box(Vec3::splat(Real(0.2)));
    int pairsWithPoints = 0;
    for (int k = 0; k < 40; ++k) {
        // Cubes along the rod, some touching it, some near, some apart.
        const Real along = Real(-11) + Real(0.55) * Real(k);
        const Vec3 local{along, Real(0.62) + Real(0.01) * Real(k % 7), Real(0.05) * Real(k % 3)};
        const Transform xc{transformPoint(xr, local), Quat::fromAxisAngle(normalize(Vec3{1, 1, 0}), Real(0.1) * Real(k))};
        ManifoldBuffer perPair, once;
        collide(r, xr, cube, xc, reach, perPair);
        SpeculativeReach withKnown = reach;
        withKnown.childrenA = known.data();
        collide(r, xr, cube, xc, withKnown, once);
        // And with the rod as B: the same through the other branch.
        ManifoldBuffer flippedPerPair, flippedOnce;
        SpeculativeReach flipped;
        flipped.base = reach.base;
        flipped.linear = reach.linear;
        flipped.spinB = reach.spinA;
        flipped.dt = reach.dt;
        flipped.centreB = reach.centreA;
        flipped.extentB = reach.extentA;
        collide(cube, xc, r, xr, flipped, flippedPerPair);
        flipped.childrenB = known.data();
        collide(cube, xc, r, xr, flipped, flippedOnce);
        ASSERT_EQ(perPair.size(), once.size()) << "cube " << k;
        ASSERT_EQ(flippedPerPair.size(), flippedOnce.size()) << "cube " << k;
        ASSERT_EQ(perPair.size(), flippedOnce.size()) << "cube " << k;
        EXPECT_EQ(perPair.apartBy(), once.apartBy()) << "cube " << k;
        EXPECT_EQ(flippedPerPair.apartBy(), flippedOnce.apartBy()) << "cube " << k;
        pairsWithPoints += perPair.empty() ? 0 : 1;
        for (std::size_t i = 0; i < perPair.size(); ++i) {
            ASSERT_EQ(perPair[i].childA, once[i].childA);
            ASSERT_EQ(perPair[i].pointCount, once[i].pointCount);
            ASSERT_EQ(flippedPerPair[i].pointCount, flippedOnce[i].pointCount);
            for (std::uint32_t p = 0; p < perPair[i].pointCount; ++p) {
                EXPECT_EQ(perPair[i].points[p].depth, once[i].points[p].depth);
                EXPECT_EQ(perPair[i].points[p].position.x, once[i].points[p].position.x);
                EXPECT_EQ(perPair[i].points[p].localAnchorB.y, once[i].points[p].localAnchorB.y);
                EXPECT_EQ(flippedPerPair[i].points[p].depth, flippedOnce[i].points[p].depth);
                EXPECT_EQ(flippedPerPair[i].points[p].position.z, flippedOnce[i].points[p].position.z);
            }
        }
    }
    EXPECT_GT(pairsWithPoints, 0);
    EXPECT_LT(pairsWithPoints, 40);
}

// A compound pair with no point proves how far apart it is (the contact
// manager's apart cache skips it while it cannot have come within the
// margin): never more than the true distance, and more than the margin.
// Axis-aligned cubes beside an axis-aligned rod: the true distance is the
// nearest child's box distance.
TEST(CompoundMargin, AnEmptyCompoundPairProvesNoMoreThanItsDistance) {
    const Shape r = rod();
    const Shape cube = Shape::box(Vec3::splat(Real(0.2)));
    SpeculativeReach reach;
    reach.base = Real(0.02);
    reach.spinA = Real(1);
    reach.dt = Real(1) / 60;
    reach.extentA = std::sqrt(Real(10.5) * Real(10.5) + 2 * kHalf * kHalf);
    int proved = 0;
    for (int k = 0; k < 60; ++k) {
        const Vec3 c{Real(-12) + Real(0.41) * Real(k), Real(0.9) + Real(0.05) * Real(k % 9), Real(0.3) * Real(k % 4)};
        Real distance = 1e30f;
        for (int i = 0; i < kRodChildren; ++i) {
            const Vec3 d = max(Vec3::zero(), max(Vec3{Real(i - kRodChildren / 2), 0, 0} - c, c - Vec3{Real(i - kRodChildren / 2), 0, 0}) -
                                                 Vec3::splat(kHalf + Real(0.2)));
            distance = std::min(distance, length(d));
        }
        ManifoldBuffer out;
        collide(r, Transform{}, cube, Transform{c, Quat{}}, reach, out);
        if (!out.empty()) continue;
        EXPECT_LE(out.apartBy(), distance + Real(1e-5)) << "cube at x = " << c.x;
        if (out.apartBy() > 0) ++proved;
    }
    EXPECT_GT(proved, 30);
}

}  // namespace
