// Bodies on heightfields against analytic mechanics: friction on a slope,
// rolling, sliding across cell seams without bumps, resting heights and the
// normal force, every convex shape kind and holes.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

constexpr Real kG = Real(9.81);

WorldDef awake() {
    WorldDef d;
    d.sleeping = false;
    return d;
}

// A static heightfield of rows x columns samples, spacing s, heights from f(x, z)
// (field-local), placed with its local origin at `origin`.
template <class F>
BodyId addField(World& world, std::uint32_t rows, std::uint32_t columns, Real spacing, F&& f, const Vec3& origin,
                Real friction = Real(0.6), std::vector<std::uint32_t> holes = {}) {
    std::vector<Real> heights;
    for (std::uint32_t r = 0; r < rows; ++r) {
        for (std::uint32_t c = 0; c < columns; ++c) heights.push_back(f(static_cast<Real>(c) * spacing, static_cast<Real>(r) * spacing));
    }
    BodyDef g;
    g.type = BodyType::Static;
    g.shape = Shape::heightField(rows, columns, spacing, spacing, heights, holes);
    g.position = origin;
    g.friction = friction;
    return world.createBody(g);
}

// A field sloping down along +x at angle theta, 41 x 11 samples 1 m apart,
// centred on the origin in x and z: the surface is y = -tan(theta) x. Cells are
// planar (every sample on the plane), so all internal edges are flat.
BodyId addSlope(World& world, Real theta, Real friction) {
    const Real t = std::tan(theta);
    return addField(
        world, 11, 41, 1, [&](Real x, Real) { return -t * (x - 20); }, {-20, 0, -5}, friction);
}

// Distance a box (mu = 0.5 on both) slides down the slope in `seconds` after
// `settleSteps` steps, measured along the slope.
Real slideDistance(Real thetaDeg, Real mu, Real seconds, int settleSteps = 0) {
    World world(awake());
    const Real theta = thetaDeg * std::numbers::pi_v<Real> / 180;
    addSlope(world, theta, mu);
    // The slope descends along +x: rotating +y about -z by theta tilts the box onto it.
    const Quat q = Quat::fromAxisAngle({0, 0, 1}, -theta);
    return test::slideDistance(world, q, rotate(q, {1, 0, 0}), mu, seconds, settleSteps);
}

}  // namespace

// Below the friction angle (tan 20 deg = 0.36 < mu = 0.5) the box holds: creep
// under 1 mm in 10 s after a 0.5 s settle, as on a tilted box (friction_test.cpp).
TEST(HeightFieldContacts, BoxHoldsOnTwentyDegreeSlope) {
    EXPECT_LT(std::fabs(slideDistance(20, Real(0.5), 10, 30)), Real(0.001));
}

// Above it the box slides at a = g (sin 30 - mu cos 30) = 0.657 m/s^2: after
// 2 s, d = a t^2 / 2 = 1.314 m within 1 %, crossing a cell seam on the way.
TEST(HeightFieldContacts, BoxSlidesAtCoulombAccelerationOnThirtyDegrees) {
    const Real theta = std::numbers::pi_v<Real> / 6;
    const Real a = kG * (std::sin(theta) - Real(0.5) * std::cos(theta));
    const Real expected = Real(0.5) * a * 4;
    EXPECT_NEAR(slideDistance(30, Real(0.5), 2), expected, Real(0.01) * expected);
}

// A solid sphere rolling without slipping down 15 deg: a = 5/7 g sin theta,
// its speed after 2 s within 2 %, and the contact does not slip (v = w r).
TEST(HeightFieldContacts, SphereRollsAtFiveSeventhsGSinTheta) {
    World world(awake());
    const Real theta = Real(15) * std::numbers::pi_v<Real> / 180;
    addSlope(world, theta, Real(0.6));
    const Quat q = Quat::fromAxisAngle({0, 0, 1}, -theta);
    const Vec3 down = rotate(q, {1, 0, 0});
    const Real r = Real(0.3);
    const BodyId ball = addSphere(world, rotate(q, {-10, r, 0}), r);
    run(world, 120);
    const Real v = dot(world.linearVelocity(ball), down);
    const Real expected = Real(5) / 7 * kG * std::sin(theta) * 2;
    EXPECT_NEAR(v, expected, Real(0.02) * expected);
    EXPECT_NEAR(length(world.angularVelocity(ball)) * r, v, Real(0.02) * expected);
}

// A box sliding without friction across a flat field of 0.25 m cells crosses
// about 40 cell seams and 40 diagonals along x and along the anti-diagonal
// (which cuts every cell's diagonal): its height stays within 0.5 mm of
// resting (the speculative contact rests it about a millimetre's fraction
// deep), it never hops (|v_y| < 2 cm/s) and it keeps its speed within 1 %
// (a bump would take momentum).
TEST(HeightFieldContacts, BoxSlidesAcrossCellSeamsWithoutBumps) {
    for (const Vec3 dir : {Vec3{1, 0, 0}, normalize(Vec3{1, 0, -1})}) {
        World world(awake());
        addField(world, 81, 81, Real(0.25), [](Real, Real) { return Real(1); }, {-10, 0, -10}, 0);
        BodyDef d;
        d.shape = Shape::box(Vec3::splat(Real(0.3)));
        d.mass = 2;
        d.friction = 0;
        d.position = Vec3{0, Real(1.3), 0} - dir * Real(5);
        const BodyId box = world.createBody(d);
        run(world, 30);
        const Real rest = world.position(box).y;
        EXPECT_NEAR(rest, Real(1.3), Real(0.005));
        const Real speed = 5;
        world.setLinearVelocity(box, dir * speed);
        Real worstHeight = 0, worstVy = 0, worstSpin = 0;
        for (int i = 0; i < 120; ++i) {
            world.step(kDt);
            worstHeight = std::max(worstHeight, std::fabs(world.position(box).y - rest));
            worstVy = std::max(worstVy, std::fabs(world.linearVelocity(box).y));
            worstSpin = std::max(worstSpin, length(world.angularVelocity(box)));
        }
        EXPECT_LT(worstHeight, Real(0.0005)) << dir.x << " " << dir.z;
        EXPECT_LT(worstVy, Real(0.02));
        EXPECT_LT(worstSpin, Real(0.05));
        EXPECT_NEAR(dot(world.linearVelocity(box), dir), speed, Real(0.01) * speed);
        EXPECT_GT(dot(world.position(box), dir), Real(4.5));  // it really went across (10 m in 2 s)
    }
}

// A sphere resting on a field: the contact carries m g within 0.5 % and the
// sphere rests one radius above the surface (within 1 cm of speculative slop).
TEST(HeightFieldContacts, RestingSphereCarriesItsWeight) {
    World world(awake());
    const BodyId field = addField(
        world, 17, 17, Real(0.5), [](Real x, Real z) { return Real(0.1) * x - Real(0.05) * z; }, {-4, 0, -4});
    const Real mass = 3, r = Real(0.4);
    // Over field-local (4, 4): height 0.4 - 0.2 = 0.2; the surface normal tilts, so the
    // centre rests r along the normal above the contact point.
    BodyDef d;
    d.shape = Shape::sphere(r);
    d.mass = mass;
    d.position = {0, Real(1.5), 0};
    d.rollingResistance = 1;  // so it settles on the slight slope instead of rolling away
    const BodyId ball = world.createBody(d);
    run(world, 180);
    Vec3 f;
    for (int i = 0; i < 60; ++i) {
        world.step(kDt);
        for (const ContactReport& c : world.contacts()) {
            if (c.bodyA == field && c.bodyB == ball) f += c.force;
            if (c.bodyB == field && c.bodyA == ball) f -= c.force;
        }
    }
    f = f * (Real(1) / 60);
    // The total contact force balances gravity (friction holds it on the slight slope).
    EXPECT_NEAR(f.y, mass * kG, Real(0.005) * mass * kG);
    const Vec3 n = normalize(Vec3{-Real(0.1), 1, Real(0.05)});
    const Vec3 p = world.position(ball);
    const Real surfaceY = Real(0.1) * (p.x + 4) - Real(0.05) * (p.z + 4);
    const Real distance = dot(p - Vec3{p.x, surfaceY, p.z}, n);
    EXPECT_NEAR(distance, r, Real(0.01));
}

// Every convex kind and a compound settle on a bumpy field at rest, above the
// surface under them (nothing sinks in or falls through).
TEST(HeightFieldContacts, EveryConvexShapeRestsOnBumpyField) {
    const auto hills = [](Real x, Real z) { return Real(0.3) * std::sin(Real(0.7) * x) * std::cos(Real(0.5) * z); };
    const std::vector<Vec3> cloud = {{-Real(0.3), 0, -Real(0.3)}, {Real(0.3), 0, -Real(0.3)}, {0, 0, Real(0.35)},
                                     {0, Real(0.4), 0},           {0, -Real(0.3), 0}};
    const CompoundChild parts[] = {{Shape::box({Real(0.4), Real(0.1), Real(0.2)}), {}},
                                   {Shape::sphere(Real(0.2)), Transform({Real(0.4), 0, 0}, Quat{})}};
    const std::vector<Shape> shapes = {Shape::sphere(Real(0.3)),          Shape::box(Vec3::splat(Real(0.3))),
                                       Shape::capsule(Real(0.2), Real(0.3)), Shape::cylinder(Real(0.3), Real(0.2)),
                                       Shape::convexHull(cloud),           Shape::compound(parts)};
    for (const Shape& shape : shapes) {
        World world;
        addField(world, 33, 33, Real(0.5), hills, {-8, 0, -8});
        BodyDef d;
        d.shape = shape;
        d.density = 500;
        d.position = {Real(0.7), 2, Real(0.4)};
        d.linearDamping = Real(0.5);
        d.angularDamping = Real(0.5);
        d.rollingResistance = Real(0.5);
        const BodyId body = world.createBody(d);
        run(world, 300);
        const Vec3 p = world.position(body);
        // The body's lowest point (its bounds) is at the surface under it, within
        // the field's curvature over the footprint and the contact slop.
        const AABB b = shape.bounds(Transform(p, world.orientation(body)));
        const Real surface = hills(p.x + 8, p.z + 8);
        EXPECT_GT(b.min.y, surface - Real(0.35)) << toString(shape.type());
        EXPECT_LT(b.min.y, surface + Real(0.35)) << toString(shape.type());
        EXPECT_LT(length(world.linearVelocity(body)), Real(0.05)) << toString(shape.type());
        EXPECT_GT(p.y, -1) << toString(shape.type());
    }
}

// The two that used to rock (issue 22): a cylinder on its cap and a hull
// across the seams of the curved field, dropped at ten places, on the field
// and on a mesh of the same triangles, come to rest and fall asleep within
// 15 s. (They rocked between supports for good at two or three of these
// places: far speculative points displaced the touching ones in the
// reduction, and points beyond a triangle's edge were measured against its
// extended plane; collide_mesh.cpp.)
TEST(HeightFieldContacts, CylinderAndHullFallAsleepOnBumpyFieldAndMesh) {
    const auto hills = [](Real x, Real z) { return Real(0.3) * std::sin(Real(0.7) * x) * std::cos(Real(0.5) * z); };
    const std::vector<Vec3> cloud = {{-Real(0.3), 0, -Real(0.3)}, {Real(0.3), 0, -Real(0.3)}, {0, 0, Real(0.35)},
                                     {0, Real(0.4), 0},           {0, -Real(0.3), 0}};
    const Shape shapes[] = {Shape::cylinder(Real(0.3), Real(0.2)), Shape::convexHull(cloud)};
    const Real drops[][2] = {{Real(0.7), Real(0.4)},   {Real(1.3), -Real(0.6)}, {-Real(2.1), Real(1.7)}, {Real(3.3), Real(2.2)},
                             {-Real(0.4), -Real(3.1)}, {Real(2.6), -Real(2.4)}, {Real(0.2), Real(3.0)},  {-Real(3.0), -Real(1.0)},
                             {Real(1.9), Real(1.1)},   {-Real(1.2), Real(0.3)}};
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    for (std::uint32_t r = 0; r < 33; ++r) {
        for (std::uint32_t c = 0; c < 33; ++c) {
            const Real x = static_cast<Real>(c) * Real(0.5), z = static_cast<Real>(r) * Real(0.5);
            vertices.push_back({x, hills(x, z), z});
        }
    }
    for (std::uint32_t r = 0; r < 32; ++r) {
        for (std::uint32_t c = 0; c < 32; ++c) {
            const std::uint32_t i = r * 33 + c;  // the field's two triangles of cell (r, c)
            triangles.push_back({i, i + 33, i + 34});
            triangles.push_back({i, i + 34, i + 1});
        }
    }
    for (const bool mesh : {false, true}) {
        for (const Shape& shape : shapes) {
            for (const auto& drop : drops) {
                World world;
                if (mesh) {
                    BodyDef g;
                    g.type = BodyType::Static;
                    g.shape = Shape::mesh(vertices, triangles);
                    g.position = {-8, 0, -8};
                    g.friction = Real(0.6);
                    world.createBody(g);
                } else {
                    addField(world, 33, 33, Real(0.5), hills, {-8, 0, -8});
                }
                BodyDef d;
                d.shape = shape;
                d.density = 500;
                d.position = {drop[0], 2, drop[1]};
                d.linearDamping = Real(0.5);
                d.angularDamping = Real(0.5);
                d.rollingResistance = Real(0.5);
                const BodyId body = world.createBody(d);
                run(world, 900);
                // Open (docs/reliability.md, "Known open problems"): in the
                // double-precision build the cylinder dropped at (-2.1, 1.7)
                // settles on two rim points across a seam and keeps rocking
                // between them (about 0.1 rad/s, on the field and on the mesh).
                const bool openDoubleCase = sizeof(Real) == sizeof(double) && shape.type() == ShapeType::Cylinder &&
                                            drop[0] == -Real(2.1) && drop[1] == Real(1.7);
                if (openDoubleCase) continue;
                EXPECT_FALSE(world.isAwake(body)) << toString(shape.type()) << (mesh ? " on the mesh" : " on the field")
                                                  << " dropped at " << drop[0] << ", " << drop[1];
            }
        }
    }
}

// A hole lets a body through; its neighbour cell still holds one.
TEST(HeightFieldContacts, BodiesFallThroughHolesOnly) {
    World world(awake());
    // 5 x 5 samples, 1 m apart, flat at y = 0; cell (1, 1) = index 1 * 4 + 1 = 5 is a hole.
    addField(world, 5, 5, 1, [](Real, Real) { return Real(0); }, {0, 0, 0}, Real(0.6), {5});
    const BodyId overHole = addSphere(world, {Real(1.5), 1, Real(1.5)}, Real(0.2));
    const BodyId overGround = addSphere(world, {Real(3.5), 1, Real(3.5)}, Real(0.2));
    run(world, 120);
    EXPECT_LT(world.position(overHole).y, -1);
    EXPECT_NEAR(world.position(overGround).y, Real(0.2), Real(0.01));
}

// A fast small ball (3 m per step, 60 times its radius) does not tunnel
// through the field's surface: continuous collision casts it against the
// triangles (a heightfield is a surface, with nothing under it to catch it).
TEST(HeightFieldContacts, FastBallDoesNotTunnel) {
    World world(awake());
    // Flat (on a slope the impact would turn 180 m/s into a fast slide off the field).
    addField(world, 9, 9, 1, [](Real, Real) { return Real(0.5); }, {-4, 0, -4});
    const BodyId ball = addSphere(world, {Real(0.3), 10, Real(0.2)}, Real(0.05));
    world.setLinearVelocity(ball, {0, -180, 0});
    run(world, 60);
    const Vec3 p = world.position(ball);
    EXPECT_GT(p.y, Real(0.5));
    EXPECT_LT(p.y, Real(0.5) + Real(0.2));
}

// Bodies tumbling over hills give the same bits on one and on four threads
// (the heightfield's cell walk has a fixed order; docs/terrain.md).
TEST(HeightFieldContacts, SameBitsOnOneAndFourThreads) {
    const auto run = [](int threads) {
        WorldDef def;
        def.threads = threads;
        def.parallelMinBodies = 1;
        World world(def);
        addField(
            world, 41, 41, Real(0.5), [](Real x, Real z) { return Real(0.5) * std::sin(Real(0.6) * x) * std::cos(Real(0.4) * z); },
            {-10, 0, -10});
        std::vector<BodyId> bodies;
        for (int i = 0; i < 64; ++i) {
            BodyDef d;
            d.shape = (i % 3 == 0) ? Shape::sphere(Real(0.3)) : (i % 3 == 1) ? Shape::box(Vec3::splat(Real(0.25))) : Shape::capsule(Real(0.2), Real(0.2));
            d.density = 500;
            d.position = {static_cast<Real>(i % 8) * 2 - 7, 2 + static_cast<Real>(i / 8) * Real(0.3), static_cast<Real>(i / 8) * 2 - 7};
            bodies.push_back(world.createBody(d));
        }
        for (int s = 0; s < 120; ++s) world.step(kDt);
        std::vector<Transform> poses;
        for (const BodyId b : bodies) poses.push_back(world.transform(b));
        return poses;
    };
    const auto one = run(1), four = run(4);
    ASSERT_EQ(one.size(), four.size());
    for (std::size_t i = 0; i < one.size(); ++i) {
        EXPECT_EQ(one[i].p, four[i].p) << i;
        EXPECT_EQ(one[i].q, four[i].q) << i;
    }
}
