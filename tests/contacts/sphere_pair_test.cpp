// Sphere against sphere: the contact manager's own path for two centred
// spheres (ContactManager::collideSpheres, nearly every pair of a sphere
// pile) gives the exact contact geometry, the same as the general narrow
// phase, and carries the contact impulse from step to step.
#include <gtest/gtest.h>

#include <vector>

#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

// Two overlapping spheres at rest in zero gravity, stepped once by a step so
// short that the contact push moves them less than 1e-7 m; the report is then
// the geometry of the configuration they were placed in.
struct Overlap {
    Vec3 centreA{Real(0.1), Real(0.2), Real(-0.3)};
    Vec3 centreB{Real(0.6), Real(0.55), Real(-0.1)};
    Real radiusA = Real(0.5), radiusB = Real(0.3);
};

std::vector<ContactReport> contactsOf(const Overlap& o, bool bAsCompound) {
    WorldDef def;
    def.gravity = {0, 0, 0};
    def.sleeping = false;
    World world(def);
    addSphere(world, o.centreA, o.radiusA);
    BodyDef b;
    b.position = o.centreB;
    b.mass = 1;
    if (bAsCompound) {
        // The same sphere as a one-child compound: the general narrow phase.
        const CompoundChild child{Shape::sphere(o.radiusB), Transform{}};
        b.shape = Shape::compound(std::span<const CompoundChild>(&child, 1));
    } else {
        b.shape = Shape::sphere(o.radiusB);
    }
    world.createBody(b);
    world.step(Real(1e-7));
    return world.contacts();
}

}  // namespace

// Analytic: normal along the centres, depth rA + rB - |cB - cA|, the point
// midway between the two surface points. Tolerance 1e-5 (float geometry of
// numbers near 1, and < 1e-6 of motion in the step).
TEST(SpherePair, ContactIsTheExactGeometry) {
    const Overlap o;
    const std::vector<ContactReport> contacts = contactsOf(o, false);
    ASSERT_EQ(contacts.size(), 1u);
    const Vec3 d = o.centreB - o.centreA;
    const Real dist = length(d);
    const Vec3 n = d / dist;
    const ContactReport& c = contacts[0];
    EXPECT_NEAR(c.depth, o.radiusA + o.radiusB - dist, Real(1e-5));
    EXPECT_NEAR(length(c.normal - n), 0, Real(1e-5));
    ASSERT_EQ(c.points.size(), 1u);
    const Vec3 expected = ((o.centreA + n * o.radiusA) + (o.centreB - n * o.radiusB)) * Real(0.5);
    EXPECT_NEAR(length(c.points[0] - expected), 0, Real(1e-5));
}

// The same pair through the general narrow phase (B as a compound of one
// sphere) reports the same contact, to float rounding.
TEST(SpherePair, AgreesWithTheGeneralNarrowPhase) {
    const Overlap o;
    const std::vector<ContactReport> direct = contactsOf(o, false);
    const std::vector<ContactReport> general = contactsOf(o, true);
    ASSERT_EQ(direct.size(), 1u);
    ASSERT_EQ(general.size(), 1u);
    EXPECT_NEAR(direct[0].depth, general[0].depth, Real(1e-6));
    EXPECT_NEAR(length(direct[0].normal - general[0].normal), 0, Real(1e-6));
    ASSERT_EQ(general[0].points.size(), 1u);
    EXPECT_NEAR(length(direct[0].points[0] - general[0].points[0]), 0, Real(1e-6));
}

// A column of five balls standing on a static ball (a vertical line of
// centres, an equilibrium) holds still once settled: every speed stays below
// 1e-3 m/s for 5 s and the top ball's centre is within 2 cm of 5.5 m (soft
// contacts overlap by millimetres). The warm start carries each contact's
// impulse across steps; one Gauss-Seidel iteration per sub-step cannot pass
// the column's weight down without it: with the impulse not carried the
// balls move at 0.014 m/s for good, against 3e-5 m/s with it (measured).
TEST(SpherePair, ColumnOfBallsRestsWithoutJitter) {
    WorldDef def;
    def.sleeping = false;
    World world(def);
    BodyDef base;
    base.type = BodyType::Static;
    base.shape = Shape::sphere(1);
    world.createBody(base);
    BodyId balls[5];
    for (int i = 0; i < 5; ++i) balls[i] = addSphere(world, {0, Real(1.55) + Real(1.01) * static_cast<Real>(i), 0}, Real(0.5));
    run(world, 300);
    Real maxSpeed = 0;
    for (int i = 0; i < 300; ++i) {
        world.step(kDt);
        for (const BodyId b : balls) maxSpeed = std::max(maxSpeed, length(world.linearVelocity(b)));
    }
    EXPECT_LT(maxSpeed, Real(1e-3));
    EXPECT_NEAR(world.position(balls[4]).y, Real(5.5), Real(0.02));
}
