// Pairs that get deeper within a step (a box struck into its neighbour faster
// than one soft iteration per sub-step can pass the blow on) are pushed apart
// by position after the sub-steps (ContactSolver::pushOutGrown; docs/solver.md,
// "Grown overlaps"): the overlap goes, and no velocity comes with it.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

struct StrikeRun {
    Real deepest = 0;         // deepest reported overlap after any step, m
    double maxKinetic = 0;    // largest kinetic energy after any step, J
    double startKinetic = 0;  // J
    Vec3 momentum;            // total linear momentum at the end, N s
};

// No gravity: a row of `count` unit boxes (1 kg) touching face to face along
// x, at rest, struck end-on by a `strikerMass` box at `speed`.
StrikeRun strikeRow(int count, Real strikerMass, Real speed, int steps) {
    WorldDef def;
    def.gravity = {0, 0, 0};
    World world(def);
    std::vector<BodyId> row;
    for (int i = 0; i < count; ++i) row.push_back(addBox(world, {Real(i), 0, 0}, Vec3::splat(Real(0.5)), 1, 0));
    const BodyId striker = addBox(world, {Real(-1.5), 0, 0}, Vec3::splat(Real(0.5)), strikerMass, 0);
    world.setLinearVelocity(striker, {speed, 0, 0});
    row.push_back(striker);
    StrikeRun r;
    r.startKinetic = 0.5 * double(strikerMass) * double(speed) * double(speed);
    for (int s = 0; s < steps; ++s) {
        world.step(kDt);
        for (const ContactReport& c : world.contacts()) r.deepest = std::max(r.deepest, c.depth);
        r.maxKinetic = std::max(r.maxKinetic, world.energy().kinetic);
    }
    for (const BodyId b : row) r.momentum += world.linearVelocity(b) * world.mass(b);
    return r;
}

}  // namespace

// A 10 kg box at 20 m/s into a row of five 1 kg boxes at rest: the blow
// drives each box of the row into the next within the step (measured: the
// deepest reported overlap 1.83 cm; the bound leaves room for another
// compiler's bits). The push-out moves positions and takes out approach
// speed only, so it adds no energy (the kinetic energy never exceeds the
// striker's 2,000 J, restitution 0; a push-out by velocity, as the `pile`
// branch's growing push limit, threw boxes apart) and keeps the momentum
// (200 N s along x).
TEST(GrownOverlap, StruckRowIsPushedApartWithoutAddingEnergy) {
    const StrikeRun r = strikeRow(5, 10, 20, 60);
    RecordProperty("deepest", std::to_string(r.deepest));
    RecordProperty("max_kinetic", std::to_string(r.maxKinetic));
    EXPECT_LT(r.deepest, Real(0.025));
    EXPECT_LE(r.maxKinetic, r.startKinetic * (1 + 1e-4));
    EXPECT_NEAR(r.momentum.x, 200, 200 * 1e-4);
    EXPECT_NEAR(r.momentum.y, 0, 1e-3);
    EXPECT_NEAR(r.momentum.z, 0, 1e-3);
}
