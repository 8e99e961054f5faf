// The joint example of docs/api.md ("Joints"), compiled and run as a test
// (keep them in sync). Physics check: the motor (1 rad/s, up to 50 N m)
// turns the door until the upper limit holds it: after 3 s the hinge angle
// is the limit, 1.5 rad (within 0.02 rad: the limit row is soft once
// reached), and the weight still hangs from the door's corner (joint error
// below the 5 mm projection slop).
#include <gtest/gtest.h>

// ---- example begins
#include <fulcrum/fulcrum.hpp>

double openDoor(double& weightError) {
    using namespace fulcrum;
    World world;

    BodyDef door;
    door.name = "door";
    door.shape = Shape::box({0.4f, 1.0f, 0.02f});
    door.mass = 10;
    door.position = {0.4f, 1, 0};
    const BodyId doorId = world.createBody(door);

    // In world space: the hinge line is the door's left edge, x = 0.
    HingeJointDef hinge = HingeJointDef::fromWorld(world, kWorldBody, doorId, {0, 1, 0}, {0, 1, 0});
    hinge.name = "door hinge";
    hinge.hasLimits = true;
    hinge.lowerLimit = 0;
    hinge.upperLimit = 1.5f;                       // rad
    hinge.motor = {true, 1.0f, 50};                // 1 rad/s, at most 50 N m
    const JointId hingeId = world.createJoint(hinge);

    // In each body's own frame (body axes, from its centre of mass): a weight
    // hanging 0.5 m below the door's free bottom corner.
    BodyDef weight;
    weight.shape = Shape::sphere(0.05f);
    weight.mass = 1;
    weight.position = {0.8f, -0.5f, 0};
    BallJointDef rope;
    rope.name = "weight";
    rope.bodyA = doorId;
    rope.bodyB = world.createBody(weight);
    rope.localAnchorA = {0.4f, -1, 0};             // the door's free bottom corner
    rope.localAnchorB = {0, 0.5f, 0};              // 0.5 m above the weight's centre
    const JointId ropeId = world.createJoint(rope);

    for (int i = 0; i < 180; ++i) world.step(1.0f / 60);
    weightError = world.jointError(ropeId);
    return world.jointPosition(hingeId);           // the door's angle, rad
}
// ---- example ends

TEST(ApiExample, OpenDoor) {
    double weightError = 1;
    EXPECT_NEAR(openDoor(weightError), 1.5, 0.02);  // measured 1.5002 rad
    EXPECT_LT(weightError, 0.005);  // measured 0.15 mm
}
