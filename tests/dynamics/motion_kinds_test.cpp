// Each awake body's integration path (its MotionKind: kinematic, isotropic,
// axisymmetric about one of three axes, general; and whether its velocity
// stage is v += a h alone: dynamic, no damping, no torque) is decided once
// per step (integrators.hpp, classifyMotion) instead of tested at every
// sub-step. The results must be the bits of the per-sub-step tests
// (detail::setMotionKindsPerStepEnabled(false)), at one thread and three,
// while what the kinds depend on changes between steps: a torque applied for
// a step and held for several, damping set and cleared, a body destroyed
// (another body moves into its dense slot) and bodies of other types and
// inertias created, a ForceCallback (the forces evaluated every sub-step),
// the integrator switched. And a world loaded fresh from a snapshot taken in
// the middle of that must go on with the bits of the world it was taken
// from: nothing decided for one step may outlive it.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "determinism/state_hash.hpp"
#include "fulcrum/snapshot.hpp"
#include "fulcrum/world.hpp"
#include "threads/staged_parallel.hpp"

using namespace fulcrum;

namespace {

constexpr int kSteps = 130;
constexpr Real kDt = Real(1) / 60;

Quat turnedAbout(const Vec3& axis, Real angle) {
    const Vec3 a = normalize(axis);
    const Real s = std::sin(angle / 2);
    return normalize(Quat{std::cos(angle / 2), a.x * s, a.y * s, a.z * s});
}

// Bodies of every kind: isotropic (sphere, cube), axisymmetric about each
// body axis (two boxes with two equal sides, a capsule), general (a box of
// three sides, a tensor with off-diagonal entries), kinematic, damped.
std::vector<BodyId> populate(World& world) {
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::box({40, 1, 40});
    ground.position = {0, -1, 0};
    std::vector<BodyId> ids{world.createBody(ground)};
    const auto add = [&](Shape shape, const Vec3& position, const Vec3& spin) {
        BodyDef d;
        d.shape = shape;
        d.mass = 2;
        d.position = position;
        d.orientation = turnedAbout({1, 2, 3}, Real(0.3) * position.x);
        d.angularVelocity = spin;
        ids.push_back(world.createBody(d));
        return ids.size() - 1;
    };
    add(Shape::sphere(Real(0.4)), {-8, Real(0.4), 0}, {0, 0, 0});                                     // 1
    add(Shape::box({Real(0.4), Real(0.4), Real(0.4)}), {-6, Real(1.5), 0}, {1, 2, 0});                // 2
    add(Shape::box({Real(0.6), Real(0.3), Real(0.3)}), {-4, Real(0.3), 0}, {0, 0, 0});                // 3: axis 0
    add(Shape::box({Real(0.3), Real(0.6), Real(0.3)}), {-2, Real(2), 0}, {0, 3, 1});                  // 4: axis 1
    add(Shape::capsule(Real(0.25), Real(0.5)), {0, Real(1.2), 0}, {2, 0, 1});                          // 5
    add(Shape::box({Real(0.2), Real(0.35), Real(0.5)}), {2, Real(1), 0}, {1, -1, 2});                 // 6: general
    {
        BodyDef d;  // 7: an inertia with off-diagonal entries
        d.shape = Shape::box({Real(0.4), Real(0.3), Real(0.35)});
        d.mass = 3;
        d.inertia = Mat3{Vec3{Real(0.2), Real(0.02), Real(-0.01)}, Vec3{Real(0.02), Real(0.25), Real(0.03)},
                         Vec3{Real(-0.01), Real(0.03), Real(0.3)}};
        d.position = {4, Real(2.5), 0};
        d.angularVelocity = {Real(0.5), 4, -1};
        ids.push_back(world.createBody(d));
    }
    {
        BodyDef d;  // 8: kinematic, moving and turning through the others' space
        d.type = BodyType::Kinematic;
        d.shape = Shape::box({Real(0.5), Real(0.2), Real(0.5)});
        d.position = {-8, Real(0.3), 3};
        d.linearVelocity = {Real(0.8), 0, 0};
        d.angularVelocity = {0, Real(0.7), 0};
        ids.push_back(world.createBody(d));
    }
    {
        BodyDef d;  // 9: damped from the start
        d.shape = Shape::sphere(Real(0.3));
        d.position = {6, 3, 0};
        d.linearVelocity = {0, 0, 1};
        d.angularVelocity = {2, 0, 0};
        d.linearDamping = Real(0.3);
        d.angularDamping = Real(0.6);
        ids.push_back(world.createBody(d));
    }
    return ids;
}

// The changes before step s. `callbacks`: also a ForceCallback for a while
// (not saved in snapshots).
void script(World& world, std::vector<BodyId>& ids, int s, bool callbacks) {
    switch (s) {
        case 10:  // a torque for one step, on an isotropic and a general body
            world.applyTorque(ids[1], {0, 2, 0});
            world.applyTorque(ids[6], {1, 0, 0});
            break;
        case 20: world.setDamping(ids[2], Real(0.5), Real(0.8)); break;
        case 35: world.setDamping(ids[2], 0, 0); break;
        case 40: {
            // Body 4 destroyed: another body's data moves into its dense slot.
            world.destroyBody(ids[4]);
            BodyDef k;  // a kinematic body where none was
            k.type = BodyType::Kinematic;
            k.shape = Shape::sphere(Real(0.3));
            k.position = {1, 3, -2};
            k.linearVelocity = {0, Real(-0.5), Real(0.5)};
            k.angularVelocity = {1, 1, 0};
            ids[4] = world.createBody(k);
            BodyDef c;  // an axisymmetric body of another mass
            c.shape = Shape::cylinder(Real(0.3), Real(0.4));
            c.mass = 5;
            c.position = {-1, 4, 1};
            c.angularVelocity = {0, 1, 3};
            ids.push_back(world.createBody(c));
            break;
        }
        case 50:
            world.setAngularVelocity(ids[7], {3, 1, -2});
            world.applyTorque(ids[7], {0, 0, -1});
            break;
        case 60: world.setIntegrator(Integrator::Verlet); break;
        case 70: world.setIntegrator(Integrator::ExplicitEuler); break;
        case 80: world.setIntegrator(Integrator::SemiImplicitEuler); break;
        case 85:
            if (callbacks) {
                world.setForceCallback(ids[2], [](const BodyKinematics& k) {
                    return Wrench{Vec3{0, 10, 0} - k.linearVelocity, Vec3{0, Real(0.5), 0} - k.angularVelocity * Real(0.1)};
                });
            }
            break;
        case 95:
            if (callbacks) world.setForceCallback(ids[2], {});
            break;
        case 100: {
            // An isotropic body destroyed, a general one created.
            world.destroyBody(ids[1]);
            BodyDef d;
            d.shape = Shape::box({Real(0.25), Real(0.4), Real(0.55)});
            d.mass = Real(1.5);
            d.position = {-7, 2, -1};
            d.angularVelocity = {2, 1, 0};
            ids[1] = world.createBody(d);
            break;
        }
        default: break;
    }
    // A torque held over several steps (the user's, applied before each step).
    if (s >= 15 && s < 25) world.applyTorque(ids[3], {0, 0, Real(0.7)});
    if (s >= 110 && s < 120) world.applyTorque(ids[5], {Real(0.3), 0, 0});
}

WorldDef worldDef(int threads) {
    WorldDef def;
    def.threads = threads;
    def.parallelMinBodies = 0;  // the parallel stages even for a few bodies
    return def;
}

std::vector<std::uint64_t> scriptedHashes(int threads, bool kindsPerStep) {
    detail::setMotionKindsPerStepEnabled(kindsPerStep);
    World world(worldDef(threads));
    std::vector<BodyId> ids = populate(world);
    std::vector<std::uint64_t> hashes;
    for (int s = 0; s < kSteps; ++s) {
        script(world, ids, s, true);
        world.step(kDt);
        hashes.push_back(test::stateHash(world));
    }
    detail::setMotionKindsPerStepEnabled(true);
    return hashes;
}

}  // namespace

TEST(MotionKinds, SameBitsAsTestingEverySubStep) {
    for (const int threads : {1, 3}) {
        const std::vector<std::uint64_t> perStep = scriptedHashes(threads, true);
        const std::vector<std::uint64_t> perSubStep = scriptedHashes(threads, false);
        ASSERT_EQ(perStep.size(), perSubStep.size());
        for (std::size_t s = 0; s < perStep.size(); ++s) {
            ASSERT_EQ(perStep[s], perSubStep[s]) << "threads " << threads << ", step " << s;
        }
        if (threads == 3) {
            EXPECT_EQ(perStep, scriptedHashes(1, true));  // and whatever the thread count
        }
    }
}

// A world loaded from a snapshot right after each change (before the step
// that first sees it) decides every kind afresh; the world it was taken from
// carries the last step's. Both go on through the rest of the script with the
// same bits at every step.
TEST(MotionKinds, AWorldLoadedAfterAChangeGoesOnWithTheSameBits) {
    for (const int threads : {1, 3}) {
        for (const int changeStep : {10, 20, 40, 50, 60, 100}) {
            World world(worldDef(threads));
            std::vector<BodyId> ids = populate(world);
            for (int s = 0; s < changeStep; ++s) {
                script(world, ids, s, false);
                world.step(kDt);
            }
            script(world, ids, changeStep, false);
            const std::vector<std::uint8_t> bytes = saveSnapshotToMemory(world);
            World fresh = loadSnapshotFromMemory(bytes);
            fresh.setThreadCount(threads);
            std::vector<BodyId> freshIds = ids;
            for (int s = changeStep; s < changeStep + 25; ++s) {
                if (s > changeStep) {
                    script(world, ids, s, false);
                    script(fresh, freshIds, s, false);
                    ASSERT_EQ(ids, freshIds) << "step " << s;
                }
                world.step(kDt);
                fresh.step(kDt);
                ASSERT_EQ(test::stateHash(world), test::stateHash(fresh))
                    << "threads " << threads << ", changed at step " << changeStep << ", step " << s;
            }
        }
    }
}
