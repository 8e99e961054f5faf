// Measures every integrator on the same four problems and prints the table that
// docs/integrators.md quotes (run: build/tests/test_dynamics --gtest_filter=IntegratorFigures*).
// Asserts the ranking the theory predicts: explicit Euler gains energy on every
// problem, Verlet is the most accurate, the symplectic pair stays bounded.
#include <algorithm>
#include <cstdio>

#include "dynamics/test_scenes.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

struct Figures {
    double freeFallError60 = 0;   // m, y error after 1 s at 60 Hz x1
    double freeFallError120 = 0;  // m, same at 120 Hz x1
    double springEnergy = 0;      // max |E/E0 - 1| over 20 periods, h = 1/240 (w h = 0.026)
    double orbitEnergy = 0;       // max |E/E0 - 1| over 10 orbits, h = 1/240
    double tumbleMomentum = 0;    // max | |L|/|L0| - 1 |, box tumbling 10 s at 240 Hz x1
    double tumbleEnergy = 0;      // max |E/E0 - 1|, same run
};

Figures measure(Integrator integrator) {
    Figures f;
    for (int hz : {60, 120}) {
        World world(worldDef(integrator));
        const BodyId b = world.createBody(pointMass(1, {0, 0, 0}));
        for (int i = 0; i < hz; ++i) world.step(Real(1) / static_cast<Real>(hz));
        (hz == 60 ? f.freeFallError60 : f.freeFallError120) = std::fabs(world.position(b).y + 0.5 * 9.81);
    }
    {
        World world(worldDef(integrator, 4, {0, 0, 0}));
        const BodyId b = world.createBody(pointMass(1, {Real(1.1), 0, 0}));
        SpringDef s;
        s.bodyB = b;
        s.anchorB = {Real(1.1), 0, 0};
        s.restLength = 1;
        s.stiffness = Real(4 * kPi * kPi);
        world.createSpring(s);
        const double e0 = world.energy().total;
        for (int i = 0; i < 20 * 60; ++i) {
            world.step(Real(1) / 60);
            f.springEnergy = std::max(f.springEnergy, std::fabs(world.energy().total / e0 - 1));
        }
    }
    {
        World world(worldDef(integrator, 4, {0, 0, 0}));
        const BodyId p = world.createBody(pointMass(1, {1, 0, 0}, {0, Real(2 * kPi), 0}));
        const double gm = 4 * kPi * kPi;
        world.setForceCallback(p, [gm](const BodyKinematics& k) {
            const Real r = length(k.position);
            return Wrench{k.position * (-Real(gm) / (r * r * r)), {}};
        });
        auto energy = [&] {
            const Vec3 v = world.linearVelocity(p);
            return 0.5 * dot(v, v) - gm / length(world.centerOfMass(p));
        };
        const double e0 = energy();
        for (int i = 0; i < 10 * 60; ++i) {
            world.step(Real(1) / 60);
            f.orbitEnergy = std::max(f.orbitEnergy, std::fabs(energy() / e0 - 1));
        }
    }
    {
        World world(worldDef(integrator, 1, {0, 0, 0}));
        BodyDef d;
        d.shape = Shape::box({Real(0.1), Real(0.2), Real(0.4)});
        d.mass = 2;
        d.angularVelocity = {Real(0.005), 5, Real(0.005)};
        world.createBody(d);
        const double l0 = length(world.angularMomentum()), e0 = world.energy().total;
        for (int i = 0; i < 2400; ++i) {
            world.step(Real(1) / 240);
            f.tumbleMomentum = std::max(f.tumbleMomentum, std::fabs(length(world.angularMomentum()) / l0 - 1));
            f.tumbleEnergy = std::max(f.tumbleEnergy, std::fabs(world.energy().total / e0 - 1));
        }
    }
    return f;
}

}  // namespace

TEST(IntegratorFigures, PrintAndRank) {
    const Figures ee = measure(Integrator::ExplicitEuler);
    const Figures si = measure(Integrator::SemiImplicitEuler);
    const Figures vv = measure(Integrator::Verlet);
    std::printf("| measure | explicit_euler | semi_implicit_euler | verlet |\n|---|---|---|---|\n");
    auto row = [](const char* name, double a, double b, double c) {
        std::printf("| %s | %.3g | %.3g | %.3g |\n", name, a, b, c);
    };
    row("free fall y error after 1 s, 60 Hz (m)", ee.freeFallError60, si.freeFallError60, vv.freeFallError60);
    row("free fall y error after 1 s, 120 Hz (m)", ee.freeFallError120, si.freeFallError120, vv.freeFallError120);
    row("spring max abs(dE/E), 20 periods, h = T/240", ee.springEnergy, si.springEnergy, vv.springEnergy);
    row("orbit max abs(dE/E), 10 orbits, h = T/240", ee.orbitEnergy, si.orbitEnergy, vv.orbitEnergy);
    row("tumbling box max abs(d|L|/|L|), 10 s at 240 Hz x1", ee.tumbleMomentum, si.tumbleMomentum, vv.tumbleMomentum);
    row("tumbling box max abs(dE/E), 10 s at 240 Hz x1", ee.tumbleEnergy, si.tumbleEnergy, vv.tumbleEnergy);

    // First order: the Euler errors halve with h (2 % tolerance); Verlet is exact (5e-5 m).
    EXPECT_NEAR(ee.freeFallError60 / ee.freeFallError120, 2, 0.04);
    EXPECT_NEAR(si.freeFallError60 / si.freeFallError120, 2, 0.04);
    EXPECT_LT(vv.freeFallError60, 5e-5);
    // Energy: explicit Euler worst on every problem, Verlet best.
    EXPECT_GT(ee.springEnergy, 10 * si.springEnergy);
    EXPECT_GT(ee.orbitEnergy, 10 * si.orbitEnergy);
    EXPECT_GT(ee.tumbleEnergy, si.tumbleEnergy);
    EXPECT_LT(vv.springEnergy, si.springEnergy);
    EXPECT_LT(vv.orbitEnergy, si.orbitEnergy);
    // Rotation: semi-implicit Euler and Verlet share the drift at constant world
    // angular momentum, so both keep |L| and E of a tumbling body to ~1e-5
    // (1e-4 tolerance), where explicit Euler's explicit gyroscopic term gains 19 %.
    EXPECT_LT(si.tumbleMomentum, 1e-4);
    EXPECT_LT(si.tumbleEnergy, 1e-4);
    EXPECT_LT(vv.tumbleMomentum, 1e-4);
    EXPECT_LT(vv.tumbleEnergy, 1e-4);
}
