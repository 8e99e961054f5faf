// The contact manager's apart cache (docs/narrow-phase.md, "Pairs proved
// apart"): a pair the narrow phase proved apart is skipped while the motion
// since then cannot have closed the gap. It must skip only pairs that are
// truly farther apart than the margin: the bound collide() reports, and that
// bound less apartMotionBound after a random move, are checked here against
// a full GJK run on the shapes at their poses.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "../../bench/box3d_scenes.hpp"
#include "collision/gjk.hpp"
#include "collision/narrow_phase.hpp"
#include "collision/support.hpp"
#include "contacts/contact_manager.hpp"
#include "fulcrum/fulcrum.hpp"

using namespace fulcrum;

namespace {

Quat randomTurn(std::mt19937& rng) {
    std::normal_distribution<Real> g(0, 1);
    return normalize(Quat{g(rng), g(rng), g(rng), g(rng)});
}

// The distance between two plain convex shapes by a full GJK run on their
// cores (the radii of spheres and capsules taken off), 0 when they overlap.
Real fullDistance(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb) {
    const detail::ConvexShape ca = detail::makeConvexCore(a, xa), cb = detail::makeConvexCore(b, xb);
    const detail::GjkResult g = detail::gjkDistance(ca, cb, false);
    return g.overlap ? Real(0) : std::max(Real(0), g.distance - ca.radius - cb.radius);
}

std::vector<Shape> plainShapes() {
    std::vector<Shape> shapes;
    const bench::HullPileSpec pile = bench::convexPile(1, 1, 1);
    std::vector<Vec3> points;
    for (const bench::V3& p : pile.hullPoints) points.push_back({Real(p.x), Real(p.y), Real(p.z)});
    shapes.push_back(Shape::convexHull(points));  // Box3D's 32-point hull of radius 2
    std::mt19937 rng(5);
    std::normal_distribution<Real> g(0, 1);
    std::vector<Vec3> cloud;
    for (int i = 0; i < 12; ++i) cloud.push_back(Vec3{g(rng) * Real(1.5), g(rng) * Real(0.4), g(rng)});
    shapes.push_back(Shape::convexHull(cloud));   // a flat, uneven one
    shapes.push_back(Shape::box({Real(1.5), Real(0.2), Real(0.7)}));
    shapes.push_back(Shape::box({40, Real(0.5), 40}));  // a ground: GJK on the box's near part
    shapes.push_back(Shape::sphere(Real(0.8)));
    shapes.push_back(Shape::capsule(Real(0.4), Real(1.2)));
    shapes.push_back(Shape::cylinder(Real(0.9), Real(0.6)));
    return shapes;
}

Real reachOf(const Shape& s) { return detail::makeConvex(s, Transform{}).boundingRadius(); }

}  // namespace

TEST(ApartCache, ProvedDistanceNeverExceedsTheTrueOne) {
    // Pairs at random poses and margins: whenever collide() rejects a pair
    // with a proved distance, that distance is above the margin and at most
    // the true one (GJK run to convergence; 1e-5 m of rounding on shapes a few
    // metres across). And after a random move of both shapes, the true
    // distance is at least the proved one less the motion bound: the cache
    // skips a pair only while that is above the margin.
    const std::vector<Shape> shapes = plainShapes();
    std::mt19937 rng(21);
    std::uniform_real_distribution<Real> unit(0, 1);
    std::normal_distribution<Real> g(0, 1);
    ManifoldBuffer buffer;
    int proved = 0, moved = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        const Shape& a = shapes[static_cast<std::size_t>(trial) % shapes.size()];
        const Shape& b = shapes[static_cast<std::size_t>(trial / 7) % shapes.size()];
        const Real spread = Real(2) + Real(6) * unit(rng);
        const Transform xa{Vec3{g(rng), g(rng), g(rng)} * Real(0.5), randomTurn(rng)};
        const Transform xb{xa.p + normalize(Vec3{g(rng), g(rng), g(rng)}) * spread, randomTurn(rng)};
        const Real margin = Real(0.5) * unit(rng);
        collide(a, xa, b, xb, margin, buffer);
        if (!buffer.empty() || buffer.apartBy() <= 0) continue;
        ++proved;
        const Real bound = buffer.apartBy();
        EXPECT_GT(bound, margin) << "trial " << trial;
        const Real truth = fullDistance(a, xa, b, xb);
        EXPECT_LE(bound, truth + Real(1e-5)) << "trial " << trial;
        // Small moves (a step's worth: centimetres, a few degrees) and large ones.
        for (const Real size : {Real(0.02), Real(0.3), Real(2)}) {
            const Quat turnA = normalize(Quat{1, g(rng) * size * Real(0.1), g(rng) * size * Real(0.1), g(rng) * size * Real(0.1)});
            const Quat turnB = normalize(Quat{1, g(rng) * size * Real(0.1), g(rng) * size * Real(0.1), g(rng) * size * Real(0.1)});
            const Transform ya{xa.p + Vec3{g(rng), g(rng), g(rng)} * size, normalize(turnA * xa.q)};
            const Transform yb{xb.p + Vec3{g(rng), g(rng), g(rng)} * size, normalize(turnB * xb.q)};
            const Real motion = detail::apartMotionBound(relative(xa, xb), relative(ya, yb), reachOf(a), reachOf(b));
            const Real after = fullDistance(a, ya, b, yb);
            EXPECT_GE(after + Real(1e-5), bound - motion) << "trial " << trial << " move " << size;
            if (bound - motion > 0) ++moved;
        }
    }
    // Enough of both kinds to mean something.
    EXPECT_GT(proved, 500);
    EXPECT_GT(moved, 300);
}

TEST(ApartCache, RoundPairsProveTheirDistance) {
    // Capsule against capsule, sphere against capsule and sphere against box
    // (their own pair functions, not GJK) prove the distance they reject a
    // pair at: the core segments' or centre's distance less the radii, the
    // true distance up to rounding, so rain's capsule pairs apart are skipped
    // (docs/narrow-phase.md, "Pairs proved apart"). Without the proof these
    // pairs never held a bound and ran their test every step.
    const Shape capsule = Shape::capsule(Real(0.11), Real(0.19));
    const Shape longCapsule = Shape::capsule(Real(0.05), Real(0.6));
    const Shape sphere = Shape::sphere(Real(0.3));
    const Shape box = Shape::box({Real(0.5), Real(0.2), Real(0.35)});
    const std::pair<const Shape*, const Shape*> pairs[] = {{&capsule, &longCapsule}, {&capsule, &capsule},
                                                           {&sphere, &capsule},      {&capsule, &sphere},
                                                           {&sphere, &box},          {&box, &sphere}};
    std::mt19937 rng(33);
    std::uniform_real_distribution<Real> unit(0, 1);
    std::normal_distribution<Real> g(0, 1);
    ManifoldBuffer buffer;
    for (const auto& [a, b] : pairs) {
        int proved = 0;
        for (int trial = 0; trial < 400; ++trial) {
            const Transform xa{Vec3{g(rng), g(rng), g(rng)} * Real(0.3), randomTurn(rng)};
            const Real spread = Real(0.2) + Real(1.5) * unit(rng);
            const Transform xb{xa.p + normalize(Vec3{g(rng), g(rng), g(rng)}) * spread, randomTurn(rng)};
            const Real margin = Real(0.1) * unit(rng);
            collide(*a, xa, *b, xb, margin, buffer);
            const Real truth = fullDistance(*a, xa, *b, xb);
            if (!buffer.empty()) {
                EXPECT_LE(truth, margin + Real(1e-5)) << "trial " << trial;
                continue;
            }
            ++proved;
            ASSERT_GT(buffer.apartBy(), margin) << "trial " << trial;
            EXPECT_NEAR(buffer.apartBy(), truth, Real(1e-5)) << "trial " << trial;
        }
        EXPECT_GT(proved, 100) << toString(a->type()) << " against " << toString(b->type());
    }
}

TEST(ApartCache, TinyTurnsCount) {
    // A turn too small for 1 - dot(q0, q1) to register in floats still moves a
    // far point: the bound must see it (0.2 mrad at 100 m: 2 cm).
    const Transform from{{}, Quat::identity()};
    const Transform to{{}, Quat::fromAxisAngle({0, 1, 0}, Real(2e-4))};
    EXPECT_GE(detail::apartMotionBound(from, to, 100, 100), Real(0.0199));
}

TEST(ApartCache, FastTumblingHullsStillCollide) {
    // Two of Box3D's pile hulls flung at each other, spinning fast, from far
    // enough apart that their pair is proved apart (and skipped) for several
    // steps before they meet: they must still meet face to face, not pass
    // through each other.
    const bench::HullPileSpec pile = bench::convexPile(1, 1, 1);
    std::vector<Vec3> points;
    for (const bench::V3& p : pile.hullPoints) points.push_back({Real(p.x), Real(p.y), Real(p.z)});
    const Shape hull = Shape::convexHull(points);
    for (const Real speed : {Real(5), Real(40)}) {
        WorldDef def;
        def.gravity = {};
        World world(def);
        BodyDef d;
        d.shape = hull;
        d.position = {-8, 0, 0};
        d.linearVelocity = {speed, 0, 0};
        d.angularVelocity = {3, 11, 7};
        const BodyId left = world.createBody(d);
        d.position = {8, Real(0.5), 0};
        d.linearVelocity = {-speed, 0, 0};
        d.angularVelocity = {-9, 2, 5};
        const BodyId right = world.createBody(d);
        bool crossed = false;
        for (int step = 0; step < 120; ++step) {
            world.step(Real(1) / 60);
            crossed = crossed || world.position(left).x > world.position(right).x;
        }
        EXPECT_FALSE(crossed) << "speed " << speed;
        EXPECT_LT(world.position(left).x, Real(-1)) << "speed " << speed;  // bounced or stopped, not through
    }
}

TEST(ApartCache, BoxPairsProvedApartByTheirSeparatingAxis) {
    // Box against box runs its own SAT (collide_box.cpp), which leaves the
    // separation along the first axis past the margin as the proof: a face
    // axis of either box or an edge-edge axis. Cubes, slabs and rods at random
    // poses, 0 to 1.5 m apart: every proof is above the margin and at most the
    // true distance (a full GJK run; 1e-5 m of rounding), and after a random
    // move the true distance is at least the proof less the motion bound.
    std::vector<Shape> boxes;
    boxes.push_back(Shape::box({Real(0.2), Real(0.2), Real(0.2)}));  // the washer's cube
    boxes.push_back(Shape::box({Real(1.5), Real(0.2), Real(0.7)}));
    boxes.push_back(Shape::box({Real(0.05), Real(1.2), Real(0.05)}));
    std::mt19937 rng(77);
    std::uniform_real_distribution<Real> unit(0, 1);
    std::normal_distribution<Real> g(0, 1);
    ManifoldBuffer buffer;
    int proved = 0, touching = 0;
    for (int trial = 0; trial < 6000; ++trial) {
        const Shape& a = boxes[static_cast<std::size_t>(trial) % boxes.size()];
        const Shape& b = boxes[static_cast<std::size_t>(trial / 3) % boxes.size()];
        const Transform xa{Vec3{g(rng), g(rng), g(rng)}, randomTurn(rng)};
        const Transform xb0{xa.p, randomTurn(rng)};
        // Along a random direction, just beyond where the two reach.
        const Vec3 dir = normalize(Vec3{g(rng), g(rng), g(rng)});
        const Real reach = reachOf(a) + reachOf(b);
        const Transform xb{xa.p + dir * (Real(0.3) * reach + Real(1.5) * unit(rng)), xb0.q};
        const Real margin = Real(0.1) * unit(rng);
        collide(a, xa, b, xb, margin, buffer);
        if (!buffer.empty()) {
            ++touching;
            continue;
        }
        // Rejected with no axis past the margin (the clipped points all beyond
        // it): no proof, the pair runs again next step.
        if (buffer.apartBy() <= 0) continue;
        ++proved;
        const Real bound = buffer.apartBy();
        EXPECT_GT(bound, margin) << "trial " << trial;
        const Real truth = fullDistance(a, xa, b, xb);
        EXPECT_LE(bound, truth + Real(1e-5)) << "trial " << trial;
        const Quat turnA = normalize(Quat{1, g(rng) * Real(0.01), g(rng) * Real(0.01), g(rng) * Real(0.01)});
        const Quat turnB = normalize(Quat{1, g(rng) * Real(0.01), g(rng) * Real(0.01), g(rng) * Real(0.01)});
        const Transform ya{xa.p + Vec3{g(rng), g(rng), g(rng)} * Real(0.02), normalize(turnA * xa.q)};
        const Transform yb{xb.p + Vec3{g(rng), g(rng), g(rng)} * Real(0.02), normalize(turnB * xb.q)};
        const Real motion = detail::apartMotionBound(relative(xa, xb), relative(ya, yb), reachOf(a), reachOf(b));
        EXPECT_GE(fullDistance(a, ya, b, yb) + Real(1e-5), bound - motion) << "trial " << trial;
    }
    EXPECT_GT(proved, 2000);
    EXPECT_GT(touching, 300);
}
