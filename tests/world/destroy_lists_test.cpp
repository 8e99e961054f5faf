// World::destroyBody finds the body's contacts from the contact manager's
// per-body lists and skips its scan of every joint slot when the joint graph
// names no joint of the body (contact_manager.cpp removeBody, world.cpp;
// docs/benchmarks.md, the `rain10` block). The reference is a copy of the
// world (through a snapshot) whose contact lists are dropped before each
// destroyBody, so its removeBody scans every contact: the unchanged path.
// Both must destroy the same contacts (a contact left behind names a dead
// slot) and wake the same resting partners, so the two worlds stay
// bit-identical for every following step. (The lists are destroyed in the
// scan's ascending order, for the same free list; in this pile a reversed
// order happened to give the same bits, so that part is kept by
// construction rather than proved here.) The joints: a body destroyed with
// its joints still attached takes them with it, one destroyed after its
// joints leaves every other joint alive.
#include <gtest/gtest.h>

#include <vector>

#include "determinism/state_hash.hpp"
#include "fulcrum/snapshot.hpp"
#include "world/world_access.hpp"
#include "world/world_impl.hpp"
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
    // Two loose capsules (no joints) dropped onto the chains: destroying one
    // while the pile sleeps wakes its partners through removeBody alone.
    std::vector<BodyId> loose;
    for (int k = 0; k < 2; ++k) {
        BodyDef b;
        b.shape = Shape::capsule(Real(0.08), Real(0.3));
        b.position = {Real(-0.3) + Real(0.6) * static_cast<Real>(k), Real(2.6), Real(-0.3)};
        b.orientation = Quat::fromAxisAngle({0, 0, 1}, Real(1.5707963));
        loose.push_back(p.world.createBody(b));
    }
    p.chains.push_back(loose);
    p.joints.push_back({});
    return p;
}

std::size_t awakeCount(const World& w, const Pile& p) {
    std::size_t n = 0;
    for (const auto& chain : p.chains) {
        for (const BodyId id : chain) n += w.isValid(id) && w.isAwake(id) ? 1 : 0;
    }
    return n;
}

// The same destructions in `w`, with handles from the pile (a snapshot keeps
// them). With `scan`, the contact lists are dropped before each destroyBody
// (a joint's destruction rebuilds them), so removeBody scans every contact.
void destroySome(World& w, const Pile& p, bool scan) {
    detail::ContactManager& cm = detail::implOf(w).contactManager;
    const auto destroy = [&](BodyId b) {
        if (scan) cm.dropContactLists();
        EXPECT_EQ(cm.contactListsBuilt(), !scan);
        w.destroyBody(b);
    };
    // A loose capsule first: the pile is asleep, only removeBody wakes.
    const std::size_t awake = awakeCount(w, p);
    destroy(p.chains[8][0]);
    EXPECT_GT(awakeCount(w, p), awake) << "the bodies it rested on wake";
    // Chain 3 as rain's script does it: its joints first, then its bodies.
    for (const JointId j : p.joints[3]) w.destroyJoint(j);
    for (const BodyId b : p.chains[3]) destroy(b);
    // The middle of chain 5 with its two joints still attached (the joint scan).
    destroy(p.chains[5][2]);
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
    const std::size_t jointsBefore = p.world.joints().size();

    destroySome(p.world, p, false);
    destroySome(scans, p, true);
    const auto events = endEvents(p.world);
    EXPECT_EQ(events, endEvents(scans)) << "the same touching contacts end, in the same order";
    EXPECT_GE(events.size(), 5u) << "the destroyed bodies were touching others";
    EXPECT_GT(awakeCount(p.world, p), 0u) << "their resting partners wake";
    EXPECT_EQ(awakeCount(p.world, p), awakeCount(scans, p));
    EXPECT_EQ(test::stateHash(p.world), test::stateHash(scans));
    // Chain 3's four joints went first; chain 5's middle body took its two.
    EXPECT_EQ(p.world.joints().size(), jointsBefore - 6);
    EXPECT_EQ(scans.joints().size(), jointsBefore - 6);
    for (const JointId j : p.world.joints()) {
        const JointDef& d = p.world.jointDef(j);
        EXPECT_TRUE(d.bodyA != p.chains[5][2] && d.bodyB != p.chains[5][2]);
    }
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
