// World::destroyBody finds the body's contacts from the contact manager's
// per-body lists and skips its scan of every joint slot when the joint graph
// names no joint of the body (contact_manager.cpp removeBody, world.cpp;
// docs/benchmarks.md, the `rain10` block). A world just loaded from a
// snapshot has neither list built, so its destroyBody takes the old scans:
// the unchanged path. Both must destroy the same contacts (a contact left
// behind names a dead slot) and wake the same resting partners, so the two
// worlds stay bit-identical for every following step. (The lists are also
// destroyed in the scan's ascending order, for the same free list; in this
// pile a reversed order happened to give the same bits, so that part is
// kept by construction rather than proved here.)
#include <gtest/gtest.h>

#include <vector>

#include "determinism/state_hash.hpp"
#include "fulcrum/snapshot.hpp"
#include "joints/joint_test_util.hpp"

namespace fulcrum::jointtest {
namespace {

struct Pile {
    World world;
    std::vector<std::vector<BodyId>> chains;
    std::vector<std::vector<JointId>> joints;
    explicit Pile(const WorldDef& d) : world(d) {}
};

// Eight chains of five capsules (ball, hinge and cone-twist joints) dropped
// crosswise onto a ground box, so they rest on the ground and on each other.
Pile makePile(int threads) {
    WorldDef d = worldDef(4);
    d.sleeping = true;  // (the helper's default is off)
    d.threads = threads;
    Pile p(d);
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::box({10, Real(0.5), 10});
    ground.position = {0, Real(-0.5), 0};
    p.world.createBody(ground);
    for (int c = 0; c < 8; ++c) {
        const bool alongX = c % 2 == 0;
        const Vec3 dir = alongX ? Vec3{1, 0, 0} : Vec3{0, 0, 1};
        const Vec3 origin = Vec3{Real(-1.2), Real(0.2) + Real(0.25) * static_cast<Real>(c), Real(-1.2)} +
                            (alongX ? Vec3{0, 0, Real(0.3) * static_cast<Real>(c)} : Vec3{Real(0.3) * static_cast<Real>(c), 0, 0});
        std::vector<BodyId> links;
        std::vector<JointId> joints;
        for (int i = 0; i < 5; ++i) {
            BodyDef b;
            b.shape = Shape::capsule(Real(0.08), Real(0.2));
            b.mass = Real(1 + i % 2);
            b.position = origin + dir * (Real(0.28) + Real(0.56) * static_cast<Real>(i));
            b.orientation = alongX ? Quat::fromAxisAngle({0, 0, 1}, Real(1.5707963)) : Quat::fromAxisAngle({1, 0, 0}, Real(1.5707963));
            links.push_back(p.world.createBody(b));
            if (i > 0) {
                const JointType type = i % 3 == 0 ? JointType::Ball : (i % 3 == 1 ? JointType::Hinge : JointType::ConeTwist);
                JointDef j = jointDef(type, links[i - 1], links[i], origin + dir * (Real(0.56) * static_cast<Real>(i)),
                                      alongX ? Vec3{0, 0, 1} : Vec3{1, 0, 0});
                j.swingLimit = Real(0.8);
                j.twistLower = Real(-0.3);
                j.twistUpper = Real(0.3);
                joints.push_back(p.world.createJoint(j));
            }
        }
        p.chains.push_back(links);
        p.joints.push_back(joints);
    }
    return p;
}

std::size_t awakeCount(const World& w, const Pile& p) {
    std::size_t n = 0;
    for (const auto& chain : p.chains) {
        for (const BodyId id : chain) n += w.isValid(id) && w.isAwake(id) ? 1 : 0;
    }
    return n;
}

// The same destructions in `w`, with handles from the pile (a snapshot keeps them).
void destroySome(World& w, const Pile& p) {
    // Chain 3 as rain's script does it: its joints first, then its bodies.
    for (const JointId j : p.joints[3]) w.destroyJoint(j);
    for (const BodyId b : p.chains[3]) w.destroyBody(b);
    // The middle of chain 5 with its two joints still attached (the joint scan).
    w.destroyBody(p.chains[5][2]);
}

std::vector<std::pair<BodyId, BodyId>> endEvents(const World& w) {
    std::vector<std::pair<BodyId, BodyId>> out;
    for (const ContactEvent& e : w.contactEndEvents()) out.push_back({e.bodyA, e.bodyB});
    return out;
}

void checkSameAsScans(int threads) {
    Pile p = makePile(threads);
    for (int i = 0; i < 1200 && awakeCount(p.world, p) > 0; ++i) p.world.step(kDt);
    // The pile has come to rest and fallen asleep (so a destruction must wake
    // the bodies resting on the destroyed ones), and it has been stepped (so
    // the original's contact lists and joint graph are built).
    ASSERT_EQ(awakeCount(p.world, p), 0u) << "the pile should be asleep";
    World scans = loadSnapshotFromMemory(saveSnapshotToMemory(p.world));
    ASSERT_EQ(test::stateHash(p.world), test::stateHash(scans));

    destroySome(p.world, p);
    destroySome(scans, p);
    const auto events = endEvents(p.world);
    EXPECT_EQ(events, endEvents(scans)) << "the same touching contacts end, in the same order";
    EXPECT_GE(events.size(), 5u) << "the destroyed bodies were touching others";
    EXPECT_GT(awakeCount(p.world, p), 0u) << "their resting partners wake";
    EXPECT_EQ(awakeCount(p.world, p), awakeCount(scans, p));
    EXPECT_EQ(test::stateHash(p.world), test::stateHash(scans));
    for (int i = 0; i < 120; ++i) {
        p.world.step(kDt);
        scans.step(kDt);
        ASSERT_EQ(test::stateHash(p.world), test::stateHash(scans)) << "diverged at step " << i + 1;
    }
}

TEST(DestroyLists, DestroyBodyMatchesTheScansBitForBit) { checkSameAsScans(1); }

TEST(DestroyLists, DestroyBodyMatchesTheScansBitForBitOnThreeThreads) { checkSameAsScans(3); }

}  // namespace
}  // namespace fulcrum::jointtest
