// Ball joints in SIMD lanes (src/solver/joints/joint_wide.hpp) against the
// scalar reference: the same float operations in the same order, so the
// scalar path, 4 lanes (SSE2) and 8 lanes (AVX2) give the same positions,
// orientations and velocities after every step, on a jointed lattice (every
// joint in lanes) and on a mixed scene that makes every branch run: static
// and kinematic ends, joints with friction and other types beside the wide
// ones in a colour, colours smaller than a block, the overflow colour, joint
// trees, and the task system (its friction joints, cone-twists and hinges
// are in lanes too since the second round; joint_simd_rows_test.cpp has those
// in depth). Then the physics: a hanging lattice carries exactly its weight
// at its static anchors.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "joint_test_util.hpp"
#include "support/same_motion.hpp"
#include "world/world_access.hpp"

using namespace fulcrum;
using namespace fulcrum::jointtest;

namespace {

using detail::SimdPath;

struct Scene {
    std::vector<BodyId> bodies;          // every body whose state is compared (dynamic and kinematic)
    std::vector<JointId> anchors;        // lattice joints to the static top layer
    std::vector<BodyId> latticeBodies;   // the lattice's dynamic bodies
    std::vector<JointId> joints;         // the lattice's joints
};

// A side x side lattice of spheres (mass 1, 1 m apart) with `layers` dynamic
// layers hanging below a static one, each joined by ball joints to its
// neighbours above and beside: loops. With the tree solver on, each column
// is a tree solved exactly and the cross joints close loops (Gauss-Seidel
// rows); with it off (WorldDef::jointDirectSolve), every joint is a
// Gauss-Seidel row, what the lane tests below want.
// `tweak` may change a joint's definition (friction, type) by its index.
void addLattice(World& world, Scene& s, Vec3 origin, int side, int layers,
                const std::function<void(JointDef&, int)>& tweak = {}) {
    std::vector<BodyId> ids(static_cast<std::size_t>(side * side * (layers + 1)));
    const auto at = [&](int x, int y, int z) -> BodyId& {
        return ids[static_cast<std::size_t>((y * side + z) * side + x)];
    };
    for (int y = 0; y <= layers; ++y) {
        for (int z = 0; z < side; ++z) {
            for (int x = 0; x < side; ++x) {
                BodyDef d = sphereBody(1, origin + Vec3{static_cast<Real>(x), static_cast<Real>(-y), static_cast<Real>(z)},
                                       Real(0.2));
                d.type = y == 0 ? BodyType::Static : BodyType::Dynamic;
                at(x, y, z) = world.createBody(d);
                if (y > 0) {
                    s.bodies.push_back(at(x, y, z));
                    s.latticeBodies.push_back(at(x, y, z));
                }
            }
        }
    }
    int index = 0;
    for (int y = 1; y <= layers; ++y) {
        for (int z = 0; z < side; ++z) {
            for (int x = 0; x < side; ++x) {
                const BodyId b = at(x, y, z);
                const auto link = [&](BodyId a, bool anchor) {
                    JointDef j = jointDef(JointType::Ball, a, b, (world.position(a) + world.position(b)) * Real(0.5));
                    if (tweak) tweak(j, index);
                    ++index;
                    const JointId id = world.createJoint(j);
                    s.joints.push_back(id);
                    if (anchor) s.anchors.push_back(id);
                };
                link(at(x, y - 1, z), y == 1);
                if (x > 0) link(at(x - 1, y, z), false);
                if (z > 0) link(at(x, y, z - 1), false);
            }
        }
    }
}

// The lattice alone, swinging (pushed sideways at the start).
Scene buildSwingingLattice(World& world) {
    Scene s;
    addLattice(world, s, {0, 0, 0}, 8, 6);
    for (std::size_t i = 0; i < s.bodies.size(); i += 7) world.setLinearVelocity(s.bodies[i], {Real(1.5), 0, Real(-0.7)});
    return s;
}

// Everything the joint solver distinguishes, in one world.
Scene buildMixedScene(World& world) {
    Scene s;
    // A lattice with joints of every wide kind in its colours: ball joints
    // with and without friction, cone-twist and hinge joints.
    addLattice(world, s, {0, 10, 0}, 4, 3, [](JointDef& j, int index) {
        if (index % 5 == 2) j.frictionTorque = Real(0.3);
        if (index % 11 == 4) {
            j.type = JointType::ConeTwist;
            j.swingLimit = Real(0.5);
        }
        if (index % 13 == 6) j.type = JointType::Hinge;
    });
    // A kinematic rotor with a ring of six spheres joined to it and to each
    // other: kinematic ends, which lanes read and never write.
    BodyDef rotor = boxBody(1, {12, 5, 0}, {Real(0.4), Real(0.4), Real(0.4)});
    rotor.type = BodyType::Kinematic;
    rotor.angularVelocity = {0, Real(1.2), Real(0.3)};
    rotor.linearVelocity = {Real(0.3), 0, 0};
    const BodyId kinematic = world.createBody(rotor);
    s.bodies.push_back(kinematic);
    std::vector<BodyId> ring;
    for (int i = 0; i < 6; ++i) {
        const Real angle = Real(2 * kPi / 6) * static_cast<Real>(i);
        const Vec3 p = Vec3{12, 5, 0} + Vec3{std::cos(angle), 0, std::sin(angle)} * Real(1.5);
        ring.push_back(world.createBody(sphereBody(Real(0.5) + Real(0.25) * static_cast<Real>(i), p, Real(0.2))));
        s.bodies.push_back(ring.back());
        world.createJoint(jointDef(JointType::Ball, kinematic, ring.back(), (Vec3{12, 5, 0} + p) * Real(0.5)));
    }
    for (int i = 0; i < 6; ++i) {
        const BodyId a = ring[static_cast<std::size_t>(i)], b = ring[static_cast<std::size_t>((i + 1) % 6)];
        world.createJoint(jointDef(JointType::Ball, a, b, (world.position(a) + world.position(b)) * Real(0.5)));
    }
    // A hub with 30 spokes joined to it and in a ring: the hub's joints need
    // 30 colours, so some land in the overflow colour, and the late colours
    // hold fewer joints than a block has lanes. The hub hangs from the world.
    const BodyId hub = world.createBody(sphereBody(5, {-12, 5, 0}, Real(0.5)));
    s.bodies.push_back(hub);
    world.createJoint(jointDef(JointType::Ball, kWorldBody, hub, {-12, Real(5.5), 0}));
    std::vector<BodyId> spokes;
    for (int i = 0; i < 30; ++i) {
        const Real angle = Real(2 * kPi / 30) * static_cast<Real>(i);
        const Vec3 p = Vec3{-12, 5, 0} + Vec3{std::cos(angle), Real(0.1) * static_cast<Real>(i % 3), std::sin(angle)} * Real(2);
        spokes.push_back(world.createBody(sphereBody(Real(0.3), p, Real(0.1))));
        s.bodies.push_back(spokes.back());
        world.createJoint(jointDef(JointType::Ball, hub, spokes.back(), (world.position(hub) + p) * Real(0.5)));
    }
    for (int i = 0; i < 30; ++i) {
        const BodyId a = spokes[static_cast<std::size_t>(i)], b = spokes[static_cast<std::size_t>((i + 1) % 30)];
        world.createJoint(jointDef(JointType::Ball, a, b, (world.position(a) + world.position(b)) * Real(0.5)));
    }
    // Chains from the world: joint trees (the tree solver's point rows), one
    // of them with friction (its friction rows in lanes, the other's joints scalar).
    for (int chain = 0; chain < 2; ++chain) {
        BodyId previous = kWorldBody;
        for (int i = 0; i < 5; ++i) {
            const Vec3 p{Real(20) + Real(0.6) * static_cast<Real>(i), 8, Real(3) * static_cast<Real>(chain)};
            const BodyId link = world.createBody(sphereBody(1, p, Real(0.15)));
            s.bodies.push_back(link);
            JointDef j = jointDef(JointType::Ball, previous, link, p - Vec3{Real(0.3), 0, 0});
            if (chain == 1) j.frictionTorque = Real(0.2);
            world.createJoint(j);
            previous = link;
        }
    }
    return s;
}

// Steps a world per path (the joint solver's; the contact solver's is the
// scalar one in all) and requires every compared body's position,
// orientation and velocities to equal the scalar run's after every step
// (==: the sign of a zero may differ, no later operation turns it into a
// different value). `check` looks at each world's joint solver after step 1.
void expectPathsAgree(const std::function<Scene(World&)>& build, int steps, int threads,
                      const std::function<void(const detail::JointSolver&, SimdPath)>& check, bool trees = true) {
    std::vector<SimdPath> paths = {SimdPath::Scalar, SimdPath::Sse2};
    if (detail::avx2Available()) paths.push_back(SimdPath::Avx2);
    std::vector<std::unique_ptr<World>> worlds;
    std::vector<Scene> scenes;
    for (const SimdPath path : paths) {
        WorldDef def = worldDef(5);
        def.parallelMinBodies = 0;
        def.jointDirectSolve = trees;
        worlds.push_back(std::make_unique<World>(def));
        World& world = *worlds.back();
        world.setThreadCount(path == SimdPath::Scalar ? 1 : threads);
        detail::implOf(world).contactSolver.setSimdPath(SimdPath::Scalar);
        ASSERT_EQ(detail::implOf(world).jointSolver.setSimdPath(path), path);
        scenes.push_back(build(world));
    }
    for (int step = 0; step < steps; ++step) {
        for (std::size_t p = 0; p < worlds.size(); ++p) {
            worlds[p]->step(kDt);
            if (step == 0) check(detail::implOf(*worlds[p]).jointSolver, paths[p]);
        }
        const World& reference = *worlds[0];
        for (std::size_t p = 1; p < worlds.size(); ++p) {
            const World& world = *worlds[p];
            for (std::size_t i = 0; i < scenes[0].bodies.size(); ++i) {
                ASSERT_TRUE(test::sameMotion(world, scenes[p].bodies[i], reference, scenes[0].bodies[i]))
                    << detail::simdPathName(paths[p]) << " (" << threads << " threads): body " << i
                    << " differs from the scalar path at step " << step + 1;
            }
        }
    }
}

int lanesOf(SimdPath path) { return path == SimdPath::Avx2 ? 8 : 4; }

void expectLatticeAgrees(int threads) {
    expectPathsAgree(buildSwingingLattice, 60, threads, [](const detail::JointSolver& solver, SimdPath path) {
        if (path == SimdPath::Scalar) {
            EXPECT_EQ(solver.wideJointCount(), 0u);
            return;
        }
        // Every joint is a Gauss-Seidel ball joint (the tree solver off) in a
        // regular colour, and the colours are large enough for the task system
        // (over 2 x 64 joints).
        EXPECT_EQ(solver.wideJointCount(), solver.constraintCount());
        EXPECT_GT(solver.wideJointsInColour(0), 128u);
        EXPECT_GE(solver.wideBlockCount() * static_cast<std::size_t>(lanesOf(path)), solver.wideJointCount());
    }, /*trees=*/false);
}

}  // namespace

TEST(JointSimd, SwingingLatticeIsTheSameOnEveryPath) { expectLatticeAgrees(1); }

// The colours' blocks in ranges on three threads: the same bits as the scalar
// path on one (a colour's lanes and ranges share no dynamic body).
TEST(JointSimd, SwingingLatticeIsTheSameOnEveryPathAcrossThreads) { expectLatticeAgrees(3); }

TEST(JointSimd, MixedSceneIsTheSameOnEveryPath) {
    for (const int threads : {1, 2}) {
        expectPathsAgree(buildMixedScene, 150, threads, [](const detail::JointSolver& solver, SimdPath path) {
            if (path == SimdPath::Scalar) return;
            // Lanes and scalar joints side by side.
            EXPECT_GT(solver.wideJointCount(), 100u);
            EXPECT_LT(solver.wideJointCount(), solver.constraintCount());
            // The overflow colour is in use (it stays scalar), and a regular
            // colour has wide joints but fewer than a block's lanes.
            const std::size_t colours = solver.colourCount();
            ASSERT_GE(colours, 2u);
            EXPECT_LT(solver.colourStart(colours - 1), solver.constraintCount());
            EXPECT_EQ(solver.wideJointsInColour(colours - 1), 0u);
            bool partColour = false;
            for (std::size_t c = 0; c + 1 < colours; ++c) {
                const std::size_t n = solver.wideJointsInColour(c);
                partColour = partColour || (n > 0 && n < static_cast<std::size_t>(lanesOf(path)));
            }
            EXPECT_TRUE(partColour) << "no colour with fewer wide joints than lanes";
            // The chains are trees: their joints are not in lanes.
            EXPECT_FALSE(solver.trees().empty());
        });
    }
}

// One switch for both solvers: the joint solver starts on the contact
// solver's path (FULCRUM_SIMD, else the widest this CPU runs), and asking for
// AVX2 where it cannot run gives SSE2.
TEST(JointSimd, PathFollowsTheContactSolversAndFallsBack) {
    World world;
    EXPECT_EQ(detail::implOf(world).jointSolver.simdPath(), detail::implOf(world).contactSolver.simdPath());
    const SimdPath expected = detail::avx2Available() ? SimdPath::Avx2 : SimdPath::Sse2;
    EXPECT_EQ(detail::implOf(world).jointSolver.setSimdPath(SimdPath::Avx2), expected);
    EXPECT_EQ(detail::implOf(world).jointSolver.setSimdPath(SimdPath::Scalar), SimdPath::Scalar);
}

// A hanging lattice at rest carries its weight at its static anchors: the
// joints to the top layer apply, together, exactly the lattice's weight
// upward (every other joint force is internal and cancels). Checked on the
// default path (lanes where the CPU has them) after 4 s of settling, within
// 0.5 % (what is left of the swing; the soft rows' error is not a force
// error at rest).
TEST(JointSimd, HangingLatticeCarriesItsWeightAtItsAnchors) {
    WorldDef def = worldDef(5);
    def.jointDirectSolve = false;  // every joint a Gauss-Seidel row, in lanes
    World world(def);
    Scene s;
    addLattice(world, s, {0, 0, 0}, 5, 4);
    for (int step = 0; step < 240; ++step) world.step(kDt);
    const detail::JointSolver& solver = detail::implOf(world).jointSolver;
    if (solver.simdPath() != SimdPath::Scalar) {
        EXPECT_EQ(solver.wideJointCount(), solver.constraintCount());
    }
    Vec3 total;
    for (const JointId j : s.anchors) total += world.jointReactionForce(j);
    const double weight = static_cast<double>(s.latticeBodies.size()) * kG;
    EXPECT_NEAR(total.y, weight, 0.005 * weight);
    EXPECT_NEAR(total.x, 0, 0.005 * weight);
    EXPECT_NEAR(total.z, 0, 0.005 * weight);
    // At rest, and every joint within the projection slop (5 mm).
    for (const BodyId b : s.latticeBodies) EXPECT_LT(length(world.linearVelocity(b)), Real(0.01));
    for (const JointId j : s.joints) EXPECT_LE(world.jointError(j), Real(0.005));
}

// The same lattice with the tree solver on (the default): a spanning forest,
// one tree per column hanging from its anchor (the joints that carry the
// weight, solved exactly), the cross joints Gauss-Seidel rows closing the
// loops. It carries the same weight at its anchors within 0.5 %, comes to
// rest, and every joint holds within 0.1 mm (Gauss-Seidel alone: up to the
// 5 mm projection slop).
TEST(JointTrees, HangingLatticeIsAForestOfColumns) {
    const int side = 5, layers = 4;
    World world(worldDef(5));
    Scene s;
    addLattice(world, s, {0, 0, 0}, side, layers);
    for (int step = 0; step < 240; ++step) world.step(kDt);
    const detail::JointSolver& solver = detail::implOf(world).jointSolver;
    EXPECT_EQ(solver.trees().treeCount(), static_cast<std::size_t>(side * side));
    // Column joints in trees, the cross joints (2 side (side - 1) per layer) on rows.
    EXPECT_EQ(solver.constraintCount() - solver.trees().directJointCount(),
              static_cast<std::size_t>(2 * side * (side - 1) * layers));
    Vec3 total;
    for (const JointId j : s.anchors) total += world.jointReactionForce(j);
    const double weight = static_cast<double>(s.latticeBodies.size()) * kG;
    EXPECT_NEAR(total.y, weight, 0.005 * weight);
    EXPECT_NEAR(total.x, 0, 0.005 * weight);
    EXPECT_NEAR(total.z, 0, 0.005 * weight);
    for (const BodyId b : s.latticeBodies) EXPECT_LT(length(world.linearVelocity(b)), Real(0.01));
    for (const JointId j : s.joints) EXPECT_LE(world.jointError(j), Real(1e-4));
}
