// Every persistent manifold against a fresh narrow phase over long pile runs
// (issue 27, defect 2: a ground-hull manifold 300 m deep with a sideways
// normal in Box3D's convex pile).
//
// After a step each live contact holds the manifolds of the poses at the
// step's start (World::previousTransform): the narrow phase ran on them, or
// the manifold of an earlier pose was recycled (contact_manager.cpp: B moved
// less than kRecycleDistance = 1 mm and kRecycleAngle = 0.1 degree relative to
// A since the narrow phase last ran; the stored surface points then move
// with the bodies and their depths are measured anew along the normal, which
// turns with A). Every few steps each manifold is compared with collide() on
// those poses:
// - depth: the deepest point's depth. A recycled point's depth is exact for
//   its features; the deepest feature of the new pose is deeper than the
//   deepest old one by at most the relative motion at the farthest contact
//   point: 1 mm + 0.1 degree x R, with R the largest distance from a body's
//   origin to its surface (2 m for Box3D's hull): 4.5 mm. Collided manifolds
//   come from the same call (only the margin differs, and the deepest point
//   does not depend on it). The defect's depths were off by up to 300 m, the
//   margin-dependent depths of the clipping defect by up to 0.34 m.
// - normal: compared by what it is for, separating the shapes. Two normals
//   can both be right (an edge resting on a face; a face on a face), so the
//   stored normal must separate the shapes (support functions at the poses)
//   as well as the fresh one does, within twice the depth tolerance (each
//   normal's separation moves by at most that bound since the narrow phase)
//   plus the narrow phase's own accuracy (below): 2.6 cm. The defect's
//   normals, up to 90 degrees off over a 500 m box, missed by tens to
//   hundreds of metres.
// - presence: a pair the fresh narrow phase sees overlapping by more than the
//   depth tolerance has a manifold.
// The piles stand on Box3D's convex-pile ground (a static 500 x 2 x 500 m box).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "../../bench/box3d_scenes.hpp"
#include "collision/narrow_phase.hpp"
#include "collision/support.hpp"
#include "fulcrum/fulcrum.hpp"
#include "world/world_access.hpp"

using namespace fulcrum;

namespace {

constexpr Real kDt = Real(1) / 60;
constexpr Real kRecycleDistance = Real(0.001);                            // contact_manager.cpp
constexpr Real kRecycleAngle = Real(0.1) * Real(3.14159265358979) / 180;  // contact_manager.cpp
constexpr Real kLargestRadius = 2;                                        // Box3D's hull; the other shapes are smaller
constexpr Real kDepthTolerance = kRecycleDistance + kRecycleAngle * kLargestRadius;  // 4.5 mm
// The narrow phase's hull-hull normal near touching: a face contact gets the
// exact face normal, but at an edge contact GJK/EPA's direction between
// hulls a fraction of a millimetre apart stands, and separates Box3D's hulls
// up to 1.7 cm less than the best axis (measured by HullNormal.* in
// tests/narrowphase/large_box_test.cpp; docs/narrow-phase.md, "Hull face axes"). So a stored
// normal may be that much worse or better than the fresh one.
constexpr Real kNarrowPhaseNormalAccuracy = Real(0.017);
constexpr Real kSeparationTolerance = 2 * kDepthTolerance + kNarrowPhaseNormalAccuracy;
constexpr Real kFreshMargin = 1;  // every manifold the contact manager can hold (its margin grows with speed)
constexpr Real kNear = Real(0.02);  // WorldDef::speculativeMargin's default

Shape convexPileHull() {
    std::vector<Vec3> points;
    for (const bench::V3& p : bench::convexPileHullPoints()) {
        points.push_back({static_cast<Real>(p.x), static_cast<Real>(p.y), static_cast<Real>(p.z)});
    }
    return Shape::convexHull(points);
}

enum class Mix { Hulls, Boxes, Mixed };

// A 3 x 3 x `layers` grid of bodies dropped tumbling on Box3D's ground box.
World buildPile(Mix mix, int layers) {
    const bench::HullPileSpec spec = bench::convexPile(1, 1, 1);
    WorldDef def;
    def.substeps = spec.substeps;
    World world(def);
    BodyDef ground;
    ground.type = BodyType::Static;
    ground.shape = Shape::box({Real(spec.groundHalf.x), Real(spec.groundHalf.y), Real(spec.groundHalf.z)});
    ground.position = {Real(spec.groundPosition.x), Real(spec.groundPosition.y), Real(spec.groundPosition.z)};
    world.createBody(ground);
    const Shape hull = convexPileHull();
    const Shape shapes[5] = {hull, Shape::box({1, Real(0.6), Real(0.8)}), Shape::capsule(Real(0.5), Real(0.8)),
                             Shape::cylinder(Real(0.8), Real(0.6)), Shape::sphere(Real(0.9))};
    std::mt19937 rng(7);
    std::uniform_real_distribution<Real> unit(-1, 1);
    int index = 0;
    for (int layer = 0; layer < layers; ++layer) {
        for (int i = 0; i < 3; ++i) {
            for (int k = 0; k < 3; ++k, ++index) {
                BodyDef d;
                d.shape = mix == Mix::Hulls ? shapes[0] : mix == Mix::Boxes ? shapes[1] : shapes[index % 5];
                d.density = Real(spec.density);
                d.friction = Real(spec.friction);
                d.position = {Real(3.6) * static_cast<Real>(i - 1) + Real(0.4) * unit(rng), Real(2.2) + Real(4) * static_cast<Real>(layer),
                              Real(3.6) * static_cast<Real>(k - 1) + Real(0.4) * unit(rng)};
                // Drawn last component first, as GCC evaluated the former
                // constructor call: the same pile with every compiler.
                const Real qz = unit(rng), qy = unit(rng), qx = unit(rng), qw = unit(rng);
                d.orientation = normalize(Quat(qw, qx, qy, qz));
                d.angularVelocity = {unit(rng), unit(rng), unit(rng)};
                world.createBody(d);
            }
        }
    }
    return world;
}

// B's lowest point along n minus A's highest (negative: overlap along n).
Real separationAlong(const detail::ConvexShape& a, const detail::ConvexShape& b, const Vec3& n) {
    return dot(b.support(-n) - a.support(n), n);
}

struct Check {
    int manifolds = 0, recycled = 0, fresh = 0, near = 0;
    int depthErrors = 0, normalErrors = 0, missing = 0;
    Real worstDepth = 0, worstSeparation = 0;
    std::string first;  // the first failure, for the message
    void fail(const std::string& what) {
        if (first.empty()) first = what;
    }
};

// Every persistent manifold of `world` against collide() at the poses it describes.
void checkManifolds(World& world, int step, Check& out) {
    const WorldImpl& w = detail::implOf(world);
    const auto& contacts = w.contactManager.contacts();
    ManifoldBuffer fresh;
    std::vector<char> paired(w.motion.size() * w.motion.size(), 0);
    for (const detail::Contact& c : contacts) {
        if (!c.alive || c.sensor) continue;
        const std::uint32_t dA = w.bodySlots[c.slotA].dense, dB = w.bodySlots[c.slotB].dense;
        paired[dA * w.motion.size() + dB] = paired[dB * w.motion.size() + dA] = 1;
        if (c.manifolds.empty()) continue;
        const Transform xa = w.previous[dA], xb = w.previous[dB];
        const Shape &sa = w.cold[dA].shape, &sb = w.cold[dB].shape;
        const detail::ConvexShape ca = detail::makeConvex(sa, xa), cb = detail::makeConvex(sb, xb);
        collide(sa, xa, sb, xb, kFreshMargin, fresh);
        const Transform rel = relative(xa, xb);
        const bool recycled = c.hasPose && !(rel.p == c.relativePose.p);
        for (const detail::CachedManifold& m : c.manifolds) {
            ++out.manifolds;
            Real depth = -1e30f;
            for (std::uint32_t k = 0; k < m.pointCount; ++k) depth = std::max(depth, m.points[k].depth);
            const std::string pair = "step " + std::to_string(step) + ", bodies " + std::to_string(dA) + "-" +
                                     std::to_string(dB) + (recycled ? " (recycled)" : " (collided)");
            if (fresh.size() != 1) {
                ++out.depthErrors;
                out.fail(pair + ": stored depth " + std::to_string(depth) + ", the narrow phase finds no contact");
                continue;
            }
            const Manifold& f = fresh[0];
            // Speculative points farther apart than the base margin come and
            // go with the pair's speed (the margin grows with it): not compared.
            if (depth < -kNear && f.maxDepth() < -kNear) continue;
            ++out.near;
            ++(recycled ? out.recycled : out.fresh);
            const Real depthError = std::fabs(depth - f.maxDepth());
            out.worstDepth = std::max(out.worstDepth, depthError);
            if (depthError > kDepthTolerance) {
                ++out.depthErrors;
                out.fail(pair + ": stored depth " + std::to_string(depth) + ", fresh " + std::to_string(f.maxDepth()));
            }
            const Real loss = separationAlong(ca, cb, f.normal) - separationAlong(ca, cb, m.normal);
            out.worstSeparation = std::max(out.worstSeparation, loss);
            if (loss > kSeparationTolerance) {
                ++out.normalErrors;
                out.fail(pair + ": stored normal (" + std::to_string(m.normal.x) + ", " + std::to_string(m.normal.y) +
                         ", " + std::to_string(m.normal.z) + ") separates " + std::to_string(loss) +
                         " m less than the fresh normal (" + std::to_string(f.normal.x) + ", " +
                         std::to_string(f.normal.y) + ", " + std::to_string(f.normal.z) + ")");
            }
        }
    }
    // Overlapping pairs without a contact (static pairs aside).
    for (std::uint32_t i = 0; i < w.motion.size(); ++i) {
        for (std::uint32_t j = i + 1; j < w.motion.size(); ++j) {
            if (paired[i * w.motion.size() + j]) continue;
            if (w.params[i].type == BodyType::Static && w.params[j].type == BodyType::Static) continue;
            collide(w.cold[i].shape, w.previous[i], w.cold[j].shape, w.previous[j], 0, fresh);
            if (fresh.size() == 1 && fresh[0].maxDepth() > kDepthTolerance) {
                ++out.missing;
                out.fail("step " + std::to_string(step) + ", bodies " + std::to_string(i) + "-" + std::to_string(j) +
                         " overlap by " + std::to_string(fresh[0].maxDepth()) + " m without a contact");
            }
        }
    }
}

void runAndCheck(Mix mix, int layers, int steps, int every) {
    World world = buildPile(mix, layers);
    Check check;
    for (int step = 1; step <= steps; ++step) {
        world.step(kDt);
        if (step % every == 0) checkManifolds(world, step, check);
    }
    // The run exercised both kinds of manifolds.
    EXPECT_GT(check.recycled, 100);
    EXPECT_GT(check.fresh, 100);
    EXPECT_EQ(check.depthErrors, 0) << check.first << "; worst depth error " << check.worstDepth << " m of "
                                    << check.manifolds << " manifolds";
    EXPECT_EQ(check.normalErrors, 0) << check.first << "; worst separation lost " << check.worstSeparation << " m";
    EXPECT_EQ(check.missing, 0) << check.first;
}

}  // namespace

TEST(PersistentManifold, HullPileMatchesAFreshNarrowPhase) { runAndCheck(Mix::Hulls, 6, 400, 4); }

TEST(PersistentManifold, BoxPileMatchesAFreshNarrowPhase) { runAndCheck(Mix::Boxes, 6, 400, 4); }

TEST(PersistentManifold, MixedPileMatchesAFreshNarrowPhase) { runAndCheck(Mix::Mixed, 6, 400, 4); }
