// Joint trees of one shape solved four at a time in SIMD lanes of doubles
// (src/solver/joints/tree_lanes.hpp) against the same trees one by one: the
// lanes do each tree's scalar operations in the scalar order, so every
// ragdoll's positions, orientations and velocities equal the ungrouped run's
// (SimdPath::Scalar: no lanes) bit for bit after every step, on the baseline
// and AVX2 kernels and on one and three threads. Nine ragdolls: two groups of
// four and one left over (scalar); they tumble in the air and land on a floor
// and on each other, so guards trip (a tree that trips factors alone, outside
// its group's lanes) and contacts touch them.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "joint_test_util.hpp"
#include "support/same_motion.hpp"
#include "world/world_access.hpp"

using namespace fulcrum;
using namespace fulcrum::jointtest;

namespace {

using detail::SimdPath;

// The bench's ragdoll (joint_simd_rows_test.cpp's): pelvis, torso, head,
// arms, legs; cone-twists and hinges with limits and friction. Eleven bodies,
// the pelvis and torso branch (6 x 6 body blocks in the tree).
void addRagdoll(World& world, std::vector<BodyId>& bodies, Vec3 o, Vec3 velocity, Vec3 spin) {
    const auto body = [&](Shape shape, Real mass, Vec3 p, Quat q = Quat{}) {
        BodyDef d;
        d.shape = shape;
        d.mass = mass;
        d.position = p;
        d.orientation = q;
        d.linearVelocity = velocity;
        d.angularVelocity = spin;
        const BodyId id = world.createBody(d);
        bodies.push_back(id);
        return id;
    };
    const auto joint = [&](JointType type, BodyId a, BodyId b, Vec3 anchor, Vec3 axis, Real lower, Real upper,
                           Real swing = 0) {
        JointDef j = jointDef(type, a, b, anchor, axis);
        if (type == JointType::Hinge) {
            j.hasLimits = true;
            j.lowerLimit = lower;
            j.upperLimit = upper;
        } else {
            j.twistLower = lower;
            j.twistUpper = upper;
            j.swingLimit = swing;
        }
        j.frictionTorque = Real(0.5);
        world.createJoint(j);
    };
    const Quat side = Quat::fromAxisAngle({0, 0, 1}, Real(1.5707963));
    const BodyId pelvis = body(Shape::box({Real(0.15), Real(0.1), Real(0.1)}), 8, o + Vec3{0, 1, 0});
    const BodyId torso = body(Shape::box({Real(0.18), Real(0.22), Real(0.1)}), 15, o + Vec3{0, Real(1.35), 0});
    const BodyId head = body(Shape::sphere(Real(0.11)), 4, o + Vec3{0, Real(1.72), 0});
    joint(JointType::ConeTwist, pelvis, torso, o + Vec3{0, Real(1.1), 0}, {0, 1, 0}, Real(-0.3), Real(0.3), Real(0.4));
    joint(JointType::ConeTwist, torso, head, o + Vec3{0, Real(1.59), 0}, {0, 1, 0}, Real(-0.8), Real(0.8), Real(0.6));
    for (const Real k : {Real(-1), Real(1)}) {
        const BodyId ua = body(Shape::capsule(Real(0.05), Real(0.1)), 2, o + Vec3{k * Real(0.38), Real(1.5), 0}, side);
        const BodyId la = body(Shape::capsule(Real(0.045), Real(0.1)), Real(1.5), o + Vec3{k * Real(0.66), Real(1.5), 0}, side);
        joint(JointType::ConeTwist, torso, ua, o + Vec3{k * Real(0.24), Real(1.5), 0}, {k, 0, 0}, Real(-0.5), Real(0.5), Real(1.2));
        joint(JointType::Hinge, ua, la, o + Vec3{k * Real(0.52), Real(1.5), 0}, {0, 1, 0}, 0, Real(2.5));
        const BodyId th = body(Shape::capsule(Real(0.07), Real(0.13)), 7, o + Vec3{k * Real(0.1), Real(0.7), 0});
        const BodyId sh = body(Shape::capsule(Real(0.06), Real(0.15)), 4, o + Vec3{k * Real(0.1), Real(0.27), 0});
        joint(JointType::ConeTwist, pelvis, th, o + Vec3{k * Real(0.1), Real(0.9), 0}, {0, -1, 0}, Real(-0.3), Real(0.3), Real(0.8));
        joint(JointType::Hinge, th, sh, o + Vec3{k * Real(0.1), Real(0.49), 0}, {1, 0, 0}, Real(-2.5), 0);
    }
}

std::vector<BodyId> buildRagdolls(World& world) {
    world.createBody(boxBody(0, {0, -1, 0}, {20, 1, 20}));  // the floor (mass 0: static)
    std::vector<BodyId> bodies;
    for (int r = 0; r < 9; ++r) {
        const Real x = Real(0.9) * static_cast<Real>(r % 3), z = Real(0.7) * static_cast<Real>(r / 3);
        const Real y = Real(0.3) + Real(0.8) * static_cast<Real>(r % 4);
        addRagdoll(world, bodies, {x, y, z}, {Real(r % 3) - 1, Real(0.5) * static_cast<Real>(r % 2), Real(-0.4)},
                   {Real(0.5) + Real(0.3) * static_cast<Real>(r), Real(-1.5), Real(2) - Real(0.4) * static_cast<Real>(r)});
    }
    return bodies;
}

struct Run {
    SimdPath path;
    int threads;
};

void expectGroupedAsUngrouped(int steps) {
    std::vector<Run> runs = {{SimdPath::Scalar, 1}, {SimdPath::Sse2, 1}, {SimdPath::Sse2, 3}};
    if (detail::avx2Available()) {
        runs.push_back({SimdPath::Avx2, 1});
        runs.push_back({SimdPath::Avx2, 3});
    }
    std::vector<std::unique_ptr<World>> worlds;
    std::vector<std::vector<BodyId>> bodies;
    for (const Run& run : runs) {
        WorldDef def = worldDef(4);
        def.parallelMinBodies = 0;
        worlds.push_back(std::make_unique<World>(def));
        World& world = *worlds.back();
        world.setThreadCount(run.threads);
        ASSERT_EQ(detail::implOf(world).jointSolver.setSimdPath(run.path), run.path);
        bodies.push_back(buildRagdolls(world));
    }
    for (int step = 0; step < steps; ++step) {
        for (std::size_t p = 0; p < worlds.size(); ++p) {
            worlds[p]->step(kDt);
            if (step != 0) continue;
            const detail::JointTreeSolver& trees = detail::implOf(*worlds[p]).jointSolver.trees();
            ASSERT_EQ(trees.treeCount(), 9u);
            EXPECT_EQ(trees.groupedTreeCount(), 8u);  // trees 0-7; the ninth alone
            EXPECT_EQ(trees.lanes(), runs[p].path == SimdPath::Scalar ? 0 : runs[p].path == SimdPath::Avx2 ? 2 : 1);
        }
        const World& reference = *worlds[0];
        for (std::size_t p = 1; p < worlds.size(); ++p) {
            const World& world = *worlds[p];
            for (std::size_t i = 0; i < bodies[0].size(); ++i) {
                ASSERT_TRUE(test::sameMotion(world, bodies[p][i], reference, bodies[0][i]))
                    << detail::simdPathName(runs[p].path) << " (" << runs[p].threads << " threads): body " << i
                    << " differs from the ungrouped run at step " << step + 1;
            }
        }
    }
    // The lanes ran, and so did the trees that tripped out of them (the same
    // trips as one by one: the same anchors).
    const detail::JointTreeSolver& ungrouped = detail::implOf(*worlds[0]).jointSolver.trees();
    EXPECT_EQ(ungrouped.lanePasses(), 0u);
    EXPECT_GT(ungrouped.guardTrips(), 0u);
    for (std::size_t p = 1; p < worlds.size(); ++p) {
        const detail::JointTreeSolver& trees = detail::implOf(*worlds[p]).jointSolver.trees();
        EXPECT_GT(trees.lanePasses(), 0u);
        EXPECT_EQ(trees.guardTrips(), ungrouped.guardTrips());
        EXPECT_EQ(trees.factorizations(), ungrouped.factorizations());
    }
}

}  // namespace

TEST(TreeLanes, GroupedRagdollsMoveAsUngrouped) { expectGroupedAsUngrouped(240); }

// The group's residuals and impulses in SSE float lanes (JointTreeSolver::
// setWideEnds, branch `rain7`) against the same groups with them tree by
// tree: every body bit for bit after each step, on the baseline and AVX2
// kernels and on one and three threads. Besides eight free ragdolls (two
// groups of the scene above), four ragdolls hang from the static world by a
// ball joint at the pelvis (a root joint with a static end: those joints'
// a static end, never pushed) and four frictionless three-armed stars of
// ball joints (trees that fold the warm start into the step's first biased
// pass, which factors tree by tree; their later passes take the wide ends).
// A wrong lane in the residuals or the pushes fails at the first step
// (checked by breaking one product of the pushes).
namespace {

void addStar(World& world, std::vector<BodyId>& bodies, Vec3 o, Vec3 spin) {
    BodyDef hub = sphereBody(3, o, Real(0.15));
    hub.angularVelocity = spin;
    const BodyId centre = world.createBody(hub);
    bodies.push_back(centre);
    const Vec3 arms[3] = {{Real(0.4), 0, 0}, {Real(-0.2), 0, Real(0.35)}, {Real(-0.2), Real(0.1), Real(-0.35)}};
    for (const Vec3& arm : arms) {
        BodyDef d = sphereBody(1, o + arm, Real(0.08));
        d.angularVelocity = spin;
        const BodyId b = world.createBody(d);
        bodies.push_back(b);
        world.createJoint(jointDef(JointType::Ball, centre, b, o + arm * Real(0.5)));
    }
}

std::vector<BodyId> buildMixedTrees(World& world) {
    world.createBody(boxBody(0, {0, -1, 0}, {20, 1, 20}));  // the floor (mass 0: static)
    std::vector<BodyId> bodies;
    for (int r = 0; r < 8; ++r) {
        const Real x = Real(0.9) * static_cast<Real>(r % 3), z = Real(0.7) * static_cast<Real>(r / 3);
        addRagdoll(world, bodies, {x, Real(0.3) + Real(0.8) * static_cast<Real>(r % 4), z},
                   {Real(r % 3) - 1, 0, Real(-0.4)}, {Real(0.5) + Real(0.3) * static_cast<Real>(r), Real(-1.5), Real(1)});
    }
    for (int r = 0; r < 4; ++r) {
        const Vec3 o{Real(5) + Real(1.2) * static_cast<Real>(r), Real(1.5), 0};
        const std::size_t pelvis = bodies.size();
        addRagdoll(world, bodies, o, {Real(1.5), 0, Real(0.5) * static_cast<Real>(r)}, {0, Real(2), Real(-1)});
        world.createJoint(jointDef(JointType::Ball, kWorldBody, bodies[pelvis], o + Vec3{0, Real(1.05), 0}));
    }
    for (int r = 0; r < 4; ++r) {
        addStar(world, bodies, {Real(-5) - Real(1.2) * static_cast<Real>(r), Real(1) + Real(0.5) * static_cast<Real>(r), 2},
                {Real(3), Real(1) - static_cast<Real>(r), Real(2)});
    }
    return bodies;
}

}  // namespace

TEST(TreeLanes, WideEndsMoveAsTreeByTree) {
    struct WideRun {
        SimdPath path;
        int threads;
        bool wide;
    };
    std::vector<WideRun> runs = {{SimdPath::Sse2, 1, false}, {SimdPath::Sse2, 1, true}, {SimdPath::Sse2, 3, true}};
    if (detail::avx2Available()) {
        runs.push_back({SimdPath::Avx2, 1, true});
        runs.push_back({SimdPath::Avx2, 3, true});
    }
    std::vector<std::unique_ptr<World>> worlds;
    std::vector<std::vector<BodyId>> bodies;
    for (const WideRun& run : runs) {
        WorldDef def = worldDef(4);
        def.parallelMinBodies = 0;
        worlds.push_back(std::make_unique<World>(def));
        World& world = *worlds.back();
        world.setThreadCount(run.threads);
        detail::JointSolver& joints = detail::implOf(world).jointSolver;
        ASSERT_EQ(joints.setSimdPath(run.path), run.path);
        joints.trees().setWideEnds(run.wide);
        bodies.push_back(buildMixedTrees(world));
    }
    const int steps = 200;
    for (int step = 0; step < steps; ++step) {
        for (std::size_t p = 0; p < worlds.size(); ++p) {
            worlds[p]->step(kDt);
            if (step != 0) continue;
            const detail::JointTreeSolver& trees = detail::implOf(*worlds[p]).jointSolver.trees();
            ASSERT_EQ(trees.treeCount(), 16u);
            EXPECT_EQ(trees.groupedTreeCount(), 16u);  // free, hanging, stars: four groups
            EXPECT_EQ(trees.wideEnds(), runs[p].wide);
        }
        const World& reference = *worlds[0];
        for (std::size_t p = 1; p < worlds.size(); ++p) {
            const World& world = *worlds[p];
            for (std::size_t i = 0; i < bodies[0].size(); ++i) {
                ASSERT_TRUE(test::sameMotion(world, bodies[p][i], reference, bodies[0][i]))
                    << detail::simdPathName(runs[p].path) << " (" << runs[p].threads << " threads): body " << i
                    << " differs from the tree-by-tree ends at step " << step + 1;
            }
        }
    }
    // Every run solved groups in lanes, tripped guards (the tree-by-tree
    // impulses after wide residuals) and folded warm starts alike.
    const detail::JointTreeSolver& reference = detail::implOf(*worlds[0]).jointSolver.trees();
    EXPECT_GT(reference.lanePasses(), 0u);
    EXPECT_GT(reference.guardTrips(), 0u);
    for (std::size_t p = 1; p < worlds.size(); ++p) {
        const detail::JointTreeSolver& trees = detail::implOf(*worlds[p]).jointSolver.trees();
        EXPECT_EQ(trees.lanePasses(), reference.lanePasses());
        EXPECT_EQ(trees.guardTrips(), reference.guardTrips());
        EXPECT_EQ(trees.factorizations(), reference.factorizations());
    }
    // The stars stayed joined (a wrong impulse would open them): each ball
    // joint's anchor, at the middle of its arm, as carried by the hub and by
    // the arm (both created unrotated), within 1 cm.
    const World& world = *worlds.back();
    const std::vector<BodyId>& b = bodies.back();
    const Vec3 arms[3] = {{Real(0.4), 0, 0}, {Real(-0.2), 0, Real(0.35)}, {Real(-0.2), Real(0.1), Real(-0.35)}};
    for (std::size_t s = 0; s < 4; ++s) {
        const BodyId hub = b[b.size() - 16 + 4 * s];
        for (std::size_t k = 0; k < 3; ++k) {
            const BodyId arm = b[b.size() - 16 + 4 * s + 1 + k];
            const Vec3 onHub = world.position(hub) + rotate(world.orientation(hub), arms[k] * Real(0.5));
            const Vec3 onArm = world.position(arm) + rotate(world.orientation(arm), arms[k] * Real(-0.5));
            EXPECT_LT(length(onHub - onArm), Real(0.01)) << "star " << s << ", arm " << k;
        }
    }
}


// The passes that factor, for a group of four, in lanes too
// (JointTreeSolver::setLaneFactor, branch `rain8`: factorTreeLanes, the
// eliminations of every node kind and the back-substitution, then the
// group's impulses) against the same groups factored tree by tree (and
// their blocks copied into the lanes): every body bit for bit after each
// step, on the baseline and AVX2 kernels, on one and three threads, and with
// the wide ends off (the factoring pass's impulses tree by tree, from the
// lanes' y). The mixed trees above: free ragdolls (root body, body below a
// joint, joints below bodies and below joints), hanging ragdolls (a root
// joint with a static end) and stars (a root body, contracted leaves,
// folded warm starts). The same lane passes, guard trips and
// factorizations. A tree whose guard trips on a kept-factor pass factors
// again in its group's lanes (branch `rain11`: refactorTrippedInLanes, in
// place when all four trip, else in a scratch copy whose other lanes are
// dropped), against the reference's tree-by-tree factorization and its
// copy into the lanes: the bodies, the kept blocks (sameLaneBlocks) and
// each such factorization against the scalar one (setLaneFactorCheck); and
// with two lanes of every such group made to fail there
// (setTrippedLaneFailures), their trees factoring alone at once.
TEST(TreeLanes, LaneFactorizationsMoveAsTreeByTree) {
    struct FactorRun {
        SimdPath path;
        int threads;
        bool laneFactor, wide;
        unsigned failLanes = 0;  // setTrippedLaneFailures: these lanes' trees take the fallback
    };
    std::vector<FactorRun> runs = {{SimdPath::Sse2, 1, false, true},
                                   {SimdPath::Sse2, 1, true, true},
                                   {SimdPath::Sse2, 3, true, true},
                                   {SimdPath::Sse2, 1, true, false},
                                   {SimdPath::Sse2, 1, true, true, 5u}};
    if (detail::avx2Available()) {
        runs.push_back({SimdPath::Avx2, 1, true, true});
        runs.push_back({SimdPath::Avx2, 3, true, true});
        runs.push_back({SimdPath::Avx2, 1, true, false});
        runs.push_back({SimdPath::Avx2, 3, true, true, 10u});
    }
    std::vector<std::unique_ptr<World>> worlds;
    std::vector<std::vector<BodyId>> bodies;
    for (const FactorRun& run : runs) {
        WorldDef def = worldDef(4);
        def.parallelMinBodies = 0;
        worlds.push_back(std::make_unique<World>(def));
        World& world = *worlds.back();
        world.setThreadCount(run.threads);
        detail::JointSolver& joints = detail::implOf(world).jointSolver;
        ASSERT_EQ(joints.setSimdPath(run.path), run.path);
        joints.trees().setLaneFactor(run.laneFactor);
        joints.trees().setLaneFactorCheck(run.laneFactor);
        joints.trees().setWideEnds(run.wide);
        joints.trees().setTrippedLaneFailures(run.failLanes);
        bodies.push_back(buildMixedTrees(world));
    }
    const int steps = 200;
    for (int step = 0; step < steps; ++step) {
        for (std::size_t p = 0; p < worlds.size(); ++p) {
            worlds[p]->step(kDt);
            if (step != 0) continue;
            const detail::JointTreeSolver& trees = detail::implOf(*worlds[p]).jointSolver.trees();
            ASSERT_EQ(trees.treeCount(), 16u);
            EXPECT_EQ(trees.groupedTreeCount(), 16u);
            EXPECT_EQ(trees.laneFactor(), runs[p].laneFactor);
            // Every group factored at the step's first pass: in lanes, or not at all.
            EXPECT_EQ(trees.laneFactorPasses(), runs[p].laneFactor ? 4u : 0u);
        }
        const World& reference = *worlds[0];
        for (std::size_t p = 1; p < worlds.size(); ++p) {
            const World& world = *worlds[p];
            for (std::size_t i = 0; i < bodies[0].size(); ++i) {
                ASSERT_TRUE(test::sameMotion(world, bodies[p][i], reference, bodies[0][i]))
                    << detail::simdPathName(runs[p].path) << " (" << runs[p].threads << " threads, wide ends "
                    << runs[p].wide << "): body " << i << " differs from the tree-by-tree factorizations at step "
                    << step + 1;
            }
            // The double blocks kept at the step's end too (a last-bit error
            // there rarely reaches a float; most are a tripped tree's own).
            ASSERT_TRUE(detail::implOf(world).jointSolver.trees().sameLaneBlocks(detail::implOf(reference).jointSolver.trees()))
                << detail::simdPathName(runs[p].path) << " (" << runs[p].threads << " threads, wide ends " << runs[p].wide
                << "): the lanes' factorizations differ from the tree-by-tree ones at step " << step + 1;
            // Every factorization in lanes against the scalar one, in doubles (setLaneFactorCheck).
            ASSERT_EQ(detail::implOf(world).jointSolver.trees().laneFactorMismatches(), 0u)
                << detail::simdPathName(runs[p].path) << " (" << runs[p].threads << " threads, wide ends " << runs[p].wide
                << "): a tree factored in lanes differs from its scalar factorization at step " << step + 1;
        }
    }
    const detail::JointTreeSolver& reference = detail::implOf(*worlds[0]).jointSolver.trees();
    EXPECT_EQ(reference.laneFactorPasses(), 0u);
    EXPECT_EQ(reference.trippedLaneFactors(), 0u);
    EXPECT_GT(reference.guardTrips(), 0u);
    for (std::size_t p = 1; p < worlds.size(); ++p) {
        const detail::JointTreeSolver& trees = detail::implOf(*worlds[p]).jointSolver.trees();
        EXPECT_GT(trees.laneFactorPasses(), 0u);
        EXPECT_GT(trees.trippedLaneFactors(), 0u);
        EXPECT_EQ(trees.laneFactorChecks(), 4 * trees.laneFactorPasses() + trees.trippedLaneFactors());
        EXPECT_EQ(trees.lanePasses(), reference.lanePasses());
        EXPECT_EQ(trees.guardTrips(), reference.guardTrips());
        EXPECT_EQ(trees.factorizations(), reference.factorizations());
    }
}
