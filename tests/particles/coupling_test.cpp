// Two-way coupling with rigid bodies and the aerodynamic force, against
// conservation of momentum and the flat-plate formula.
#include <gtest/gtest.h>

#include <cmath>

#include "particles/particle_builders.hpp"
#include "particles/particle_metrics.hpp"
#include "particles/particle_world.hpp"
#include "rigid_test_world.hpp"

using namespace fulcrum;

namespace {
constexpr Real kDt = Real(1) / 60;
}

// Zero gravity: an 8 x 8 cloth (0.64 kg) flies at 2 m/s into a free 50 g box.
// The box must move, its velocity must equal the impulse it received over its
// mass (two-way coupling "moves it by the impulse"), and the total linear
// momentum of cloth + box must stay the cloth's initial 1.28 kg m/s (the
// coupling exchanges momentum, never creates it) within 1e-3 relative.
TEST(Coupling, ClothPushesALightBoxAndConservesMomentum) {
    ParticleWorldSettings settings;
    settings.gravity = Vec3::zero();
    ParticleWorld world(settings);
    test_support::TestRigidWorld rigid;
    const Real boxMass = Real(0.05);
    const std::uint32_t box = rigid.addDynamic(Shape::box({Real(0.1), Real(0.1), Real(0.1)}), {{0, 0, 0}, {}}, boxMass);
    ClothDef def;
    def.size = {8, 8};
    def.spacing = Real(0.05);
    def.particleMass = Real(0.01);
    def.origin = {Real(-0.175), Real(-0.175), Real(-0.3)};
    def.uAxis = {1, 0, 0};
    def.vAxis = {0, 1, 0};
    def.bendCompliance = Real(0.1);
    ParticleSystem cloth = buildCloth(def);
    const Real h = kDt / static_cast<Real>(settings.substeps);
    for (std::uint32_t i = 0; i < cloth.particleCount(); ++i) setParticleVelocity(cloth, i, {0, 0, 2}, h);
    const ParticleSystemId id = world.add(std::move(cloth), &rigid);
    const Vec3 initial = linearMomentum(world.system(id));
    ASSERT_NEAR(initial.z, 1.28, 1e-4);
    for (int stepIndex = 0; stepIndex < 60; ++stepIndex) {
        rigid.integrate(kDt, Vec3::zero());
        world.step(kDt, &rigid);
    }
    const test_support::TestBody& b = rigid.bodies[box];
    EXPECT_GT(b.linearVelocity.z, Real(0.5));  // pushed hard: a light box ahead of a heavy cloth
    EXPECT_NEAR(b.linearVelocity.z, b.receivedLinearImpulse.z / boxMass, 1e-4);
    EXPECT_GT(b.transform.p.z, Real(0.2));
    const Vec3 total = linearMomentum(world.system(id)) + b.linearVelocity * boxMass;
    EXPECT_NEAR(total.z / initial.z, 1.0, 1e-3);
    EXPECT_NEAR(total.x, 0.0, 1e-3);
    EXPECT_NEAR(total.y, 0.0, 1e-3);
}

// A cloth falling onto a light box resting on nothing but its own weight
// budget: the box (zero gravity for it, gravity for the cloth) is pushed down,
// and the momentum it receives equals what the cloth lost relative to free
// fall (gravity's impulse minus the cloth's momentum). Tolerance 1 %: the
// measured ratio oscillates within +-0.25 % from step to step (the cloth's
// momentum is read from the last sub-step's Verlet velocity, the box's is a
// sum over sub-steps; the source of the residual is not pinned down yet).
TEST(Coupling, FallingClothTransfersItsMomentumToTheBox) {
    ParticleWorld world;  // gravity on the particles
    test_support::TestRigidWorld rigid;
    const std::uint32_t box = rigid.addDynamic(Shape::box({Real(0.3), Real(0.05), Real(0.3)}), {{0, 0, 0}, {}}, Real(0.2));
    ClothDef def;
    def.size = {10, 10};
    def.spacing = Real(0.05);
    def.origin = {Real(-0.225), Real(0.2), Real(-0.225)};
    def.bendCompliance = Real(0.1);
    const ParticleSystemId id = world.addCloth(def, &rigid);
    const int steps = 40;
    for (int stepIndex = 0; stepIndex < steps; ++stepIndex) {
        rigid.integrate(kDt, Vec3::zero());  // the box floats: only the cloth pushes it
        world.step(kDt, &rigid);
    }
    const double clothMass = 100 * 0.01;
    const double gravityImpulse = -clothMass * 9.81 * steps * kDt;
    const double lost = gravityImpulse - linearMomentum(world.system(id)).y;
    EXPECT_LT(rigid.bodies[box].linearVelocity.y, -0.1);
    EXPECT_NEAR(rigid.bodies[box].receivedLinearImpulse.y / lost, 1.0, 1e-2);
}

// Aerodynamics: a free square of cloth (zero gravity) held face-on to a
// 10 m/s wind. Over the first step it receives the flat-plate drag
// F = 1/2 rho C_D A |u|^2 (A = its area, face-on: |cos| = 1). The momentum
// reported is the mean over the last sub-step h, so after one step from rest
// it is F (dt - h / 2), within 1 % (its speed, ~0.08 m/s at the end, lowers u
// by ~0.8 % on average: measured 0.991).
TEST(Coupling, WindDragOnAFaceOnClothMatchesTheFlatPlateFormula) {
    ParticleWorldSettings settings;
    settings.gravity = Vec3::zero();
    settings.wind = {0, 0, 10};
    ParticleWorld world(settings);
    ClothDef def;
    def.size = {5, 5};
    def.spacing = Real(0.1);
    def.particleMass = Real(0.1);
    def.uAxis = {1, 0, 0};
    def.vAxis = {0, 1, 0};  // normal along z: face-on
    def.dragCoefficient = Real(1.2);
    def.liftCoefficient = 1;  // no lift face-on
    def.selfCollision = false;
    const ParticleSystemId id = world.addCloth(def);
    world.step(kDt);
    const double area = 0.4 * 0.4;
    const double force = 0.5 * 1.2 * 1.2 * area * 100;
    const Vec3 p = linearMomentum(world.system(id));
    const double h = static_cast<double>(kDt) / world.settings().substeps;
    EXPECT_NEAR(p.z / (force * (kDt - h / 2)), 1.0, 0.01);
    // Sideways: only lift from the slight billowing, < 0.5 % of the drag.
    EXPECT_NEAR(p.x, 0.0, 1e-3);
    EXPECT_NEAR(p.y, 0.0, 1e-3);
}
