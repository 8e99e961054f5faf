// Rounded shapes in contact (docs/narrow-phase.md, "Rounded shapes"): the
// narrow phase's depths against closed-form values for rounded pairs and
// rounded shapes on meshes and heightfields; a rounded box resting on the
// ground at its outer half height without jitter; a rounded cube that tips on
// a slope where the sharp cube of the same size holds, at the angle the
// flat part of its face predicts.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "collision/narrow_phase.hpp"
#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

constexpr double kPi = std::numbers::pi;
const double kSqrt2 = std::sqrt(2.0);

Quat about(const Vec3& axis, double degrees) { return Quat::fromAxisAngle(axis, Real(degrees * kPi / 180)); }

ManifoldBuffer collidePair(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb, Real margin = Real(0.02)) {
    ManifoldBuffer out;
    collide(a, xa, b, xb, margin, out);
    return out;
}

void expectAllDepths(const ManifoldBuffer& out, double depth, double tol, const Vec3& normal) {
    ASSERT_FALSE(out.empty());
    for (const Manifold& m : out) {
        EXPECT_NEAR(dot(m.normal, normal), 1, 1e-4);
        ASSERT_GT(m.pointCount, 0u);
        for (const ContactPoint& p : m.contacts()) EXPECT_NEAR(p.depth, depth, tol);
    }
}

// Cube of outer half extent 0.5, rounded by 0.1: core half extent 0.4.
Shape roundedCube() { return Shape::roundedBox(Vec3::splat(Real(0.5)), Real(0.1)); }

TEST(RoundedContacts, FaceOnFaceDepthAndPoints) {
    const ManifoldBuffer out = collidePair(roundedCube(), Transform::identity(), roundedCube(),
                                           Transform({0, Real(0.95), 0}, about({0, 1, 0}, 30)));
    expectAllDepths(out, 0.05, 1e-5, {0, 1, 0});
    ASSERT_EQ(out.size(), 1u);
    EXPECT_EQ(out[0].pointCount, 4u);
    // Midway between A's top (0.5) and B's bottom (0.45).
    for (const ContactPoint& p : out[0].contacts()) EXPECT_NEAR(p.position.y, 0.475, 1e-5);
    // The anchors are on the rounded surfaces.
    for (const ContactPoint& p : out[0].contacts()) EXPECT_NEAR(p.localAnchorA.y, 0.5, 1e-5);
}

TEST(RoundedContacts, SpeculativeGapIsTheRoundedSurfacesGap) {
    const ManifoldBuffer near = collidePair(roundedCube(), Transform::identity(), roundedCube(), Transform({0, Real(1.02), 0}, {}),
                                            Real(0.05));
    expectAllDepths(near, -0.02, 1e-5, {0, 1, 0});
    // Beyond the margin: nothing, although the cores are within margin + 2 r.
    EXPECT_TRUE(collidePair(roundedCube(), Transform::identity(), roundedCube(), Transform({0, Real(1.02), 0}, {}), Real(0.01)).empty());
}

// Two rounded cubes standing on edges crossed at right angles: the cores'
// edges are (y_B - 0.8 sqrt 2) apart, the rounded surfaces that minus 2 r.
TEST(RoundedContacts, CrossedEdgesDepthIsClosedForm) {
    const double yB = 0.8 * kSqrt2 + 0.15;  // depth 0.2 - 0.15
    const ManifoldBuffer out = collidePair(roundedCube(), Transform({0, 0, 0}, about({0, 0, 1}, 45)), roundedCube(),
                                           Transform({0, Real(yB), 0}, about({1, 0, 0}, 45)));
    expectAllDepths(out, 0.05, 1e-5, {0, 1, 0});
    EXPECT_NEAR(out[0].points[0].position.y, yB / 2, 1e-5);
    EXPECT_NEAR(out[0].points[0].position.x, 0, 1e-4);
    EXPECT_NEAR(out[0].points[0].position.z, 0, 1e-4);
}

// A sphere off the rounded corner, along the diagonal: depth r + R - distance to the core's corner.
TEST(RoundedContacts, SphereOnRoundedCorner) {
    const Vec3 diag = normalize(Vec3{1, 1, 1});
    const Vec3 centre = Vec3::splat(Real(0.4)) + diag * Real(0.35);
    const ManifoldBuffer out = collidePair(roundedCube(), Transform::identity(), Shape::sphere(Real(0.3)), Transform(centre, {}));
    expectAllDepths(out, 0.05, 1e-5, diag);
    // And the other way round: the same depth, the normal flipped.
    const ManifoldBuffer flipped = collidePair(Shape::sphere(Real(0.3)), Transform(centre, {}), roundedCube(), Transform::identity());
    expectAllDepths(flipped, 0.05, 1e-5, -diag);
}

// A rounded cube on an edge, a rounded cylinder on its side and a rounded
// hull on a vertex, each on a two-triangle mesh floor and a heightfield: the
// lowest point is the core's lowest point minus r.
TEST(RoundedContacts, OnMeshAndHeightfieldDepthIsClosedForm) {
    const std::vector<Vec3> verts{{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}};
    const std::vector<std::array<std::uint32_t, 3>> tris{{0, 2, 1}, {0, 3, 2}};
    const Shape mesh = Shape::mesh(verts, tris);
    const std::vector<Real> heights(11 * 11, 0);
    const Shape field = Shape::heightField(11, 11, 1, 1, heights);
    const Transform fieldAt({-5, 0, -5}, {});
    const std::vector<Vec3> tet{{Real(0.3), Real(0.3), Real(0.3)}, {Real(-0.3), Real(-0.3), Real(0.3)},
                                {Real(-0.3), Real(0.3), Real(-0.3)}, {Real(0.3), Real(-0.3), Real(-0.3)}};
    // The tetrahedron turned so its vertex (-0.3, -0.3, 0.3) points straight down: core reach 0.3 sqrt 3.
    const Quat tetDown = Quat::fromTo(normalize(Vec3{-1, -1, 1}), {0, -1, 0});
    struct Case {
        Shape shape;
        Quat q;
        double coreReach;  // the core's lowest point below its origin
        double r;
    };
    const Case cases[] = {
        {roundedCube(), about({0, 0, 1}, 45), 0.4 * kSqrt2, 0.1},
        {Shape::roundedCylinder(Real(0.3), Real(0.5), Real(0.05)), about({0, 0, 1}, 90), 0.25, 0.05},
        {Shape::roundedConvexHull(tet, Real(0.08)), tetDown, 0.3 * std::sqrt(3.0), 0.08},
    };
    for (const Case& c : cases) {
        const double depth = 0.03;
        const double y = c.coreReach + c.r - depth;
        const Transform at({Real(0.2), Real(y), Real(0.3)}, c.q);
        SCOPED_TRACE(toString(c.shape.type()));
        expectAllDepths(collidePair(mesh, Transform::identity(), c.shape, at), depth, 2e-5, {0, 1, 0});
        expectAllDepths(collidePair(field, fieldAt, c.shape, at), depth, 2e-5, {0, 1, 0});
        // And on a plane, with the shape as A: normal down.
        expectAllDepths(collidePair(c.shape, at, Shape::plane({0, 1, 0}, 0), Transform::identity()), depth, 2e-5, {0, -1, 0});
    }
}

WorldDef noSleep() {
    WorldDef d;
    d.sleeping = false;
    return d;
}

// The test: a rounded box resting on the ground sits at its outer
// half height (within 1 mm) and is still (below 1 mm/s) after 2 s.
TEST(RoundedContacts, RoundedBoxRestsAtItsOuterHalfHeightWithoutJitter) {
    for (int ground = 0; ground < 2; ++ground) {
        World world(noSleep());
        if (ground == 0) {
            addGround(world);
        } else {
            BodyDef g;
            g.type = BodyType::Static;
            g.shape = Shape::plane({0, 1, 0}, 0);
            world.createBody(g);
        }
        BodyDef d;
        d.shape = Shape::roundedBox({Real(0.5), Real(0.25), Real(0.4)}, Real(0.1));
        d.mass = 2;
        d.position = {0, Real(0.4), 0};
        const BodyId box = world.createBody(d);
        run(world, 120);
        EXPECT_NEAR(world.position(box).y, 0.25, 1e-3);
        Real maxSpeed = 0;
        for (int i = 0; i < 60; ++i) {
            world.step(kDt);
            maxSpeed = std::max(maxSpeed, length(world.linearVelocity(box)));
            maxSpeed = std::max(maxSpeed, length(world.angularVelocity(box)) * Real(0.5));
        }
        EXPECT_LT(maxSpeed, Real(1e-3));
        EXPECT_NEAR(world.position(box).y, 0.25, 1e-3);
    }
}

// With sleeping on, a rounded box and a rounded cylinder on its side settle
// and fall asleep (a rocking rounded edge would keep them awake) at their
// outer half height.
TEST(RoundedContacts, RestingRoundedShapesFallAsleep) {
    World world;
    addGround(world);
    BodyDef box;
    box.shape = Shape::roundedBox({Real(0.5), Real(0.25), Real(0.4)}, Real(0.1));
    box.mass = 2;
    box.position = {0, Real(0.4), 0};
    BodyDef cyl;
    cyl.shape = Shape::roundedCylinder(Real(0.3), Real(0.5), Real(0.05));
    cyl.mass = 1;
    cyl.position = {3, Real(0.4), 0};
    cyl.orientation = about({1, 0, 0}, 90);  // lying on its side, rolling along x would need a push
    const BodyId b = world.createBody(box), c = world.createBody(cyl);
    run(world, 300);
    EXPECT_FALSE(world.isAwake(b));
    EXPECT_FALSE(world.isAwake(c));
    EXPECT_NEAR(world.position(b).y, 0.25, 1e-3);
    EXPECT_NEAR(world.position(c).y, 0.3, 1e-3);
}

// A cube of half extent a on a slope with friction enough not to slide
// (mu = 1.2 > tan of the angles here) tips once the line of its weight leaves
// the flat part of its face: tan(theta) > (a - r) / a. The sharp cube tips
// at 45 degrees, the rounded one (a = 0.5, r = 0.1) at atan(0.8) = 38.7.
// The slope is a tilted gravity on flat ground: the same physics.
double tiltAfter(bool rounded, double slopeDegrees, Real& slid) {
    WorldDef def = noSleep();
    const double t = slopeDegrees * kPi / 180;
    def.gravity = {Real(9.81 * std::sin(t)), Real(-9.81 * std::cos(t)), 0};
    World world(def);
    addGround(world, Real(1.2));
    BodyDef d;
    d.shape = rounded ? roundedCube() : Shape::box(Vec3::splat(Real(0.5)));
    d.mass = 1;
    d.friction = Real(1.2);
    d.position = {0, Real(0.5), 0};
    const BodyId box = world.createBody(d);
    run(world, 120);
    slid = length(world.position(box) - Vec3{0, Real(0.5), 0});
    const Quat q = world.orientation(box);
    return 2 * std::acos(std::min(1.0, static_cast<double>(std::fabs(q.w)))) * 180 / kPi;
}

TEST(RoundedContacts, RoundedCubeTipsOnASlopeWhereTheSharpCubeHolds) {
    Real slid = 0;
    // Each cube on both sides of its predicted angle, half a degree off.
    const double roundedTip = std::atan(0.8) * 180 / kPi, sharpTip = 45;
    EXPECT_LT(tiltAfter(true, roundedTip - 0.5, slid), 1.0);
    EXPECT_GT(tiltAfter(true, roundedTip + 0.5, slid), 45.0);
    EXPECT_LT(tiltAfter(false, sharpTip - 0.5, slid), 1.0);
    EXPECT_GT(tiltAfter(false, sharpTip + 0.5, slid), 45.0);
    // 42 degrees: past the rounded cube's 38.7, short of the sharp cube's 45.
    EXPECT_LT(tiltAfter(false, 42, slid), 1.0);
    EXPECT_LT(slid, Real(0.01));
    EXPECT_GT(tiltAfter(true, 42, slid), 45.0);  // tipped over its rounded edge
    EXPECT_GT(slid, Real(0.3));
    // 36 degrees: short of both; the rounded cube holds too.
    EXPECT_LT(tiltAfter(true, 36, slid), 1.0);
    EXPECT_LT(slid, Real(0.01));
}

}  // namespace
