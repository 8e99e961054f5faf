// The per-type joint definitions (BallJointDef, HingeJointDef...; fulcrum/joint.hpp).
//
// - Each one, built with fromWorld from the same world-space anchor and axis,
//   creates the same joint as the generic JointDef: the same bits in every
//   body's state after 120 steps, limits, motors, springs and friction on
//   (JointDef itself is created through the per-type definition, so any
//   difference would be a second creation path).
// - Local anchors and axes are in each body's frame: on rotated bodies they
//   give the world anchor and axis the body's pose says.
// - Bad input throws a fulcrum::Error naming the joint and the field.
#include <cstring>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "fulcrum/snapshot.hpp"
#include "joints/joint_test_util.hpp"

namespace fulcrum {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;
using namespace jointtest;

// Bodies of a pendulum chain in poses no axis lines up with.
struct Chain {
    World world{worldDef(4)};
    std::vector<BodyId> bodies;
    Chain() {
        for (int k = 0; k < 4; ++k) {
            BodyDef b = boxBody(1 + Real(0.5) * static_cast<Real>(k), {Real(0.6) * static_cast<Real>(k), 3, Real(0.1) * static_cast<Real>(k)},
                                {Real(0.2), Real(0.1), Real(0.15)});
            b.orientation = Quat::fromAxisAngle(normalize(Vec3{Real(0.3) + static_cast<Real>(k), 1, Real(0.2)}), Real(0.4) + Real(0.3) * static_cast<Real>(k));
            b.angularVelocity = {Real(0.5), Real(-0.3), Real(0.8)};
            bodies.push_back(world.createBody(b));
        }
    }
    BodyId end(int k) const { return k < 0 ? kWorldBody : bodies[static_cast<std::size_t>(k)]; }
    Vec3 anchor(int k) const { return {Real(0.6) * static_cast<Real>(k) - Real(0.3), Real(3.05), Real(0.1) * static_cast<Real>(k)}; }
};

const Vec3 kAxis = normalize(Vec3{Real(0.2), 1, Real(0.5)});

// Every body's position, orientation and velocities, bit for bit.
std::vector<unsigned char> state(const World& w) {
    std::vector<unsigned char> out;
    const auto add = [&](const auto& v) {
        const auto* p = reinterpret_cast<const unsigned char*>(&v);
        out.insert(out.end(), p, p + sizeof v);
    };
    for (BodyId b : w.bodies()) {
        add(w.position(b));
        add(w.orientation(b));
        add(w.linearVelocity(b));
        add(w.angularVelocity(b));
    }
    return out;
}

// Runs the chain with joints made by `generic` (JointDef) and by `perType`, and compares.
void expectSameJoints(const std::function<JointDef(const Chain&, int)>& generic,
                      const std::function<JointId(Chain&, int)>& perType) {
    Chain a, b;
    std::vector<JointId> ja, jb;
    for (int k = 0; k < 4; ++k) {
        ja.push_back(a.world.createJoint(generic(a, k)));
        jb.push_back(perType(b, k));
    }
    for (int s = 0; s < 120; ++s) {
        a.world.step(kDt);
        b.world.step(kDt);
    }
    EXPECT_TRUE(state(a.world) == state(b.world)) << "the bodies' states differ";
    for (std::size_t k = 0; k < ja.size(); ++k) {
        const Vec3 fa = a.world.jointReactionForce(ja[k]), fb = b.world.jointReactionForce(jb[k]);
        EXPECT_EQ(std::memcmp(&fa, &fb, sizeof fa), 0) << "joint " << k;
        EXPECT_EQ(a.world.jointPosition(ja[k]), b.world.jointPosition(jb[k])) << "joint " << k;
        // What World::jointDef reports: the per-type joint's world anchor comes
        // back from its local anchor (to rounding).
        const JointDef& da = a.world.jointDef(ja[k]);
        const JointDef& db = b.world.jointDef(jb[k]);
        EXPECT_EQ(da.type, db.type);
        EXPECT_LT(length(da.anchor - db.anchor), 1e-5) << "joint " << k;
    }
    // Something happened: the chain moved from where it was built.
    EXPECT_GT(length(a.world.linearVelocity(a.bodies.back())), 0.01);
}

JointDef genericDef(const Chain& c, int k, JointType type) {
    JointDef d;
    d.type = type;
    d.name = "j" + std::to_string(k);
    d.bodyA = c.end(k - 1);
    d.bodyB = c.end(k);
    d.anchor = c.anchor(k);
    d.axis = kAxis * Real(3);  // JointDef normalises its axis
    return d;
}

template <class Def>
Def withBase(Def d, int k) {
    d.name = "j" + std::to_string(k);
    return d;
}

TEST(PerTypeJointDef, HingeWithLimitsMotorSpringAndFrictionIsTheJointDefsHinge) {
    expectSameJoints(
        [](const Chain& c, int k) {
            JointDef d = genericDef(c, k, JointType::Hinge);
            d.hasLimits = k != 1;
            d.lowerLimit = Real(-0.3);
            d.upperLimit = Real(0.4);
            d.motor = {k == 2, Real(1.5), 3};
            d.spring = {k == 1, Real(0.2), 40, 2};
            d.frictionTorque = k == 3 ? Real(0.3) : 0;
            return d;
        },
        [](Chain& c, int k) {
            HingeJointDef d = withBase(HingeJointDef::fromWorld(c.world, c.end(k - 1), c.end(k), c.anchor(k), kAxis * Real(3)), k);
            d.hasLimits = k != 1;
            d.lowerLimit = Real(-0.3);
            d.upperLimit = Real(0.4);
            d.motor = {k == 2, Real(1.5), 3};
            d.spring = {k == 1, Real(0.2), 40, 2};
            d.frictionTorque = k == 3 ? Real(0.3) : 0;
            return c.world.createJoint(d);
        });
}

TEST(PerTypeJointDef, SliderWithLimitsMotorAndSpringIsTheJointDefsSlider) {
    expectSameJoints(
        [](const Chain& c, int k) {
            JointDef d = genericDef(c, k, JointType::Slider);
            d.hasLimits = k != 1;
            d.lowerLimit = Real(-0.1);
            d.upperLimit = Real(0.2);
            d.motor = {k == 2, Real(0.5), 20};
            d.spring = {k == 1, Real(0.05), 100, 5};
            return d;
        },
        [](Chain& c, int k) {
            SliderJointDef d = withBase(SliderJointDef::fromWorld(c.world, c.end(k - 1), c.end(k), c.anchor(k), kAxis * Real(3)), k);
            d.hasLimits = k != 1;
            d.lowerLimit = Real(-0.1);
            d.upperLimit = Real(0.2);
            d.motor = {k == 2, Real(0.5), 20};
            d.spring = {k == 1, Real(0.05), 100, 5};
            return c.world.createJoint(d);
        });
}

TEST(PerTypeJointDef, ConeTwistWithLimitsAndFrictionIsTheJointDefsConeTwist) {
    expectSameJoints(
        [](const Chain& c, int k) {
            JointDef d = genericDef(c, k, JointType::ConeTwist);
            d.swingLimit = Real(0.5);
            d.twistLower = Real(-0.4);
            d.twistUpper = Real(0.3);
            d.frictionTorque = k % 2 ? Real(0.2) : 0;
            return d;
        },
        [](Chain& c, int k) {
            ConeTwistJointDef d =
                withBase(ConeTwistJointDef::fromWorld(c.world, c.end(k - 1), c.end(k), c.anchor(k), kAxis * Real(3)), k);
            d.swingLimit = Real(0.5);
            d.twistLower = Real(-0.4);
            d.twistUpper = Real(0.3);
            d.frictionTorque = k % 2 ? Real(0.2) : 0;
            return c.world.createJoint(d);
        });
}

TEST(PerTypeJointDef, BallFixedAndDistanceAreTheJointDefsJoints) {
    expectSameJoints(
        [](const Chain& c, int k) {
            JointDef d = genericDef(c, k, JointType::Ball);
            d.frictionTorque = Real(0.1);
            return d;
        },
        [](Chain& c, int k) {
            BallJointDef d = withBase(BallJointDef::fromWorld(c.world, c.end(k - 1), c.end(k), c.anchor(k)), k);
            d.frictionTorque = Real(0.1);
            return c.world.createJoint(d);
        });
    expectSameJoints([](const Chain& c, int k) { return genericDef(c, k, JointType::Fixed); },
                     [](Chain& c, int k) {
                         return c.world.createJoint(
                             withBase(FixedJointDef::fromWorld(c.world, c.end(k - 1), c.end(k), c.anchor(k)), k));
                     });
    // Distance: a rod, a rope and a spring.
    const Vec3 offset{Real(0.1), Real(0.25), 0};
    expectSameJoints(
        [offset](const Chain& c, int k) {
            JointDef d = genericDef(c, k, JointType::Distance);
            d.anchorB = c.anchor(k) + offset;
            if (k == 1) d.minLength = 0;
            if (k == 2) d.stiffness = 50, d.damping = 1;
            return d;
        },
        [offset](Chain& c, int k) {
            DistanceJointDef d = withBase(
                DistanceJointDef::fromWorld(c.world, c.end(k - 1), c.end(k), c.anchor(k), c.anchor(k) + offset), k);
            if (k == 1) d.minLength = 0;
            if (k == 2) {
                d.stiffness = 50, d.damping = 1;
                d.minLength = 0;
                d.maxLength = std::numeric_limits<Real>::infinity();
            }
            return c.world.createJoint(d);
        });
}

TEST(PerTypeJointDef, LocalAnchorsAndAxesFollowTheBodiesPoses) {
    World world(worldDef(4));
    // B turned a quarter about z: its local x is world y.
    BodyDef bd = boxBody(1, {1, 2, 3}, {Real(0.5), Real(0.1), Real(0.1)});
    bd.orientation = Quat::fromAxisAngle({0, 0, 1}, Real(kPi / 2));
    const BodyId b = world.createBody(bd);
    BodyDef ad = boxBody(1, {1, 0, 3}, {Real(0.1), Real(0.5), Real(0.1)});
    ad.orientation = Quat::fromAxisAngle({1, 0, 0}, Real(kPi / 2));  // A's local z is world -y
    const BodyId a = world.createBody(ad);

    HingeJointDef h;
    h.name = "elbow";
    h.bodyA = a;
    h.bodyB = b;
    h.localAnchorA = {0, 0, -1};       // A's centre + 1 m along world +y
    h.localAnchorB = {Real(-1), 0, 0};  // B's centre - 1 m along world y
    h.localAxisA = {0, 1, 0};           // world +z
    h.localAxisB = {0, 0, 1};           // world +z
    const JointId hinge = world.createJoint(h);
    const JointDef& record = world.jointDef(hinge);
    EXPECT_LT(length(record.anchor - Vec3{1, 1, 3}), 1e-6);
    EXPECT_LT(length(record.axis - Vec3{0, 0, 1}), 1e-6);
    EXPECT_LT(world.jointError(hinge), 1e-6) << "the two local anchors are one world point";
    EXPECT_NEAR(world.jointPosition(hinge), 0, 1e-6);

    // The static world's "local" frame is world space.
    BallJointDef ball;
    ball.bodyB = b;
    ball.localAnchorA = {1, Real(2.5), 3};
    ball.localAnchorB = {Real(0.5), 0, 0};  // world y + 0.5 from B's centre
    EXPECT_LT(world.jointError(world.createJoint(ball)), 1e-6);

    // An anchor off by 0.25 m shows as that much error.
    FixedJointDef fixed;
    fixed.bodyA = a;
    fixed.bodyB = b;
    fixed.localAnchorA = {0, 0, -1};
    fixed.localAnchorB = {Real(-0.75), 0, 0};
    EXPECT_NEAR(world.jointError(world.createJoint(fixed)), 0.25, 1e-6);

    // fromWorld gives these local values back.
    const HingeJointDef back = HingeJointDef::fromWorld(world, a, b, {1, 1, 3}, {0, 0, 2});
    EXPECT_LT(length(back.localAnchorA - h.localAnchorA), 1e-6);
    EXPECT_LT(length(back.localAnchorB - h.localAnchorB), 1e-6);
    EXPECT_LT(length(back.localAxisA - h.localAxisA), 1e-6);
    EXPECT_LT(length(back.localAxisB - h.localAxisB), 1e-6);
}

TEST(PerTypeJointDef, LocalJointHoldsARotatedPendulumWhereItsAnchorSays) {
    // A rod pendulum hanging from a hinge given in local coordinates only:
    // after swinging, B's anchor is still on the world anchor.
    World world(worldDef(8));
    BodyDef bd = boxBody(1, {0, 0, 0}, {Real(0.05), Real(0.5), Real(0.05)});
    bd.orientation = Quat::fromAxisAngle({0, 0, 1}, Real(0.7));
    const BodyId b = world.createBody(bd);
    HingeJointDef h;
    h.bodyB = b;
    h.localAnchorA = rotate(bd.orientation, Vec3{0, Real(0.5), 0});  // world point at B's top
    h.localAnchorB = {0, Real(0.5), 0};
    h.localAxisA = {0, 0, 1};
    h.localAxisB = {0, 0, 1};
    const JointId j = world.createJoint(h);
    for (int s = 0; s < 120; ++s) world.step(kDt);
    const Vec3 top = world.centerOfMass(b) + rotate(world.orientation(b), Vec3{0, Real(0.5), 0});
    EXPECT_LT(length(top - h.localAnchorA), 5e-3);
    EXPECT_LT(world.jointError(j), 5e-3);
    EXPECT_GT(length(world.angularVelocity(b)), 0.1) << "it swings";
}

TEST(PerTypeJointDef, SnapshotOfPerTypeJointsContinuesBitForBit) {
    // A per-type joint keeps its local values: a snapshot carries them, and
    // the restored world goes on exactly as the original.
    Chain c;
    for (int k = 0; k < 4; ++k) {
        SliderJointDef d;
        d.bodyA = c.end(k - 1);
        d.bodyB = c.end(k);
        d.localAnchorB = {Real(0.1), Real(0.05), 0};
        d.localAnchorA = k == 0 ? c.anchor(0) : Vec3{Real(0.3), 0, 0};
        d.localAxisA = normalize(Vec3{1, 1, 0});
        d.localAxisB = {0, 1, 0};  // not A's axis at creation: the rows align them
        d.hasLimits = true;
        d.lowerLimit = Real(-0.2);
        d.upperLimit = Real(0.2);
        c.world.createJoint(d);
    }
    for (int s = 0; s < 30; ++s) c.world.step(kDt);
    World restored = loadSnapshotFromMemory(saveSnapshotToMemory(c.world));
    for (int s = 0; s < 60; ++s) {
        c.world.step(kDt);
        restored.step(kDt);
    }
    EXPECT_TRUE(state(c.world) == state(restored));
}

// The Error's message from `f`, or "" if it threw none.
std::string errorOf(const std::function<void()>& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(PerTypeJointDef, BadInputThrowsNamingTheJointAndTheField) {
    World world(worldDef(4));
    const BodyId a = world.createBody(sphereBody(1, {0, 1, 0}));
    const BodyId b = world.createBody(sphereBody(1, {0, 2, 0}));

    HingeJointDef hinge;
    hinge.name = "knee";
    hinge.bodyA = a;
    hinge.bodyB = b;
    {
        HingeJointDef d = hinge;
        d.localAxisA = {0, 0, 0};
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), AllOf(HasSubstr("joint 'knee'"), HasSubstr("localAxisA")));
        d.localAxisA = {0, 2, 0};
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), AllOf(HasSubstr("'knee'"), HasSubstr("localAxisA"), HasSubstr("unit")));
        d = hinge;
        d.localAxisB = {std::numeric_limits<Real>::quiet_NaN(), 1, 0};
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), HasSubstr("localAxisB"));
        d = hinge;
        d.hasLimits = true;
        d.lowerLimit = Real(0.5);
        d.upperLimit = Real(-0.5);
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), AllOf(HasSubstr("'knee'"), HasSubstr("lowerLimit")));
        d.lowerLimit = -4;
        d.upperLimit = 0;
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), HasSubstr("[-pi, pi]"));
        d = hinge;
        d.motor.maxForce = -1;
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), HasSubstr("motor.maxForce"));
        d = hinge;
        d.localAnchorB = {0, std::numeric_limits<Real>::infinity(), 0};
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), HasSubstr("localAnchorB"));
        d = hinge;
        d.breakForce = 0;
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), HasSubstr("breakForce"));
    }
    {
        SliderJointDef d;
        d.name = "rail";
        d.bodyA = a;
        d.bodyB = b;
        d.localAxisA = {1, 1, 0};
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), AllOf(HasSubstr("'rail'"), HasSubstr("localAxisA")));
        d.localAxisA = {1, 0, 0};
        d.hasLimits = true;
        d.lowerLimit = 2;
        d.upperLimit = 1;
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), HasSubstr("lowerLimit"));
    }
    {
        DistanceJointDef d;
        d.name = "rope";
        d.bodyA = a;
        d.bodyB = b;
        d.length = -1;
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), AllOf(HasSubstr("'rope'"), HasSubstr("length")));
        d.length = 1;
        d.minLength = -1;
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), HasSubstr("minLength"));
        d.minLength = 0;
        d.maxLength = -1;
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), HasSubstr("maxLength"));
        d.minLength = 2;
        d.maxLength = 1;
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), AllOf(HasSubstr("minLength"), HasSubstr("above maxLength")));
        d.minLength = 0;
        d.stiffness = -5;
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), HasSubstr("stiffness"));
    }
    {
        ConeTwistJointDef d;
        d.name = "shoulder";
        d.bodyA = a;
        d.bodyB = b;
        d.twistLower = Real(0.5);
        d.twistUpper = Real(-0.5);
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), AllOf(HasSubstr("'shoulder'"), HasSubstr("twistLower")));
        d.twistLower = Real(-0.5);
        d.swingLimit = 0;
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), HasSubstr("swingLimit"));
        d.swingLimit = 1;
        d.frictionTorque = -1;
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), HasSubstr("frictionTorque"));
    }
    {
        // Bodies: stale, missing, the same twice.
        const BodyId gone = world.createBody(sphereBody(1, {3, 1, 0}));
        world.destroyBody(gone);
        BallJointDef d;
        d.name = "socket";
        d.bodyA = a;
        d.bodyB = gone;
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }),
                    AllOf(HasSubstr("'socket'"), HasSubstr("bodyB"), HasSubstr("destroyed")));
        d.bodyB = BodyId{};
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), HasSubstr("bodyB"));
        d.bodyB = a;
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), HasSubstr("same body"));
        d.bodyA = gone;
        d.bodyB = b;
        EXPECT_THAT(errorOf([&] { world.createJoint(d); }), HasSubstr("bodyA"));
        // The world-space helpers check what they read.
        EXPECT_THAT(errorOf([&] { BallJointDef::fromWorld(world, a, gone, {}); }),
                    AllOf(HasSubstr("BallJointDef::fromWorld"), HasSubstr("bodyB")));
        EXPECT_THAT(errorOf([&] { HingeJointDef::fromWorld(world, a, b, {}, {0, 0, 0}); }),
                    AllOf(HasSubstr("HingeJointDef::fromWorld"), HasSubstr("axis")));
    }
    EXPECT_TRUE(world.joints().empty()) << "no joint was created by a refused definition";
}

}  // namespace
}  // namespace fulcrum
