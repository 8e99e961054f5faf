// Determinism proofs: the same scene gives bit-identical states (a) across
// repeated runs, (b) whatever WorldDef::threads says, and (c) when the run is
// saved to a snapshot and resumed from it, at several points - before contact,
// in the middle of a settling pile, while a cloth drapes over a sphere, after
// parts fell asleep. The reference is always the uninterrupted run; every
// comparison is exact (64-bit hash of all positions, orientations, velocities
// and particle states, see state_hash.hpp), tolerance zero.
#include <gtest/gtest.h>

#include <vector>

#include "determinism/state_hash.hpp"
#include "fulcrum/scene.hpp"
#include "fulcrum/snapshot.hpp"
#include "fulcrum/world.hpp"

namespace fulcrum {
namespace {

using test::stateHash;

constexpr int kSteps = 150;

Scene mixedScene(int threads = 1) {
    Scene scene = parseScene(test::kMixedScene, "mixed");
    scene.world.threads = threads;
    return scene;
}

// Hash after every step 0..steps.
std::vector<std::uint64_t> run(World& world, Real dt, int steps) {
    std::vector<std::uint64_t> hashes{stateHash(world)};
    for (int i = 0; i < steps; ++i) {
        world.step(dt);
        hashes.push_back(stateHash(world));
    }
    return hashes;
}

TEST(Determinism, RepeatedRunsAreBitIdentical) {
    const Scene scene = mixedScene();
    World a = buildWorld(scene), b = buildWorld(scene);
    const auto ha = run(a, scene.dt, kSteps), hb = run(b, scene.dt, kSteps);
    EXPECT_EQ(ha, hb);
    // The scene really moves and touches (else the proof would be empty): the
    // state changes over the run, and the pile has contacts.
    EXPECT_NE(ha.front(), ha.back());
    EXPECT_GT(a.contacts().size(), 5u);
}

TEST(Determinism, HashSeesOneBit) {
    // The hash is sensitive: the same scene with a time step one ulp longer
    // ends in a different state.
    const Scene scene = mixedScene();
    World a = buildWorld(scene), b = buildWorld(scene);
    const Real dt2 = std::nextafter(scene.dt, Real(1));
    for (int i = 0; i < 20; ++i) a.step(scene.dt), b.step(dt2);
    EXPECT_NE(stateHash(a), stateHash(b));
}

TEST(Determinism, ThreadCountChangesNothing) {
    std::vector<std::vector<std::uint64_t>> runs;
    for (int threads : {1, 2, 4}) {
        const Scene scene = mixedScene(threads);
        World w = buildWorld(scene);
        EXPECT_EQ(w.settings().threads, threads);
        runs.push_back(run(w, scene.dt, kSteps));
    }
    EXPECT_EQ(runs[0], runs[1]);
    EXPECT_EQ(runs[0], runs[2]);
}

// Snapshot after `at` steps, resume from the bytes in a fresh World, and
// compare every following step with the uninterrupted run.
void expectResumeMatches(const Scene& scene, const std::vector<int>& points, int steps) {
    World reference = buildWorld(scene);
    const auto expected = run(reference, scene.dt, steps);
    for (const int at : points) {
        SCOPED_TRACE("snapshot after step " + std::to_string(at));
        World original = buildWorld(scene);
        for (int i = 0; i < at; ++i) original.step(scene.dt);
        const std::vector<std::uint8_t> bytes = saveSnapshotToMemory(original);
        World resumed = loadSnapshotFromMemory(bytes);
        ASSERT_EQ(stateHash(resumed), expected[static_cast<std::size_t>(at)]);
        for (int i = at; i < steps; ++i) {
            resumed.step(scene.dt);
            original.step(scene.dt);
            ASSERT_EQ(stateHash(resumed), expected[static_cast<std::size_t>(i + 1)]) << "diverged at step " << i + 1;
        }
        // The contact cache came back too: same manifolds, same impulses, as reported.
        const auto ca = resumed.contacts(), cb = original.contacts();
        ASSERT_EQ(ca.size(), cb.size());
        for (std::size_t k = 0; k < ca.size(); ++k) {
            EXPECT_EQ(ca[k].bodyA, cb[k].bodyA);
            EXPECT_EQ(ca[k].bodyB, cb[k].bodyB);
            EXPECT_EQ(ca[k].points.size(), cb[k].points.size());
        }
    }
}

TEST(Determinism, ResumeMatchesUninterruptedMixedScene) {
    // 0: before anything moved; 25: boxes falling into each other; 70: the pile
    // settling with warm-started contacts, the chain swinging, the cloth on the sphere.
    expectResumeMatches(mixedScene(), {0, 25, 70}, 110);
}

TEST(Determinism, ResumeMatchesMidContactSettlingPile) {
    // A 3-layer pile of boxes dropped with a gap, snapshotted while it bounces
    // and settles (contacts persist across the snapshot with their impulses).
    std::string json = R"({"world": {"dt": 0.0166667, "steps": 1}, "bodies": [
      {"name": "ground", "type": "static", "shape": {"type": "box", "half_extents": [5, 0.5, 5]}, "position": [0, -0.5, 0]})";
    int k = 0;
    for (int layer = 0; layer < 3; ++layer) {
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 2; ++j) {
                const double x = 0.42 * i + 0.05 * layer, z = 0.42 * j - 0.03 * layer, y = 0.25 + 0.55 * layer + 0.05;
                json += ",\n{\"name\": \"box" + std::to_string(k++) + "\", \"shape\": {\"type\": \"box\", \"half_extents\": [0.2, 0.2, 0.2]}, " +
                        "\"mass\": 1, \"position\": [" + std::to_string(x) + ", " + std::to_string(y) + ", " + std::to_string(z) + "]}";
            }
        }
    }
    json += "]}";
    const Scene scene = parseScene(json, "pile");
    expectResumeMatches(scene, {12, 40}, 90);
}

TEST(Determinism, ResumeMatchesMidCloth) {
    // A cloth falling on a sphere: snapshot as it first touches and while it drapes.
    const Scene scene = parseScene(R"({"world": {"dt": 0.0166667, "steps": 1}, "bodies": [
        {"name": "ground", "type": "static", "shape": {"type": "plane", "normal": [0, 1, 0], "offset": 0}},
        {"name": "sphere", "type": "static", "shape": {"type": "sphere", "radius": 0.5}, "position": [0, 0.5, 0]},
        {"name": "crate", "shape": {"type": "box", "half_extents": [0.15, 0.15, 0.15]}, "mass": 0.2, "position": [0.7, 0.15, 0.1]}],
      "cloths": [{"name": "cloth", "origin": [-0.75, 1.4, -0.75], "size": [16, 16], "spacing": 0.1,
                  "particle_mass": 0.01, "radius": 0.03, "bend_compliance": 0.1}]})",
                                   "cloth");
    expectResumeMatches(scene, {20, 45}, 80);
}

TEST(Determinism, ResumeAfterSleepAndWake) {
    // Bodies asleep at the snapshot; the resumed and the original world are
    // both woken by the same push: island tags and timers came back exactly.
    const Scene scene = mixedScene();
    World original = buildWorld(scene);
    int steps = 0;
    const BodyId b0 = original.findBody("b0");
    // (20 s: how long the pile takes depends on where the capsule c0, which
    // hits the pile spinning at 22 rad/s, comes to rest, and that on the last
    // bits of every step: it has rolled for 12 s down a box before falling off.)
    while (original.isAwake(b0) && steps < 1200) original.step(scene.dt), ++steps;
    ASSERT_FALSE(original.isAwake(b0)) << "the pile should fall asleep within 20 s";
    World resumed = loadSnapshotFromMemory(saveSnapshotToMemory(original));
    EXPECT_FALSE(resumed.isAwake(b0));
    for (World* w : {&original, &resumed}) w->applyLinearImpulseAtCenter(w->findBody("b4"), {0, 2, 0});
    for (int i = 0; i < 40; ++i) {
        original.step(scene.dt);
        resumed.step(scene.dt);
        ASSERT_EQ(stateHash(resumed), stateHash(original)) << "step " << i;
    }
    EXPECT_TRUE(original.isAwake(b0));  // the push woke the island it slept with
}

}  // namespace
}  // namespace fulcrum
