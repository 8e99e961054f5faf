// Hinge and cone-twist rows in SIMD lanes (src/solver/joints/
// hinge_wide.hpp, cone_twist_wide.hpp) against the scalar
// kernels: the scalar path, 4 lanes (SSE2) and 8 lanes (AVX2), on 1 and 3
// threads, give the same positions, orientations and velocities after every
// step on a scene that runs every row and branch: hinges with limits (hit),
// motors, springs (some force-limited and saturated) and friction (a motor
// at speed 0), cone-twists with swing and twist limits (hit), unlimited cones
// and friction, ball joints with friction (in the cone-twist blocks), in
// loops (Gauss-Seidel point blocks) and in joint trees (ragdolls, chains: the tree solver
// has the point rows), to static and kinematic ends, with contacts. Then the
// physics on the wide path: a hinge pendulum's period, a limit holding a
// load, friction holding a load below its torque and not above.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include "joint_test_util.hpp"
#include "support/same_motion.hpp"
#include "world/world_access.hpp"

using namespace fulcrum;
using namespace fulcrum::jointtest;

namespace {

using detail::SimdPath;

// A ragdoll (the bench's: pelvis, torso, head, arms, legs; cone-twists and
// hinges with limits and 0.5 N m friction): a joint tree.
void addRagdoll(World& world, std::vector<BodyId>& bodies, Vec3 o, Vec3 velocity) {
    const auto body = [&](Shape shape, Real mass, Vec3 p, Quat q = Quat{}) {
        BodyDef d;
        d.shape = shape;
        d.mass = mass;
        d.position = p;
        d.orientation = q;
        d.linearVelocity = velocity;
        d.angularVelocity = {Real(0.5), Real(-1.5), Real(2)};
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

// Every kind of hinge and cone-twist row, in loops and trees.
std::vector<BodyId> buildRowScene(World& world) {
    std::vector<BodyId> bodies;
    BodyDef floor = boxBody(1, {0, Real(-0.5), 0}, {30, Real(0.5), 30});
    floor.type = BodyType::Static;
    world.createBody(floor);
    // A lattice of spheres hanging from a static layer, joined in loops by
    // hinges (limits, motors, springs, friction, in mixes), cone-twists
    // (limited and unlimited cones, friction) and ball joints; swinging.
    const int side = 4, layers = 3;
    std::vector<BodyId> ids(static_cast<std::size_t>(side * side * (layers + 1)));
    const auto at = [&](int x, int y, int z) -> BodyId& { return ids[static_cast<std::size_t>((y * side + z) * side + x)]; };
    const Vec3 origin{-6, 12, -6};
    for (int y = 0; y <= layers; ++y) {
        for (int z = 0; z < side; ++z) {
            for (int x = 0; x < side; ++x) {
                BodyDef d = sphereBody(Real(1) + Real(0.1) * static_cast<Real>(x),
                                       origin + Vec3{static_cast<Real>(x), static_cast<Real>(-y), static_cast<Real>(z)}, Real(0.2));
                d.type = y == 0 ? BodyType::Static : BodyType::Dynamic;
                if (y > 0 && (x + z) % 3 == 0) d.linearVelocity = {Real(2), 0, Real(-1)};
                at(x, y, z) = world.createBody(d);
                if (y > 0) bodies.push_back(at(x, y, z));
            }
        }
    }
    int index = 0;
    const auto link = [&](BodyId a, BodyId b) {
        const Vec3 axes[3] = {{1, 0, 0}, {0, 0, 1}, normalize(Vec3{1, 1, 0})};
        JointDef j = jointDef(JointType::Ball, a, b, (world.position(a) + world.position(b)) * Real(0.5), axes[index % 3]);
        // The rows in every mix (h: the hinge's or cone's ordinal): a
        // spring, a motor and limits on one hinge, friction with limits...
        const int h = index / 3;
        switch (index % 3) {
            case 0:
                j.type = JointType::Hinge;
                if (h % 2 == 0) {
                    j.hasLimits = true;
                    j.lowerLimit = Real(-0.2);
                    j.upperLimit = Real(0.25);
                }
                if (h % 3 == 1) {
                    j.motor.enabled = true;
                    j.motor.speed = Real(1.5);
                    j.motor.maxForce = 3;
                }
                if (h % 5 >= 2) {
                    j.spring.enabled = true;
                    j.spring.stiffness = 40;
                    j.spring.damping = Real(0.5);
                    j.spring.target = Real(0.2);
                    // Every other spring with a force limit it reaches (the drive saturated).
                    if (h % 2 == 1) j.spring.maxForce = Real(1.5);
                }
                if (h % 3 == 2) j.frictionTorque = Real(0.4);  // a motor at speed 0
                break;
            case 1:
                j.type = JointType::ConeTwist;
                j.swingLimit = h % 4 == 3 ? Real(kPi) : Real(0.25);  // pi: no cone
                j.twistLower = Real(-0.1);
                j.twistUpper = Real(0.15);
                if (h % 2 == 1) j.frictionTorque = Real(0.3);
                break;
            default:
                if (h % 2 == 0) j.frictionTorque = Real(0.25);  // a ball joint with friction: the cone blocks
                break;
        }
        ++index;
        world.createJoint(j);
    };
    for (int y = 1; y <= layers; ++y) {
        for (int z = 0; z < side; ++z) {
            for (int x = 0; x < side; ++x) {
                link(at(x, y - 1, z), at(x, y, z));
                if (x > 0) link(at(x - 1, y, z), at(x, y, z));
                if (z > 0) link(at(x, y, z - 1), at(x, y, z));
            }
        }
    }
    // A kinematic rotor with hinges (motor, limits) and cone-twists to a ring
    // of spheres: kinematic ends, read and never written.
    BodyDef rotor = boxBody(1, {12, 6, 0}, {Real(0.4), Real(0.4), Real(0.4)});
    rotor.type = BodyType::Kinematic;
    rotor.angularVelocity = {0, Real(1.2), Real(0.3)};
    const BodyId kinematic = world.createBody(rotor);
    bodies.push_back(kinematic);
    for (int i = 0; i < 10; ++i) {
        const Real angle = Real(2 * kPi / 10) * static_cast<Real>(i);
        const Vec3 p = Vec3{12, 6, 0} + Vec3{std::cos(angle), 0, std::sin(angle)} * Real(1.5);
        const BodyId s = world.createBody(sphereBody(Real(0.5) + Real(0.2) * static_cast<Real>(i), p, Real(0.2)));
        bodies.push_back(s);
        JointDef j = jointDef(i % 2 == 0 ? JointType::Hinge : JointType::ConeTwist, kinematic, s, (Vec3{12, 6, 0} + p) * Real(0.5),
                              {std::cos(angle), 0, std::sin(angle)});
        j.hasLimits = true;
        j.lowerLimit = Real(-0.3);
        j.upperLimit = Real(0.3);
        j.motor.enabled = i % 4 == 0;
        j.motor.speed = -2;
        j.motor.maxForce = 5;
        j.swingLimit = Real(0.4);
        j.frictionTorque = i % 3 == 0 ? Real(0.2) : 0;
        world.createJoint(j);
    }
    // Chains from the world (trees): hinges with limits and a spring, and
    // cone-twists with friction; the first joint of each has a static end.
    for (int chain = 0; chain < 2; ++chain) {
        BodyId previous = kWorldBody;
        for (int i = 0; i < 6; ++i) {
            const Vec3 p{Real(20) + Real(0.6) * static_cast<Real>(i), 8, Real(3) * static_cast<Real>(chain)};
            const BodyId l = world.createBody(boxBody(1, p, {Real(0.25), Real(0.08), Real(0.08)}));
            bodies.push_back(l);
            JointDef j = jointDef(chain == 0 ? JointType::Hinge : JointType::ConeTwist, previous, l, p - Vec3{Real(0.3), 0, 0},
                                  chain == 0 ? Vec3{0, 0, 1} : Vec3{1, 0, 0});
            j.hasLimits = true;
            j.lowerLimit = Real(-0.4);
            j.upperLimit = Real(0.4);
            j.spring.enabled = i % 2 == 0;
            j.spring.stiffness = 20;
            j.spring.damping = Real(0.2);
            if (i == 2) j.spring.maxForce = Real(0.8);  // a force-limited drive in a tree
            j.swingLimit = Real(0.3);
            j.frictionTorque = chain == 1 ? Real(0.2) : 0;
            world.createJoint(j);
            previous = l;
        }
    }
    // Ragdolls thrown onto the floor and each other (trees and contacts).
    for (int r = 0; r < 6; ++r) {
        addRagdoll(world, bodies, {Real(-3) + Real(1.3) * static_cast<Real>(r), Real(0.6) + Real(0.5) * static_cast<Real>(r % 2), 4},
                   {Real(r % 3) - 1, Real(1), Real(0.5) * static_cast<Real>(r % 2)});
    }
    return bodies;
}

int lanesOf(SimdPath path) { return path == SimdPath::Avx2 ? 8 : 4; }

// Steps one world per path (the contact solver scalar in all) and requires
// every body's state to equal the scalar run's after every step (==).
void expectRowsAgree(int threads, int steps) {
    std::vector<SimdPath> paths = {SimdPath::Scalar, SimdPath::Sse2};
    if (detail::avx2Available()) paths.push_back(SimdPath::Avx2);
    std::vector<std::unique_ptr<World>> worlds;
    std::vector<std::vector<BodyId>> bodies;
    for (const SimdPath path : paths) {
        WorldDef def = worldDef(4);
        def.parallelMinBodies = 0;
        worlds.push_back(std::make_unique<World>(def));
        World& world = *worlds.back();
        world.setThreadCount(path == SimdPath::Scalar ? 1 : threads);
        detail::implOf(world).contactSolver.setSimdPath(SimdPath::Scalar);
        ASSERT_EQ(detail::implOf(world).jointSolver.setSimdPath(path), path);
        bodies.push_back(buildRowScene(world));
    }
    for (int step = 0; step < steps; ++step) {
        for (std::size_t p = 0; p < worlds.size(); ++p) {
            worlds[p]->step(kDt);
            if (step != 0) continue;
            const detail::JointSolver& solver = detail::implOf(*worlds[p]).jointSolver;
            if (paths[p] == SimdPath::Scalar) {
                EXPECT_EQ(solver.wideJointCount(), 0u);
                continue;
            }
            // Nearly every joint in lanes (the overflow colour's stay
            // scalar), blocks of a kind part-filled, and trees present.
            EXPECT_GT(solver.wideJointCount() * 10, solver.constraintCount() * 9);
            EXPECT_GT(solver.wideBlockCount() * static_cast<std::size_t>(lanesOf(paths[p])), solver.wideJointCount());
            EXPECT_FALSE(solver.trees().empty());
        }
        const World& reference = *worlds[0];
        for (std::size_t p = 1; p < worlds.size(); ++p) {
            const World& world = *worlds[p];
            for (std::size_t i = 0; i < bodies[0].size(); ++i) {
                ASSERT_TRUE(test::sameMotion(world, bodies[p][i], reference, bodies[0][i]))
                    << detail::simdPathName(paths[p]) << " (" << threads << " threads): body " << i
                    << " differs from the scalar path at step " << step + 1;
            }
        }
    }
}

}  // namespace

TEST(JointSimdRows, HingesAndConeTwistsAreTheSameOnEveryPath) { expectRowsAgree(1, 200); }

// Blocks in ranges across three threads, against the scalar path on one.
TEST(JointSimdRows, HingesAndConeTwistsAreTheSameOnEveryPathAcrossThreads) { expectRowsAgree(3, 120); }

namespace {

// Each path in turn for a physics check (the scalar path as the reference).
std::vector<SimdPath> allPaths() {
    std::vector<SimdPath> paths = {SimdPath::Scalar, SimdPath::Sse2};
    if (detail::avx2Available()) paths.push_back(SimdPath::Avx2);
    return paths;
}

World& onPath(World& world, SimdPath path) {
    detail::implOf(world).jointSolver.setSimdPath(path);
    return world;
}

}  // namespace

// A thin rod (mass 1, length 2 l = 0.8 m, its end on a hinge to the world):
// a compound pendulum of equivalent length I / (m d) = (4/3 l^2) / l = 4 l / 3,
// released from 10 degrees: the period within 1 % of the AGM's on every path.
TEST(JointSimdRows, HingePendulumPeriod) {
    for (const SimdPath path : allPaths()) {
        World world(worldDef(4));
        onPath(world, path);
        const double l = 0.4, theta0 = 10 * kPi / 180;
        const Quat tilt = Quat::fromAxisAngle({0, 0, 1}, Real(theta0));
        BodyDef d = boxBody(1, rotate(tilt, Vec3{0, Real(-l), 0}), {Real(0.01), Real(l), Real(0.01)});
        d.orientation = tilt;
        const BodyId rod = world.createBody(d);
        const JointId hinge = world.createJoint(jointDef(JointType::Hinge, kWorldBody, rod, {0, 0, 0}, {0, 0, 1}));
        const double T = measurePeriod(world, [&] { return double(world.position(rod).x); }, 6, 2000);
        const double expected = pendulumPeriod(4 * l / 3, theta0);
        EXPECT_NEAR(T / expected, 1, 0.01) << detail::simdPathName(path) << ": T " << T << " expected " << expected;
        EXPECT_LT(world.jointError(hinge), 1e-3);
        EXPECT_EQ(detail::implOf(world).jointSolver.wideJointCount(), path == SimdPath::Scalar ? 0u : 1u);
    }
}

// A horizontal lever (mass m = 2, centre r = 0.5 m from its hinge) held up by
// the hinge's lower limit at 0: after 2 s at rest within 0.02 rad of the
// limit, the hinge carries its weight (force m g up within 1 %) and the
// limit its moment (torque m g r within 2 %), on every path.
TEST(JointSimdRows, HingeLimitHoldsALoad) {
    for (const SimdPath path : allPaths()) {
        World world(worldDef(4));
        onPath(world, path);
        const double m = 2, r = 0.5;
        const BodyId lever = world.createBody(boxBody(Real(m), {Real(r), 0, 0}, {Real(r), Real(0.03), Real(0.03)}));
        JointDef j = jointDef(JointType::Hinge, kWorldBody, lever, {0, 0, 0}, {0, 0, 1});
        j.hasLimits = true;
        j.lowerLimit = 0;  // the lever falls clockwise about +z, to negative angles
        j.upperLimit = Real(1);
        const JointId hinge = world.createJoint(j);
        for (int i = 0; i < 120; ++i) world.step(kDt);
        const Vec3 tip = world.position(lever);
        const double angle = std::atan2(double(tip.y), double(tip.x));
        EXPECT_NEAR(angle, 0, 0.02) << detail::simdPathName(path);
        const Vec3 force = world.jointReactionForce(hinge), torque = world.jointReactionTorque(hinge);
        EXPECT_NEAR(force.y, m * kG, 0.01 * m * kG) << detail::simdPathName(path);
        EXPECT_NEAR(std::fabs(double(torque.z)), m * kG * r, 0.02 * m * kG * r) << detail::simdPathName(path);
        EXPECT_EQ(detail::implOf(world).jointSolver.wideJointCount(), path == SimdPath::Scalar ? 0u : 1u);
    }
}

// Friction on a lever's hinge (the lever's weight has moment m g r = 4.9 N m
// about it): 1.5 x that holds it (turned under 0.01 rad in 1 s), 0.5 x lets
// it fall (over 0.3 rad), on every path; and the same with a cone-twist (its
// friction block) holding a side lever.
TEST(JointSimdRows, FrictionHoldsALoadBelowItsTorqueOnly) {
    for (const SimdPath path : allPaths()) {
        for (const JointType type : {JointType::Hinge, JointType::ConeTwist}) {
            for (const double factor : {1.5, 0.5}) {
                World world(worldDef(4));
                onPath(world, path);
                const double m = 1, r = 0.5;
                const BodyId lever = world.createBody(boxBody(Real(m), {Real(r), 0, 0}, {Real(r), Real(0.03), Real(0.03)}));
                JointDef j = jointDef(type, kWorldBody, lever, {0, 0, 0}, type == JointType::Hinge ? Vec3{0, 0, 1} : Vec3{1, 0, 0});
                j.frictionTorque = Real(factor * m * kG * r);
                j.swingLimit = Real(kPi);  // the cone-twist: no limits in the way
                j.twistLower = Real(-3);
                j.twistUpper = Real(3);
                world.createJoint(j);
                for (int i = 0; i < 60; ++i) world.step(kDt);
                const Vec3 c = world.position(lever);
                const double drop = std::atan2(-double(c.y), double(c.x));
                if (factor > 1) {
                    EXPECT_LT(std::fabs(drop), 0.01) << detail::simdPathName(path) << " type " << static_cast<int>(type);
                } else {
                    EXPECT_GT(drop, 0.3) << detail::simdPathName(path) << " type " << static_cast<int>(type);
                }
            }
        }
    }
}
