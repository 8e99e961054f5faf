// World::previousTransform is the body's transform at the start of the last
// step, bit for bit, for every body: the awake ones (written by the contact
// manager's proxy update, which forms that transform for their boxes:
// WorldImpl::refreshPrevious), the sleeping and static ones, kinematic
// bodies, compounds whose centre of mass is off their origin, a teleported
// body and one created mid-run. At 1 and 3 threads.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <vector>

#include "contacts/helpers.hpp"

using namespace fulcrum;
using namespace fulcrum::test;

namespace {

bool sameBits(const Transform& a, const Transform& b) {
    return std::memcmp(&a.p, &b.p, sizeof a.p) == 0 && std::memcmp(&a.q, &b.q, sizeof a.q) == 0;
}

BodyId addCompound(World& world, const Vec3& position, const Vec3& spin) {
    const std::array<CompoundChild, 2> children{
        CompoundChild{Shape::box({Real(0.5), Real(0.15), Real(0.15)}), Transform{{Real(0.5), 0, 0}, Quat::identity()}},
        CompoundChild{Shape::sphere(Real(0.3)), Transform{{0, Real(0.4), Real(0.1)}, Quat::identity()}}};
    BodyDef d;
    d.shape = Shape::compound(children);
    d.mass = 2;
    d.position = position;
    d.angularVelocity = spin;
    return world.createBody(d);
}

void run(int threads) {
    WorldDef def;
    def.threads = threads;
    World world(def);
    world.setParallelMinBodies(1);
    std::vector<BodyId> bodies{addGround(world)};
    for (int i = 0; i < 24; ++i) {
        const Vec3 p{Real(-6) + Real(i % 6) * Real(2.2), Real(0.8) + Real(i / 6) * Real(1.5), Real(i % 4) * Real(0.3)};
        if (i % 3 == 0) {
            bodies.push_back(addSphere(world, p, Real(0.4)));
        } else if (i % 3 == 1) {
            bodies.push_back(addBox(world, p, Vec3::splat(Real(0.4))));
        } else {
            bodies.push_back(addCompound(world, p, {Real(1), Real(2), Real(-0.5)}));
        }
        world.setLinearVelocity(bodies.back(), {Real(i % 5) - 2, 0, Real(1)});
    }
    BodyDef k;
    k.type = BodyType::Kinematic;
    k.shape = Shape::box({1, Real(0.2), 1});
    k.position = {0, Real(0.2), -4};
    k.linearVelocity = {Real(0.5), 0, 0};
    k.angularVelocity = {0, Real(0.3), 0};
    const BodyId kinematic = world.createBody(k);
    bodies.push_back(kinematic);
    int asleepSeen = 0;
    for (int step = 0; step < 400; ++step) {
        if (step == 150) world.setTransform(bodies[3], {0, 3, 2}, Quat::identity());
        if (step == 200) bodies.push_back(addCompound(world, {2, 4, 1}, {0, 1, 0}));
        if (step == 300) world.setLinearVelocity(kinematic, {0, 0, 0});
        std::vector<Transform> before;
        for (const BodyId id : bodies) before.push_back(world.transform(id));
        world.step(kDt);
        for (std::size_t i = 0; i < bodies.size(); ++i) {
            ASSERT_TRUE(sameBits(world.previousTransform(bodies[i]), before[i])) << "threads " << threads << ", body " << i << ", step " << step;
            if (i > 0 && bodies[i] != kinematic && !world.isAwake(bodies[i])) ++asleepSeen;
        }
    }
    EXPECT_GT(asleepSeen, 0);  // sleeping dynamic bodies were checked too
}

TEST(PreviousTransform, IsTheStepStartForEveryBodyOneThread) { run(1); }
TEST(PreviousTransform, IsTheStepStartForEveryBodyThreeThreads) { run(3); }

}  // namespace
