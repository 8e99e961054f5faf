// Sleeping costs nothing: the awake list (WorldImpl::awakeBodies), the
// per-body contact lists of the contact manager and the lazy contact report
// (docs/solver.md, "Sleeping"). Each is an acceleration structure, so the tests
// check them against what they stand for after every step of scenes that go
// through every way a body falls asleep or wakes: the list must equal the
// awake non-static bodies in dense order, a sleeping body must not move and
// must keep previousTransform() equal to its transform (interpolation of a
// still body is still), and results must be bit-identical to a world that
// built everything from scratch (a snapshot restored mid-run).
#include <gtest/gtest.h>

#include <cstring>
#include <limits>
#include <vector>

#include "contacts/helpers.hpp"
#include "determinism/state_hash.hpp"
#include "fulcrum/snapshot.hpp"
#include "world/world_access.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

bool sameBits(const Transform& a, const Transform& b) {
    return std::memcmp(&a.p, &b.p, sizeof a.p) == 0 && std::memcmp(&a.q, &b.q, sizeof a.q) == 0;
}

// The awake list equals the awake non-static bodies in ascending dense order,
// and every body asleep since the last check did not move and interpolates still.
class Checker {
public:
    void check(World& world) {
        WorldImpl& w = detail::implOf(world);
        w.refreshAwakeList();  // applies the pending changes; the list is a pure function of the state
        std::vector<std::uint32_t> expected;
        for (std::uint32_t d = 0; d < w.motion.size(); ++d) {
            if (w.params[d].type != BodyType::Static && w.params[d].awake) expected.push_back(d);
        }
        ASSERT_EQ(w.awakeBodies, expected) << "awake list out of date at step " << world.stepCount();
        std::vector<std::pair<BodyId, Transform>> asleep;
        for (const BodyId id : world.bodies()) {
            if (world.bodyType(id) == BodyType::Static || world.isAwake(id)) continue;
            const Transform now = world.transform(id);
            asleep.emplace_back(id, now);
            for (const auto& [was, before] : asleepBefore_) {
                if (was != id) continue;
                EXPECT_TRUE(sameBits(now, before)) << "a sleeping body moved at step " << world.stepCount();
                EXPECT_TRUE(sameBits(world.previousTransform(id), now))
                    << "a sleeping body's previousTransform differs from its transform at step " << world.stepCount();
            }
        }
        asleepBefore_ = std::move(asleep);
    }
    void forget() { asleepBefore_.clear(); }  // after a teleport of a sleeping body

private:
    std::vector<std::pair<BodyId, Transform>> asleepBefore_;
};

struct Pile {
    std::vector<BodyId> towerA, towerB, towerC, loose;
};

// Three 4-box towers far apart (three islands), two loose boxes.
Pile buildPile(World& world) {
    addGround(world);
    Pile p;
    for (int i = 0; i < 4; ++i) {
        const Real y = Real(0.5) + static_cast<Real>(i);
        p.towerA.push_back(addBox(world, {-6, y, 0}));
        p.towerB.push_back(addBox(world, {0, y, 0}));
        p.towerC.push_back(addBox(world, {6, y, 0}));
    }
    p.loose.push_back(addBox(world, {0, Real(0.5), 6}));
    p.loose.push_back(addBox(world, {0, Real(0.5), -6}));
    return p;
}

void stepChecked(World& world, Checker& checker, int steps) {
    for (int i = 0; i < steps; ++i) {
        world.step(kDt);
        checker.check(world);
        if (::testing::Test::HasFatalFailure()) return;
    }
}

bool allAsleep(const World& world) {
    for (const BodyId id : world.bodies()) {
        if (world.bodyType(id) != BodyType::Static && world.isAwake(id)) return false;
    }
    return true;
}

// Steps (checking the awake list every step) until every body sleeps, at most
// 5 s; true if they all did.
bool stepCheckedUntilAllAsleep(World& world, Checker& checker) {
    for (int i = 0; i < 300 && !allAsleep(world); ++i) stepChecked(world, checker, 1);
    return allAsleep(world);
}

bool anyAwake(const World& world, const std::vector<BodyId>& ids) {
    for (const BodyId id : ids) {
        if (world.isAwake(id)) return true;
    }
    return false;
}

}  // namespace

// Resting towers fall asleep (timeToSleep 0.5 s after settling), and then a
// step does no per-body and no per-contact work: the integrators and forces
// walk an empty awake list, the contact manager visits no contact, the solver
// has only its static stand-in, and no body moves by a single bit.
TEST(SleepCost, SleepingWorldStepsWithoutPerBodyWork) {
    World world;
    Checker checker;
    buildPile(world);
    ASSERT_TRUE(stepCheckedUntilAllAsleep(world, checker));
    // The body state alone (stateHash also counts the steps).
    const auto bodyHash = [&world] {
        StateHasher h;
        for (const BodyId id : world.bodies()) {
            h.add(world.position(id)), h.add(world.orientation(id));
            h.add(world.linearVelocity(id)), h.add(world.angularVelocity(id));
            h.add64(world.isAwake(id) ? 1 : 0);
        }
        return h.value();
    };
    const std::uint64_t before = bodyHash();
    const std::size_t reports = world.contacts().size();
    EXPECT_GT(reports, 12u);  // every box rests on something: at least one manifold each
    stepChecked(world, checker, 30);
    const WorldImpl& w = detail::implOf(world);
    EXPECT_TRUE(w.awakeBodies.empty());
    EXPECT_EQ(w.contactManager.visitedContactCount(), 0u);
    EXPECT_EQ(w.denseOfSolver.size(), 1u);  // the awake set: entry 0, the static stand-in, alone
    EXPECT_EQ(bodyHash(), before);
    EXPECT_EQ(world.contacts().size(), reports);  // the lazy report still lists the resting contacts
}

// Every way to wake, one island at a time: touch (a ball dropped on tower A),
// a user force (tower B), a teleport (a loose box), a destroyed support (tower
// C's bottom box: the boxes above it fall), a joint to a sleeping body. Other
// islands stay asleep and the awake list follows exactly.
TEST(SleepCost, AwakeListFollowsEveryWake) {
    World world;
    Checker checker;
    const Pile p = buildPile(world);
    ASSERT_TRUE(stepCheckedUntilAllAsleep(world, checker));

    // Touch.
    addSphere(world, {-6, Real(6), 0}, Real(0.3), 2);
    bool woke = false;
    for (int i = 0; i < 90 && !woke; ++i) {
        stepChecked(world, checker, 1);
        woke = world.isAwake(p.towerA[3]);
    }
    EXPECT_TRUE(woke);
    EXPECT_FALSE(anyAwake(world, p.towerB));
    EXPECT_FALSE(anyAwake(world, p.towerC));

    // User force on the bottom box: the whole island wakes.
    world.applyForceAtCenter(p.towerB[0], {0, 1, 0});
    EXPECT_TRUE(world.isAwake(p.towerB[3]));
    stepChecked(world, checker, 2);
    EXPECT_FALSE(anyAwake(world, p.towerC));

    // Teleport of a sleeping loose box onto the ground elsewhere: it wakes and settles.
    if (!world.isAwake(p.loose[0])) {
        world.setTransform(p.loose[0], {3, Real(0.6), 6}, Quat{});
        checker.forget();
        EXPECT_TRUE(world.isAwake(p.loose[0]));
    }
    stepChecked(world, checker, 2);

    // Destroying tower C's bottom box while it sleeps: the box above loses its
    // support, wakes, and falls (the dense arrays are renumbered: full rebuild).
    ASSERT_FALSE(world.isAwake(p.towerC[1]));
    const Real yBefore = world.position(p.towerC[1]).y;
    world.destroyBody(p.towerC[0]);
    EXPECT_TRUE(world.isAwake(p.towerC[1]));
    stepChecked(world, checker, 30);
    EXPECT_LT(world.position(p.towerC[1]).y, yBefore - Real(0.5));  // fell most of a box height

    // A joint made on a sleeping body wakes its island (a rod to the other
    // loose box, anchored where they are, so nothing is yanked).
    for (int i = 0; i < 300 && world.isAwake(p.loose[1]); ++i) stepChecked(world, checker, 1);
    ASSERT_FALSE(world.isAwake(p.loose[1]));
    JointDef j;
    j.type = JointType::Ball;
    j.bodyA = p.loose[0];
    j.bodyB = p.loose[1];
    j.anchor = world.position(p.loose[1]);
    world.createJoint(j);
    stepChecked(world, checker, 2);
    EXPECT_TRUE(world.isAwake(p.loose[1]));
    stepChecked(world, checker, 240);
}

// A snapshot of a half-asleep world resumes bit for bit: the restored world
// rebuilds its awake list, contact lists and previous transforms from scratch,
// the running one keeps them incrementally; both give the same states and the
// same contact reports at every step.
TEST(SleepCost, HalfAsleepSnapshotResumesBitIdentical) {
    World world;
    const Pile p = buildPile(world);
    for (int i = 0; i < 300 && !allAsleep(world); ++i) world.step(kDt);
    ASSERT_TRUE(allAsleep(world));
    world.applyLinearImpulseAtCenter(p.towerB[3], {Real(0.5), 0, 0});
    world.step(kDt);
    ASSERT_TRUE(world.isAwake(p.towerB[0]));
    ASSERT_FALSE(world.isAwake(p.towerA[0]));
    World restored = loadSnapshotFromMemory(saveSnapshotToMemory(world));
    Checker checker;
    for (int i = 0; i < 120; ++i) {
        world.step(kDt);
        restored.step(kDt);
        checker.check(restored);
        ASSERT_EQ(stateHash(restored), stateHash(world)) << "step " << i;
        if (i % 10 == 0) {
            const std::vector<ContactReport> a = world.contacts(), b = restored.contacts();
            ASSERT_EQ(a.size(), b.size());
            for (std::size_t k = 0; k < a.size(); ++k) {
                EXPECT_EQ(a[k].bodyA, b[k].bodyA);
                EXPECT_EQ(a[k].bodyB, b[k].bodyB);
                EXPECT_EQ(std::memcmp(&a[k].depth, &b[k].depth, sizeof(Real)), 0);
                ASSERT_EQ(a[k].points.size(), b[k].points.size());
                EXPECT_EQ(std::memcmp(a[k].points.data(), b[k].points.data(), a[k].points.size() * sizeof(Vec3)), 0);
            }
        }
    }
}

// The report is built when read, from the contacts as the last step left
// them: reading it after every step or only once gives the same reports, and
// destroying a body between the step and the read does not drop the body's
// contacts from the last step's report (they are reported as of the step).
TEST(SleepCost, LazyContactReportEqualsTheStepsReport) {
    World eager, lazy;
    const Pile pe = buildPile(eager);
    const Pile pl = buildPile(lazy);
    for (int i = 0; i < 20; ++i) {
        eager.step(kDt);
        (void)eager.contacts();
        lazy.step(kDt);
    }
    const std::vector<ContactReport> fromEager = eager.contacts();
    eager.destroyBody(pe.towerA[0]);
    lazy.destroyBody(pl.towerA[0]);
    const std::vector<ContactReport> fromLazy = lazy.contacts();
    ASSERT_EQ(fromLazy.size(), fromEager.size());
    bool namesDestroyed = false;
    for (std::size_t k = 0; k < fromLazy.size(); ++k) {
        EXPECT_EQ(fromLazy[k].bodyA, fromEager[k].bodyA);
        EXPECT_EQ(fromLazy[k].bodyB, fromEager[k].bodyB);
        EXPECT_EQ(fromLazy[k].depth, fromEager[k].depth);
        namesDestroyed = namesDestroyed || fromLazy[k].bodyA == pl.towerA[0] || fromLazy[k].bodyB == pl.towerA[0];
    }
    EXPECT_TRUE(namesDestroyed);
    EXPECT_EQ(stateHash(lazy), stateHash(eager));
}

// Turning sleeping off wakes every body at the next step and the list holds
// them all; turned back on, the resting towers fall asleep again (0.5 s below
// the sleep speeds) and the list empties.
TEST(SleepCost, SleepingOffAndOnAgain) {
    World world;
    Checker checker;
    const Pile p = buildPile(world);
    ASSERT_TRUE(stepCheckedUntilAllAsleep(world, checker));
    world.setSleepingEnabled(false);
    stepChecked(world, checker, 1);
    EXPECT_EQ(detail::implOf(world).awakeBodies.size(), world.bodyCount() - 1);  // all but the ground
    stepChecked(world, checker, 30);
    world.setSleepingEnabled(true);
    for (int i = 0; i < 300 && !allAsleep(world); ++i) stepChecked(world, checker, 1);
    EXPECT_TRUE(allAsleep(world));
    EXPECT_TRUE(detail::implOf(world).awakeBodies.empty());
    EXPECT_FALSE(anyAwake(world, p.towerA));
}

namespace {

// Zero gravity: a 99 kg box at rest and a 1 kg box drifting at `speed` inside
// the slack of a 3 m rope (a distance joint, min 0): one island, whose
// mass-weighted RMS speed is speed / 10.
// `spin`: the light box's angular velocity about y (rad/s); it is a cube, so
// with no torque its spin stays constant.
bool ropePairSleeps(Real speed, Real seconds, Real spin = 0) {
    WorldDef def;
    def.gravity = {};
    World world(def);
    const BodyId heavy = addBox(world, {0, 0, 0}, Vec3::splat(Real(0.5)), 99);
    const BodyId light = addBox(world, {0, 0, Real(-1)}, Vec3::splat(Real(0.1)), 1);
    JointDef rope;
    rope.type = JointType::Distance;
    rope.bodyA = heavy;
    rope.bodyB = light;
    rope.anchor = {0, 0, 0};
    rope.anchorB = {0, 0, Real(-1)};
    rope.minLength = 0;
    rope.maxLength = 3;
    world.createJoint(rope);
    world.setLinearVelocity(light, {speed, 0, 0});  // 1 m of drift per 12 s at 0.08 m/s: the rope stays slack
    world.setAngularVelocity(light, {0, spin, 0});
    const int steps = static_cast<int>(seconds / kDt);
    for (int i = 0; i < steps; ++i) world.step(kDt);
    return !world.isAwake(light) && !world.isAwake(heavy);
}

}  // namespace

// The sleep measure (src/islands/sleep.hpp): an island is still when its
// mass-weighted RMS speed is below linearSleepVelocity (0.05 m/s) and no body
// of it is faster than twice that. A lone body is held to 0.05 m/s exactly.
TEST(SleepMeasure, IslandRmsSpeedWithAPerBodyCap) {
    // RMS 0.008 m/s, the light body at 0.08 < 0.1: asleep after timeToSleep (0.5 s).
    EXPECT_TRUE(ropePairSleeps(Real(0.08), 1));
    // The light body at 0.12 m/s > 0.1 (RMS only 0.012): never, though the island barely moves.
    EXPECT_FALSE(ropePairSleeps(Real(0.12), 3));

    // A lone body drifting at 0.07 m/s (above the sleep speed) stays awake; at 0.03 it sleeps.
    for (const Real speed : {Real(0.07), Real(0.03)}) {
        WorldDef def;
        def.gravity = {};
        World world(def);
        const BodyId box = addBox(world, {0, 0, 0});
        world.setLinearVelocity(box, {speed, 0, 0});
        for (int i = 0; i < 120; ++i) world.step(kDt);
        EXPECT_EQ(world.isAwake(box), speed > Real(0.05)) << "speed " << speed;
    }
}

// Rotation (src/islands/sleep.hpp): a body of a group is still when its spin is
// below angularSleepVelocity (0.05 rad/s) or the speed the spin gives its
// farthest point is below linearSleepVelocity (0.05 m/s). The light box is a
// 0.2 m cube: its farthest corner is sqrt(3) * 0.1 = 0.173 m from its centre.
TEST(SleepMeasure, GroupRotationByItsFarthestPointsSpeed) {
    // 0.2 rad/s, 4x the angular sleep speed, moves the corner at 0.035 m/s: asleep.
    EXPECT_TRUE(ropePairSleeps(0, 1, Real(0.2)));
    // 0.4 rad/s moves it at 0.069 m/s: never.
    EXPECT_FALSE(ropePairSleeps(0, 3, Real(0.4)));

    // A lone body keeps the plain spin test: the same cube at 0.2 rad/s stays awake.
    WorldDef def;
    def.gravity = {};
    World world(def);
    const BodyId cube = addBox(world, {0, 0, 0}, Vec3::splat(Real(0.1)), 1);
    world.setAngularVelocity(cube, {0, Real(0.2), 0});
    for (int i = 0; i < static_cast<int>(3 / kDt); ++i) world.step(kDt);
    EXPECT_TRUE(world.isAwake(cube));
    EXPECT_NEAR(world.angularVelocity(cube).y, Real(0.2), Real(1e-5));  // torque-free: the spin holds
}

// The speeds tested are the smaller of a body's velocity and how far it moved
// over the step (sleep.hpp, "Held bodies": the wedged-limb case is
// Ragdoll.APileComesToRestAndSleeps in tests/joints). Moving bodies must stay
// awake on both counts: a lone body gliding at 0.06 m/s (above the 0.05 m/s
// sleep speed) and one spinning at exactly a full turn per step, whose turn over
// the step alone would read zero, keep their timers at zero for 3 s.
TEST(SleepMeasure, DisplacementNeverHidesMotion) {
    WorldDef def;
    def.gravity = {};
    def.maxRotationPerSubstep = std::numeric_limits<Real>::infinity();  // 377 rad/s is above the spin limit
    World world(def);
    const BodyId glider = addBox(world, {0, 0, 0}, Vec3::splat(Real(0.1)), 1);
    world.setLinearVelocity(glider, {Real(0.06), 0, 0});
    const BodyId spinner = addBox(world, {5, 0, 0}, Vec3::splat(Real(0.1)), 1);
    const Real fullTurnPerStep = Real(2 * 3.14159265358979) / kDt;
    world.setAngularVelocity(spinner, {0, fullTurnPerStep, 0});
    const int steps = 180;  // 3 s
    for (int i = 0; i < steps; ++i) world.step(kDt);
    EXPECT_TRUE(world.isAwake(glider));
    EXPECT_NEAR(world.position(glider).x, 0.06 * steps * kDt, 1e-5);  // x = v t
    EXPECT_TRUE(world.isAwake(spinner));
    EXPECT_NEAR(world.angularVelocity(spinner).y, fullTurnPerStep, 1e-3);
}
