// The six-DOF joint against the joints it generalises and against analytic
// results: all axes locked as the fixed joint, one free angle as a hinge
// pendulum, one free linear axis on a spring, limits, motors, and bad input.
#include <algorithm>

#include "fulcrum/snapshot.hpp"
#include "joints/joint_test_util.hpp"
#include "solver/joints/six_dof.hpp"
#include "world/snapshot_versions.hpp"

using namespace fulcrum;
using namespace fulcrum::jointtest;

namespace {

SixDofAxes axesAll(AxisMode mode) {
    SixDofAxes axes;
    for (SixDofAxis& a : axes) a.mode = mode;
    return axes;
}

JointDef sixDof(BodyId a, BodyId b, Vec3 anchor, const SixDofAxes& axes) {
    JointDef j = jointDef(JointType::SixDof, a, b, anchor, {1, 0, 0});
    j.axisY = {0, 1, 0};
    j.axes = axes;
    return j;
}

double angleBetween(const Quat& p, const Quat& q) {
    return double(length(toRotationVector(q * conjugate(p))));
}

}  // namespace

// A box hanging off-centre from the world, spun and pushed: with every axis
// locked it follows the fixed joint's motion within 1 mm and 1 mrad over 2 s.
TEST(SixDof, AllLockedIsTheFixedJoint) {
    const auto run = [](bool six) {
        World world(worldDef());
        BodyDef d = boxBody(3, {Real(0.4), Real(-0.3), Real(0.1)}, {Real(0.3), Real(0.1), Real(0.2)});
        d.linearVelocity = {1, 0, -1};
        d.angularVelocity = {0.5, 2, -1};
        const BodyId box = world.createBody(d);
        const Vec3 anchor{0, 0, 0};
        world.createJoint(six ? sixDof(kWorldBody, box, anchor, axesAll(AxisMode::Locked))
                              : jointDef(JointType::Fixed, kWorldBody, box, anchor));
        for (int i = 0; i < 120; ++i) world.step(kDt);
        return std::pair{world.position(box), world.orientation(box)};
    };
    const auto fixed = run(false), six = run(true);
    EXPECT_LT(double(length(six.first - fixed.first)), 1e-3);
    EXPECT_LT(angleBetween(six.second, fixed.second), 1e-3);
    EXPECT_LT(double(length(six.first - Vec3{Real(0.4), Real(-0.3), Real(0.1)})), 1e-3);
}

// A ball on a rigid lever, its rotation about z free (every other axis locked):
// a compound pendulum, period 2 pi sqrt(I / (m g L)) at 3 degrees (finite
// amplitude factor included), within 1 %; the angle read-out is the swing.
TEST(SixDof, OneFreeAngleIsAHingePendulum) {
    World world(worldDef());
    const double L = 1, r = 0.1, m = 2, theta0 = 3 * kPi / 180;
    const Vec3 p{Real(L * std::sin(theta0)), Real(-L * std::cos(theta0)), 0};
    const BodyId bob = world.createBody(sphereBody(Real(m), p, Real(r)));
    SixDofAxes axes = axesAll(AxisMode::Locked);
    axes[kAxisRotZ].mode = AxisMode::Free;
    const JointId j = world.createJoint(sixDof(kWorldBody, bob, {0, 0, 0}, axes));
    const double I = 0.4 * m * r * r + m * L * L;
    const double expected = pendulumPeriod(I / (m * L), theta0);
    const double T = measurePeriod(world, [&] { return double(world.position(bob).x); }, 6, 2000);
    EXPECT_NEAR(T, expected, 0.01 * expected);
    EXPECT_LT(world.jointError(j), Real(1e-3));
    EXPECT_LT(std::fabs(double(world.position(bob).z)), 1e-4);
    // The angle about z is the swing from the start: -theta0 .. theta0 - theta0.
    const SixDofReading s = world.sixDofReading(j);
    EXPECT_LE(double(s.position[kAxisRotZ]), 1e-3);
    EXPECT_GE(double(s.position[kAxisRotZ]), -2 * theta0 - 1e-3);
}

// One free linear axis with a spring (no gravity): period 2 pi sqrt(m / k) within 1 %.
TEST(SixDof, LinearSpringPeriod) {
    World world(worldDef(4, {0, 0, 0}));
    const double m = 2, k = 200;
    const BodyId block = world.createBody(boxBody(Real(m), {0, 0, 0}, {Real(0.1), Real(0.1), Real(0.1)}));
    SixDofAxes axes = axesAll(AxisMode::Locked);
    axes[kAxisX].mode = AxisMode::Free;
    axes[kAxisX].spring = {true, Real(-0.1), Real(k), 0};
    const JointId j = world.createJoint(sixDof(kWorldBody, block, {0, 0, 0}, axes));
    const double T = measurePeriod(world, [&] { return double(world.position(block).x) + 0.1; }, 6, 2000);
    const double expected = 2 * kPi * std::sqrt(m / k);
    EXPECT_NEAR(T, expected, 0.01 * expected);
    EXPECT_LT(std::hypot(double(world.position(block).y), double(world.position(block).z)), 1e-4);
    EXPECT_NEAR(double(world.sixDofReading(j).position[kAxisX]), double(world.position(block).x), 1e-5);
}

// A block falling onto its y limit stops there (overshoot below 1 mm); a
// lever swung against its z angle limit stops there (below 5 mrad).
TEST(SixDof, LimitsHold) {
    World world(worldDef());
    const BodyId block = world.createBody(boxBody(1, {0, 0, 0}, {Real(0.1), Real(0.1), Real(0.1)}));
    SixDofAxes axes = axesAll(AxisMode::Locked);
    axes[kAxisY] = {AxisMode::Limited, Real(-0.2), Real(0.2), {}, {}};
    const JointId slide = world.createJoint(sixDof(kWorldBody, block, {0, 0, 0}, axes));

    BodyDef d = sphereBody(1, {1, 0, 3});
    d.angularVelocity = {0, 0, -4};
    d.linearVelocity = {0, -4, 0};
    const BodyId bob = world.createBody(d);
    SixDofAxes hinge = axesAll(AxisMode::Locked);
    hinge[kAxisRotZ] = {AxisMode::Limited, Real(-0.5), Real(0.5), {}, {}};
    const JointId lever = world.createJoint(sixDof(kWorldBody, bob, {0, 0, 3}, hinge));
    double worstY = 0, worstAngle = 0, lowest = 0;
    for (int i = 0; i < 180; ++i) {
        world.step(kDt);
        const SixDofReading a = world.sixDofReading(slide), b = world.sixDofReading(lever);
        worstY = std::max(worstY, -0.2 - double(a.position[kAxisY]));
        worstAngle = std::max(worstAngle, -0.5 - double(b.position[kAxisRotZ]));
        lowest = std::min(lowest, double(b.position[kAxisRotZ]));
    }
    EXPECT_LT(worstY, 1e-3);
    EXPECT_LT(worstAngle, 5e-3);
    EXPECT_LT(lowest, -0.45);  // it did reach the limit
    EXPECT_NEAR(double(world.position(block).y), -0.2, 1e-3);
}

// Velocity motors reach their target speeds: 2 rad/s about z, 0.5 m/s along x
// (within 1 %), against a load they can overcome.
TEST(SixDof, VelocityMotorsReachTheirSpeed) {
    World world(worldDef(4, {0, 0, 0}));
    const BodyId wheel = world.createBody(boxBody(2, {0, 0, 0}, {Real(0.3), Real(0.3), Real(0.1)}));
    SixDofAxes axes = axesAll(AxisMode::Locked);
    axes[kAxisRotZ].mode = AxisMode::Free;
    axes[kAxisRotZ].motor = {true, 2, 50};
    axes[kAxisX].mode = AxisMode::Free;
    axes[kAxisX].motor = {true, Real(0.5), 100};
    const JointId j = world.createJoint(sixDof(kWorldBody, wheel, {0, 0, 0}, axes));
    for (int i = 0; i < 120; ++i) world.step(kDt);
    const SixDofReading s = world.sixDofReading(j);
    EXPECT_NEAR(double(s.velocity[kAxisRotZ]), 2, 0.02);
    EXPECT_NEAR(double(s.velocity[kAxisX]), 0.5, 0.005);
    EXPECT_NEAR(double(world.angularVelocity(wheel).z), 2, 0.02);
    EXPECT_NEAR(double(world.linearVelocity(wheel).x), 0.5, 0.005);
}

// Six-DOF joints with their linear axes locked form trees for the exact
// solver: a 6-link chain whose angles are free about z hangs with its
// anchors together (below 0.1 mm) under a heavy load. Released level, it
// swings down and whips: the worst error over the whole run stays as small
// as with every pass factored (1.2 mm), which a factorization kept too long
// breaks first under this 100:1 load (kept up to 0.1 rad of turn, the
// schedule before issue 21: 45 mm; JointTreeSolver::kGuardTurn).
TEST(SixDof, ChainOfPointLockedJointsHolds) {
    World world(worldDef());
    BodyId prev = kWorldBody;
    SixDofAxes axes = axesAll(AxisMode::Locked);
    axes[kAxisRotZ].mode = AxisMode::Free;
    std::vector<JointId> joints;
    for (int i = 0; i < 6; ++i) {
        const Real mass = i == 5 ? Real(50) : Real(0.5);
        const BodyId link = world.createBody(boxBody(mass, {Real(0.5) * Real(i) + Real(0.25), 0, 0}, {Real(0.25), Real(0.05), Real(0.05)}));
        joints.push_back(world.createJoint(sixDof(prev, link, {Real(0.5) * Real(i), 0, 0}, axes)));
        prev = link;
    }
    double worst = 0;
    for (int i = 0; i < 240; ++i) {
        world.step(kDt);
        for (const JointId j : joints) worst = std::max(worst, double(world.jointError(j)));
    }
    EXPECT_LT(worst, 2e-3);
    for (const JointId j : joints) EXPECT_LT(world.jointError(j), Real(1e-4)) << world.name(j);
}

// Bad input names the field: lower above upper, NaN, negative stiffness, a
// y angle limit at the gimbal lock, a mode change after creation.
TEST(SixDof, BadInputNamesTheField) {
    World world(worldDef());
    const BodyId box = world.createBody(boxBody(1, {0, 0, 0}, {Real(0.1), Real(0.1), Real(0.1)}));
    SixDofAxes axes = axesAll(AxisMode::Locked);
    axes[kAxisX] = {AxisMode::Limited, 1, -1, {}, {}};
    EXPECT_THAT(errorOf([&] { world.createJoint(sixDof(kWorldBody, box, {}, axes)); }), testing::HasSubstr("axes[x].lower"));
    axes = axesAll(AxisMode::Free);
    axes[kAxisRotX].motor = {true, std::numeric_limits<Real>::quiet_NaN(), 1};
    EXPECT_THAT(errorOf([&] { world.createJoint(sixDof(kWorldBody, box, {}, axes)); }),
                testing::HasSubstr("axes[rx].motor.speed"));
    axes = axesAll(AxisMode::Free);
    axes[kAxisZ].spring = {true, 0, -5, 0};
    EXPECT_THAT(errorOf([&] { world.createJoint(sixDof(kWorldBody, box, {}, axes)); }),
                testing::HasSubstr("axes[z].spring.stiffness"));
    axes = axesAll(AxisMode::Free);
    axes[kAxisRotY] = {AxisMode::Limited, Real(-0.5), Real(1.6), {}, {}};
    EXPECT_THAT(errorOf([&] { world.createJoint(sixDof(kWorldBody, box, {}, axes)); }), testing::HasSubstr("axes[ry].upper"));
    SixDofJointDef def = SixDofJointDef::fromWorld(world, kWorldBody, box, {}, {0, 0, 1});
    def.localFrameA = Quat{2, 0, 0, 0};
    EXPECT_THAT(errorOf([&] { world.createJoint(def); }), testing::HasSubstr("localFrameA"));
    def = SixDofJointDef::fromWorld(world, kWorldBody, box, {}, {0, 0, 1});
    const JointId j = world.createJoint(def);
    SixDofAxis free;
    free.mode = AxisMode::Free;
    EXPECT_THAT(errorOf([&] { world.setSixDofAxis(j, kAxisX, free); }), testing::HasSubstr("mode"));
    EXPECT_THAT(errorOf([&] { world.setSixDofAxis(j, 6, free); }), testing::HasSubstr("axis"));
    SixDofAxis locked;
    world.setSixDofAxis(j, kAxisX, locked);  // the same mode: accepted
}

// The per-type definition's frame: fromWorld with x = world z puts the
// linear x axis along world z; setSixDofAxis changes a drive after creation.
TEST(SixDof, FrameAndDriveAfterCreation) {
    World world(worldDef(4, {0, 0, 0}));
    const BodyId box = world.createBody(boxBody(1, {0, 0, 0}, {Real(0.1), Real(0.1), Real(0.1)}));
    SixDofJointDef def = SixDofJointDef::fromWorld(world, kWorldBody, box, {}, {0, 0, 1}, {1, 0, 0});
    def.axes[kAxisX].mode = AxisMode::Free;
    const JointId j = world.createJoint(def);
    EXPECT_EQ(world.jointDef(j).type, JointType::SixDof);
    EXPECT_NEAR(double(world.jointDef(j).axis.z), 1, 1e-6);
    SixDofAxis drive;
    drive.mode = AxisMode::Free;
    drive.motor = {true, Real(0.25), 100};
    world.setSixDofAxis(j, kAxisX, drive);
    for (int i = 0; i < 60; ++i) world.step(kDt);
    EXPECT_NEAR(double(world.linearVelocity(box).z), 0.25, 0.003);
    EXPECT_NEAR(double(world.sixDofReading(j).position[kAxisX]), double(world.position(box).z), 1e-5);
}

// A snapshot of a world with a six-DOF joint (frame, axes, drive impulses)
// continues with the same bits.
TEST(SixDof, SnapshotContinuesBitForBit) {
    World world(worldDef());
    const BodyId bob = world.createBody(sphereBody(1, {1, 0, 0}));
    SixDofAxes axes = axesAll(AxisMode::Locked);
    axes[kAxisRotZ] = {AxisMode::Limited, Real(-1), Real(1), {true, 1, 2}, {true, Real(0.2), 3, Real(0.1)}};
    axes[kAxisX].mode = AxisMode::Free;
    axes[kAxisX].spring = {true, 0, 50, 1};
    world.createJoint(sixDof(kWorldBody, bob, {0, 0, 0}, axes));
    for (int i = 0; i < 30; ++i) world.step(kDt);
    World copy = loadSnapshotFromMemory(saveSnapshotToMemory(world));
    for (int i = 0; i < 60; ++i) {
        world.step(kDt);
        copy.step(kDt);
    }
    const Vec3 p = world.position(bob), q = copy.position(copy.bodies()[0]);
    EXPECT_EQ(p.x, q.x);
    EXPECT_EQ(p.y, q.y);
    EXPECT_EQ(p.z, q.z);
    // Version 6 has no six-DOF joint: writing one in it is refused, naming it.
    EXPECT_THAT(errorOf([&] { (void)detail::saveSnapshotAsVersion(world, 6); }), testing::HasSubstr("six-DOF"));
}

// The angles are intrinsic x-y-z Euler angles: a rotation built as
// Rx(a) Ry(b) Rz(c) reads back as (a, b, c); each row's velocity is its
// angle's rate (finite differences, 1e-3 relative); at the gimbal lock
// (b = +-pi/2) the whole turn is read as a, and the rows stay finite.
TEST(SixDof, EulerAnglesAndTheirRates) {
    const auto rotation = [](double a, double b, double c) {
        return Quat::fromAxisAngle({1, 0, 0}, Real(a)) * Quat::fromAxisAngle({0, 1, 0}, Real(b)) *
               Quat::fromAxisAngle({0, 0, 1}, Real(c));
    };
    const Quat frame = normalize(Quat{1, Real(0.2), Real(-0.3), Real(0.1)});  // the joint frame in A
    const Quat qA = normalize(Quat{Real(0.9), Real(0.1), Real(0.4), Real(-0.2)});
    const double cases[][3] = {{0.3, -0.4, 1.1}, {-2.5, 1.2, -0.7}, {0.1, -1.4, 3.0}};
    for (const auto& e : cases) {
        // B's frame = A's frame turned by R (rest pose: identity).
        const Quat qB = qA * frame * rotation(e[0], e[1], e[2]) * conjugate(frame);
        const detail::SixDofGeometry g = detail::sixDofGeometry(qA, qB, Quat{}, frame, {});
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(double(g.angle[k]), e[k], 2e-5) << k;
        // Spin B by w for a short time either side: each angle changes by dot(row, w) dt (central differences).
        const Vec3 w{Real(0.3), Real(-0.5), Real(0.8)};
        const Real dt = Real(2e-3);
        const Quat half = Quat::fromAxisAngle(normalize(w), length(w) * dt / 2);
        const detail::SixDofGeometry after = detail::sixDofGeometry(qA, normalize(half * qB), Quat{}, frame, {});
        const detail::SixDofGeometry before = detail::sixDofGeometry(qA, normalize(conjugate(half) * qB), Quat{}, frame, {});
        for (int k = 0; k < 3; ++k) {
            const double rate = double(dot(g.angularRow[k], w));
            EXPECT_NEAR(double(after.angle[k] - before.angle[k]) / double(dt), rate, 2e-3 * (1 + std::fabs(rate))) << k;
        }
    }
    for (const double b : {kPi / 2, -kPi / 2}) {
        const Quat qB = qA * frame * rotation(0.4, b, 0) * conjugate(frame);
        const detail::SixDofGeometry g = detail::sixDofGeometry(qA, qB, Quat{}, frame, {});
        EXPECT_NEAR(double(g.angle[0]), 0.4, 2e-3);
        EXPECT_NEAR(double(g.angle[1]), b, 2e-3);
        for (int k = 0; k < 3; ++k) EXPECT_TRUE(isFinite(g.angularRow[k])) << k;
    }
}
