// Joined bodies don't collide (collideConnected off), through the per-body
// joint lists (src/solver/joints/joint_graph.hpp): kept on joint creation and
// destruction, honouring disabled joints, and rebuilt after a snapshot load.
// Physics: in zero gravity overlapping spheres that may collide are pushed
// apart with equal and opposite momentum; joined ones (a slack rope) stay put.
#include <cmath>
#include <vector>

#include "fulcrum/snapshot.hpp"
#include "joints/joint_test_util.hpp"

using namespace fulcrum;
using namespace fulcrum::jointtest;

namespace {

// Pairs of overlapping spheres (radius 0.5, centres 0.6 m apart), each pair
// joined by a slack rope (max 3 m); every sphere also has ropes to two far
// spheres, so the lists hold several joints. A sphere overlaps only its pair.
struct Scene {
    std::vector<BodyId> left, right;
    std::vector<JointId> pairJoints;
    explicit Scene(World& w, int pairs) {
        for (int i = 0; i < pairs; ++i) {
            const Real z = Real(4 * i);
            left.push_back(w.createBody(sphereBody(1, {0, 0, z}, Real(0.5))));
            right.push_back(w.createBody(sphereBody(1, {Real(0.6), 0, z}, Real(0.5))));
            pairJoints.push_back(rope(w, left.back(), right.back()));
        }
        for (int i = 0; i < pairs; ++i) {
            for (const BodyId b : {left[static_cast<std::size_t>(i)], right[static_cast<std::size_t>(i)]}) {
                const BodyId far = w.createBody(sphereBody(1, w.position(b) + Vec3{0, 3, 0}, Real(0.2)));
                rope(w, b, far);
                rope(w, far, b);
            }
        }
    }
    static JointId rope(World& w, BodyId a, BodyId b) {
        JointDef j = jointDef(JointType::Distance, a, b, w.position(a));
        j.anchorB = w.position(b);
        j.minLength = 0;
        j.maxLength = 5;
        return w.createJoint(j);
    }
};

WorldDef zeroGravity() { return worldDef(4, {0, 0, 0}); }

// Gap between pair i's spheres after `steps` steps; the pair's momentum must stay 0.
double gapAfter(World& w, const Scene& s, std::size_t i, int steps) {
    for (int k = 0; k < steps; ++k) w.step(kDt);
    const Vec3 p = w.linearVelocity(s.left[i]) + w.linearVelocity(s.right[i]);
    EXPECT_LT(length(p), 1e-4) << "pair " << i << " momentum";
    return double(w.position(s.right[i]).x - w.position(s.left[i]).x);
}

}  // namespace

// Joined pairs stay exactly 0.6 m apart (1e-5); a destroyed or disabled
// joint lets its pair be pushed apart (> 0.7 m after 0.5 s); re-enabled, the
// pair no longer collides (it keeps drifting apart at a constant rate).
TEST(JointGraph, JoinedBodiesDoNotCollideUntilTheJointGoes) {
    World w(zeroGravity());
    Scene s(w, 4);
    for (std::size_t i = 0; i < 4; ++i) EXPECT_NEAR(gapAfter(w, s, i, i == 0 ? 30 : 0), 0.6, 1e-5) << i;
    w.destroyJoint(s.pairJoints[1]);
    w.setJointEnabled(s.pairJoints[2], false);
    EXPECT_GT(gapAfter(w, s, 1, 30), 0.7);
    EXPECT_GT(gapAfter(w, s, 2, 0), 0.7);
    EXPECT_NEAR(gapAfter(w, s, 0, 0), 0.6, 1e-5);
    EXPECT_NEAR(gapAfter(w, s, 3, 0), 0.6, 1e-5);
    // A new joint in the freed slot joins pair 1 again: no contact from now
    // on, so its separation speed stays constant (1e-4 m/s).
    const JointId again = Scene::rope(w, s.left[1], s.right[1]);
    w.step(kDt);
    const double v0 = double(w.linearVelocity(s.right[1]).x);
    for (int k = 0; k < 10; ++k) w.step(kDt);
    EXPECT_NEAR(double(w.linearVelocity(s.right[1]).x), v0, 1e-4);
    EXPECT_TRUE(w.isJointEnabled(again));
}

// A world loaded from a snapshot (its joints written directly, the lists out
// of sync) still keeps joined pairs apart from its first step on, and
// destroying a joint after the load lets that pair collide.
TEST(JointGraph, SnapshotLoadKeepsJoinedBodiesApart) {
    World original(zeroGravity());
    Scene s(original, 3);
    original.step(kDt);
    World w = loadSnapshotFromMemory(saveSnapshotToMemory(original));
    for (std::size_t i = 0; i < 3; ++i) EXPECT_NEAR(gapAfter(w, s, i, i == 0 ? 30 : 0), 0.6, 1e-5) << i;
    w.destroyJoint(s.pairJoints[0]);
    EXPECT_GT(gapAfter(w, s, 0, 30), 0.7);
    EXPECT_NEAR(gapAfter(w, s, 1, 0), 0.6, 1e-5);
}
