// Frame invariance, A-B symmetry and feature-id stability.
// Tolerances: 1e-3 m / 1e-3 on positions, depths and normal components (the
// configurations go through EPA and clipping in float after a random rigid
// motion of up to ~10 m, so ~1e-5 relative noise is expected).
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <set>

#include "collision/narrow_phase.hpp"
#include "helpers.hpp"

using namespace fulcrum;
using fulcrum::test::expectVecNear;
using fulcrum::test::randomRotation;

namespace {

constexpr Real kTol = Real(1e-3);
constexpr Real kMargin = Real(0.02);

struct Config {
    const char* name;
    Shape a;
    Transform xa;
    Shape b;
    Transform xb;
    // Curved cylinder side: GJK stops when the distance is known to float
    // precision (~3e-6 m here), and on a surface of radius R the normal is then
    // only known to ~sqrt(2 * 3e-6 / R) ~ 3e-3 rad, the point to ~3e-3 m.
    Real pointTol = kTol;
};

std::vector<Config> configs() {
    const Quat tilt = Quat::fromAxisAngle(normalize(Vec3{1, 0.3f, -0.5f}), 0.4f);
    const Quat lying = Quat::fromAxisAngle({0, 0, 1}, 1.5707963f);
    const CompoundChild kids[2] = {{Shape::box({0.3f, 0.3f, 0.3f}), {{-0.6f, 0, 0}, Quat::identity()}},
                                   {Shape::sphere(0.35f), {{0.6f, 0, 0}, Quat::identity()}}};
    return {
        {"sphere-sphere", Shape::sphere(1), {}, Shape::sphere(0.5f), {{1.2f, 0.5f, -0.3f}, tilt}},
        {"sphere-capsule", Shape::sphere(0.5f), {{0.3f, 0.2f, 0.6f}, {}}, Shape::capsule(0.3f, 1), {{0, 0, 0}, tilt}},
        {"sphere-box", Shape::sphere(0.5f), {{0.4f, 1.35f, 0.2f}, {}}, Shape::box({1, 1, 1}), {{0, 0, 0}, tilt}},
        {"capsule-capsule", Shape::capsule(0.3f, 1), {{0, 0, 0}, lying}, Shape::capsule(0.2f, 0.7f), {{0.2f, 0.45f, 0.1f}, tilt}},
        {"capsule-box", Shape::capsule(0.25f, 0.5f), {{0.3f, 1.22f, 0.1f}, lying}, Shape::box({1, 1, 1}), {}},
        {"box-box face", Shape::box({1, 1, 1}), {}, Shape::box({0.5f, 0.5f, 0.5f}), {{0.3f, 1.48f, 0.1f}, Quat::fromAxisAngle({0, 1, 0}, 0.3f)}},
        {"box-box tilted", Shape::box({1, 0.5f, 1}), {}, Shape::box({0.5f, 0.5f, 0.5f}), {{0.2f, 1.2f, 0}, tilt}},
        {"cylinder-box", Shape::cylinder(0.5f, 1), {{0.2f, 1.99f, -0.1f}, {}}, Shape::box({2, 1, 2}), {}},
        {"cylinder-capsule", Shape::cylinder(0.5f, 1), {}, Shape::capsule(0.3f, 0.5f), {{0.75f, 0.2f, 0}, tilt}, Real(5e-3)},
        {"cylinder-cylinder", Shape::cylinder(0.5f, 0.5f), {}, Shape::cylinder(0.4f, 0.5f), {{0.3f, 0.98f, 0}, {}}},
        {"plane-box", Shape::plane({0, 1, 0}, 0), {}, Shape::box({0.5f, 0.5f, 0.5f}), {{0, 0.6f, 0}, tilt}},
        {"plane-cylinder", Shape::plane({0, 1, 0}, 0), {}, Shape::cylinder(0.5f, 1), {{0, 0.99f, 0}, {}}},
        {"compound-box", Shape::compound(kids), {{0, 1.28f, 0}, {}}, Shape::box({2, 1, 2}), {}},
    };
}

// Each point of `a` has a point of `b` within tol (position and depth) and vice versa.
void expectSamePoints(const Manifold& a, const Manifold& b, const std::function<Vec3(const Vec3&)>& map, Real tol) {
    ASSERT_EQ(a.pointCount, b.pointCount);
    for (const ContactPoint& p : a.contacts()) {
        bool found = false;
        for (const ContactPoint& q : b.contacts()) {
            if (length(map(p.position) - q.position) < tol && std::fabs(p.depth - q.depth) < tol) found = true;
        }
        EXPECT_TRUE(found) << "point " << p.position.x << " " << p.position.y << " " << p.position.z << " depth " << p.depth;
    }
}

}  // namespace

TEST(Invariance, RigidMotionOfBothShapesMovesTheContacts) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<Real> pos(-10, 10);
    ManifoldBuffer ref, moved;
    for (const Config& c : configs()) {
        SCOPED_TRACE(c.name);
        collide(c.a, c.xa, c.b, c.xb, kMargin, ref);
        ASSERT_GE(ref.size(), 1u);
        for (int trial = 0; trial < 10; ++trial) {
            const Transform t{{pos(rng), pos(rng), pos(rng)}, randomRotation(rng)};
            collide(c.a, t * c.xa, c.b, t * c.xb, kMargin, moved);
            ASSERT_EQ(moved.size(), ref.size());
            for (std::size_t i = 0; i < ref.size(); ++i) {
                expectVecNear(rotate(t.q, ref[i].normal), moved[i].normal, c.pointTol);
                expectSamePoints(ref[i], moved[i], [&](const Vec3& p) { return transformPoint(t, p); }, c.pointTol);
            }
        }
    }
}

TEST(Invariance, SwappingTheShapesFlipsTheNormal) {
    ManifoldBuffer ab, ba;
    for (const Config& c : configs()) {
        SCOPED_TRACE(c.name);
        collide(c.a, c.xa, c.b, c.xb, kMargin, ab);
        collide(c.b, c.xb, c.a, c.xa, kMargin, ba);
        ASSERT_GE(ab.size(), 1u);
        ASSERT_EQ(ab.size(), ba.size());
        for (std::size_t i = 0; i < ab.size(); ++i) {
            expectVecNear(ab[i].normal, -ba[i].normal, c.pointTol);
            expectSamePoints(ab[i], ba[i], [](const Vec3& p) { return p; }, c.pointTol);
            EXPECT_EQ(ab[i].childA, ba[i].childB);
            EXPECT_EQ(ab[i].childB, ba[i].childA);
        }
    }
}

TEST(FeatureIds, JitteredRestingBoxKeepsItsFeatureIds) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<Real> jitter(-1e-3f, 1e-3f);
    const Shape big = Shape::box({1, 1, 1}), small = Shape::box({0.5f, 0.5f, 0.5f});
    const Transform base{{0.1f, 1.495f, -0.2f}, Quat::fromAxisAngle({0, 1, 0}, 0.2f)};
    ManifoldBuffer out;
    collide(big, {}, small, base, kMargin, out);
    ASSERT_EQ(out.size(), 1u);
    ASSERT_EQ(out[0].pointCount, 4u);
    std::set<std::uint32_t> ids;
    for (const ContactPoint& c : out[0].contacts()) ids.insert(c.featureId);
    EXPECT_EQ(ids.size(), 4u);  // distinct per point
    for (int trial = 0; trial < 50; ++trial) {
        const Quat wobble = Quat::fromAxisAngle({jitter(rng), jitter(rng), jitter(rng)}, 2e-3f);
        const Transform xb{base.p + Vec3{jitter(rng), jitter(rng), jitter(rng)}, normalize(wobble * base.q)};
        collide(big, {}, small, xb, kMargin, out);
        ASSERT_EQ(out.size(), 1u);
        ASSERT_EQ(out[0].pointCount, 4u);
        std::set<std::uint32_t> now;
        for (const ContactPoint& c : out[0].contacts()) now.insert(c.featureId);
        EXPECT_EQ(now, ids) << "trial " << trial;
    }
}

TEST(FeatureIds, BoxOnPlaneAndCylinderOnBoxKeepTheirIds) {
    std::mt19937 rng(5);
    std::uniform_real_distribution<Real> jitter(-1e-3f, 1e-3f);
    struct Case { Shape a; Transform xa; Shape b; Transform xb; };
    const Case cases[2] = {{Shape::plane({0, 1, 0}, 0), {}, Shape::box({0.5f, 0.5f, 0.5f}), {{0, 0.495f, 0}, {}}},
                           {Shape::box({2, 1, 2}), {}, Shape::cylinder(0.5f, 1), {{0.2f, 1.995f, 0}, {}}}};
    ManifoldBuffer out;
    for (const Case& c : cases) {
        collide(c.a, c.xa, c.b, c.xb, kMargin, out);
        ASSERT_EQ(out.size(), 1u);
        std::set<std::uint32_t> ids;
        for (const ContactPoint& p : out[0].contacts()) ids.insert(p.featureId);
        for (int trial = 0; trial < 30; ++trial) {
            const Transform xb{c.xb.p + Vec3{jitter(rng), jitter(rng) * Real(0.5), jitter(rng)},
                               normalize(Quat::fromAxisAngle({jitter(rng), 0, jitter(rng)}, 1e-3f) * c.xb.q)};
            collide(c.a, c.xa, c.b, xb, kMargin, out);
            ASSERT_EQ(out.size(), 1u);
            std::set<std::uint32_t> now;
            for (const ContactPoint& p : out[0].contacts()) now.insert(p.featureId);
            for (std::uint32_t id : now) EXPECT_TRUE(ids.count(id)) << "new feature id " << id;
        }
    }
}
