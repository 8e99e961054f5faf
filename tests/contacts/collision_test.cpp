// Collisions against conservation laws: 1D elastic and inelastic impacts of
// spheres (momentum conserved; velocities from the textbook formulas) and
// Newton's cradle.
#include <gtest/gtest.h>

#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

WorldDef zeroGravity() {
    WorldDef d;
    d.gravity = {};
    d.sleeping = false;
    return d;
}

struct Impact {
    Real v1, v2;
};

// Sphere 1 (mass m1) at 3 m/s hits sphere 2 (mass m2) at rest, head on along x.
Impact collide1D(Real m1, Real m2, Real e) {
    World world(zeroGravity());
    BodyDef a;
    a.shape = Shape::sphere(Real(0.5));
    a.mass = m1;
    a.position = {-2, 0, 0};
    a.linearVelocity = {3, 0, 0};
    a.restitution = e;
    BodyDef b = a;
    b.mass = m2;
    b.position = {1, 0, 0};
    b.linearVelocity = {};
    const BodyId ia = world.createBody(a), ib = world.createBody(b);
    run(world, 120);
    return {world.linearVelocity(ia).x, world.linearVelocity(ib).x};
}

}  // namespace

// Momentum m1 u conserved to 1e-4 relative; velocities within 1 % of u:
//   e = 1: v1 = (m1 - m2) u / (m1 + m2), v2 = 2 m1 u / (m1 + m2)
//   e = 0: v1 = v2 = m1 u / (m1 + m2)
//   e = 0.5: v2 - v1 = e u.
TEST(Collision, OneDimensionalImpactsConserveMomentum) {
    const Real u = 3;
    for (Real m2 : {Real(1), Real(3), Real(0.25)}) {
        const Real m1 = 1;
        for (Real e : {Real(1), Real(0), Real(0.5)}) {
            const Impact r = collide1D(m1, m2, e);
            const Real p0 = m1 * u;
            EXPECT_NEAR(m1 * r.v1 + m2 * r.v2, p0, Real(1e-4) * p0) << "m2 " << m2 << " e " << e;
            const Real vc = m1 * u / (m1 + m2);  // centre-of-mass velocity
            const Real v1 = vc - e * m2 * u / (m1 + m2);
            const Real v2 = vc + e * m1 * u / (m1 + m2);
            EXPECT_NEAR(r.v1, v1, Real(0.01) * u) << "m2 " << m2 << " e " << e;
            EXPECT_NEAR(r.v2, v2, Real(0.01) * u) << "m2 " << m2 << " e " << e;
        }
    }
}

// Newton's cradle: five equal elastic balls in a row with 1 mm gaps, the first
// at 2 m/s. Momentum is conserved (1e-4) and passes through to the last ball:
// it leaves with at least 90 % of the speed, the first ball keeps under 12.5 %
// (one restitution pass over graph-coloured contacts spreads a little of the
// momentum back: measured 0.215 m/s of 2).
TEST(Collision, NewtonsCradlePassesMomentumThrough) {
    World world(zeroGravity());
    BodyId balls[5];
    for (int i = 0; i < 5; ++i) {
        BodyDef d;
        d.shape = Shape::sphere(Real(0.5));
        d.mass = 1;
        d.restitution = 1;
        d.position = {static_cast<Real>(i) * Real(1.001), 0, 0};
        if (i == 0) {
            d.position.x -= 1;
            d.linearVelocity = {2, 0, 0};
        }
        balls[i] = world.createBody(d);
    }
    run(world, 120);
    Real p = 0;
    for (BodyId b : balls) p += world.linearVelocity(b).x;
    EXPECT_NEAR(p, 2, Real(2e-4));
    EXPECT_GT(world.linearVelocity(balls[4]).x, Real(1.8));
    EXPECT_LT(std::fabs(world.linearVelocity(balls[0]).x), Real(0.25));
}
