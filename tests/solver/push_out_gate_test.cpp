// pushOutGrown's gate (ContactSolver::setPushOutGate; docs/solver.md, "Grown
// overlaps"; every world here has WorldDef::pushOutGrownOverlaps on) skips, without reading its manifold, a pair whose bodies' motion
// since the step's start bounds the growth of its depth below the trigger. It
// must never change a decision: the same worlds run with the gate on and off
// end bit for bit alike, in scenes where the push-out acts (hulls landing at
// 20-30 m/s on a pile, a heavy box striking a row at 20 m/s) and where it
// does not (a resting box pyramid). Any one push skipped or added moves a
// body, and these chaotic piles spread the difference to the others.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "../../bench/box3d_scenes.hpp"
#include "contacts/helpers.hpp"
#include "support/hull_pile.hpp"
#include "support/same_motion.hpp"
#include "world/world_access.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

// Box3D's convex pile (bench/box3d_scenes.hpp): 3 x 3 columns of `layers` hulls.
World hullPile(int layers, std::vector<BodyId>& ids, Real& dt) {
    const bench::HullPileSpec pile = bench::convexPile(3, 3, layers);
    dt = Real(pile.dt);
    return hullPileWorld(pile, ids, true);
}

// No gravity: a row of five unit boxes at rest struck end-on by a 10 kg box at 20 m/s.
World struckRow(std::vector<BodyId>& ids) {
    WorldDef def;
    def.gravity = {0, 0, 0};
    def.pushOutGrownOverlaps = true;
    World world(def);
    for (int i = 0; i < 5; ++i) ids.push_back(addBox(world, {Real(i), 0, 0}, Vec3::splat(Real(0.5)), 1, 0));
    ids.push_back(addBox(world, {Real(-1.5), 0, 0}, Vec3::splat(Real(0.5)), 10, 0));
    world.setLinearVelocity(ids.back(), {20, 0, 0});
    return world;
}

void expectSameBits(World& gated, World& full, const std::vector<BodyId>& ids, Real dt, int steps, Real& deepest) {
    detail::implOf(full).contactSolver.setPushOutGate(false);
    for (int s = 0; s < steps; ++s) {
        gated.step(dt);
        full.step(dt);
        for (const ContactReport& c : full.contacts()) deepest = std::max(deepest, c.depth);
        for (const BodyId id : ids) ASSERT_TRUE(sameMotion(gated, id, full, id)) << "step " << s << ", body " << id.index;
    }
}

}  // namespace

TEST(PushOutGate, LandingHullPileHasTheSameBitsWithAndWithoutTheGate) {
    // 3 x 3 columns of 24 layers: the upper hulls land at 27-33 m/s from 3 s
    // on, the push-out's case (tests/contacts/hull_pile_overlap_test.cpp).
    std::vector<BodyId> ids, same;
    Real dt = 0;
    World gated = hullPile(24, ids, dt);
    World full = hullPile(24, same, dt);
    ASSERT_EQ(ids.size(), same.size());
    Real deepest = 0;
    expectSameBits(gated, full, ids, dt, 60 * 4, deepest);
    EXPECT_GT(deepest, Real(0.005));  // the pile did overlap past the trigger's depth
}

TEST(PushOutGate, StruckRowHasTheSameBitsWithAndWithoutTheGate) {
    std::vector<BodyId> ids, same;
    World gated = struckRow(ids);
    World full = struckRow(same);
    Real deepest = 0;
    expectSameBits(gated, full, ids, kDt, 60, deepest);
    EXPECT_GT(deepest, Real(0.005));
}

TEST(PushOutGate, RestingPyramidHasTheSameBitsWithAndWithoutTheGate) {
    std::vector<BodyId> ids, same;
    WorldDef def;
    def.pushOutGrownOverlaps = true;
    World gated(def), full(def);
    addGround(gated);
    addGround(full);
    for (int row = 0; row < 8; ++row) {
        for (int i = 0; i < 8 - row; ++i) {
            const Vec3 p{Real(i) * Real(1.02) + Real(row) * Real(0.51), Real(0.5) + Real(row), 0};
            ids.push_back(addBox(gated, p));
            same.push_back(addBox(full, p));
        }
    }
    Real deepest = 0;
    expectSameBits(gated, full, ids, kDt, 120, deepest);
}
