// The Recorder against a real World: frames at the requested rate, transforms
// and energy as the World reports them, and motion that matches the analytic
// free fall to the integrator's known error.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cmath>
#include <filesystem>

#include "fulcrum/recording.hpp"

using namespace fulcrum;
using namespace fulcrum::io;

namespace {

namespace fs = std::filesystem;

struct Drop {
    World world;
    BodyId ground, ball, crate;
    JointId hinge;

    Drop() : world(WorldDef{.gravity = {0, Real(-9.81), 0}, .integrator = Integrator::SemiImplicitEuler, .substeps = 1,
                            .solverIterations = 1, .sleeping = false, .threads = 1}) {
        BodyDef g;
        g.name = "ground";
        g.type = BodyType::Static;
        g.shape = Shape::box({10, Real(0.5), 10});
        g.position = {0, -100, 0};  // far below: the test is about free flight
        ground = world.createBody(g);
        BodyDef b;
        b.name = "ball";
        b.shape = Shape::sphere(Real(0.5));
        b.position = {0, 10, 0};
        b.linearVelocity = {1, 0, 0};
        ball = world.createBody(b);
        BodyDef c;
        c.name = "crate";
        c.shape = Shape::box({Real(0.3), Real(0.3), Real(0.3)});
        c.position = {3, 5, 0};
        c.orientation = Quat::fromAxisAngle({0, 1, 0}, Real(0.4));
        c.angularVelocity = {0, 2, 0};
        crate = world.createBody(c);
        JointDef j;
        j.name = "hinge";
        j.type = JointType::Ball;
        j.bodyA = ball;
        j.bodyB = crate;
        j.anchor = {Real(1.5), Real(7.5), 0};
        hinge = world.createJoint(j);
    }
};

// Semi-implicit Euler with a single sub-step gives y_n = y0 - g h^2 n(n+1)/2:
// the recorded heights must be exactly that sequence (to float rounding), which
// differs from the analytic y0 - g t^2 / 2 by g h t / 2.
TEST(Recorder, CapturesEveryStepOfAFreeFall) {
    Drop d;
    // The hinge would couple ball and crate; without it the ball is in free flight.
    d.world.destroyJoint(d.hinge);
    Recorder recorder(d.world, {.captureInterval = 0, .contacts = true, .bounds = true, .title = "drop"});
    const Real h = Real(1) / 60;
    const int steps = 60;
    recorder.capture(d.world);
    for (int i = 0; i < steps; ++i) {
        d.world.step(h);
        recorder.capture(d.world);
    }
    const Recording& rec = recorder.recording();
    ASSERT_EQ(rec.frameCount(), static_cast<std::size_t>(steps + 1));
    ASSERT_EQ(rec.bodies.size(), 3u);
    EXPECT_EQ(rec.bodies[1].name, "ball");
    EXPECT_EQ(rec.joints.size(), 0u);
    EXPECT_NO_THROW(rec.validate());
    for (std::size_t f = 0; f < rec.frameCount(); ++f) {
        const double n = static_cast<double>(f);
        const double hh = static_cast<double>(h);
        EXPECT_NEAR(rec.times[f], n * hh, 1e-5);
        const double expected = 10 - 9.81 * hh * hh * n * (n + 1) / 2;
        EXPECT_NEAR(rec.transform(f, 1).p.y, expected, 2e-4) << "frame " << f;
        EXPECT_NEAR(rec.transform(f, 1).p.x, n * hh, 1e-4);
        // Energy as the world reports it is conserved by free flight to O(h) of the integrator.
        EXPECT_NEAR(rec.energy[f].total, rec.energy[0].total, 0.02 * std::fabs(rec.energy[0].total));
        // The AABB recorded is the sphere's around its centre.
        EXPECT_NEAR(rec.bounds[f * 3 + 1].max.y - rec.transform(f, 1).p.y, 0.5, 1e-5);
    }
    // The crate spins at 2 rad/s about y: orientation angle grows by 2 h per frame.
    const Quat q0 = rec.transform(0, 2).q, q1 = rec.transform(steps, 2).q;
    const Real turned = length(toRotationVector(q1 * conjugate(q0)));
    EXPECT_NEAR(turned, 2 * h * steps, 1e-3);
    // The final frame is the world's state.
    EXPECT_EQ(rec.transform(steps, 1).p, d.world.position(d.ball));
}

TEST(Recorder, CaptureIntervalThinsFrames) {
    Drop d;
    Recorder recorder(d.world, {.captureInterval = 0.1, .contacts = false, .bounds = false, .title = "thin"});
    const Real h = Real(1) / 60;
    recorder.capture(d.world);
    for (int i = 0; i < 120; ++i) {
        d.world.step(h);
        recorder.capture(d.world);
    }
    const Recording& rec = recorder.recording();
    // 2 s at one frame per 0.1 s (6 steps): frames at 0, 0.1, ..., 2.0.
    EXPECT_EQ(rec.frameCount(), 21u);
    for (std::size_t f = 1; f < rec.frameCount(); ++f) EXPECT_NEAR(rec.times[f] - rec.times[f - 1], 0.1, 1e-4);
    EXPECT_TRUE(rec.bounds.empty());
    EXPECT_NO_THROW(rec.validate());
}

TEST(Recorder, JointAnchorsBecomeBodyLocal) {
    Drop d;
    Recorder recorder(d.world);
    recorder.capture(d.world);
    d.world.step(Real(0.01));
    recorder.capture(d.world);
    const Recording& rec = recorder.recording();
    ASSERT_EQ(rec.joints.size(), 1u);
    const RecordedJoint& j = rec.joints[0];
    EXPECT_EQ(j.name, "hinge");
    EXPECT_EQ(j.bodyA, 1);
    EXPECT_EQ(j.bodyB, 2);
    // At capture start both local anchors map back to the world anchor given at creation.
    const Vec3 anchor{Real(1.5), Real(7.5), 0};
    EXPECT_NEAR(distance(transformPoint(rec.transform(0, 1), j.localAnchorA), anchor), 0, 1e-5);
    EXPECT_NEAR(distance(transformPoint(rec.transform(0, 2), j.localAnchorB), anchor), 0, 1e-5);
    ASSERT_EQ(rec.jointErrors.size(), 2u);
    EXPECT_EQ(rec.jointErrors[1], d.world.jointError(d.hinge));
}

TEST(Recorder, DestroyedBodiesHoldTheirLastPose) {
    Drop d;
    Recorder recorder(d.world);
    recorder.capture(d.world);
    d.world.step(Real(0.01));
    recorder.capture(d.world);
    const Transform last = recorder.recording().transform(1, 2);
    d.world.destroyJoint(d.hinge);
    d.world.destroyBody(d.crate);
    d.world.step(Real(0.01));
    recorder.capture(d.world);
    EXPECT_EQ(recorder.recording().transform(2, 2), last);
    EXPECT_FALSE(recorder.recording().isAwake(2, 2));
    EXPECT_NO_THROW(recorder.recording().validate());
}

TEST(Recorder, WritesByExtension) {
    Drop d;
    Recorder recorder(d.world);
    recorder.capture(d.world);
    for (int i = 0; i < 10; ++i) {
        d.world.step(Real(0.02));
        recorder.capture(d.world);
    }
    const fs::path dir = fs::temp_directory_path();
    const fs::path glb = dir / "fulcrum_recorder_test.glb", html = dir / "fulcrum_recorder_test.HTML";
    recorder.write(glb);
    recorder.write(html);
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, glb.string())) << err;
    ASSERT_EQ(model.animations.size(), 1u);
    EXPECT_EQ(model.animations[0].channels.size(), 4u);  // translation + rotation for ball and crate
    EXPECT_GT(fs::file_size(html), 150000u);              // the viewer bundle is inside (deflated, ~200 KB)
    fs::remove(glb);
    fs::remove(html);
    try {
        recorder.write(dir / "run.obj");
        FAIL() << "unknown extension accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(".obj"), std::string::npos) << e.what();
    }
    EXPECT_THROW(Recorder(d.world, {.captureInterval = -1, .contacts = true, .bounds = true, .title = "x"}), Error);
}

}  // namespace
