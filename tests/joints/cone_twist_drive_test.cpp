// The cone-twist drive (ConeTwistDrive): a target orientation held against
// gravity, its torque against statics, a PD drive's settling, bad input.
#include "joints/joint_test_util.hpp"

using namespace fulcrum;
using namespace fulcrum::jointtest;

namespace {

// A ball on a horizontal lever of length L from a cone-twist at the origin
// (twist axis along the lever, limits out of the way).
struct Lever {
    World world{worldDef()};
    BodyId bob;
    JointId joint;
    Lever(double L, double m) {
        bob = world.createBody(sphereBody(Real(m), {Real(L), 0, 0}, Real(0.05)));
        JointDef j = jointDef(JointType::ConeTwist, kWorldBody, bob, {0, 0, 0}, {1, 0, 0});
        j.swingLimit = Real(kPi);
        j.twistLower = Real(-kPi);
        j.twistUpper = Real(kPi);
        joint = world.createJoint(j);
    }
};

}  // namespace

// A rigid drive (infinite stiffness) holds the lever at its rest pose: the
// torque it applies is m g L about z within 1 %, and the lever stays level (1 mrad).
TEST(ConeTwistDrive, HoldsTheTargetWithTheGravityTorque) {
    const double L = 0.8, m = 2;
    Lever p(L, m);
    ConeTwistDrive drive;
    drive.enabled = true;
    drive.stiffness = std::numeric_limits<Real>::infinity();
    p.world.setConeTwistDrive(p.joint, drive);
    for (int i = 0; i < 120; ++i) p.world.step(kDt);
    const Vec3 torque = p.world.jointReactionTorque(p.joint);
    EXPECT_NEAR(double(torque.z), m * kG * L, 0.01 * m * kG * L);
    EXPECT_LT(std::fabs(double(p.world.position(p.bob).y)) / L, 1e-3);
}

// A target 30 degrees up about z, PD: the lever settles there, sagging by
// m g L cos(theta) / k (within 10 % of the sag), and the drive torque is m g L cos(theta) within 1 %.
TEST(ConeTwistDrive, PdDriveSettlesAtTheTarget) {
    const double L = 0.8, m = 2, k = 400, theta = kPi / 6;
    Lever p(L, m);
    ConeTwistDrive drive;
    drive.enabled = true;
    drive.target = Quat::fromAxisAngle({0, 0, 1}, Real(theta));
    drive.stiffness = Real(k);
    drive.damping = Real(20);
    p.world.setConeTwistDrive(p.joint, drive);
    for (int i = 0; i < 600; ++i) p.world.step(kDt);
    const Vec3 x = p.world.position(p.bob);
    const double angle = std::atan2(double(x.y), double(x.x));
    const double torque = m * kG * L * std::cos(angle);
    const double sag = torque / k;
    EXPECT_NEAR(theta - angle, sag, 0.1 * sag);
    EXPECT_NEAR(double(p.world.jointReactionTorque(p.joint).z), torque, 0.01 * torque);
}

// maxTorque caps the drive: below m g L the lever falls.
TEST(ConeTwistDrive, MaxTorqueCaps) {
    const double L = 0.8, m = 2;
    Lever p(L, m);
    ConeTwistDrive drive;
    drive.enabled = true;
    drive.stiffness = std::numeric_limits<Real>::infinity();
    drive.maxTorque = Real(0.5 * m * kG * L);
    p.world.setConeTwistDrive(p.joint, drive);
    for (int i = 0; i < 30; ++i) p.world.step(kDt);
    EXPECT_LT(double(p.world.position(p.bob).y), -0.05);
}

TEST(ConeTwistDrive, BadInputNamesTheField) {
    Lever p(1, 1);
    ConeTwistDrive drive;
    drive.enabled = true;
    drive.stiffness = -1;
    EXPECT_THAT(errorOf([&] { p.world.setConeTwistDrive(p.joint, drive); }), testing::HasSubstr("drive.stiffness"));
    drive.stiffness = 1;
    drive.target = Quat{std::numeric_limits<Real>::quiet_NaN(), 0, 0, 0};
    EXPECT_THAT(errorOf([&] { p.world.setConeTwistDrive(p.joint, drive); }), testing::HasSubstr("drive.target"));
    drive.target = Quat{};
    drive.maxTorque = 0;
    EXPECT_THAT(errorOf([&] { p.world.setConeTwistDrive(p.joint, drive); }), testing::HasSubstr("drive.maxTorque"));
    const BodyId other = p.world.createBody(sphereBody(1, {3, 0, 0}));
    const JointId hinge = p.world.createJoint(jointDef(JointType::Hinge, kWorldBody, other, {3, 0, 0}));
    EXPECT_THAT(errorOf([&] { p.world.setConeTwistDrive(hinge, ConeTwistDrive{}); }), testing::HasSubstr("only cone-twist"));
}
