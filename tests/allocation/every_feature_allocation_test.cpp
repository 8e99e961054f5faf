// No heap allocation per step in steady state, with every feature of the step
// at work at once: contacts in a box pile that falls asleep and is woken by a
// dropped ball, joints of every type (hinge motor, slider limits and spring,
// rope and soft distance joints, fixed, cone-twist), a damped spring, a rope
// tied to a body, a cloth draped on a sphere, a sensor the ball passes through,
// and a fast bullet stopped by a thin wall through continuous collision.
//
// The scene repeats a 4 s cycle (the ball is lifted and dropped again, the
// bullet fired again: API calls between steps, not counted). Two cycles warm
// up every buffer; over the next two, support/counting_allocator.hpp counts
// every operator new inside World::step, and the count must be zero. The same
// cycles check that the features did their work (the pile slept and woke, the
// sensor and contacts reported events, the bullet did not pass the wall, the
// joints held), so the proof covers the paths it claims to.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <vector>

#include "fulcrum/world.hpp"
#include "support/counting_allocator.hpp"

using namespace fulcrum;

namespace {

constexpr Real kDt = Real(1) / 60;
constexpr int kCycleSteps = 240;
constexpr Real kWallX = 10;

struct Scene {
    World world;
    std::vector<BodyId> pile;
    BodyId ball, bullet;
    std::vector<JointId> joints;
    explicit Scene(const WorldDef& def) : world(def) {}
};

BodyId addBody(World& world, BodyType type, const Shape& shape, Vec3 position, Real mass = 1) {
    BodyDef d;
    d.type = type;
    d.shape = shape;
    d.position = position;
    if (type == BodyType::Dynamic) d.mass = mass;
    return world.createBody(d);
}

JointId addJoint(Scene& s, JointType type, BodyId a, BodyId b, Vec3 anchor, Vec3 axis = {0, 1, 0}) {
    JointDef j;
    j.type = type;
    j.bodyA = a;
    j.bodyB = b;
    j.anchor = anchor;
    j.anchorB = anchor;
    j.axis = axis;
    switch (type) {
        case JointType::Hinge:
            j.motor = {true, 2, 50};
            break;
        case JointType::Slider:
            j.hasLimits = true;
            j.lowerLimit = Real(-0.2);
            j.upperLimit = Real(0.2);
            j.spring = {true, 0, 200, 5};
            break;
        default: break;
    }
    const JointId id = s.world.createJoint(j);
    s.joints.push_back(id);
    return id;
}

void build(Scene& s) {
    World& w = s.world;
    addBody(w, BodyType::Static, Shape::plane({0, 1, 0}, 0), {});
    // A 2 x 2 x 3 pile of boxes (contacts, islands, sleeping).
    for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < 2; ++i) {
            for (int j = 0; j < 2; ++j) {
                s.pile.push_back(addBody(w, BodyType::Dynamic, Shape::box(Vec3::splat(Real(0.5))),
                                         {static_cast<Real>(i) * Real(1.01), Real(0.5) + static_cast<Real>(k),
                                          static_cast<Real>(j) * Real(1.01)}));
            }
        }
    }
    s.ball = addBody(w, BodyType::Dynamic, Shape::sphere(Real(0.3)), {0.5f, 6, 0.5f}, 2);
    // A static sensor above the pile: the ball passes through it each cycle.
    BodyDef sensor;
    sensor.type = BodyType::Static;
    sensor.shape = Shape::box({1, Real(0.5), 1});
    sensor.position = {0.5f, 4.5f, 0.5f};
    sensor.isSensor = true;
    w.createBody(sensor);
    // A thin wall and a fast bullet (continuous collision): 200 m/s is 3.3 m per step.
    addBody(w, BodyType::Static, Shape::box({Real(0.1), 2, 2}), {kWallX, 2, 0});
    BodyDef bullet;
    bullet.shape = Shape::sphere(Real(0.05));
    bullet.mass = Real(0.1);
    bullet.isBullet = true;
    bullet.position = {5, 1, 0};
    s.bullet = w.createBody(bullet);

    // A hanging chain with one joint of every type, away from the rest.
    const Shape link = Shape::capsule(Real(0.1), Real(0.2));
    std::vector<BodyId> c;
    for (int i = 0; i < 7; ++i) c.push_back(addBody(w, BodyType::Dynamic, link, {-8, Real(9) - Real(0.6) * static_cast<Real>(i), 0}));
    auto at = [](int i) { return Vec3{-8, Real(9.3) - Real(0.6) * static_cast<Real>(i), 0}; };
    addJoint(s, JointType::Ball, kWorldBody, c[0], at(0));
    addJoint(s, JointType::Hinge, c[0], c[1], at(1), {0, 0, 1});
    addJoint(s, JointType::Slider, c[1], c[2], at(2), {0, 1, 0});
    {
        JointDef rope;  // a rope: 0 <= distance <= its length at creation
        rope.type = JointType::Distance;
        rope.bodyA = c[2];
        rope.bodyB = c[3];
        rope.anchor = at(3);
        rope.anchorB = at(3) + Vec3{0, Real(-0.1), 0};
        rope.minLength = 0;
        s.joints.push_back(w.createJoint(rope));
    }
    addJoint(s, JointType::Fixed, c[3], c[4], at(4));
    addJoint(s, JointType::ConeTwist, c[4], c[5], at(5), {0, -1, 0});
    {
        JointDef soft;  // a soft distance joint (spring in the solver)
        soft.type = JointType::Distance;
        soft.bodyA = c[5];
        soft.bodyB = c[6];
        soft.anchor = at(6);
        soft.anchorB = at(6) + Vec3{0, Real(-0.1), 0};
        soft.stiffness = 500;
        soft.damping = 2;
        s.joints.push_back(w.createJoint(soft));
    }
    SpringDef spring;  // a force element from the world to the last link
    spring.bodyB = c[6];
    spring.anchorA = {-7, 9, 0};
    spring.anchorB = w.position(c[6]);
    spring.restLength = Real(1.5);
    spring.stiffness = 20;
    spring.damping = Real(0.5);
    w.createSpring(spring);
    w.applyTorque(c[0], {0, 0, 1});

    // A rope pinned to the world holding a box; a cloth dropped on a sphere.
    const BodyId weight = addBody(w, BodyType::Dynamic, Shape::box(Vec3::splat(Real(0.1))), {-4, Real(3.9), 0}, Real(0.5));
    RopeDef rope;
    rope.start = {-4, 5, 0};
    rope.end = {-4, 4, 0};
    rope.attachEnd = weight;
    rope.bendCompliance = 1;
    w.createRope(rope);
    addBody(w, BodyType::Static, Shape::sphere(Real(0.5)), {4, Real(0.5), 4});
    ClothDef cloth;
    cloth.size = {10, 10};
    cloth.spacing = Real(0.1);
    cloth.radius = Real(0.03);
    cloth.origin = {Real(3.55), 2, Real(3.55)};
    cloth.bendCompliance = Real(0.1);
    w.createCloth(cloth);
}

// The start of a cycle (not counted: API calls, not steps): lift and drop the
// ball, fire the bullet at the wall again.
void startCycle(Scene& s) {
    s.world.setTransform(s.ball, {0.5f, 6, 0.5f}, Quat{});
    s.world.setLinearVelocity(s.ball, {0, -4, 0});
    s.world.setAngularVelocity(s.ball, {});
    s.world.setTransform(s.bullet, {5, 1, 0}, Quat{});
    s.world.setLinearVelocity(s.bullet, {200, 0, 0});
    s.world.setAngularVelocity(s.bullet, {});
}

struct CycleReport {
    long allocations = 0;
    bool pileSlept = false, pileWoke = false;
    int contactBegins = 0, sensorBegins = 0;
    Real bulletMaxX = -1e9f;
    Real worstJointError = 0;
};

CycleReport runCycle(Scene& s, bool count) {
    CycleReport r;
    startCycle(s);
    bool wasAsleep = !s.world.isAwake(s.pile.front());
    for (int i = 0; i < kCycleSteps; ++i) {
        if (count) {
            test::resetAllocationCount();
            test::setCountingAllocations(true);
        }
        s.world.step(kDt);
        if (count) {
            test::setCountingAllocations(false);
            r.allocations += test::allocationCount();
        }
        const bool asleep = !s.world.isAwake(s.pile.front());
        r.pileSlept |= asleep;
        r.pileWoke |= wasAsleep && !asleep;
        wasAsleep = asleep;
        r.contactBegins += static_cast<int>(s.world.contactBeginEvents().size());
        r.sensorBegins += static_cast<int>(s.world.sensorBeginEvents().size());
        r.bulletMaxX = std::max(r.bulletMaxX, s.world.position(s.bullet).x);
        for (JointId j : s.joints) r.worstJointError = std::max(r.worstJointError, s.world.jointError(j));
    }
    return r;
}

void expectNoAllocationPerStep(int threads) {
    WorldDef def;
    def.threads = threads;
    Scene s(def);
    build(s);
    for (int c = 0; c < 2; ++c) runCycle(s, false);  // warm-up: every buffer reaches its size
    for (int c = 0; c < 2; ++c) {
        const CycleReport r = runCycle(s, true);
        EXPECT_EQ(r.allocations, 0) << "cycle " << c << ", " << threads << " thread(s)";
        // The features were exercised in the counted steps:
        EXPECT_TRUE(r.pileSlept) << "the pile never fell asleep";
        EXPECT_TRUE(r.pileWoke) << "the dropped ball never woke the pile";
        EXPECT_GT(r.contactBegins, 0);
        EXPECT_GE(r.sensorBegins, 1) << "the ball passes through the sensor every cycle";
        // Continuous collision: the bullet (radius 5 cm) never gets past the wall's near face.
        EXPECT_LT(r.bulletMaxX, kWallX - Real(0.1));
        // The joints held (a loose bound: the hinge motor and slider spring keep the chain moving).
        EXPECT_LT(r.worstJointError, Real(0.05));
    }
}

}  // namespace

TEST(Allocation, StepWithEveryFeatureAllocatesNothingInSteadyStateOneThread) { expectNoAllocationPerStep(1); }

TEST(Allocation, StepWithEveryFeatureAllocatesNothingInSteadyStateTwoThreads) { expectNoAllocationPerStep(2); }

// Where test pointers escape to, so the compiler can't elide a new/delete pair.
const void* volatile gEscape = nullptr;

// The counter itself: it sees plain, array and over-aligned (SIMD) allocations,
// and nothing while it is off.
TEST(Allocation, CounterSeesEveryFormOfOperatorNew) {
    struct alignas(64) Wide {
        float lanes[16];
    };
    test::CountAllocations count;
    std::vector<int> plain(10);
    const auto* array = new int[3];
    gEscape = array;
    const auto* wide = new Wide;
    gEscape = wide;
    std::vector<Wide> wides(2);
    delete[] array;
    delete wide;
    EXPECT_EQ(count.stop(), 4);
    std::vector<int> uncounted(5);
    EXPECT_EQ(count.count(), 4);
    EXPECT_EQ(reinterpret_cast<std::uintptr_t>(wides.data()) % 64, 0u);
}
