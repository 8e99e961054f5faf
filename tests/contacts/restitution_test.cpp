// Restitution: bounce heights h_n = e^(2n) h0 (the rebound speed is e times
// the impact speed, and height goes with speed squared).
#include <gtest/gtest.h>

#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

// Drops a ball (radius 0.1) from h0 (bottom height) and records the apex
// heights (bottom of the ball) of the first `bounces` bounces.
std::vector<Real> apexHeights(Real e, Real h0, int bounces) {
    WorldDef def;
    def.sleeping = false;
    World world(def);
    addGround(world, Real(0.6), e);
    const Real r = Real(0.1);
    const BodyId ball = addSphere(world, {0, h0 + r, 0}, r, 1, e);
    std::vector<Real> apex;
    Real prevVy = 0;
    for (int i = 0; i < 60 * 20 && static_cast<int>(apex.size()) < bounces; ++i) {
        world.step(kDt);
        const Real vy = world.linearVelocity(ball).y;
        if (prevVy > 0 && vy <= 0) {
            // Apex between two steps: refine with the parabola through the last state.
            const Real y = world.position(ball).y - r;
            apex.push_back(y + vy * vy / (2 * Real(9.81)));
        }
        prevVy = vy;
    }
    return apex;
}

}  // namespace

// Each bounce keeps e^2 of the previous height: h_n = e^2 h_(n-1) within
// 2 % + 5 mm (the impact is resolved at sub-step resolution, which costs at most
// ~1.5 % of the height per bounce), so h_n = e^(2n) h0 follows; with e = 1 the
// ball comes back within 2 % per bounce and 7 % after five, and a bounce never
// gains height.
TEST(Restitution, BounceHeightsFollowESquared) {
    const Real h0 = 2;
    for (Real e : {Real(1), Real(0.8), Real(0.5)}) {
        const int bounces = e == 1 ? 5 : 3;
        const std::vector<Real> apex = apexHeights(e, h0, bounces);
        ASSERT_EQ(static_cast<int>(apex.size()), bounces) << "e = " << e;
        Real previous = h0;
        for (int n = 1; n <= bounces; ++n) {
            EXPECT_NEAR(apex[n - 1], e * e * previous, Real(0.02) * previous + Real(0.005)) << "e = " << e << " bounce " << n;
            EXPECT_LE(apex[n - 1], previous) << "a bounce gained height, e = " << e;
            EXPECT_NEAR(apex[n - 1], h0 * std::pow(e, Real(2 * n)), Real(0.035) * h0 * Real(n)) << "e = " << e;
            previous = apex[n - 1];
        }
    }
}

// e = 0: the ball stops at the first impact (no rebound above 1 mm).
TEST(Restitution, ZeroRestitutionDoesNotBounce) {
    WorldDef def;
    def.sleeping = false;
    World world(def);
    addGround(world);
    const BodyId ball = addSphere(world, {0, Real(2.1), 0}, Real(0.1));
    Real maxAfter = 0;
    bool landed = false;
    for (int i = 0; i < 240; ++i) {
        world.step(kDt);
        const Real y = world.position(ball).y - Real(0.1);
        if (y < Real(0.01)) landed = true;
        if (landed) maxAfter = std::max(maxAfter, y);
    }
    EXPECT_TRUE(landed);
    EXPECT_LT(maxAfter, Real(0.01));
    EXPECT_NEAR(world.position(ball).y, Real(0.1), Real(0.005));
}
