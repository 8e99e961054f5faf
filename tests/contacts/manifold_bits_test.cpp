// The solver's pending-list pass over every contact slot skips the slots
// whose bit in ContactManager::mayHaveManifoldBits is clear: a contact
// without manifolds gives no constraint, and its grownBy is 0, so the list,
// the constraints and every body's motion must be the same bits as the pass
// that reads every slot (setManifoldBits(false)), at any thread count, and a
// world restored from a snapshot (its bits rebuilt from the contacts) must
// go on as the one that never stopped.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "contacts/helpers.hpp"
#include "fulcrum/snapshot.hpp"
#include "support/same_motion.hpp"
#include "world/world_access.hpp"
#include "world/world_impl.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

// ConvexVsMesh in small: a wavy static mesh and columns of boxes, spheres,
// capsules and pyramid hulls dropped on it, close enough that neighbours'
// fat boxes overlap while their shapes are apart (contacts without
// manifolds) and that they land on and roll against each other.
std::vector<BodyId> buildScene(World& world) {
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    const int n = 16;
    for (int z = 0; z <= n; ++z) {
        for (int x = 0; x <= n; ++x) {
            const Real h = Real(0.6) * std::sin(Real(0.7) * Real(x)) * std::cos(Real(0.6) * Real(z));
            vertices.push_back({Real(x) - Real(n) / 2, h, Real(z) - Real(n) / 2});
        }
    }
    for (int x = 0; x < n; ++x) {
        for (int z = 0; z < n; ++z) {
            const auto s = static_cast<std::uint32_t>((n + 1) * z + x);
            triangles.push_back({s, s + n + 1, s + 1});
            triangles.push_back({s + 1, s + n + 1, s + n + 2});
        }
    }
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::mesh(vertices, triangles);
    ground.friction = Real(0.5);
    world.createBody(ground);
    const std::array<Vec3, 5> pyramid = {Vec3{0, Real(0.5), 0}, Vec3{Real(0.5), 0, 0}, Vec3{Real(-0.5), 0, 0},
                                         Vec3{0, 0, Real(0.5)}, Vec3{0, 0, Real(-0.5)}};
    std::vector<BodyId> bodies;
    for (int x = -3; x <= 3; ++x) {
        for (int z = -3; z <= 3; ++z) {
            for (int k = 0; k < 4; ++k) {
                BodyDef d;
                d.position = {Real(1.3) * Real(x), Real(1.6) + Real(1.15) * Real(k), Real(1.3) * Real(z)};
                d.friction = Real(0.5);
                d.restitution = Real(0.3);
                switch ((k + x + z + 12) % 4) {
                    case 0: d.shape = Shape::box({Real(0.25), Real(0.4), Real(0.5)}); break;
                    case 1: d.shape = Shape::sphere(Real(0.3)); break;
                    case 2: d.shape = Shape::capsule(Real(0.25), Real(0.35)); break;
                    default: d.shape = Shape::convexHull(pyramid); break;
                }
                d.mass = 1;
                d.angularVelocity = {Real(0.1) * Real(x), 0, Real(0.1) * Real(z)};
                bodies.push_back(world.createBody(d));
            }
        }
    }
    return bodies;
}

// Live contacts without a manifold in `world` now.
int contactsWithoutManifolds(const World& world) {
    int count = 0;
    for (const detail::Contact& c : detail::implOf(world).contactManager.contacts()) {
        if (c.alive && c.manifolds.empty()) ++count;
    }
    return count;
}

void runPair(int threads) {
    WorldDef def;
    def.threads = threads;
    World bits(def), every(def);
    for (World* w : {&bits, &every}) {
        w->setParallelMinBodies(1);
        // The pass over every slot (the live-contact list off), the one the bits serve.
        detail::implOf(*w).contactManager.setLiveContactList(false);
    }
    detail::implOf(every).contactManager.setManifoldBits(false);
    const std::vector<BodyId> a = buildScene(bits), b = buildScene(every);
    int stepsWithBits = 0, withoutManifolds = 0, constraints = 0;
    for (int step = 0; step < 160; ++step) {
        bits.step(kDt);
        every.step(kDt);
        if (detail::implOf(bits).contactManager.mayHaveManifoldBits() != nullptr) ++stepsWithBits;
        withoutManifolds += contactsWithoutManifolds(bits);
        constraints += static_cast<int>(bits.lastStepProfile().contactConstraints);
        for (std::size_t i = 0; i < a.size(); ++i) {
            ASSERT_TRUE(sameMotion(bits, a[i], every, b[i])) << "threads " << threads << ", body " << i << ", step " << step;
        }
    }
    EXPECT_EQ(stepsWithBits, 160);
    EXPECT_GT(withoutManifolds, 160 * 200);  // slots the bits skip: 78,615 over the run (~490 a step)
    EXPECT_GT(constraints, 160 * 150);       // and solved ones: 62,386
}

TEST(ManifoldBits, SameBitsAsReadingEverySlotOneThread) { runPair(1); }
TEST(ManifoldBits, SameBitsAsReadingEverySlotThreeThreads) { runPair(3); }

// A snapshot mid-run: the restored world's bits come from its contacts
// (ContactManager::rebuildLinks), and it goes on as the one that never stopped.
TEST(ManifoldBits, RestoredWorldGoesOnWithTheSameBits) {
    World original, reference;
    for (World* w : {&original, &reference}) detail::implOf(*w).contactManager.setLiveContactList(false);
    detail::implOf(reference).contactManager.setManifoldBits(false);
    const std::vector<BodyId> a = buildScene(original), b = buildScene(reference);
    for (int step = 0; step < 70; ++step) {
        original.step(kDt);
        reference.step(kDt);
    }
    ASSERT_GT(contactsWithoutManifolds(original), 10);
    World resumed = loadSnapshotFromMemory(saveSnapshotToMemory(original));
    detail::implOf(resumed).contactManager.setLiveContactList(false);
    for (int step = 70; step < 160; ++step) {
        resumed.step(kDt);
        reference.step(kDt);
        for (std::size_t i = 0; i < a.size(); ++i) {
            ASSERT_TRUE(sameMotion(resumed, a[i], reference, b[i])) << "body " << i << ", step " << step;
        }
    }
}

}  // namespace
