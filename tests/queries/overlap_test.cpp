// World overlap queries against brute force: in a random world of every
// movable shape type (plus a plane), the set a query returns must equal the
// set of bodies whose shapes truly overlap the query shape, where "truly" is
// decided independently of the query code:
//   sphere: closestPoint's signed distance to the centre <= radius;
//   box and other shapes: the narrow phase (collide) reports a point of depth >= 0;
//   AABB: the body's tight bounds (Shape::bounds) overlap the box.
// Cases within kAmbiguity (0.1 mm) of touching are not counted either way:
// GJK and the narrow phase may round a grazing contact differently, and a
// 0.1 mm band is far below anything a game or tool would notice.
// Each check runs on the world as created (no step yet) and again after 40
// steps of falling and colliding (bodies have then left their broad-phase
// proxies' fat boxes: the stray path is exercised, see StrayBodiesAfterBounce).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>
#include <vector>

#include <fulcrum/fulcrum.hpp>

#include "collision/narrow_phase.hpp"
#include "collision/shape_queries.hpp"
#include "world/world_access.hpp"

namespace {

using namespace fulcrum;

constexpr Real kAmbiguity = Real(1e-4);

enum class Truth { Overlap, Separate, Ambiguous };

Truth fromDepth(Real depth) {  // depth > 0: overlap
    if (depth > kAmbiguity) return Truth::Overlap;
    if (depth < -kAmbiguity) return Truth::Separate;
    return Truth::Ambiguous;
}

Quat randomOrientation(std::mt19937& rng) {
    std::normal_distribution<Real> g(0, 1);
    const Real z = g(rng), y = g(rng), x = g(rng), w = g(rng);  // drawn last argument first, as GCC evaluated the call: the same cases with every compiler
    return normalize(Quat(w, x, y, z));
}

Shape randomShape(std::mt19937& rng, int kind) {
    std::uniform_real_distribution<Real> size(Real(0.2), Real(1.2));
    switch (kind % 6) {
        case 0: return Shape::sphere(size(rng));
        case 1: return Shape::box({size(rng), size(rng), size(rng)});
        case 2: {
            const Real halfHeight = size(rng), radius = size(rng) * Real(0.5);  // drawn last argument first, as GCC evaluated the call: the same cases with every compiler
            return Shape::capsule(radius, halfHeight);
        }
        case 3: {
            const Real halfHeight = size(rng), radius = size(rng);
            return Shape::cylinder(radius, halfHeight);
        }
        case 4: {
            std::uniform_real_distribution<Real> u(-1, 1);
            std::vector<Vec3> pts;
            for (int i = 0; i < 12; ++i) pts.push_back(Vec3{u(rng), u(rng), u(rng)} * size(rng));
            return Shape::convexHull(pts);
        }
        default: {
            const std::array<CompoundChild, 2> children{
                CompoundChild{Shape::box({size(rng) * Real(0.5), Real(0.3), Real(0.3)}), {{Real(-0.6), 0, 0}, {}}},
                CompoundChild{Shape::sphere(size(rng) * Real(0.5)), {{Real(0.6), Real(0.2), 0}, {}}}};
            return Shape::compound(children);
        }
    }
}

// 150 bodies in a 16 m cube (a third static, some sensors), over a floor plane.
World randomWorld(unsigned seed) {
    World world{WorldDef{.gravity = {0, Real(-9.81), 0}}};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<Real> pos(-8, 8);
    BodyDef floor;
    floor.type = BodyType::Static;
    floor.shape = Shape::plane(normalize(Vec3{Real(0.1), 1, 0}), -9);
    world.createBody(floor);
    for (int i = 0; i < 150; ++i) {
        BodyDef def;
        def.shape = randomShape(rng, i);
        def.position = {pos(rng), pos(rng), pos(rng)};
        def.orientation = randomOrientation(rng);
        def.type = i % 3 == 0 ? BodyType::Static : BodyType::Dynamic;
        def.isSensor = i % 10 == 7;
        def.linearVelocity = def.type == BodyType::Dynamic ? Vec3{pos(rng), pos(rng), pos(rng)} : Vec3{};
        world.createBody(def);
    }
    return world;
}

QueryFilter everything() {
    QueryFilter f;
    f.includeSensors = true;
    return f;
}

// The query's answer must contain every body that truly overlaps, and no body
// that truly doesn't; returns how many definite cases were checked.
template <class TruthFn>
int compareWithBruteForce(const World& world, const std::vector<BodyId>& answer, TruthFn&& truth, const char* what) {
    int definite = 0;
    EXPECT_TRUE(std::is_sorted(answer.begin(), answer.end(), [&](BodyId a, BodyId b) {
        return detail::implOf(world).cold[detail::implOf(world).bodySlots[a.index].dense].creationSerial <
               detail::implOf(world).cold[detail::implOf(world).bodySlots[b.index].dense].creationSerial;
    })) << what << ": not in creation order";
    for (const BodyId id : world.bodies()) {
        const Truth t = truth(world.shape(id), world.transform(id));
        if (t == Truth::Ambiguous) continue;
        ++definite;
        const bool found = std::find(answer.begin(), answer.end(), id) != answer.end();
        EXPECT_EQ(found, t == Truth::Overlap) << what << ": body #" << id.index << " (" << toString(world.shape(id).type())
                                              << ")";
    }
    return definite;
}

Truth collideTruth(const Shape& q, const Transform& xq, const Shape& b, const Transform& xb) {
    ManifoldBuffer buffer;
    collide(q, xq, b, xb, kAmbiguity * 2, buffer);
    Real deepest = -1;
    bool any = false;
    for (const Manifold& m : buffer.manifolds()) {
        if (m.pointCount == 0) continue;
        any = true;
        deepest = std::max(deepest, m.maxDepth());
    }
    return any ? fromDepth(deepest) : Truth::Separate;
}

class RandomWorld : public ::testing::TestWithParam<int> {
protected:
    // 0: as created (no step); 1: after 40 steps.
    void SetUp() override {
        if (GetParam() == 1) {
            for (int i = 0; i < 40; ++i) world.step(Real(1) / 60);
        }
    }
    World world = randomWorld(7);
    std::mt19937 rng{12345};
    std::uniform_real_distribution<Real> pos{-9, 9};
    std::uniform_real_distribution<Real> size{Real(0.1), Real(3)};
};

TEST_P(RandomWorld, SphereMatchesClosestPoint) {
    int definite = 0, hits = 0;
    for (int i = 0; i < 60; ++i) {
        const Vec3 c{pos(rng), pos(rng), pos(rng)};
        const Real r = size(rng);
        const std::vector<BodyId> answer = world.overlapSphere(c, r, everything());
        hits += static_cast<int>(answer.size());
        definite += compareWithBruteForce(world, answer, [&](const Shape& s, const Transform& xf) {
            return fromDepth(r - closestPoint(s, xf, c).distance);
        }, "sphere");
    }
    EXPECT_GT(definite, 60 * 140);
    EXPECT_GT(hits, 60);  // the test is not vacuous: there are overlaps to find
}

TEST_P(RandomWorld, BoxMatchesNarrowPhase) {
    int definite = 0, hits = 0;
    for (int i = 0; i < 60; ++i) {
        const Vec3 c{pos(rng), pos(rng), pos(rng)};
        const Vec3 h{size(rng), size(rng), size(rng)};
        const Quat q = randomOrientation(rng);
        const std::vector<BodyId> answer = world.overlapBox(c, h, q, everything());
        hits += static_cast<int>(answer.size());
        const Shape box = Shape::box(h);
        definite += compareWithBruteForce(world, answer, [&](const Shape& s, const Transform& xf) {
            return collideTruth(box, {c, q}, s, xf);
        }, "box");
    }
    EXPECT_GT(definite, 60 * 140);
    EXPECT_GT(hits, 60);
}

TEST_P(RandomWorld, AnyShapeMatchesNarrowPhase) {
    int definite = 0, hits = 0;
    for (int i = 0; i < 150; ++i) {  // smaller than the other query shapes: more queries
        const Shape shape = randomShape(rng, i);
        const Transform xf{{pos(rng), pos(rng), pos(rng)}, randomOrientation(rng)};
        const std::vector<BodyId> answer = world.overlapShape(shape, xf, everything());
        hits += static_cast<int>(answer.size());
        definite += compareWithBruteForce(world, answer, [&](const Shape& s, const Transform& bx) {
            return collideTruth(shape, xf, s, bx);
        }, toString(shape.type()));
    }
    EXPECT_GT(definite, 150 * 140);
    EXPECT_GT(hits, 30);
}

TEST_P(RandomWorld, AabbMatchesTightBounds) {
    int hits = 0;
    for (int i = 0; i < 60; ++i) {
        const Vec3 c{pos(rng), pos(rng), pos(rng)};
        const Vec3 h{size(rng), size(rng), size(rng)};
        const AABB box{c - h, c + h};
        const std::vector<BodyId> answer = world.overlapAABB(box, everything());
        hits += static_cast<int>(answer.size());
        compareWithBruteForce(world, answer, [&](const Shape& s, const Transform& xf) {
            if (s.type() == ShapeType::Plane) {
                // Half-space n . p <= offset against the box's lowest corner along n.
                const Vec3 n = rotate(xf.q, s.planeNormal());
                const Real offset = s.planeOffset() + dot(n, xf.p);
                Real lowest = dot(n, c);
                for (std::size_t k = 0; k < 3; ++k) lowest -= std::fabs(n[k]) * h[k];
                return fromDepth(offset - lowest);
            }
            // Tight bounds are what this query tests, so the answer is exact.
            return overlaps(s.bounds(xf), box) ? Truth::Overlap : Truth::Separate;
        }, "aabb");
    }
    EXPECT_GT(hits, 60);
}

TEST_P(RandomWorld, SensorsExcludedByDefault) {
    const AABB all{Vec3::splat(-100), Vec3::splat(100)};
    const std::vector<BodyId> withSensors = world.overlapAABB(all, everything());
    const std::vector<BodyId> without = world.overlapAABB(all);
    EXPECT_EQ(withSensors.size(), world.bodyCount());
    EXPECT_EQ(without.size(), world.bodyCount() - 15);  // bodies i % 10 == 7 of 150
    EXPECT_EQ(withSensors, world.bodies());              // creation order
}

INSTANTIATE_TEST_SUITE_P(BeforeAndAfterSteps, RandomWorld, ::testing::Values(0, 1));

// ---- stray bodies: after a bounce a body can sit outside its proxy ---------------------

TEST(StrayBodies, BouncingBallIsFoundEveryStep) {
    // A ball dropped onto a plane at 10 m/s bounces (restitution 0.9). The contact
    // manager moved its proxy at the start of each step, fattened downwards by the
    // predicted motion; the bounce sends it up instead, out of that box. Every
    // step, queries that touch only the top of the ball (the part that leaves
    // the box) must still find it, and the test checks the case really arises
    // (steps where the top sits more than 1 cm above the fat box).
    World world;
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::plane({0, 1, 0}, 0);
    world.createBody(ground);
    BodyDef ballDef;
    const Real r = Real(0.25);
    ballDef.shape = Shape::sphere(r);
    ballDef.position = {0, Real(0.6), 0};
    ballDef.linearVelocity = {0, -10, 0};
    ballDef.restitution = Real(0.9);
    const BodyId ball = world.createBody(ballDef);
    int outside = 0;
    Real worstEscape = 0;
    for (int step = 0; step < 30; ++step) {
        world.step(Real(1) / 60);
        const WorldImpl& w = detail::implOf(world);
        const AABB fat = w.contactManager.broadPhase().fatAABB(w.contactManager.proxyOfSlot(ball.index));
        const AABB tight = world.shape(ball).bounds(world.transform(ball));
        const Real escape = std::max(maxComponent(tight.max - fat.max), maxComponent(fat.min - tight.min));
        if (escape > Real(0.01)) ++outside;
        worstEscape = std::max(worstEscape, escape);
        // 5 mm below the top of the ball: inside the ball, outside the fat box when it escaped upwards.
        const Vec3 top = world.position(ball) + Vec3{0, r - Real(0.005), 0};
        const std::vector<BodyId> found = world.overlapSphere(top, Real(0.001));
        ASSERT_EQ(found.size(), 1u) << "step " << step;
        EXPECT_EQ(found[0], ball);
        const auto hit = world.castRay({top - Vec3{5, 0, 0}, {10, 0, 0}});
        ASSERT_TRUE(hit.has_value()) << "step " << step;
        EXPECT_EQ(hit->body, ball);
        const auto swept = world.castShape(Shape::sphere(Real(0.002)), {top - Vec3{5, 0, 0}, {}}, {10, 0, 0});
        ASSERT_TRUE(swept.has_value()) << "step " << step;
        EXPECT_EQ(swept->body, ball);
    }
    EXPECT_GT(outside, 0) << "the scenario no longer produces a stray body; the stray path is untested";
    std::printf("ball more than 1 cm outside its proxy after %d of 30 steps, by up to %.3f m\n", outside,
                static_cast<double>(worstEscape));
}

// ---- meshes are surfaces ----------------------------------------------------------------

TEST(OverlapMesh, SurfaceWithinReach) {
    // A flat quad mesh at y = 0 over [-5, 5]^2: a sphere overlaps it when its
    // centre is within r of the plane (and over the quad), from either side.
    World world;
    const std::vector<Vec3> v{{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}};
    const std::vector<std::array<std::uint32_t, 3>> t{{0, 2, 1}, {0, 3, 2}};
    BodyDef def;
    def.type = BodyType::Static;
    def.shape = Shape::mesh(v, t);
    const BodyId mesh = world.createBody(def);
    EXPECT_EQ(world.overlapSphere({1, Real(0.49), 2}, Real(0.5)).size(), 1u);
    EXPECT_EQ(world.overlapSphere({1, Real(-0.49), 2}, Real(0.5)).size(), 1u);
    EXPECT_TRUE(world.overlapSphere({1, Real(0.51), 2}, Real(0.5)).empty());
    EXPECT_TRUE(world.overlapSphere({6, 0, 0}, Real(0.5)).empty());  // beyond the edge at x = 5
    // A box tilted 45 degrees about z, its lowest edge sqrt(2) * 0.5 below the centre.
    const Quat tilt = Quat::fromAxisAngle({0, 0, 1}, Real(0.78539816));
    EXPECT_EQ(world.overlapBox({0, Real(0.70), 0}, Vec3::splat(Real(0.5)), tilt), std::vector<BodyId>{mesh});
    EXPECT_TRUE(world.overlapBox({0, Real(0.72), 0}, Vec3::splat(Real(0.5)), tilt).empty());
}

}  // namespace
