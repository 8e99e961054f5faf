// The FULCRUM_VALIDATE checks (src/world/invariants.hpp, docs/validation.md).
//
// Every test here runs in every build: the checks are always compiled, and
// the tests call them directly between steps. In a FULCRUM_VALIDATE build
// (the sanitizer pass of scripts/test.sh) the step also runs them at each
// of its phase boundaries, so there the scenes below are checked inside
// their steps too, and one more test proves a corrupted world stops the step.
//
// Two halves: scenes that must pass (a pyramid, piles that fall asleep and
// are woken, joints), and one world corrupted per invariant, to see each
// check fire with a message naming the phase and what broke.
#include <gtest/gtest.h>
#include <gmock/gmock.h>

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include "contacts/helpers.hpp"
#include "world/invariants.hpp"
#include "world/world_access.hpp"
#include "world/world_impl.hpp"

using namespace fulcrum;
using namespace fulcrum::test;
using detail::StepPhase;
using ::testing::HasSubstr;

namespace {

// Every check that holds between two steps (the awake list may hold
// sleepers not yet removed, and the last step's solver bodies may have fallen
// asleep, so the "exact list" and solver phases are the step's own).
void expectValidBetweenSteps(const World& world, const char* scene, int step) {
    for (const StepPhase phase : {StepPhase::StepStart, StepPhase::AfterSleep, StepPhase::StepEnd}) {
        try {
            detail::checkInvariants(detail::implOf(world), phase);
        } catch (const detail::InvariantError& e) {
            ADD_FAILURE() << scene << ", after step " << step << ": " << e.what();
            return;
        }
    }
}

void runChecked(World& world, int steps, const char* scene) {
    for (int i = 0; i < steps; ++i) {
        world.step(kDt);
        expectValidBetweenSteps(world, scene, i + 1);
        if (::testing::Test::HasFailure()) return;
    }
}

// The message of the InvariantError `phase` throws (fails the test if none).
std::string violation(const World& world, StepPhase phase) {
    try {
        detail::checkInvariants(detail::implOf(world), phase);
    } catch (const detail::InvariantError& e) {
        return e.what();
    }
    ADD_FAILURE() << "no invariant broken " << detail::phaseName(phase);
    return "";
}

BodyId addKinematicSlab(World& world, const Vec3& position) {
    BodyDef d;
    d.name = "slab";
    d.type = BodyType::Kinematic;
    d.shape = Shape::box({6, Real(0.25), 2});
    d.position = position;
    return world.createBody(d);
}

JointId addBall(World& world, BodyId a, BodyId b, const Vec3& anchor) {
    JointDef j;
    j.type = JointType::Ball;
    j.bodyA = a;
    j.bodyB = b;
    j.anchor = anchor;
    return world.createJoint(j);
}

std::uint32_t denseOf(const World& world, BodyId id) { return detail::implOf(world).bodySlots[id.index].dense; }

// A live contact between `a` and `b` (by slot); fails the test if none.
detail::Contact* contactBetween(World& world, BodyId a, BodyId b) {
    for (detail::Contact& c : detail::implOf(world).contactManager.contacts()) {
        if (c.alive && ((c.slotA == a.index && c.slotB == b.index) || (c.slotA == b.index && c.slotB == a.index))) return &c;
    }
    ADD_FAILURE() << "no contact between slots " << a.index << " and " << b.index;
    return nullptr;
}

// ---------------------------------------------------------------- scenes that must pass

TEST(Invariants, HoldThroughAPyramid) {
    World world;
    buildPyramid(world, 10);
    runChecked(world, 120, "pyramid10");
}

// Stacks fall asleep; a push wakes one (its island, through the contacts);
// a box dropped onto a sleeping stack wakes it in the collide phase; a body
// destroyed renumbers the dense arrays.
TEST(Invariants, HoldThroughAPileThatSleepsAndWakes) {
    World world;
    addGround(world);
    std::vector<BodyId> boxes;
    for (int s = 0; s < 4; ++s) {
        for (int k = 0; k < 4; ++k) boxes.push_back(addBox(world, {Real(3 * s), Real(0.5) + Real(k), 0}));
    }
    runChecked(world, 240, "pile");
    ASSERT_FALSE(world.isAwake(boxes[0]));
    world.setLinearVelocity(boxes[3], {Real(0.5), 0, 0});
    runChecked(world, 30, "pile, one stack pushed");
    addBox(world, {Real(6), Real(6), 0});
    runChecked(world, 60, "pile, a box dropped on a sleeping stack");
    world.destroyBody(boxes[1]);
    runChecked(world, 120, "pile, a body destroyed");
}

// The map from dense body to solver body after each step: exactly the step's
// solver bodies map to one (BodyStore::beginStep clears only the last step's
// entries, not the whole map), through sleep, wake, creation and destruction.
TEST(Invariants, SolverBodyMapHoldsOnlyTheStepsSolverBodies) {
    World world;
    addGround(world);
    std::vector<BodyId> boxes;
    for (int s = 0; s < 3; ++s) {
        for (int k = 0; k < 3; ++k) boxes.push_back(addBox(world, {Real(3 * s), Real(0.5) + Real(k), 0}));
    }
    const auto expectExactMap = [&](const char* when) {
        const WorldImpl& w = detail::implOf(world);
        std::size_t mapped = 0;
        for (std::uint32_t d = 0; d < w.motion.size(); ++d) mapped += w.solverIndexOf(d) != 0 ? 1 : 0;
        EXPECT_EQ(mapped + 1, w.denseOfSolver.size()) << when;
        for (std::uint32_t i = 1; i < w.denseOfSolver.size(); ++i) EXPECT_EQ(w.solverIndexOf(w.denseOfSolver[i]), i) << when;
    };
    for (int i = 0; i < 240; ++i) {
        world.step(kDt);
        expectExactMap("settling");
    }
    ASSERT_FALSE(world.isAwake(boxes[0]));  // asleep: its old solver entry must be gone
    world.setLinearVelocity(boxes[3], {Real(0.5), 0, 0});
    world.step(kDt);
    expectExactMap("one stack woken");
    world.destroyBody(boxes[4]);
    addBox(world, {Real(9), Real(0.5), 0});
    for (int i = 0; i < 30; ++i) {
        world.step(kDt);
        expectExactMap("a body destroyed, one created");
    }
}

// A hanging chain (the tree solver's rows), a hinge, and joints to a
// kinematic body (an end that takes no colour slot).
TEST(Invariants, HoldWithJoints) {
    World world;
    addGround(world);
    BodyId previous = kWorldBody;
    for (int i = 0; i < 8; ++i) {
        const BodyId link = addBox(world, {Real(i) + Real(0.5), Real(10), 0}, {Real(0.45), Real(0.1), Real(0.1)});
        addBall(world, previous, link, {Real(i), Real(10), 0});
        previous = link;
    }
    const BodyId slab = addKinematicSlab(world, {0, Real(4), Real(5)});
    world.setLinearVelocity(slab, {Real(0.5), 0, 0});
    for (int i = 0; i < 3; ++i) {
        const BodyId hanging = addBox(world, {Real(-4 + 4 * i), Real(2.5), Real(5)});
        addBall(world, slab, hanging, {Real(-4 + 4 * i), Real(3.5), Real(5)});
    }
    const BodyId door = addBox(world, {Real(-5), Real(1.5), Real(-5)}, {Real(0.05), 1, Real(0.5)});
    JointDef hinge;
    hinge.type = JointType::Hinge;
    hinge.bodyB = door;
    hinge.anchor = {Real(-5), Real(1.5), Real(-5.5)};
    hinge.axis = {0, 1, 0};
    world.createJoint(hinge);
    world.setAngularVelocity(door, {0, 2, 0});
    runChecked(world, 180, "joints");
}

// In a FULCRUM_VALIDATE build the step itself checks every phase: a world
// corrupted between steps stops the next step at its start.
TEST(Invariants, ValidateBuildChecksInsideTheStep) {
    if (!detail::stepValidation()) GTEST_SKIP() << "not a FULCRUM_VALIDATE build (or FULCRUM_VALIDATE=0)";
    World world;
    buildPyramid(world, 3);
    run(world, 5);
    WorldImpl& w = detail::implOf(world);
    std::swap(w.denseToSlot[1], w.denseToSlot[2]);
    try {
        world.step(kDt);
        ADD_FAILURE() << "the step ran on a corrupted body store";
    } catch (const detail::InvariantError& e) {
        EXPECT_THAT(e.what(), HasSubstr("at the step's start: body store: denseToSlot[1]"));
    }
    std::swap(w.denseToSlot[1], w.denseToSlot[2]);
}

// ---------------------------------------------------------------- each check fires

TEST(Invariants, BodyStoreSlotMapsBroken) {
    World world;
    buildPyramid(world, 3);
    run(world, 2);
    WorldImpl& w = detail::implOf(world);
    std::swap(w.denseToSlot[1], w.denseToSlot[2]);
    EXPECT_THAT(violation(world, StepPhase::AfterStore), HasSubstr("after store: body store: denseToSlot[1] = "));
    std::swap(w.denseToSlot[1], w.denseToSlot[2]);
    w.bodySlots[w.denseToSlot[3]].dense = 4;
    EXPECT_THAT(violation(world, StepPhase::StepEnd), HasSubstr("body store: denseToSlot[3]"));
}

TEST(Invariants, BodyStoreArraysOfDifferentLengths) {
    World world;
    buildPyramid(world, 3);
    run(world, 2);
    detail::implOf(world).previous.pop_back();
    EXPECT_THAT(violation(world, StepPhase::StepEnd), HasSubstr("body store: previous holds 6 entries for 7 bodies"));
}

TEST(Invariants, StaticBodyWithMass) {
    World world;
    const BodyId ground = addGround(world);
    addBox(world, {0, Real(0.5), 0});
    run(world, 2);
    detail::implOf(world).motion[denseOf(world, ground)].invMass = 1;
    EXPECT_THAT(violation(world, StepPhase::StepEnd),
                HasSubstr("body store: body 'ground' (dense 0) is not dynamic but has a non-zero inverse mass"));
}

TEST(Invariants, AwakeListOutOfOrderOrIncomplete) {
    World world;
    buildPyramid(world, 3);
    run(world, 2);
    WorldImpl& w = detail::implOf(world);
    ASSERT_FALSE(w.awakeListRebuild);
    ASSERT_GE(w.awakeBodies.size(), 3u);
    std::swap(w.awakeBodies[0], w.awakeBodies[1]);
    EXPECT_THAT(violation(world, StepPhase::StepStart), HasSubstr("awake list: not ascending at entry 1"));
    std::swap(w.awakeBodies[0], w.awakeBodies[1]);
    const std::uint32_t dropped = w.awakeBodies.back();
    w.awakeBodies.pop_back();
    w.inAwakeList[dropped] = 0;
    EXPECT_THAT(violation(world, StepPhase::StepStart), HasSubstr("is awake but neither listed nor queued"));
    // Queued as woken, it is accounted for (the next refresh lists it) ...
    w.wokenBodies.push_back(dropped);
    EXPECT_NO_THROW(detail::checkInvariants(w, StepPhase::StepStart));
    // ... but not where the step walks the list: it must be refreshed by then.
    EXPECT_THAT(violation(world, StepPhase::AfterCollide), HasSubstr("after collide: awake list: not refreshed"));
}

TEST(Invariants, AwakeBodyWithANonFiniteState) {
    World world;
    const BodyId box = addBox(world, {0, 5, 0});
    run(world, 1);
    detail::implOf(world).motion[denseOf(world, box)].v.y = std::numeric_limits<Real>::quiet_NaN();
    EXPECT_THAT(violation(world, StepPhase::StepStart), HasSubstr("is awake with a non-finite state"));
    // Later phases leave a NaN to World::step's NumericalError.
    EXPECT_NO_THROW(detail::checkInvariants(detail::implOf(world), StepPhase::StepEnd));
}

TEST(Invariants, ContactGraphBroken) {
    World world;
    const BodyId ground = addGround(world);
    const BodyId box = addBox(world, {0, Real(0.5), 0});
    BodyDef wall;
    wall.name = "wall";
    wall.type = BodyType::Static;
    wall.shape = Shape::box({1, 1, 1});
    wall.position = {20, 1, 0};
    const BodyId other = world.createBody(wall);
    run(world, 2);
    detail::Contact* c = contactBetween(world, ground, box);
    ASSERT_NE(c, nullptr);
    const detail::Contact saved = *c;
    const std::string index = std::to_string(c - detail::implOf(world).contactManager.contacts().data());
    // A contact of a destroyed body's slot.
    c->slotB = 999;
    EXPECT_THAT(violation(world, StepPhase::AfterCollide), HasSubstr("contact graph: contact " + index + " references slot 999"));
    // Between two static bodies (the ground is slot 0, A).
    c->slotB = other.index;
    EXPECT_THAT(violation(world, StepPhase::AfterCollide), HasSubstr("joins two static bodies, body 'ground'"));
    // Dead but still in its bodies' lists.
    *c = saved;
    c->alive = false;
    EXPECT_THAT(violation(world, StepPhase::AfterSleep), HasSubstr("contact graph: 0 live contacts, the manager counts 1"));
    *c = saved;
    EXPECT_NO_THROW(detail::checkInvariants(detail::implOf(world), StepPhase::AfterSleep));
}

TEST(Invariants, IslandTagOnAnAwakeBody) {
    World world;
    addGround(world);
    const BodyId box = addBox(world, {0, Real(0.5), 0});
    run(world, 2);
    detail::implOf(world).params[denseOf(world, box)].sleepIsland = 7;
    EXPECT_THAT(violation(world, StepPhase::AfterSleep), HasSubstr("islands: body #1 (dense 1) is awake but tagged with sleeping island 7"));
}

// A box asleep under an awake one it touches: the wake pass should have woken it.
TEST(Invariants, AwakeBodyTouchingASleeper) {
    World world;
    addGround(world);
    const BodyId bottom = addBox(world, {0, Real(0.5), 0});
    addBox(world, {0, Real(1.5), 0});
    run(world, 10);
    WorldImpl& w = detail::implOf(world);
    w.params[denseOf(world, bottom)].awake = false;  // as the sleep manager does, off the list at the next refresh
    w.awakeListHasSleepers = true;
    EXPECT_THAT(violation(world, StepPhase::AfterSleep), HasSubstr("after sleep: islands: body #2 (dense 2) is awake and touches body #1"));
    // Before the wake pass, the user may have woken one of two touching bodies.
    EXPECT_NO_THROW(detail::checkInvariants(w, StepPhase::StepStart));
}

// Colours: a kinematic end takes no colour slot, so three contacts (joints)
// on one kinematic body share a colour. Giving that body mass, as a broken
// solver-body build would, puts a dynamic body twice in one colour.
TEST(Invariants, ContactColourSharingADynamicBody) {
    World world;
    const BodyId slab = addKinematicSlab(world, {0, 0, 0});
    for (int i = 0; i < 3; ++i) addBox(world, {Real(-4 + 4 * i), Real(0.75), 0});
    run(world, 1);
    EXPECT_NO_THROW(detail::checkInvariants(detail::implOf(world), StepPhase::AfterSubsteps));
    detail::ContactSolver& solver = detail::implOf(world).contactSolver;
    ASSERT_EQ(solver.constraintCount(), 3u);
    detail::implOf(world).state[detail::implOf(world).solverIndexOf(denseOf(world, slab))].invMass = 1;
    EXPECT_THAT(violation(world, StepPhase::AfterSubsteps), HasSubstr("after the sub-steps: contact colours: colour 0 holds two constraints on solver body"));
}

TEST(Invariants, StaleSolverBodyMapEntry) {
    World world;
    const BodyId ground = addGround(world);
    addBox(world, {0, Real(0.5), 0});
    run(world, 1);
    EXPECT_NO_THROW(detail::checkInvariants(detail::implOf(world), StepPhase::AfterSubsteps));
    detail::implOf(world).solverOfDense[denseOf(world, ground)] = 1;
    EXPECT_THAT(violation(world, StepPhase::AfterSubsteps),
                HasSubstr("solver bodies: 2 bodies map to a solver body, but there are 1"));
}

TEST(Invariants, JointColourSharingADynamicBody) {
    World world;
    const BodyId slab = addKinematicSlab(world, {0, 0, 0});
    for (int i = 0; i < 3; ++i) {
        const BodyId b = addBox(world, {Real(-4 + 4 * i), -2, 0});
        addBall(world, slab, b, {Real(-4 + 4 * i), -1, 0});
    }
    run(world, 1);
    EXPECT_NO_THROW(detail::checkInvariants(detail::implOf(world), StepPhase::AfterPrepare));
    ASSERT_EQ(detail::implOf(world).jointSolver.constraintCount(), 3u);
    detail::implOf(world).state[detail::implOf(world).solverIndexOf(denseOf(world, slab))].invMass = 1;
    EXPECT_THAT(violation(world, StepPhase::AfterPrepare), HasSubstr("after prepare: joint colours: colour 0 holds two constraints on solver body"));
}

}  // namespace
