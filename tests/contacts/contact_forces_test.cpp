// Contact forces (ContactReport's impulses and force), hit events and
// kinematic targets, against statics and free fall.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "contacts/helpers.hpp"
#include "world/world_access.hpp"
#include "support/real_eq.hpp"

using namespace fulcrum;
using namespace fulcrum::test;
using ::testing::AllOf;
using ::testing::HasSubstr;

namespace {

constexpr Real kG = Real(9.81);

WorldDef awake() {
    WorldDef d;
    d.sleeping = false;
    return d;
}

// The force `other` exerts on `body` over the last step, from the contact
// report (force is on bodyB; bodyA gets its opposite).
Vec3 forceOn(const World& world, BodyId body, BodyId other) {
    Vec3 f;
    for (const ContactReport& c : world.contacts()) {
        if (c.bodyA == other && c.bodyB == body) f += c.force;
        if (c.bodyA == body && c.bodyB == other) f -= c.force;
    }
    return f;
}

// The step's average force over a window of steps: the soft contact rings a
// little step to step; the statics hold on average and, once settled, per step.
Vec3 meanForceOn(World& world, BodyId body, BodyId other, int steps, const Vec3& push = {}) {
    Vec3 sum;
    for (int i = 0; i < steps; ++i) {
        if (push.x != 0 || push.y != 0 || push.z != 0) world.applyForceAtCenter(body, push);
        world.step(kDt);
        sum += forceOn(world, body, other);
    }
    return sum * (Real(1) / static_cast<Real>(steps));
}

}  // namespace

// A resting box: the ground pushes up with m g (within 0.5 %); the report's
// per-point impulses add up to its normal impulse, and force = impulse / dt.
TEST(ContactForces, RestingBoxCarriesItsWeight) {
    World world(awake());
    const BodyId ground = addGround(world);
    const Real mass = 3;
    const BodyId box = addBox(world, {0, Real(0.5), 0}, Vec3::splat(Real(0.5)), mass);
    run(world, 120);
    const Vec3 f = meanForceOn(world, box, ground, 60);
    EXPECT_NEAR(f.y, mass * kG, Real(0.005) * mass * kG);
    EXPECT_NEAR(f.x, 0, Real(0.005) * mass * kG);
    EXPECT_NEAR(f.z, 0, Real(0.005) * mass * kG);
    // The last step alone, once settled, holds too.
    EXPECT_NEAR(forceOn(world, box, ground).y, mass * kG, Real(0.005) * mass * kG);
    for (const ContactReport& c : world.contacts()) {
        ASSERT_EQ(c.pointNormalImpulses.size(), c.points.size());
        Real sum = 0;
        for (const Real p : c.pointNormalImpulses) {
            EXPECT_GE(p, 0);
            sum += p;
        }
        EXPECT_REAL_EQ(sum, c.normalImpulse);
        const Vec3 expected = (c.normal * c.normalImpulse + c.frictionImpulse) * (Real(1) / kDt);
        EXPECT_NEAR(c.force.y, expected.y, Real(1e-4) * std::abs(expected.y) + Real(1e-6));
    }
}

// Ten boxes stacked: the ground carries all ten (within 1 %).
TEST(ContactForces, StackBottomCarriesTheWholeStack) {
    World world(awake());
    const BodyId ground = addGround(world);
    BodyId bottom;
    for (int i = 0; i < 10; ++i) {
        const BodyId b = addBox(world, {0, Real(0.5) + static_cast<Real>(i), 0});
        if (i == 0) bottom = b;
    }
    run(world, 240);
    const Vec3 f = meanForceOn(world, bottom, ground, 60);
    EXPECT_NEAR(f.y, 10 * kG, Real(0.01) * 10 * kG);
}

// A box pushed sideways below the friction limit stays put: the ground's
// friction equals the push (within 1 %).
TEST(ContactForces, FrictionBalancesAPushBelowTheLimit) {
    World world(awake());
    const BodyId ground = addGround(world);
    const Real mass = 2;
    const BodyId box = addBox(world, {0, Real(0.5), 0}, Vec3::splat(Real(0.5)), mass, Real(0.6));
    run(world, 60);
    const Vec3 push{Real(0.4) * Real(0.6) * mass * kG, 0, 0};  // 40 % of mu m g
    run(world, 0);
    (void)meanForceOn(world, box, ground, 60, push);  // settle under the push
    const Vec3 start = world.position(box);
    const Vec3 f = meanForceOn(world, box, ground, 60, push);
    EXPECT_NEAR(f.x, -push.x, Real(0.01) * push.x);
    EXPECT_NEAR(f.y, mass * kG, Real(0.005) * mass * kG);
    EXPECT_LT(length(world.position(box) - start), Real(1e-3));  // it held
}

// The forces come out of the same float operations on every SIMD path.
TEST(ContactForces, SameBitsOnEverySolverPath) {
    const auto pile = [](detail::SimdPath path) {
        World world(awake());
        detail::implOf(world).contactSolver.setSimdPath(path);
        buildPyramid(world, 6);
        run(world, 30);
        return world.contacts();
    };
    const std::vector<ContactReport> scalar = pile(detail::SimdPath::Scalar);
    for (const detail::SimdPath path : {detail::SimdPath::Sse2, detail::bestSimdPath()}) {
        const std::vector<ContactReport> wide = pile(path);
        ASSERT_EQ(wide.size(), scalar.size());
        for (std::size_t i = 0; i < wide.size(); ++i) {
            EXPECT_EQ(wide[i].normalImpulse, scalar[i].normalImpulse) << i;
            EXPECT_EQ(wide[i].force.x, scalar[i].force.x) << i;
            EXPECT_EQ(wide[i].force.y, scalar[i].force.y) << i;
            EXPECT_EQ(wide[i].force.z, scalar[i].force.z) << i;
        }
    }
}

// A ball dropped from h hits the ground at sqrt(2 g h) (within 1 %): one
// event, at the bottom of the ball, normal along y. (The speed is the one when
// the ball first pushes, in the sub-step that closes the gap: up to a
// sub-step's gravity early.)
TEST(HitEvents, DroppedBallHitsAtFreeFallSpeed) {
    for (const Real h : {Real(1), Real(2), Real(3), Real(4)}) {
        World world(awake());
        const BodyId ground = addGround(world);
        const Real r = Real(0.25);
        const BodyId ball = addSphere(world, {0, r + h, 0}, r);
        std::vector<ContactHitEvent> hits;
        for (int i = 0; i < 180; ++i) {
            world.step(kDt);
            for (const ContactHitEvent& e : world.contactHitEvents()) hits.push_back(e);
        }
        ASSERT_EQ(hits.size(), 1u) << h;
        const ContactHitEvent& e = hits[0];
        EXPECT_TRUE((e.bodyA == ground && e.bodyB == ball) || (e.bodyA == ball && e.bodyB == ground));
        const Real expected = std::sqrt(2 * kG * h);
        EXPECT_NEAR(e.approachSpeed, expected, Real(0.01) * expected) << h;
        EXPECT_NEAR(std::abs(e.normal.y), 1, Real(1e-5));
        EXPECT_NEAR(e.point.x, 0, Real(1e-3));
        EXPECT_NEAR(e.point.y, 0, Real(0.2));  // at the step's start, within a step's fall
    }
}

// A slow touch (0.4 m/s, under the 1 m/s threshold) makes no event; a lower
// threshold reports it.
TEST(HitEvents, SlowTouchMakesNone) {
    for (const Real threshold : {Real(1), Real(0.2)}) {
        WorldDef def = awake();
        def.hitEventThreshold = threshold;
        World world(def);
        addGround(world);
        addSphere(world, {0, Real(0.25) + Real(0.01), 0}, Real(0.25));
        std::size_t count = 0;
        for (int i = 0; i < 60; ++i) {
            world.step(kDt);
            count += world.contactHitEvents().size();
        }
        EXPECT_EQ(count, threshold < Real(0.3) ? 1u : 0u) << threshold;
    }
    WorldDef bad;
    bad.hitEventThreshold = -1;
    EXPECT_THROW(World{bad}, Error);
    World world;
    EXPECT_THROW(world.setHitEventThreshold(std::numeric_limits<Real>::quiet_NaN()), Error);
    world.setHitEventThreshold(Real(0.5));
    EXPECT_EQ(world.settings().hitEventThreshold, Real(0.5));
}

// A kinematic platform driven by targets (sway, bob and yaw from rest, at most
// ~2 m/s^2, well under mu g) reaches every target and carries a box without slipping.
TEST(KinematicTargets, PlatformReachesTargetsAndCarriesABox) {
    World world(awake());
    BodyDef p;
    p.name = "platform";
    p.type = BodyType::Kinematic;
    p.shape = Shape::box({2, Real(0.1), 2});
    p.position = {0, Real(-0.1), 0};
    p.friction = Real(0.6);
    const BodyId platform = world.createBody(p);
    const BodyId box = addBox(world, {Real(0.5), Real(0.5), Real(0.3)}, Vec3::splat(Real(0.5)), 1, Real(0.6));
    run(world, 60);  // settle
    const Transform start{world.position(platform), world.orientation(platform)};
    const Vec3 boxLocal = inverseRotate(start.q, world.position(box) - start.p);
    const Quat boxTurn = conjugate(start.q) * world.orientation(box);
    Real worstFollow = 0, worstTarget = 0, worstTurn = 0;
    for (int i = 1; i <= 240; ++i) {
        const Real t = static_cast<Real>(i) * kDt;
        // From rest (no velocity jump at the start): accelerations at most
        // 0.5 * 2^2 = 2 m/s^2 sideways, 0.2 up and down, 0.4 rad/s^2 of yaw.
        const Transform target{{Real(0.5) * (1 - std::cos(2 * t)), Real(-0.1) + Real(0.2) * (1 - std::cos(t)),
                                Real(0.3) * (1 - std::cos(t))},
                               Quat::fromAxisAngle({0, 1, 0}, Real(0.4) * (1 - std::cos(t)))};
        world.moveKinematic(platform, target, kDt);
        world.step(kDt);
        worstTarget = std::max(worstTarget, length(world.position(platform) - target.p));
        worstTurn = std::max(worstTurn, Real(1) - std::abs(dot(world.orientation(platform), target.q)));
        const Vec3 expected = target.p + rotate(target.q, boxLocal);
        worstFollow = std::max(worstFollow, length(world.position(box) - expected));
    }
    EXPECT_LT(worstTarget, Real(1e-5));
    EXPECT_LT(worstTurn, Real(1e-6));
    EXPECT_LT(worstFollow, Real(0.01));
    const Quat relative = conjugate(world.orientation(platform)) * world.orientation(box);
    EXPECT_GT(std::abs(dot(relative, boxTurn)), Real(1) - Real(1e-4));  // it turned with the platform
}

TEST(KinematicTargets, BadInputNamesTheBodyAndField) {
    World world;
    BodyDef p;
    p.name = "lift";
    p.type = BodyType::Kinematic;
    p.shape = Shape::box({1, Real(0.1), 1});
    const BodyId lift = world.createBody(p);
    BodyDef d;
    d.name = "crate";
    d.shape = Shape::box(Vec3::splat(Real(0.5)));
    d.mass = 1;
    d.position = {5, 0, 0};
    const BodyId crate = world.createBody(d);
    const auto message = [&](BodyId id, const Transform& target, Real dt) {
        try {
            world.moveKinematic(id, target, dt);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    const Real nan = std::numeric_limits<Real>::quiet_NaN();
    EXPECT_THAT(message(lift, {{nan, 0, 0}, {}}, kDt), AllOf(HasSubstr("body 'lift'"), HasSubstr("target position")));
    EXPECT_THAT(message(lift, {{}, {nan, 0, 0, 0}}, kDt), AllOf(HasSubstr("body 'lift'"), HasSubstr("target orientation")));
    EXPECT_THAT(message(lift, {}, 0), AllOf(HasSubstr("body 'lift'"), HasSubstr("dt")));
    EXPECT_THAT(message(lift, {}, -kDt), AllOf(HasSubstr("body 'lift'"), HasSubstr("dt")));
    EXPECT_THAT(message(crate, {}, kDt), AllOf(HasSubstr("body 'crate'"), HasSubstr("kinematic")));
    // Nothing moved on bad input.
    EXPECT_EQ(length(world.linearVelocity(lift)), 0);
}
