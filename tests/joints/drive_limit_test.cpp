// Position drives with a force limit (JointSpring::maxForce, docs/joints.md):
// a stiff spring holds its target with at most maxForce. Checked against
// Newton's second law with the limit as the drive's force: a lever whose
// gravity torque m g r exceeds the limit starts to fall with
// alpha = (m g r - tau_max) / I, below it the drive holds it at the target; a
// slider lifting a load with F_max < m g sinks with a = g - F_max / m; the
// effort read-out never exceeds the limit. On hinges (scalar and SIMD lanes),
// sliders and six-DOF axes; the same bits on every SIMD path; a snapshot
// continues bit for bit, and an older format loads the limit as infinite.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "fulcrum/snapshot.hpp"
#include "joint_test_util.hpp"
#include "world/snapshot_versions.hpp"
#include "world/world_access.hpp"

using namespace fulcrum;
using namespace fulcrum::jointtest;

namespace {

using detail::SimdPath;

std::vector<SimdPath> allPaths() {
    std::vector<SimdPath> paths = {SimdPath::Scalar, SimdPath::Sse2};
    if (detail::avx2Available()) paths.push_back(SimdPath::Avx2);
    return paths;
}

// The lever: a 2 kg box 1 m long, its centre r = 0.5 m from the joint at the
// origin, horizontal along +x; gravity -y gives it the moment m g r about -z.
constexpr double kMass = 2, kLever = 0.5, kHalfThick = 0.03;
double leverInertia() {  // about the joint's z axis: I_cm + m r^2
    const double a = 2 * kLever, b = 2 * kHalfThick;
    return kMass * (a * a + b * b) / 12 + kMass * kLever * kLever;
}
double gravityMoment() { return kMass * kG * kLever; }

enum class LeverJoint { Hinge, SixDof };

// A lever held at angle 0 by a stiff position drive with torque limit tauMax.
JointId buildLever(World& world, LeverJoint kind, double tauMax, BodyId& lever) {
    lever = world.createBody(boxBody(Real(kMass), {Real(kLever), 0, 0}, {Real(kLever), Real(kHalfThick), Real(kHalfThick)}));
    JointSpring spring;
    spring.enabled = true;
    spring.target = 0;
    spring.stiffness = 2e4;
    spring.damping = 200;
    spring.maxForce = Real(tauMax);
    if (kind == LeverJoint::Hinge) {
        JointDef j = jointDef(JointType::Hinge, kWorldBody, lever, {0, 0, 0}, {0, 0, 1});
        j.spring = spring;
        return world.createJoint(j);
    }
    // Six-DOF: the frame's x along world x, y along world y, so rz turns about
    // world z; every other axis locked.
    JointDef j = jointDef(JointType::SixDof, kWorldBody, lever, {0, 0, 0}, {1, 0, 0});
    j.axisY = {0, 1, 0};
    j.axes[kAxisRotZ].mode = AxisMode::Free;
    j.axes[kAxisRotZ].spring = spring;
    return world.createJoint(j);
}

double leverAngle(const World& world, BodyId lever) {
    const Vec3 c = world.position(lever);
    return std::atan2(double(c.y), double(c.x));
}

double leverEffort(const World& world, JointId joint, LeverJoint kind) {
    return kind == LeverJoint::Hinge ? double(world.jointEffort(joint)) : double(world.sixDofReading(joint).effort[kAxisRotZ]);
}

const char* nameOf(LeverJoint kind) { return kind == LeverJoint::Hinge ? "hinge" : "six-DOF"; }

}  // namespace

// tau_max = 0.6 m g r: the drive saturates from the first sub-step and the
// lever falls with alpha = (m g r - tau_max) / I (the rod's angle stays
// under 0.05 rad over the 0.1 s measured, so cos(angle) differs from 1 by
// 1e-3: within 1 %); its effort reads tau_max and never more.
TEST(DriveLimit, SaturatedLeverFallsWithTheRemainingTorque) {
    for (const LeverJoint kind : {LeverJoint::Hinge, LeverJoint::SixDof}) {
        World world(worldDef(4));
        const double tauMax = 0.6 * gravityMoment();
        BodyId lever;
        const JointId joint = buildLever(world, kind, tauMax, lever);
        const int steps = 6;  // 0.1 s
        for (int i = 0; i < steps; ++i) {
            world.step(kDt);
            EXPECT_LE(std::fabs(leverEffort(world, joint, kind)), tauMax * (1 + 1e-5)) << nameOf(kind) << " step " << i;
        }
        const double alpha = (gravityMoment() - tauMax) / leverInertia();
        const double omega = double(world.angularVelocity(lever).z);
        EXPECT_NEAR(-omega / (steps * double(kDt)), alpha, 0.01 * alpha) << nameOf(kind);
        EXPECT_NEAR(std::fabs(leverEffort(world, joint, kind)), tauMax, 1e-4 * tauMax) << nameOf(kind);
    }
}

// tau_max = 1.5 m g r: the drive holds the lever at its target (sag m g r / k
// = 0.5 mrad), its effort m g r within 1 %.
TEST(DriveLimit, LeverBelowTheLimitIsHeld) {
    for (const LeverJoint kind : {LeverJoint::Hinge, LeverJoint::SixDof}) {
        World world(worldDef(4));
        BodyId lever;
        const JointId joint = buildLever(world, kind, 1.5 * gravityMoment(), lever);
        for (int i = 0; i < 120; ++i) world.step(kDt);
        EXPECT_NEAR(leverAngle(world, lever), -gravityMoment() / 2e4, 2e-4) << nameOf(kind);
        EXPECT_NEAR(std::fabs(leverEffort(world, joint, kind)), gravityMoment(), 0.01 * gravityMoment()) << nameOf(kind);
    }
}

// The hinge's spring row in SIMD lanes clamps as the scalar one: the falling
// lever gives the same bits on every path (and is wide off the scalar path).
TEST(DriveLimit, SaturatedHingeIsTheSameOnEverySimdPath) {
    std::vector<Vec3> reference;
    for (const SimdPath path : allPaths()) {
        World world(worldDef(4));
        detail::implOf(world).jointSolver.setSimdPath(path);
        BodyId lever;
        buildLever(world, LeverJoint::Hinge, 0.6 * gravityMoment(), lever);
        std::vector<Vec3> trace;
        for (int i = 0; i < 30; ++i) {
            world.step(kDt);
            trace.push_back(world.position(lever));
            trace.push_back(world.angularVelocity(lever));
        }
        EXPECT_EQ(detail::implOf(world).jointSolver.wideJointCount(), path == SimdPath::Scalar ? 0u : 1u);
        if (reference.empty()) {
            reference = trace;
            continue;
        }
        ASSERT_EQ(std::memcmp(trace.data(), reference.data(), trace.size() * sizeof(Vec3)), 0) << detail::simdPathName(path);
    }
}

namespace {

// A 3 kg block on a vertical slider from the world, held at 0 by a stiff
// position drive with force limit fMax (slider or six-DOF y axis).
JointId buildLift(World& world, bool sixDof, double fMax, BodyId& load) {
    load = world.createBody(boxBody(3, {0, 0, 0}, {Real(0.1), Real(0.1), Real(0.1)}));
    JointSpring spring;
    spring.enabled = true;
    spring.stiffness = 1e5;
    spring.damping = 500;
    spring.maxForce = Real(fMax);
    if (!sixDof) {
        JointDef j = jointDef(JointType::Slider, kWorldBody, load, {0, 0, 0}, {0, 1, 0});
        j.spring = spring;
        return world.createJoint(j);
    }
    JointDef j = jointDef(JointType::SixDof, kWorldBody, load, {0, 0, 0}, {1, 0, 0});
    j.axisY = {0, 1, 0};
    j.axes[kAxisY].mode = AxisMode::Free;
    j.axes[kAxisY].spring = spring;
    return world.createJoint(j);
}

}  // namespace

// F_max = m g / 2: the load sinks with a = g - F_max / m (1 %), the effort
// reads F_max and never more; F_max = 2 m g holds it within m g / k.
TEST(DriveLimit, SliderWithTooSmallAForceSinks) {
    for (const bool sixDof : {false, true}) {
        const double m = 3, fMax = 0.5 * m * kG;
        World world(worldDef(4));
        BodyId load;
        const JointId joint = buildLift(world, sixDof, fMax, load);
        const auto effort = [&] {
            return sixDof ? double(world.sixDofReading(joint).effort[kAxisY]) : double(world.jointEffort(joint));
        };
        const int steps = 12;
        for (int i = 0; i < steps; ++i) {
            world.step(kDt);
            EXPECT_LE(std::fabs(effort()), fMax * (1 + 1e-5)) << (sixDof ? "six-DOF" : "slider") << " step " << i;
        }
        const double a = kG - fMax / m;
        EXPECT_NEAR(-double(world.linearVelocity(load).y) / (steps * double(kDt)), a, 0.01 * a) << (sixDof ? "six-DOF" : "slider");
        EXPECT_NEAR(std::fabs(effort()), fMax, 1e-4 * fMax);

        World held(worldDef(4));
        BodyId heldLoad;
        const JointId heldJoint = buildLift(held, sixDof, 2 * m * kG, heldLoad);
        for (int i = 0; i < 120; ++i) held.step(kDt);
        EXPECT_NEAR(double(held.position(heldLoad).y), -m * kG / 1e5, 5e-5) << (sixDof ? "six-DOF" : "slider");
        const double heldEffort = sixDof ? double(held.sixDofReading(heldJoint).effort[kAxisY]) : double(held.jointEffort(heldJoint));
        EXPECT_NEAR(std::fabs(heldEffort), m * kG, 0.005 * m * kG);
    }
}

// Lowering the limit between steps: the warm-started impulse is cut to the
// new limit at once, so the next step's effort is within it.
TEST(DriveLimit, LoweredLimitAppliesAtTheNextStep) {
    World world(worldDef(4));
    BodyId lever;
    const JointId joint = buildLever(world, LeverJoint::Hinge, 2 * gravityMoment(), lever);
    for (int i = 0; i < 60; ++i) world.step(kDt);
    JointSpring s = world.jointDef(joint).spring;
    s.maxForce = Real(0.25 * gravityMoment());
    world.setJointSpring(joint, s);
    world.step(kDt);
    EXPECT_LE(std::fabs(double(world.jointEffort(joint))), 0.25 * gravityMoment() * (1 + 1e-5));
}

TEST(DriveLimit, BadLimitIsAnError) {
    World world(worldDef(4));
    BodyId lever;
    const JointId joint = buildLever(world, LeverJoint::Hinge, 1, lever);
    JointSpring s = world.jointDef(joint).spring;
    s.maxForce = -1;
    EXPECT_THROW(world.setJointSpring(joint, s), Error);
    s.maxForce = std::numeric_limits<Real>::quiet_NaN();
    EXPECT_THROW(world.setJointSpring(joint, s), Error);
}

namespace {

void buildDrivenScene(World& world, std::vector<BodyId>& bodies) {
    BodyId lever;
    buildLever(world, LeverJoint::Hinge, 0.6 * gravityMoment(), lever);
    bodies.push_back(lever);
    BodyId load;
    buildLift(world, false, 10, load);
    bodies.push_back(load);
    BodyId six;
    buildLift(world, true, 12, six);
    bodies.push_back(six);
}

std::vector<Real> stateOf(const World& world, const std::vector<BodyId>& bodies) {
    std::vector<Real> out;
    for (const BodyId b : bodies) {
        for (const Vec3 v : {world.position(b), world.linearVelocity(b), world.angularVelocity(b)}) {
            out.insert(out.end(), {v.x, v.y, v.z});
        }
        const Quat q = world.orientation(b);
        out.insert(out.end(), {q.w, q.x, q.y, q.z});
    }
    return out;
}

}  // namespace

// Saved mid-motion (the drives saturated), restored, and stepped on: the same
// bits as the world that never stopped; the limits come back.
TEST(DriveLimit, SnapshotContinuesBitForBit) {
    World world(worldDef(4));
    std::vector<BodyId> bodies;
    buildDrivenScene(world, bodies);
    for (int i = 0; i < 10; ++i) world.step(kDt);
    const std::vector<std::uint8_t> bytes = saveSnapshotToMemory(world);
    World restored = loadSnapshotFromMemory(bytes);
    const std::vector<JointId> before = world.joints(), after = restored.joints();
    ASSERT_EQ(before.size(), after.size());
    for (std::size_t i = 0; i < before.size(); ++i) {
        EXPECT_EQ(world.jointDef(before[i]).spring.maxForce, restored.jointDef(after[i]).spring.maxForce);
        EXPECT_EQ(world.jointDef(before[i]).axes[kAxisY].spring.maxForce, restored.jointDef(after[i]).axes[kAxisY].spring.maxForce);
    }
    EXPECT_EQ(restored.jointDef(after[2]).axes[kAxisY].spring.maxForce, Real(12));
    for (int i = 0; i < 20; ++i) {
        world.step(kDt);
        restored.step(kDt);
    }
    const std::vector<Real> a = stateOf(world, bodies), b = stateOf(restored, bodies);
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(Real)), 0);
}

// A version-8 file has no limits: they load as infinite (and a world whose
// drives are unlimited round-trips through it).
TEST(DriveLimit, OlderSnapshotLoadsUnlimited) {
    World world(worldDef(4));
    std::vector<BodyId> bodies;
    buildDrivenScene(world, bodies);
    const std::vector<std::uint8_t> bytes = detail::saveSnapshotAsVersion(world, 8);
    World old = loadSnapshotFromMemory(bytes);
    int checked = 0;
    for (const JointId j : old.joints()) {
        const JointDef& d = old.jointDef(j);
        EXPECT_TRUE(std::isinf(d.spring.maxForce));
        for (const SixDofAxis& s : d.axes) EXPECT_TRUE(std::isinf(s.spring.maxForce));
        ++checked;
    }
    EXPECT_EQ(checked, 3);
}
