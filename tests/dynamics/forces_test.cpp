// Force elements and body types: springs between bodies (momentum), kinematic
// bodies, drag (terminal velocity), damping, user forces over a step.
#include "dynamics/test_scenes.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

TEST(Forces, SpringBetweenTwoBodiesConservesMomentum) {
    // Two bodies (1 kg and 3 kg) joined at their centres by a damped spring, moving
    // and turning: internal forces are equal, opposite and along the line between
    // the points, so linear and angular momentum about the origin are conserved.
    // Semi-implicit Euler conserves both exactly up to float rounding (1e-5 relative).
    World world(worldDef(Integrator::SemiImplicitEuler, 4, {0, 0, 0}));
    const BodyId a = world.createBody(pointMass(1, {0, 0, 0}, {1, 2, 0}));
    const BodyId b = world.createBody(pointMass(3, {2, 0, 0}, {0, -1, Real(0.5)}));
    SpringDef s;
    s.bodyA = a;
    s.bodyB = b;
    s.anchorA = {0, 0, 0};
    s.anchorB = {2, 0, 0};
    s.restLength = 1;
    s.stiffness = 50;
    s.damping = 2;
    const SpringId spring = world.createSpring(s);
    EXPECT_NEAR(world.springLength(spring), 2.0, 1e-6);
    const Vec3 p0 = world.linearMomentum(), l0 = world.angularMomentum();
    for (int i = 0; i < 300; ++i) world.step(Real(1) / 60);
    const Vec3 p1 = world.linearMomentum(), l1 = world.angularMomentum();
    EXPECT_LT(length(p1 - p0), 1e-5 * length(p0));
    EXPECT_LT(length(l1 - l0), 1e-4 * length(l0));  // |x| grows to ~5 m: rounding of x cross v
    // The damping dissipated energy: the total went down (and the spring did work).
    EXPECT_GT(length(world.centerOfMass(a) - world.centerOfMass(b)), 0.0);
}

TEST(Forces, SpringAnchorsOffCentreProduceTorque) {
    // A rod-like box hangs from a zero-length spring attached at its end, no gravity,
    // pulled sideways: the spring force at the end must give r x F torque. Check the
    // first step's angular acceleration: alpha = I^-1 (r x F) with F = -k (pB - pA).
    World world(worldDef(Integrator::SemiImplicitEuler, 1, {0, 0, 0}));
    BodyDef d;
    d.shape = Shape::box({Real(0.5), Real(0.05), Real(0.05)});
    d.mass = 1;
    const BodyId rod = world.createBody(d);
    SpringDef s;
    s.bodyB = rod;
    s.anchorA = {Real(0.5), 1, 0};  // world point above the rod's end
    s.anchorB = {Real(0.5), 0, 0};  // the rod's end
    s.stiffness = 10;
    world.createSpring(s);
    world.step(Real(0.01));
    // F = 10 N along +y at r = (0.5, 0, 0): torque (0, 0, 5); Iz = m (0.25 + 0.0025) / 3.
    const double iz = (0.25 + 0.0025) / 3;
    EXPECT_NEAR(world.angularVelocity(rod).z, 5 / iz * 0.01, 1e-4);
    EXPECT_NEAR(world.linearVelocity(rod).y, 10 * 0.01, 1e-6);
}

TEST(Forces, KinematicBodiesIgnoreForcesAndMoveAtTheirVelocity) {
    for (Integrator integrator : kAllIntegrators) {
        SCOPED_TRACE(toString(integrator));
        World world(worldDef(integrator, 4));
        BodyDef d;
        d.type = BodyType::Kinematic;
        d.position = {0, 1, 0};
        d.linearVelocity = {1, 0, 0};
        d.angularVelocity = {0, Real(kPi), 0};
        d.shape = Shape::box({1, 1, 1});
        const BodyId k = world.createBody(d);
        const BodyId ball = world.createBody(pointMass(1, {0, 3, 0}));
        SpringDef s;
        s.bodyA = ball;
        s.bodyB = k;
        s.anchorA = {0, 3, 0};
        s.anchorB = {0, 1, 0};
        s.stiffness = 1000;
        world.createSpring(s);
        world.applyForceAtCenter(k, {100, 100, 100});
        world.applyLinearImpulseAtCenter(k, {5, 5, 5});
        for (int i = 0; i < 60; ++i) world.step(Real(1) / 60);
        // Exactly x0 + v t (1e-5 m), half a turn about y (1e-5), velocity unchanged.
        EXPECT_NEAR(world.position(k).x, 1.0, 1e-5);
        EXPECT_NEAR(world.position(k).y, 1.0, 1e-6);
        EXPECT_NEAR(std::fabs(world.orientation(k).y), 1.0, 1e-5);
        EXPECT_EQ(world.linearVelocity(k), Vec3(1, 0, 0));
        EXPECT_EQ(world.mass(k), 0);
    }
}

TEST(Forces, StaticBodiesNeverMove) {
    World world;
    BodyDef d;
    d.type = BodyType::Static;
    d.shape = Shape::plane({0, 1, 0}, 0);
    d.linearVelocity = {1, 0, 0};  // ignored for a static body
    const BodyId ground = world.createBody(d);
    world.applyForceAtCenter(ground, {0, 100, 0});
    for (int i = 0; i < 10; ++i) world.step(Real(1) / 60);
    EXPECT_EQ(world.position(ground), Vec3(0, 0, 0));
    EXPECT_EQ(world.linearVelocity(ground), Vec3(0, 0, 0));
    EXPECT_FALSE(world.isAwake(ground));
}

TEST(Forces, LinearDragReachesTerminalVelocity) {
    // m dv/dt = -m g - b v: v(t) = -v_t (1 - exp(-t b / m)), v_t = m g / b.
    // m = 1 kg, b = 2 N s/m: v_t = 4.905 m/s, time constant 0.5 s.
    for (Integrator integrator : {Integrator::SemiImplicitEuler, Integrator::Verlet}) {
        SCOPED_TRACE(toString(integrator));
        World world(worldDef(integrator, 4));
        BodyDef d = pointMass(1, {0, 100, 0});
        d.linearDrag = 2;
        const BodyId b = world.createBody(d);
        for (int i = 0; i < 30; ++i) world.step(Real(1) / 60);  // t = 0.5 s
        const double vt = 9.81 / 2;
        // First-order methods at h = 1/240: relative error ~ h b / 2m = 0.4 %; 1 % tolerance.
        EXPECT_NEAR(world.linearVelocity(b).y, -vt * (1 - std::exp(-1.0)), 0.01 * vt);
        for (int i = 0; i < 570; ++i) world.step(Real(1) / 60);  // t = 10 s: e^-20 from terminal
        EXPECT_NEAR(world.linearVelocity(b).y, -vt, 1e-4 * vt);
    }
}

TEST(Forces, QuadraticDragReachesTerminalVelocity) {
    // m dv/dt = -m g + c v^2: v_t = sqrt(m g / c). m = 2 kg, c = 0.5: v_t = 6.264 m/s;
    // v(t) = -v_t tanh(g t / v_t). Check at t = 0.5 s (1 %) and at 10 s (1e-4).
    const double vt = std::sqrt(2 * 9.81 / 0.5);
    World world(worldDef(Integrator::SemiImplicitEuler, 4));
    BodyDef d = pointMass(2, {0, 100, 0});
    d.quadraticDrag = Real(0.5);
    const BodyId b = world.createBody(d);
    for (int i = 0; i < 30; ++i) world.step(Real(1) / 60);
    EXPECT_NEAR(world.linearVelocity(b).y, -vt * std::tanh(9.81 * 0.5 / vt), 0.01 * vt);
    for (int i = 0; i < 570; ++i) world.step(Real(1) / 60);
    EXPECT_NEAR(world.linearVelocity(b).y, -vt, 1e-4 * vt);
    // setDrag switches it to linear: v_t = m g / b = 2 * 9.81 / 4.
    world.setDrag(b, 4, 0);
    for (int i = 0; i < 600; ++i) world.step(Real(1) / 60);
    EXPECT_NEAR(world.linearVelocity(b).y, -2 * 9.81 / 4, 1e-4 * vt);
}

TEST(Forces, DampingIsTheImplicitDecayPerSubstep) {
    // v *= 1 / (1 + h c) per sub-step: after N sub-steps v = v0 / (1 + h c)^N
    // (1e-5 relative), which tends to v0 exp(-c t): the relative gap is N (h c)^2 / 2
    // = 0.83 % for N = 240, h c = 1/120 (1 % tolerance).
    World world(worldDef(Integrator::SemiImplicitEuler, 4, {0, 0, 0}));
    BodyDef d = pointMass(1, {}, {10, 0, 0});
    d.angularVelocity = {0, 0, 4};
    d.linearDamping = 2;
    d.angularDamping = Real(0.5);
    const BodyId b = world.createBody(d);
    for (int i = 0; i < 60; ++i) world.step(Real(1) / 60);
    const double h = 1.0 / 240;
    EXPECT_NEAR(world.linearVelocity(b).x, 10 / std::pow(1 + h * 2, 240), 1e-5 * 10);
    EXPECT_NEAR(world.angularVelocity(b).z, 4 / std::pow(1 + h * 0.5, 240), 1e-5 * 4);
    EXPECT_NEAR(world.linearVelocity(b).x, 10 * std::exp(-2.0), 0.01 * 10 * std::exp(-2.0));
    world.setDamping(b, 0, 0);
    const Vec3 v = world.linearVelocity(b);
    world.step(Real(1) / 60);
    EXPECT_EQ(world.linearVelocity(b), v);
}

TEST(Forces, GravityEnergyIsConservedInFreeFall) {
    // E = 1/2 m v^2 - m g . x is exactly conserved by Verlet under constant gravity
    // (1e-5 relative); potential is zero at the origin.
    World world(worldDef(Integrator::Verlet, 4));
    const BodyId b = world.createBody(pointMass(2, {0, 10, 0}, {3, 0, 0}));
    const double e0 = world.energy().total;
    EXPECT_NEAR(world.energy().potential, 2 * 9.81 * 10, 1e-3);
    for (int i = 0; i < 60; ++i) world.step(Real(1) / 60);
    EXPECT_NEAR(world.energy().total, e0, 1e-5 * e0);
    EXPECT_LT(world.position(b).y, 10);
}
