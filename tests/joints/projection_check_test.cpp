// The position projection first checks every point joint's anchor separation
// four joints at a time in SIMD lanes (JointSolver::firstGroupBeyondSlop) and runs
// its Gauss-Seidel passes only when one is beyond the slop. A joint pulled
// open in any lane position, including the lanes of a last, partial round,
// must still be closed to the slop by the end of the step, exactly as with
// the check skipped; and where nothing is beyond the slop the check must not
// change a bit.
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "fulcrum/fulcrum.hpp"
#include "world/world_access.hpp"

using namespace fulcrum;

namespace {

// A horizontal chain of `links` capsules (1 m between anchors) on ball joints,
// the first hung from the world at the origin, in zero gravity and at rest.
struct Chain {
    World world;
    std::vector<BodyId> links;
    std::vector<JointId> joints;
    Chain(int count, Real slop) : world([&] {
        WorldDef d;
        d.gravity = {0, 0, 0};
        d.jointProjectionSlop = slop;
        return d;
    }()) {
        BodyId prev = kWorldBody;
        for (int i = 0; i < count; ++i) {
            BodyDef b;
            b.shape = Shape::capsule(Real(0.1), Real(0.4));
            b.mass = 1;
            b.position = {Real(0.5) + static_cast<Real>(i), 0, 0};
            b.orientation = Quat::fromAxisAngle({0, 0, 1}, Real(1.5707963));
            links.push_back(world.createBody(b));
            JointDef j;
            j.type = JointType::Ball;
            j.bodyA = prev;
            j.bodyB = links.back();
            j.anchor = {static_cast<Real>(i), 0, 0};
            joints.push_back(world.createJoint(j));
            prev = links.back();
        }
    }
};

}  // namespace

TEST(ProjectionCheck, AJointPulledOpenInAnyLaneIsClosedToTheSlop) {
    const Real slop = Real(0.005);
    // 7 joints: a round of four lanes and a partial round of three.
    for (int open = 0; open < 7; ++open) {
        Chain chain(7, slop);
        // Pull link `open` 10 cm along the chain: its joint to the previous
        // link (and to the next one) opens by 10 cm.
        const BodyId link = chain.links[static_cast<std::size_t>(open)];
        chain.world.setTransform(link, chain.world.position(link) + Vec3{Real(0.1), 0, 0}, chain.world.orientation(link));
        chain.world.step(Real(1) / 60);
        for (std::size_t k = 0; k < chain.joints.size(); ++k) {
            // Closed to the slop (float rounding of the anchors: 1e-5 m).
            EXPECT_LE(chain.world.jointError(chain.joints[k]), slop + Real(1e-5)) << "link " << open << " pulled, joint " << k;
        }
        // Without the projection the same pull leaves the soft rows' share open.
        Chain unprojected(7, std::numeric_limits<Real>::infinity());
        const BodyId same = unprojected.links[static_cast<std::size_t>(open)];
        unprojected.world.setTransform(same, unprojected.world.position(same) + Vec3{Real(0.1), 0, 0},
                                       unprojected.world.orientation(same));
        unprojected.world.step(Real(1) / 60);
        EXPECT_GT(unprojected.world.jointError(unprojected.joints[static_cast<std::size_t>(open)]), 2 * slop)
            << "the test needs an opening the projection has to close";
    }
}

TEST(ProjectionCheck, ClosedJointsKeepTheirBitsWhateverTheSlop) {
    // A chain swinging under gravity with every joint within 1 mm: a slop of
    // 5 cm (nothing to do, the check says so) and of 1 m give the same bits.
    std::vector<std::vector<Vec3>> runs;
    for (const Real slop : {Real(0.05), Real(1)}) {
        Chain chain(9, slop);
        chain.world.setGravity({0, Real(-9.81), 0});
        std::vector<Vec3> positions;
        for (int i = 0; i < 60; ++i) {
            chain.world.step(Real(1) / 60);
            for (const BodyId b : chain.links) positions.push_back(chain.world.position(b));
        }
        for (const JointId j : chain.joints) EXPECT_LT(chain.world.jointError(j), slop);
        runs.push_back(positions);
    }
    ASSERT_EQ(runs[0].size(), runs[1].size());
    EXPECT_EQ(std::memcmp(runs[0].data(), runs[1].data(), runs[0].size() * sizeof(Vec3)), 0);
}

// The passes skip a joint found within the slop (by the check or an earlier
// pass) while neither of its bodies has moved since (JointSolver's
// withinAt_ and movedAt_): the same positions give the same decision, so the
// same bits as checking every joint in every pass. Three chains with links
// pulled open at every step, in every lane position, so that the passes run
// several times and correct joints next to ones they skip.
TEST(ProjectionCheck, PassesSkippingKnownJointsKeepEveryBit) {
    const Real slop = Real(0.005);
    std::vector<std::vector<Real>> runs;
    for (const bool memory : {true, false}) {
        WorldDef d;
        d.gravity = {0, Real(-9.81), 0};
        d.jointProjectionSlop = slop;
        World world(d);
        detail::implOf(world).jointSolver.setProjectionMemory(memory);
        std::vector<BodyId> links;
        for (int c = 0; c < 3; ++c) {
            BodyId prev = kWorldBody;
            const Real z = static_cast<Real>(2 * c);
            for (int i = 0; i < 7; ++i) {
                BodyDef b;
                b.shape = Shape::capsule(Real(0.1), Real(0.4));
                b.mass = static_cast<Real>(1 + i % 3);
                b.position = {Real(0.5) + static_cast<Real>(i), 0, z};
                b.orientation = Quat::fromAxisAngle({0, 0, 1}, Real(1.5707963));
                b.filter.group = -1;
                links.push_back(world.createBody(b));
                JointDef j;
                j.type = JointType::Ball;
                j.bodyA = prev;
                j.bodyB = links.back();
                j.anchor = {static_cast<Real>(i), 0, z};
                world.createJoint(j);
                prev = links.back();
            }
        }
        std::vector<Real> state;
        for (int step = 0; step < 40; ++step) {
            for (int k = 0; k < 3; ++k) {
                const BodyId link = links[static_cast<std::size_t>((5 * step + 7 * k) % 21)];
                world.setTransform(link, world.position(link) + Vec3{Real(0.06), Real(-0.03), Real(0.02)}, world.orientation(link));
            }
            world.step(Real(1) / 60);
            for (const BodyId b : links) {
                const Vec3 p = world.position(b);
                const Quat q = world.orientation(b);
                state.insert(state.end(), {p.x, p.y, p.z, q.w, q.x, q.y, q.z});
            }
        }
        runs.push_back(state);
    }
    ASSERT_EQ(runs[0].size(), runs[1].size());
    EXPECT_EQ(std::memcmp(runs[0].data(), runs[1].data(), runs[0].size() * sizeof(Real)), 0);
}
