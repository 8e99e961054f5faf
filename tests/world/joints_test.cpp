// Joints: validated and stored (not yet enforced by a solver); jointError is the
// geometric violation in metres, checked here against hand-computed geometry.
#include <gmock/gmock.h>

#include <limits>

#include "dynamics/test_scenes.hpp"

using namespace fulcrum;
using namespace fulcrum::test;
using ::testing::AllOf;
using ::testing::HasSubstr;

namespace {

constexpr Real kNaN = std::numeric_limits<Real>::quiet_NaN();

struct Pair {
    World world{worldDef(Integrator::SemiImplicitEuler, 4, {0, 0, 0})};
    BodyId a, b;
    Pair() {
        a = world.createBody(pointMass(1, {0, 0, 0}, {}, "a"));
        b = world.createBody(pointMass(1, {1, 0, 0}, {}, "b"));
    }
    JointDef def(JointType type) const {
        JointDef j;
        j.name = "joint-under-test";  // > 15 chars: GCC 12 -Wrestrict misfires on short-string assignment here
        j.type = type;
        j.bodyA = a;
        j.bodyB = b;
        j.anchor = {Real(0.5), 0, 0};
        j.anchorB = {1, 0, 0};
        j.axis = {1, 0, 0};
        return j;
    }
    std::string error(const JointDef& j) { return errorOf([&] { world.createJoint(j); }); }
};

}  // namespace

TEST(Joints, Validation) {
    Pair p;
    JointDef j = p.def(JointType::Hinge);
    j.bodyB = kWorldBody;
    EXPECT_THAT(p.error(j), AllOf(HasSubstr("joint 'joint-under-test'"), HasSubstr("bodyB")));
    j = p.def(JointType::Ball);
    j.bodyA = p.b;
    EXPECT_THAT(p.error(j), HasSubstr("same body"));
    j = p.def(JointType::Ball);
    j.bodyA = BodyId{p.a.index, p.a.generation + 1};
    EXPECT_THAT(p.error(j), AllOf(HasSubstr("bodyA"), HasSubstr("destroyed")));
    for (JointType t : {JointType::Hinge, JointType::Slider, JointType::ConeTwist}) {
        j = p.def(t);
        j.axis = {0, 0, 0};
        EXPECT_THAT(p.error(j), AllOf(HasSubstr("axis"), HasSubstr("non-zero"))) << toString(t);
        j.axis = {kNaN, 1, 0};
        EXPECT_THAT(p.error(j), HasSubstr("axis")) << toString(t);
    }
    j = p.def(JointType::Hinge);
    j.hasLimits = true;
    j.lowerLimit = 1;
    j.upperLimit = -1;
    EXPECT_THAT(p.error(j), AllOf(HasSubstr("lowerLimit"), HasSubstr("upperLimit")));
    j = p.def(JointType::Distance);
    j.minLength = kNaN;
    EXPECT_THAT(p.error(j), HasSubstr("minLength"));
    j = p.def(JointType::Distance);
    j.minLength = 2;
    j.maxLength = 1;
    EXPECT_THAT(p.error(j), AllOf(HasSubstr("minLength"), HasSubstr("above maxLength")));
    j = p.def(JointType::Distance);
    j.maxLength = Real(0.2);  // min = -1: the creation distance (0.5 m) > 0.2
    EXPECT_THAT(p.error(j), HasSubstr("distance at creation"));
    j = p.def(JointType::Distance);
    j.stiffness = -1;
    EXPECT_THAT(p.error(j), HasSubstr("stiffness"));
    j = p.def(JointType::Distance);
    j.damping = -1;
    EXPECT_THAT(p.error(j), HasSubstr("damping"));
    j = p.def(JointType::Fixed);
    j.breakForce = 0;
    EXPECT_THAT(p.error(j), HasSubstr("breakForce"));
    j = p.def(JointType::Fixed);
    j.breakTorque = kNaN;
    EXPECT_THAT(p.error(j), HasSubstr("breakTorque"));
    j = p.def(JointType::Ball);
    j.anchor.y = kNaN;
    EXPECT_THAT(p.error(j), HasSubstr("anchor"));
    j = p.def(JointType::Hinge);
    j.motor.maxForce = -1;
    EXPECT_THAT(p.error(j), HasSubstr("motor.maxForce"));
    j = p.def(JointType::ConeTwist);
    j.twistLower = 1;
    j.twistUpper = 0;
    EXPECT_THAT(p.error(j), HasSubstr("twistLower"));
    j = p.def(JointType::ConeTwist);
    j.swingLimit = -Real(0.1);
    EXPECT_THAT(p.error(j), HasSubstr("swingLimit"));
    EXPECT_TRUE(p.world.joints().empty());
}

TEST(Joints, ErrorIsTheGeometricViolation) {
    Pair p;
    const JointId ball = p.world.createJoint(p.def(JointType::Ball));
    const JointId slider = p.world.createJoint(p.def(JointType::Slider));
    JointDef rope = p.def(JointType::Distance);
    rope.anchor = {0, 0, 0};
    rope.minLength = 0;
    rope.maxLength = Real(1.5);
    const JointId distance = p.world.createJoint(rope);
    EXPECT_EQ(p.world.name(ball), "joint-under-test");
    EXPECT_EQ(p.world.jointDef(slider).type, JointType::Slider);
    EXPECT_EQ(p.world.joints().size(), 3u);
    EXPECT_NEAR(p.world.jointError(ball), 0, 1e-6);
    EXPECT_NEAR(p.world.jointError(slider), 0, 1e-6);
    EXPECT_NEAR(p.world.jointError(distance), 0, 1e-6);

    // Slide b along the axis by 0.3 m: the slider is fine, the ball joint is off by
    // 0.3 m, the rope (1.3 m < 1.5 m) is slack.
    p.world.setTransform(p.b, {Real(1.3), 0, 0}, {});
    EXPECT_NEAR(p.world.jointError(ball), 0.3, 1e-6);
    EXPECT_NEAR(p.world.jointError(slider), 0, 1e-6);
    EXPECT_NEAR(p.world.jointError(distance), 0, 1e-6);
    // Then 0.4 m off the axis: slider error 0.4; ball |(0.3, 0.4)| = 0.5; rope |(1.3, 0.4)| - 1.5 < 0.
    p.world.setTransform(p.b, {Real(1.3), Real(0.4), 0}, {});
    EXPECT_NEAR(p.world.jointError(slider), 0.4, 1e-6);
    EXPECT_NEAR(p.world.jointError(ball), 0.5, 1e-6);
    // Rotate b by 90 deg about z: its anchor (-0.5, 0, 0) in b's frame now sits at (1.3, -0.1, 0).
    p.world.setTransform(p.b, {Real(1.3), Real(0.4), 0}, Quat::fromAxisAngle({0, 0, 1}, Real(kPi / 2)));
    EXPECT_NEAR(p.world.jointError(ball), std::sqrt(0.8 * 0.8 + 0.1 * 0.1), 1e-5);
    // Stretch the rope to 2 m: error 0.5 m.
    p.world.setTransform(p.b, {2, 0, 0}, {});
    EXPECT_NEAR(p.world.jointError(distance), 0.5, 1e-6);

    // The joint solver enforces joints: one step pulls the over-stretched rope
    // in (its 0.5 m error shrinks; tests/joints checks the solver in detail).
    p.world.step(Real(1) / 60);
    EXPECT_LT(p.world.jointError(distance), 0.5);

    // Destroying a body destroys its joints.
    p.world.destroyBody(p.a);
    EXPECT_FALSE(p.world.isValid(ball));
    EXPECT_TRUE(p.world.joints().empty());
    EXPECT_THAT(errorOf([&] { (void)p.world.jointError(ball); }), HasSubstr("stale JointId"));
}

TEST(Joints, WorldAnchoredJoint) {
    // bodyA null: the anchor is a fixed world point. Moving b 1 m down gives 1 m error.
    Pair p;
    JointDef j = p.def(JointType::Ball);
    j.bodyA = kWorldBody;
    j.anchor = {1, 1, 0};
    const JointId id = p.world.createJoint(j);
    p.world.setTransform(p.b, {1, -1, 0}, {});
    EXPECT_NEAR(p.world.jointError(id), 1.0, 1e-6);
    p.world.destroyJoint(id);
    EXPECT_FALSE(p.world.isValid(id));
}
