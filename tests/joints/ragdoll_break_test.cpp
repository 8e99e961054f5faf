// Ragdolls, fixed joints, cone-twist limits, reaction forces, breaking and validation.
#include <cmath>
#include <algorithm>
#include <vector>

#include "joints/joint_test_util.hpp"

using namespace fulcrum;
using namespace fulcrum::jointtest;

namespace {

BodyDef capsule(Real mass, Vec3 p, Real r, Real hh, Quat q = {}) {
    BodyDef d;
    d.shape = Shape::capsule(r, hh);
    d.mass = mass;
    d.position = p;
    d.orientation = q;
    return d;
}

// An 11-body ragdoll standing at height `y0` (feet at y0): pelvis, torso, head
// (boxes / sphere), upper and lower arms and legs (capsules); cone-twist at the
// neck, shoulders, hips and spine, hinges at elbows and knees.
struct Ragdoll {
    std::vector<BodyId> bodies;
    std::vector<JointId> joints;
    Real friction = 0;  // N m, every joint
    Ragdoll(World& w, Vec3 o, Real jointFriction) : friction(jointFriction) {
        const Quat side = Quat::fromAxisAngle({0, 0, 1}, Real(kPi / 2));
        const BodyId pelvis = add(w, boxBody(8, o + Vec3{0, Real(1.0), 0}, {Real(0.15), Real(0.1), Real(0.1)}));
        const BodyId torso = add(w, boxBody(15, o + Vec3{0, Real(1.35), 0}, {Real(0.18), Real(0.22), Real(0.1)}));
        const BodyId head = add(w, sphereBody(4, o + Vec3{0, Real(1.72), 0}, Real(0.11)));
        cone(w, pelvis, torso, o + Vec3{0, Real(1.1), 0}, {0, 1, 0}, Real(0.4), Real(0.3));
        cone(w, torso, head, o + Vec3{0, Real(1.59), 0}, {0, 1, 0}, Real(0.6), Real(0.8));
        for (const Real s : {Real(-1), Real(1)}) {
            const BodyId upperArm = add(w, capsule(2, o + Vec3{s * Real(0.38), Real(1.5), 0}, Real(0.05), Real(0.1), side));
            const BodyId lowerArm = add(w, capsule(Real(1.5), o + Vec3{s * Real(0.66), Real(1.5), 0}, Real(0.045), Real(0.1), side));
            cone(w, torso, upperArm, o + Vec3{s * Real(0.24), Real(1.5), 0}, {s, 0, 0}, Real(1.2), Real(0.5));
            hinge(w, upperArm, lowerArm, o + Vec3{s * Real(0.52), Real(1.5), 0}, {0, 1, 0}, 0, Real(2.5));
            const BodyId thigh = add(w, capsule(7, o + Vec3{s * Real(0.1), Real(0.7), 0}, Real(0.07), Real(0.13)));
            const BodyId shin = add(w, capsule(4, o + Vec3{s * Real(0.1), Real(0.27), 0}, Real(0.06), Real(0.15)));
            cone(w, pelvis, thigh, o + Vec3{s * Real(0.1), Real(0.9), 0}, {0, -1, 0}, Real(0.8), Real(0.3));
            hinge(w, thigh, shin, o + Vec3{s * Real(0.1), Real(0.49), 0}, {1, 0, 0}, -Real(2.5), 0);
        }
    }
    // Limbs get the usual ragdoll damping (0.5 /s angular): without any, a limb
    // launched round its cone boundary circles there for ever, as it would in
    // vacuum on frictionless joints.
    BodyId add(World& w, BodyDef d) {
        d.angularDamping = Real(0.5);
        bodies.push_back(w.createBody(d));
        return bodies.back();
    }
    void cone(World& w, BodyId a, BodyId b, Vec3 p, Vec3 axis, Real swing, Real twist) {
        JointDef j = jointDef(JointType::ConeTwist, a, b, p, axis);
        j.swingLimit = swing;
        j.twistLower = -twist;
        j.twistUpper = twist;
        j.frictionTorque = friction;
        joints.push_back(w.createJoint(j));
    }
    void hinge(World& w, BodyId a, BodyId b, Vec3 p, Vec3 axis, Real lo, Real hi) {
        JointDef j = jointDef(JointType::Hinge, a, b, p, axis);
        j.hasLimits = true;
        j.lowerLimit = lo;
        j.upperLimit = hi;
        j.frictionTorque = friction;
        joints.push_back(w.createJoint(j));
    }
};

}  // namespace

// A ragdoll dropped from 1 m, tipped over, falls onto the ground and comes to
// rest. Its joints have a little dry friction (0.5 N m, JointDef::frictionTorque,
// as game ragdolls do; without it a limb propped on the floor swings as a
// frictionless pendulum for tens of seconds: see the next test). Within 6 s
// the whole ragdoll falls asleep (every body below 0.05 m/s and 0.05 rad/s for
// 0.5 s: the world's sleep thresholds), pelvis, torso and head lie on the
// floor (centres below 0.5 m, above 0), no body sank through it, and no joint
// opened by more than 6 mm at any time (the projection slop, 5 mm, plus 1 mm;
// measured 5.0 mm, 8.1 mm with a single projection pass; asleep after 2.5 s).
TEST(Ragdoll, FallsAndComesToRest) {
    WorldDef def = worldDef();
    def.sleeping = true;
    World world(def);
    BodyDef ground = boxBody(0, {0, Real(-0.5), 0}, {20, Real(0.5), 20});
    ground.type = BodyType::Static;
    world.createBody(ground);
    Ragdoll r(world, {0, 1, 0}, Real(0.5));
    world.setAngularVelocity(r.bodies[1], {0, 0, 2});
    world.setLinearVelocity(r.bodies[1], {1, 0, 0});
    double worst = 0;
    for (int i = 0; i < 360; ++i) {
        world.step(kDt);
        for (JointId j : r.joints) worst = std::max(worst, double(world.jointError(j)));
    }
    EXPECT_LT(worst, 0.006);
    for (std::size_t k = 0; k < r.bodies.size(); ++k) {
        const BodyId b = r.bodies[k];
        EXPECT_FALSE(world.isAwake(b)) << "body " << k;
        EXPECT_LT(length(world.linearVelocity(b)), 0.05);
        EXPECT_LT(length(world.angularVelocity(b)), 0.05);
        EXPECT_GT(world.position(b).y, 0.04);  // the thinnest limb's radius is 0.045 m
        if (k < 3) {
            EXPECT_LT(world.position(b).y, 0.5) << "body " << k;  // pelvis, torso, head lying down
        }
    }
}

// The same ragdoll with frictionless joints and sleeping off doesn't explode:
// over 10 s its energy never rises above the start's (kinetic + potential,
// 1e-3 relative), no joint opens by more than 6 mm (measured 5.0 mm, the
// projection slop; 7.7 mm on impact with a single projection pass) and every
// body ends on the floor.
TEST(Ragdoll, FrictionlessDoesNotGainEnergy) {
    World world(worldDef());
    BodyDef ground = boxBody(0, {0, Real(-0.5), 0}, {20, Real(0.5), 20});
    ground.type = BodyType::Static;
    world.createBody(ground);
    Ragdoll r(world, {0, 1, 0}, 0);
    world.setAngularVelocity(r.bodies[1], {0, 0, 2});
    world.setLinearVelocity(r.bodies[1], {1, 0, 0});
    const double e0 = world.energy().total;
    double worst = 0, highest = e0;
    for (int i = 0; i < 600; ++i) {
        world.step(kDt);
        for (JointId j : r.joints) worst = std::max(worst, double(world.jointError(j)));
        highest = std::max(highest, world.energy().total);
    }
    EXPECT_LT(highest, e0 + 1e-3 * std::fabs(e0));
    EXPECT_LT(worst, 0.006);
    for (BodyId b : r.bodies) {
        EXPECT_GT(world.position(b).y, 0.04);
        EXPECT_LT(world.position(b).y, 1.0);
    }
}

// Cone-twist: an arm hanging from the world on a cone of 0.5 rad, pushed
// sideways hard: the swing angle never exceeds the cone by more than 0.03 rad.
TEST(ConeTwist, SwingLimitHolds) {
    World world(worldDef());
    const BodyId arm = world.createBody(capsule(1, {0, Real(-0.5), 0}, Real(0.05), Real(0.4)));
    JointDef j = jointDef(JointType::ConeTwist, kWorldBody, arm, {0, 0, 0}, {0, -1, 0});
    j.swingLimit = Real(0.5);
    world.createJoint(j);
    world.setLinearVelocity(arm, {5, 0, 3});
    double widest = 0;
    for (int i = 0; i < 120; ++i) {
        world.step(kDt);
        const Vec3 down = rotate(world.orientation(arm), {0, -1, 0});
        widest = std::max(widest, std::acos(std::clamp(double(-down.y), -1.0, 1.0)));
    }
    EXPECT_LT(widest, 0.53);
    EXPECT_GT(widest, 0.45);  // it did reach the cone
}

// Fixed joint: a beam welded to the world at one end stays put (0.5 mm, 2 mrad)
// and its reaction torque balances gravity's moment m g L/2 (1 %).
TEST(Fixed, CantileverHoldsWithReaction) {
    World world(worldDef());
    const BodyId beam = world.createBody(boxBody(2, {Real(0.5), 0, 0}, {Real(0.5), Real(0.05), Real(0.05)}));
    const JointId weld = world.createJoint(jointDef(JointType::Fixed, kWorldBody, beam, {0, 0, 0}));
    for (int i = 0; i < 120; ++i) world.step(kDt);
    EXPECT_LT(world.jointError(weld), 5e-4);
    EXPECT_LT(length(toRotationVector(world.orientation(beam))), 2e-3);
    EXPECT_NEAR(world.jointReactionForce(weld).y / (2 * kG), 1, 0.01);
    EXPECT_NEAR(world.jointReactionTorque(weld).z / (2 * kG * 0.5), 1, 0.01);
}

// The reaction force of a ball joint holding a static hanging mass is m g (1 %).
TEST(Reaction, HangingMassIsMG) {
    World world(worldDef());
    const BodyId ball = world.createBody(sphereBody(3, {0, -1, 0}));
    const JointId j = world.createJoint(jointDef(JointType::Ball, kWorldBody, ball, {0, 0, 0}));
    for (int i = 0; i < 60; ++i) world.step(kDt);
    const Vec3 f = world.jointReactionForce(j);
    EXPECT_NEAR(f.y / (3 * kG), 1, 0.01);
    EXPECT_LT(std::hypot(f.x, f.z), 1e-3);
}

// A joint holding a static 3 kg load (29.4 N) with breakForce 2 % above the
// load holds for 2 s; 2 % below, it breaks at once, reports one event with the
// force, is disabled, and the mass falls freely.
TEST(Breaking, BreaksAtItsThreshold) {
    for (const double factor : {1.02, 0.98}) {
        World world(worldDef());
        const BodyId ball = world.createBody(sphereBody(3, {0, -1, 0}));
        JointDef d = jointDef(JointType::Ball, kWorldBody, ball, {0, 0, 0});
        d.breakForce = Real(factor * 3 * kG);
        const JointId j = world.createJoint(d);
        int events = 0;
        for (int i = 0; i < 120; ++i) {
            world.step(kDt);
            for (const JointBreakEvent& e : world.jointBreakEvents()) {
                ++events;
                EXPECT_EQ(e.joint, j);
                EXPECT_EQ(e.bodyB, ball);
                EXPECT_GT(length(e.force), d.breakForce);
            }
        }
        if (factor > 1) {
            EXPECT_EQ(events, 0);
            EXPECT_TRUE(world.isJointEnabled(j));
            EXPECT_NEAR(world.position(ball).y, -1, 1e-3);
        } else {
            EXPECT_EQ(events, 1);
            EXPECT_TRUE(world.isJointBroken(j));
            EXPECT_FALSE(world.isJointEnabled(j));
            EXPECT_LT(world.position(ball).y, -1 - 0.4 * 0.5 * kG * 4);  // fell most of g t^2 / 2
        }
    }
}

// Joint friction: a 1 kg ball on a massless 1 m lever (a ball joint to the
// world 1 m beside it), released horizontal, needs m g L = 9.81 N m to be held.
// With frictionTorque 20 % above that it stays put (1 mm over 1 s); 20 % below,
// it falls, and its angular acceleration at the start is (m g L - f) / (m L^2)
// (the point mass's inertia about the anchor; within 5 %).
TEST(Friction, HoldsBelowItsTorqueAndSlipsAbove) {
    for (const double factor : {1.2, 0.8}) {
        World world(worldDef());
        const BodyId ball = world.createBody(sphereBody(1, {1, 0, 0}, Real(0.01)));
        JointDef j = jointDef(JointType::Ball, kWorldBody, ball, {0, 0, 0});
        j.frictionTorque = Real(factor * kG);
        world.createJoint(j);
        if (factor > 1) {
            for (int i = 0; i < 60; ++i) world.step(kDt);
            EXPECT_NEAR(world.position(ball).y, 0, 1e-3);
        } else {
            world.step(kDt);
            const double alpha = length(world.angularVelocity(ball)) / kDt;
            EXPECT_NEAR(alpha / ((1 - factor) * kG), 1, 0.05) << alpha;
        }
    }
}

// Bad input names the joint and the field.
TEST(JointValidation, ClearErrors) {
    using ::testing::AllOf;
    using ::testing::HasSubstr;
    World world(worldDef());
    const BodyId a = world.createBody(sphereBody(1, {0, 0, 0}));
    const BodyId b = world.createBody(sphereBody(1, {1, 0, 0}));
    JointDef j = jointDef(JointType::Ball, a, BodyId{77, 0}, {0, 0, 0});
    j.name = "elbow-of-the-test";
    EXPECT_THAT(errorOf([&] { world.createJoint(j); }), AllOf(HasSubstr("elbow-of-the-test"), HasSubstr("bodyB"), HasSubstr("does not exist")));
    j = jointDef(JointType::Hinge, a, b, {0, 0, 0}, {0, 0, 0});
    EXPECT_THAT(errorOf([&] { world.createJoint(j); }), HasSubstr("axis"));
    j = jointDef(JointType::Slider, a, b, {0, 0, 0}, {1, 0, 0});
    j.hasLimits = true;
    j.lowerLimit = 1;
    j.upperLimit = 0;
    EXPECT_THAT(errorOf([&] { world.createJoint(j); }), AllOf(HasSubstr("lowerLimit"), HasSubstr("above upperLimit")));
    j = jointDef(JointType::Hinge, a, b, {0, 0, 0}, {1, 0, 0});
    j.hasLimits = true;
    j.lowerLimit = -4;
    j.upperLimit = 0;
    EXPECT_THAT(errorOf([&] { world.createJoint(j); }), AllOf(HasSubstr("lowerLimit"), HasSubstr("[-pi, pi]")));
    j = jointDef(JointType::Distance, a, b, {0, 0, 0});
    j.anchorB = {1, 0, 0};
    j.minLength = 0;
    j.maxLength = Real(-0.5);  // negative: the creation distance (1 m)... fine
    EXPECT_NO_THROW(world.createJoint(j));
    j.minLength = 2;  // above the resolved max
    EXPECT_THAT(errorOf([&] { world.createJoint(j); }), AllOf(HasSubstr("minLength"), HasSubstr("above maxLength")));
    j = jointDef(JointType::Distance, a, b, {0, 0, 0});
    j.stiffness = -1;
    EXPECT_THAT(errorOf([&] { world.createJoint(j); }), HasSubstr("stiffness"));
    j = jointDef(JointType::ConeTwist, a, b, {0, 0, 0});
    j.swingLimit = 0;
    EXPECT_THAT(errorOf([&] { world.createJoint(j); }), AllOf(HasSubstr("swingLimit"), HasSubstr("(0, pi]")));
    j = jointDef(JointType::ConeTwist, a, b, {0, 0, 0});
    j.twistUpper = 4;
    EXPECT_THAT(errorOf([&] { world.createJoint(j); }), HasSubstr("twistUpper"));
    j = jointDef(JointType::Hinge, a, b, {0, 0, 0});
    j.spring = {true, 0, -5, 0};
    EXPECT_THAT(errorOf([&] { world.createJoint(j); }), HasSubstr("spring.stiffness"));
    j = jointDef(JointType::ConeTwist, a, b, {0, 0, 0});
    j.frictionTorque = -1;
    EXPECT_THAT(errorOf([&] { world.createJoint(j); }), AllOf(HasSubstr("frictionTorque"), HasSubstr("negative")));
    WorldDef bad = worldDef();
    bad.jointHertz = 0;
    EXPECT_THAT(errorOf([&] { World w2(bad); }), AllOf(HasSubstr("world"), HasSubstr("jointHertz")));
    bad = worldDef();
    bad.jointProjectionSlop = -Real(0.001);
    EXPECT_THAT(errorOf([&] { World w2(bad); }), HasSubstr("jointProjectionSlop"));
    const JointId ball = world.createJoint(jointDef(JointType::Ball, a, b, {0, 0, 0}));
    EXPECT_THAT(errorOf([&] { world.setJointMotor(ball, {true, 1, 1}); }), HasSubstr("only hinge and slider"));
    const JointId hinge = world.createJoint(jointDef(JointType::Hinge, a, b, {0, 0, 0}));
    EXPECT_THAT(errorOf([&] { world.setJointMotor(hinge, {true, 1, -1}); }), HasSubstr("motor.maxForce"));
}

// Twenty-four ragdolls dropped onto each other (6 columns 1.2 m apart, 4
// high, as in bench_joints' pile) come to rest and fall asleep within 10 s.
// Forearms end up wedged between the floor, another ragdoll and their own
// elbow, where the joint's position projection and the contacts undo each
// other every sub-step: such a body stands still with a velocity (here 0.028
// m/s) that never decays. Sleeping now tests how far bodies actually moved
// (src/islands/sleep.hpp, "Held bodies"); on the velocities alone this pile
// never slept. Which limbs wedge depends on the pile to the last bit, so this
// pile is one that did.
TEST(Ragdoll, APileComesToRestAndSleeps) {
    WorldDef def = worldDef(5);  // the world default, as the bench
    def.sleeping = true;
    World world(def);
    BodyDef ground = boxBody(0, {0, Real(-0.5), 0}, {40, Real(0.5), 40});
    ground.type = BodyType::Static;
    world.createBody(ground);
    std::vector<Ragdoll> dolls;
    for (int layer = 0; layer < 4; ++layer) {
        for (int k = 0; k < 6; ++k) {
            dolls.emplace_back(world, Vec3{0, 1 + Real(2.2) * static_cast<Real>(layer), static_cast<Real>(k - 2) * Real(1.2)},
                               Real(0.5));
        }
    }
    for (int i = 0; i < 600; ++i) world.step(kDt);
    std::size_t awake = 0;
    double fastest = 0;
    for (const Ragdoll& r : dolls) {
        for (const BodyId b : r.bodies) {
            awake += world.isAwake(b);
            fastest = std::max(fastest, double(length(world.linearVelocity(b))));
        }
    }
    EXPECT_EQ(awake, 0u) << "fastest body " << fastest << " m/s";
}

// The spin limit (WorldDef::maxRotationPerSubstep, 0.25 pi per sub-step): a
// 100-link chain hanging sideways from the world has its middle joint disabled
// for 30 steps while it swings down, then re-enabled: the loose half, metres
// away and falling at ~20 m/s, is yanked back, and the links whip. (25 steps
// until issue 8's fifth round: with the tree factorization reused across a
// position update, docs/joints.md, that yank whipped the links to 95 rad/s
// only, under half the limit, and 30 steps to ~300 rad/s; with every pass
// factored exactly, 136 and 288 rad/s.) Without
// the limit a link spun up to 670 rad/s and the step threw a NumericalError
// at step 271 (NaN); with it no link's end-of-step spin passes twice the limit
// (0.25 pi x 300 / s = 236 rad/s in the drift; the relax pass after the drift
// adds to it: measured at most 360 rad/s), the joints close (under 5 cm at the end) and, once the yank
// is over (5 steps after it, step 125: closing the joint lifts the loose half,
// which adds energy), the chain never gains more than 1 % of its energy.
TEST(SpinLimit, AChainYankedTautStaysFinite) {
    WorldDef def;
    def.sleeping = false;
    World world(def);
    std::vector<JointId> links;
    BodyId prev = kWorldBody;
    for (int i = 0; i < 100; ++i) {
        BodyDef b = capsule(1, {Real(0.5) + static_cast<Real>(i), 60, 0}, Real(0.1), Real(0.4),
                            Quat::fromAxisAngle({0, 0, 1}, Real(kPi / 2)));
        const BodyId id = world.createBody(b);
        JointDef j = jointDef(JointType::Ball, prev, id, {static_cast<Real>(i), 60, 0});
        j.anchorB = j.anchor;
        links.push_back(world.createJoint(j));
        prev = id;
    }
    const double limit = double(def.maxRotationPerSubstep) * def.substeps / double(kDt);
    double spinMax = 0;
    double energySettled = 0;  // once the yank is over (re-closing the joint lifts the loose half: energy)
    for (int s = 0; s < 400; ++s) {
        if (s == 90) world.setJointEnabled(links[50], false);
        if (s == 120) world.setJointEnabled(links[50], true);
        ASSERT_NO_THROW(world.step(kDt)) << "step " << s;
        double fastest = 0;
        for (const BodyId b : world.bodies()) fastest = std::max(fastest, double(length(world.angularVelocity(b))));
        // The limit holds in the drift; the relax pass after it may add some.
        ASSERT_LE(fastest, limit * 2) << "step " << s;
        spinMax = std::max(spinMax, fastest);
        if (s == 125) energySettled = world.energy().total;
        if (s > 125) {
            ASSERT_LE(world.energy().total, energySettled * 1.01) << "step " << s;
        }
    }
    double worst = 0;
    for (const JointId j : links) worst = std::max(worst, double(world.jointError(j)));
    EXPECT_LT(worst, 0.05);
    EXPECT_GT(spinMax, limit * 0.5) << "the chain no longer whips: the test lost its point";
}
