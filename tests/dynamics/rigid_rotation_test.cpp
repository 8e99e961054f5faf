// Rotational dynamics: torque-free motion of an asymmetric body (Euler's
// equations: |L| and E conserved, instability about the intermediate axis),
// torque from an off-centre force, impulses, and rotation about the centre of mass.
#include <algorithm>

#include "dynamics/test_scenes.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

// Box 0.2 x 0.4 x 0.8 m, 2 kg: I = m/3 (b^2 + c^2, ...) = (0.1133, 0.1133*0.85, 0.0333):
// Ix = 0.1333, Iy = 0.1133, Iz = 0.0333 kg m^2 -> y is the intermediate axis.
BodyDef asymmetricBox(Vec3 omega) {
    BodyDef d;
    d.name = "tumbler";
    d.shape = Shape::box({Real(0.1), Real(0.2), Real(0.4)});
    d.mass = 2;
    d.angularVelocity = omega;
    return d;
}

struct TumbleResult {
    double maxAngularMomentumError = 0;  // max | |L| / |L0| - 1 |
    double maxEnergyError = 0;           // max | E / E0 - 1 |
    int flips = 0;                       // sign changes of the body-y component of w
};

TumbleResult tumble(Integrator integrator, int hz, int substeps, double seconds) {
    World world(worldDef(integrator, substeps, {0, 0, 0}));
    // Spin about the intermediate axis with a 1e-3 perturbation about the others.
    const BodyId box = world.createBody(asymmetricBox({Real(0.005), 5, Real(0.005)}));
    const double l0 = length(world.angularMomentum()), e0 = world.energy().total;
    TumbleResult r;
    double prevSign = 1;
    for (int i = 0; i < static_cast<int>(seconds * hz); ++i) {
        world.step(Real(1) / static_cast<Real>(hz));
        r.maxAngularMomentumError = std::max(r.maxAngularMomentumError, std::fabs(length(world.angularMomentum()) / l0 - 1));
        r.maxEnergyError = std::max(r.maxEnergyError, std::fabs(world.energy().total / e0 - 1));
        const double wy = inverseRotate(world.orientation(box), world.angularVelocity(box)).y;
        const double sign = wy >= 0 ? 1 : -1;
        if (sign != prevSign) ++r.flips;
        prevSign = sign;
    }
    return r;
}

}  // namespace

TEST(RigidRotation, TorqueFreeAsymmetricBoxConservesAndFlips) {
    // The default integrator at 240 Hz for 10 s (default 4 sub-steps). The
    // perturbation grows as exp(lambda t), lambda = w sqrt((Ix - Iy)(Iy - Iz) / (Ix Iz))
    // = 5 * 0.866 = 4.3 /s, so the first flip comes after ~ln(1000)/4.3 ~ 1.6 s and
    // the body keeps flipping back and forth (Dzhanibekov effect).
    WorldDef def;
    const TumbleResult r = tumble(def.integrator, 240, def.substeps, 10);
    std::printf("tumble (semi-implicit, 240 Hz x4): max |dL|/L %.3e, max |dE|/E %.3e, flips %d\n",
                r.maxAngularMomentumError, r.maxEnergyError, r.flips);
    EXPECT_LT(r.maxAngularMomentumError, 0.01);  // brief: within 1 %
    EXPECT_LT(r.maxEnergyError, 0.02);           // brief: within 2 %
    EXPECT_GE(r.flips, 2);                       // the body-axis component changed sign (and back)
}

TEST(RigidRotation, VerletConservesAngularMomentumExactly) {
    // Verlet turns the body at constant world angular momentum in its drift, so |L| is
    // conserved up to float rounding (measured 1.0e-5 over 2,400 sub-steps; bound 1e-4)
    // and E to O((w h)^2) (measured 2.2e-5; bound 1e-3); the flip still happens.
    const TumbleResult r = tumble(Integrator::Verlet, 240, 1, 10);
    std::printf("tumble (verlet, 240 Hz x1): max |dL|/L %.3e, max |dE|/E %.3e, flips %d\n", r.maxAngularMomentumError,
                r.maxEnergyError, r.flips);
    EXPECT_LT(r.maxAngularMomentumError, 1e-4);
    EXPECT_LT(r.maxEnergyError, 1e-3);
    EXPECT_GE(r.flips, 2);
}

TEST(RigidRotation, ExplicitGyroscopicTermGainsEnergy) {
    // The explicit gyroscopic term w x I w pumps energy into a tumbling body: at 240 Hz
    // x1 over 10 s the energy grows visibly (by more than 5 %).
    const TumbleResult r = tumble(Integrator::ExplicitEuler, 240, 1, 10);
    std::printf("tumble (explicit, 240 Hz x1): max |dL|/L %.3e, max |dE|/E %.3e, flips %d\n", r.maxAngularMomentumError,
                r.maxEnergyError, r.flips);
    EXPECT_GT(r.maxEnergyError, 0.05);
}

TEST(RigidRotation, StableSpinAboutTheMajorAxisStaysPut) {
    // About the axis of largest inertia (x) the spin is stable: the body-x component
    // of w keeps its sign and |w| stays within 1 % over 10 s.
    World world;
    const BodyId box = world.createBody(asymmetricBox({5, Real(0.005), Real(0.005)}));
    world.setGravity({0, 0, 0});
    for (int i = 0; i < 2400; ++i) {
        world.step(Real(1) / 240);
        ASSERT_GT(inverseRotate(world.orientation(box), world.angularVelocity(box)).x, 0);
    }
    EXPECT_NEAR(length(world.angularVelocity(box)), 5.0, 0.05);
    EXPECT_NEAR(length(world.orientation(box)), 1.0, 1e-6);  // stays a unit quaternion
}

TEST(RigidRotation, OffCentreForceGivesTorqueAndAngularAcceleration) {
    // F = (0, 0, 10) N at r = (0.5, 0, 0) from the centre of a box at rest, one step
    // of 0.01 s: v = F/m dt, w = I^-1 (r x F) dt (the gyroscopic term is zero at
    // w = 0, so every integrator gives this exactly; 1e-5 relative tolerance).
    for (Integrator integrator : kAllIntegrators) {
        SCOPED_TRACE(toString(integrator));
        World world(worldDef(integrator, 1, {0, 0, 0}));
        const BodyId box = world.createBody(asymmetricBox({}));
        const Vec3 force{0, 0, 10}, point{Real(0.5), 0, 0};
        world.applyForce(box, force, point);
        world.step(Real(0.01));
        const Mat3 inertia = world.localInertia(box);
        const Vec3 torque = cross(point, force);  // (0, -5, 0)
        EXPECT_NEAR(world.linearVelocity(box).z, 10.0 / 2 * 0.01, 1e-7);
        EXPECT_NEAR(world.angularVelocity(box).y, torque.y / inertia(1, 1) * 0.01, 1e-5 * 0.5);
        EXPECT_NEAR(world.angularVelocity(box).x, 0, 1e-7);
        // Forces last one step: the next step leaves v unchanged.
        const Vec3 v = world.linearVelocity(box);
        world.step(Real(0.01));
        EXPECT_NEAR(world.linearVelocity(box).z, v.z, 1e-7);
    }
}

TEST(RigidRotation, PureTorqueAndForceAtCentre) {
    World world(worldDef(Integrator::SemiImplicitEuler, 1, {0, 0, 0}));
    const BodyId box = world.createBody(asymmetricBox({}));
    world.applyTorque(box, {0, 0, 2});
    world.applyForceAtCenter(box, {4, 0, 0});
    world.step(Real(0.1));
    // alpha = tau / Iz, a = F / m; one step of 0.1 s (1e-5 relative).
    EXPECT_NEAR(world.angularVelocity(box).z, 2 / world.localInertia(box)(2, 2) * 0.1, 1e-5 * 6);
    EXPECT_NEAR(world.linearVelocity(box).x, 4.0 / 2 * 0.1, 1e-6);
}

TEST(RigidRotation, ImpulsesChangeVelocityAtOnce) {
    World world(worldDef(Integrator::SemiImplicitEuler, 1, {0, 0, 0}));
    const BodyId box = world.createBody(asymmetricBox({}));
    const Mat3 inertia = world.localInertia(box);
    // Linear impulse J = (0, 3, 0) at r = (0.1, 0, 0): dv = J/m, dw = I^-1 (r x J) = (0, 0, 0.3 / Iz).
    world.applyLinearImpulse(box, {0, 3, 0}, {Real(0.1), 0, 0});
    EXPECT_NEAR(world.linearVelocity(box).y, 1.5, 1e-6);
    EXPECT_NEAR(world.angularVelocity(box).z, 0.3 / inertia(2, 2), 1e-5);
    // Impulse at the centre: no spin change.
    world.applyLinearImpulseAtCenter(box, {2, 0, 0});
    EXPECT_NEAR(world.linearVelocity(box).x, 1.0, 1e-6);
    EXPECT_NEAR(world.angularVelocity(box).z, 0.3 / inertia(2, 2), 1e-5);
    // Angular impulse: dw = I^-1 H.
    world.applyAngularImpulse(box, {Real(0.5), 0, 0});
    EXPECT_NEAR(world.angularVelocity(box).x, 0.5 / inertia(0, 0), 1e-5);
    // Momentum: m v and, about the origin, the spin I w plus the impulse moments.
    EXPECT_NEAR(world.linearMomentum().y, 3.0, 1e-5);
    EXPECT_NEAR(world.angularMomentum().z, 0.3, 1e-5);
    EXPECT_NEAR(world.angularMomentum().x, 0.5, 1e-5);
}

TEST(RigidRotation, BodySpinsAboutItsCentreOfMass) {
    // Compound of two spheres (1 kg at x = 0 and 3 kg at x = 1, equal density via
    // radii): the centre of mass sits off the origin. Spinning at w about z with no
    // gravity, the centre of mass stays put and the origin circles around it.
    const Real r1 = Real(0.1), r2 = r1 * std::cbrt(Real(3));
    const CompoundChild children[] = {{Shape::sphere(r1), Transform({0, 0, 0}, {})},
                                      {Shape::sphere(r2), Transform({1, 0, 0}, {})}};
    BodyDef d;
    d.shape = Shape::compound(children);
    d.angularVelocity = {0, 0, Real(kPi)};  // half a turn per second
    World world(worldDef(Integrator::SemiImplicitEuler, 4, {0, 0, 0}));
    const BodyId b = world.createBody(d);
    EXPECT_NEAR(world.localCenterOfMass(b).x, 0.75, 1e-5);  // (0 * 1 + 1 * 3) / 4
    EXPECT_NEAR(world.centerOfMass(b).x, 0.75, 1e-5);
    for (int i = 0; i < 60; ++i) world.step(Real(1) / 60);
    // After half a turn the origin is mirrored through the centre of mass: x = 1.5 (1e-4 m).
    EXPECT_NEAR(world.centerOfMass(b).x, 0.75, 1e-5);
    EXPECT_NEAR(world.position(b).x, 1.5, 1e-4);
    EXPECT_NEAR(world.position(b).y, 0.0, 1e-4);
}

// Torque-free symmetric top (a capsule: I_t, I_t, I_a about its y axis):
// analytically q(t) = rot(L, |L| t / I_t) q0 rot_body(y, w0.y (1 - I_a / I_t) t),
// the axis precessing about the fixed L on a cone. The drift is exact for such
// bodies, so after 1,200 sub-steps the orientation is within float rounding
// (measured: 0 to the printed digits; the general midpoint drift, which these
// bodies used before, ends 0.031 rad off); w is I_w^-1 L and L is kept.
TEST(RigidRotation, SymmetricTopPrecessesAsTheClosedForm) {
    for (const Integrator integrator : {Integrator::SemiImplicitEuler, Integrator::Verlet}) {
        World world(worldDef(integrator, 2, {0, 0, 0}));
        BodyDef d;
        d.shape = Shape::capsule(Real(0.1), Real(0.4));
        d.mass = 3;
        const Vec3 w0{Real(1.5), 5, Real(-0.7)};
        d.angularVelocity = w0;
        const BodyId top = world.createBody(d);
        const Mat3 inertia = world.localInertia(top);
        const double it = inertia(0, 0), ia = inertia(1, 1);
        ASSERT_EQ(inertia(0, 0), inertia(2, 2));
        ASSERT_GT(std::fabs(ia / it - 1), 0.5);  // a flat enough top for the two rates to differ
        const Vec3 l0 = inertia * w0;             // q0 = identity
        const double seconds = 10;
        for (int i = 0; i < 600; ++i) world.step(Real(seconds / 600));
        const double precession = length(l0) / it * seconds;
        const double spin = static_cast<double>(w0.y) * (1 - ia / it) * seconds;
        const Quat expected = Quat::fromAxisAngle(l0, static_cast<Real>(std::fmod(precession, 4 * M_PI))) *
                              Quat::fromAxisAngle({0, 1, 0}, static_cast<Real>(std::fmod(spin, 4 * M_PI)));
        const Quat q = world.orientation(top);
        const double angleError = 2 * std::acos(std::min(1.0, static_cast<double>(std::fabs(dot(q, expected)))));
        EXPECT_LT(angleError, 2e-4) << "orientation off the closed form by " << angleError << " rad";
        EXPECT_LT(length(world.angularMomentum() - l0) / length(l0), 1e-5);
        // w = I_w^-1 L with the world inverse inertia the solver sees.
        const Vec3 axis = rotate(q, {0, 1, 0});
        const Vec3 w = world.angularVelocity(top);
        const Vec3 expectedW = l0 / static_cast<Real>(it) + axis * (dot(l0, axis) * static_cast<Real>(1 / ia - 1 / it));
        EXPECT_LT(length(w - expectedW) / length(expectedW), 1e-5);
    }
}
