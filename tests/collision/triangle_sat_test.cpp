// Boxes and hulls against one triangle by the separating-axis test
// (src/collision/collide_triangle.cpp), against closed forms and against the
// general path it replaces (GJK, EPA, face clipping: collideTriangleWithConvex
// without a prepared polytope), with the mesh path's one-sided and
// internal-edge rules on top.
#include <gtest/gtest.h>


#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include "collision/collide_mesh.hpp"
#include "collision/collide_pairs.hpp"
#include "collision/collide_triangle.hpp"
#include "collision/narrow_phase.hpp"
#include "narrowphase/helpers.hpp"

using namespace fulcrum;
using fulcrum::test::expectVecNear;

namespace {

constexpr Real kMargin = Real(0.02);
constexpr std::uint8_t kAllConvex = 7;

// The candidates of one triangle through the separating-axis test (sat) or
// the general path.
std::vector<detail::MeshContactCandidate> collideOne(const Vec3 w[3], std::uint8_t mask, const detail::ConvexShape& b,
                                                     bool sat, Real margin = kMargin) {
    std::vector<detail::MeshContactCandidate> out;
    std::vector<detail::PolytopeEdge> edges;
    detail::TrianglePolytope polytope;
    const bool prepared = polytope.prepare(b, edges);
    EXPECT_TRUE(!sat || prepared);
    detail::collideTriangleWithConvex(w, mask, 0, b, margin, out, sat ? &polytope : nullptr);
    return out;
}

Real deepest(const std::vector<detail::MeshContactCandidate>& c) {
    Real d = -1e30f;
    for (const auto& k : c) d = std::max(d, k.contact.depth);
    return d;
}

// How far b lies beyond the triangle along unit n (support functions):
// every direction's is a lower bound of the distance, the best one's exact.
Real separationAlong(const Vec3 w[3], const detail::ConvexShape& b, const Vec3& n) {
    Real lo, hi;
    b.extent(n, lo, hi);
    return lo - std::max({dot(n, w[0]), dot(n, w[1]), dot(n, w[2])});
}

Shape cubeHull(Real h) {
    std::vector<Vec3> p;
    for (int i = 0; i < 8; ++i) p.push_back({(i & 1) ? h : -h, (i & 2) ? h : -h, (i & 4) ? h : -h});
    return Shape::convexHull(p);
}

// A six-sided prism along y (a tree's trunk segment in bench/mesh_scenes.hpp).
Shape hexPrism(Real radius, Real halfHeight) {
    std::vector<Vec3> p;
    for (int i = 0; i < 6; ++i) {
        const Real a = Real(6.283185307) * static_cast<Real>(i) / 6;
        for (const Real y : {-halfHeight, halfHeight}) p.push_back({radius * std::cos(a), y, radius * std::sin(a)});
    }
    return Shape::convexHull(p);
}

Shape pyramid(Real half, Real height) {
    const std::vector<Vec3> p = {{-half, 0, -half}, {half, 0, -half}, {half, 0, half}, {-half, 0, half}, {0, height, 0}};
    return Shape::convexHull(p);
}

Shape rock(std::mt19937& rng) {
    std::uniform_real_distribution<Real> u(-0.4f, 0.4f);
    std::vector<Vec3> p;
    for (int i = 0; i < 10; ++i) p.push_back({u(rng), u(rng) * Real(0.7), u(rng)});
    return Shape::convexHull(p);
}

// A random triangle of size r, flattened towards y = 0 (|y| <= 0.3 r), in
// the order its vertices are drawn (a random winding).
void randomTriangle(std::mt19937& rng, Real r, Vec3 w[3]) {
    std::uniform_real_distribution<Real> unit(-1, 1);
    for (int i = 0; i < 3; ++i) w[i] = {unit(rng) * r, unit(rng) * Real(0.3) * r, unit(rng) * r};
}

// A large counter-clockwise triangle in y = 0 around the origin.
const Vec3 kGround[3] = {{-5, 0, -5}, {0, 0, 5}, {5, 0, -5}};

// A random triangle and a piece of `shape` near it, for the edge lanes'
// tests: every fifth trial a sliver (the third vertex near the line of the
// other two), every seventh an axis-aligned edge (parallel to a box or
// prism face's), every eleventh the piece unturned; the piece over or
// beside the triangle, its lowest point from a little under the triangle's
// plane to well above it. False when the triangle has no normal.
bool pieceBesideEdgeCaseTriangle(std::mt19937& rng, const Shape& shape, int trial, Vec3 w[3], Vec3& faceN,
                                 detail::ConvexShape& b) {
    std::uniform_real_distribution<Real> unit(-1, 1), size(0.05f, 2.5f), height(-0.4f, 1.2f);
    const Real r = size(rng);
    randomTriangle(rng, r, w);
    if (trial % 5 == 0) {
        w[2] = w[0] + (w[1] - w[0]) * (unit(rng) * Real(1.5)) + Vec3{unit(rng), unit(rng), unit(rng)} * (r * Real(1e-3));
    } else if (trial % 7 == 0) {
        w[1] = w[0] + Vec3{r, 0, 0};
    }
    const Vec3 nRaw = cross(w[1] - w[0], w[2] - w[0]);
    if (!(lengthSquared(nRaw) > Real(1e-14))) return false;
    faceN = normalize(nRaw);
    if (!(lengthSquared(faceN) > Real(0.5))) return false;
    const Real a = std::fabs(unit(rng)), bb = std::fabs(unit(rng)) * (1 - a);
    const Vec3 onTri = w[0] + (w[1] - w[0]) * a + (w[2] - w[0]) * bb + Vec3{unit(rng), 0, unit(rng)} * Real(0.4);
    const Quat q = trial % 11 == 0 ? Quat{} : test::randomRotation(rng);
    b = detail::makeConvexCore(shape, {onTri, q});
    Real lo, hi;
    b.extent(faceN, lo, hi);
    b.xf.p += faceN * (dot(faceN, onTri) - lo + height(rng) * (hi - lo) * Real(0.25));
    return true;
}

// A box, three hulls and four rocks (the rocks drawn from `rng`).
std::vector<Shape> boxHullsAndRocks(std::mt19937& rng) {
    std::vector<Shape> shapes = {Shape::box({0.4f, 0.2f, 0.3f}), cubeHull(0.5f), hexPrism(0.35f, 1.2f), pyramid(0.5f, 0.8f)};
    for (int i = 0; i < 4; ++i) shapes.push_back(rock(rng));
    return shapes;
}

// For the cached-axis tests: a random triangle of size 0.5-2.5 and a pose
// of `shape` over it, moved sideways by up to `sideways` times the size and
// lifted so that its lowest point is `lift` margins above the triangle's
// plane (lift drawn from [liftLo, liftHi)). False when the triangle is too
// thin for a steady normal.
bool poseOverTriangle(std::mt19937& rng, const Shape& shape, Real sideways, Real liftLo, Real liftHi, Vec3 w[3], Vec3& faceN,
                      Transform& xf) {
    std::uniform_real_distribution<Real> unit(-1, 1), size(0.5f, 2.5f), lift(liftLo, liftHi);
    const Real r = size(rng);
    randomTriangle(rng, r, w);
    const Vec3 nRaw = cross(w[1] - w[0], w[2] - w[0]);
    if (lengthSquared(nRaw) < Real(0.05) * r * r * r * r) return false;
    faceN = normalize(nRaw);
    const Real a = std::fabs(unit(rng)), bb = std::fabs(unit(rng)) * (1 - a);
    xf = Transform{w[0] + (w[1] - w[0]) * a + (w[2] - w[0]) * bb + Vec3{unit(rng), 0, unit(rng)} * (sideways * r),
                   test::randomRotation(rng)};
    const detail::ConvexShape b = detail::makeConvexCore(shape, xf);
    Real lo, hi;
    b.extent(faceN, lo, hi);
    xf.p += faceN * (dot(faceN, w[0]) - lo + lift(rng) * kMargin);
    return true;
}

}  // namespace

TEST(TriangleSat, BoxRestingOnTheFaceGetsFourCornersAtItsDepth) {
    const Vec3 h{0.5f, 0.25f, 0.5f};
    const Vec3 centre{0.1f, 0.24f, -1};
    const detail::ConvexShape box = detail::makeConvexCore(Shape::box(h), {centre, {}});
    const auto c = collideOne(kGround, kAllConvex, box, true);
    ASSERT_EQ(c.size(), 4u);
    std::vector<std::uint32_t> ids;
    for (const auto& k : c) {
        expectVecNear(k.normal, {0, 1, 0}, Real(1e-6));
        EXPECT_NEAR(k.contact.depth, 0.01f, Real(1e-6));
        // Midway between the box's bottom (y = -0.01) and the triangle (y = 0), at a corner.
        EXPECT_NEAR(k.contact.position.y, -0.005f, Real(1e-6));
        EXPECT_NEAR(std::fabs(k.contact.position.x - centre.x), h.x, Real(1e-5));
        EXPECT_NEAR(std::fabs(k.contact.position.z - centre.z), h.z, Real(1e-5));
        ids.push_back(k.contact.featureId);
    }
    std::sort(ids.begin(), ids.end());
    EXPECT_EQ(std::unique(ids.begin(), ids.end()), ids.end()) << "each corner its own feature id";
    // The same box a few micrometres and a thousandth of a degree away keeps its feature ids (warm starting).
    detail::ConvexShape moved = box;
    moved.xf = {centre + Vec3{3e-6f, -2e-6f, 1e-6f}, Quat::fromAxisAngle(normalize(Vec3{1, 2, 3}), 2e-5f)};
    const auto c2 = collideOne(kGround, kAllConvex, moved, true);
    std::vector<std::uint32_t> ids2;
    for (const auto& k : c2) ids2.push_back(k.contact.featureId);
    std::sort(ids2.begin(), ids2.end());
    EXPECT_EQ(ids, ids2);
}

TEST(TriangleSat, HullEdgeAcrossTheTrianglesEdgeMeetsItAtTheCommonPerpendicular) {
    // The triangle's edge v1 v2 is the z axis (x = 0, y = 0); the triangle lies at x < 0.
    const Vec3 w[3] = {{-2, 0, 0}, {0, 0, 2}, {0, 0, -2}};
    // A cube's edge along u = (1, -1, 0)/sqrt 2 (its local x at y = z = -h),
    // its two faces there symmetric about -N, N = (1, 1, 0)/sqrt 2 (the two
    // edges' common perpendicular, out of the triangle's edge and up),
    // crossing the z axis d below it along N.
    const Real h = 0.5f, d = 0.01f;
    const Vec3 u = normalize(Vec3{1, -1, 0}), n = normalize(Vec3{1, 1, 0}), k = cross(u, n);
    const Real s = std::sqrt(Real(0.5));
    const Quat q = Quat::fromMatrix(Mat3(u, (n - k) * s, (n + k) * s));
    const Vec3 centre = n * (h * std::sqrt(Real(2)) - d);
    const Shape cube = cubeHull(h);
    const detail::ConvexShape hull = detail::makeConvexCore(cube, {centre, q});
    const auto c = collideOne(w, kAllConvex, hull, true);
    ASSERT_EQ(c.size(), 1u);
    expectVecNear(c[0].normal, n, Real(1e-6));
    EXPECT_NEAR(c[0].contact.depth, d, Real(1e-6));
    expectVecNear(c[0].contact.position, n * (-d / 2), Real(1e-6));
    // The general path finds the same normal, but clips the triangle against
    // a cube face 45 degrees off it (kMinFaceAlignment is cos 45.6 degrees)
    // and measures 2 cm at a point 1.4 cm off the edges' crossing.
    const auto g = collideOne(w, kAllConvex, hull, false);
    ASSERT_EQ(g.size(), 1u);
    expectVecNear(g[0].normal, n, Real(1e-4));
    EXPECT_NEAR(g[0].contact.depth, 2 * d, Real(1e-4));
    // The same edge inside a flat surface (not convex): rebuilt along the face normal.
    const auto flat = collideOne(w, 0, hull, true);
    for (const auto& f : flat) expectVecNear(f.normal, {0, 1, 0}, Real(1e-6));
}

TEST(TriangleSat, HullStandingOnAVertexGetsThatVertex) {
    const Real h = 0.5f, d = 0.02f;
    const Quat q = Quat::fromTo(normalize(Vec3{1, 1, 1}), {0, -1, 0});
    const Vec3 centre{0.3f, h * std::sqrt(Real(3)) - d, -0.7f};
    const Shape cube = cubeHull(h);
    const detail::ConvexShape hull = detail::makeConvexCore(cube, {centre, q});
    const auto c = collideOne(kGround, kAllConvex, hull, true);
    ASSERT_EQ(c.size(), 1u);
    expectVecNear(c[0].normal, {0, 1, 0}, Real(1e-6));
    EXPECT_NEAR(c[0].contact.depth, d, Real(2e-6));
    expectVecNear(c[0].contact.position, {centre.x, -d / 2, centre.z}, Real(2e-6));
}

TEST(TriangleSat, ShapesBehindOrBeyondTheMarginGetNothing) {
    const detail::ConvexShape box = detail::makeConvexCore(Shape::box({0.5f, 0.25f, 0.5f}), {{0, 0.25f + 0.021f, 0}, {}});
    EXPECT_TRUE(collideOne(kGround, kAllConvex, box, true).empty());  // 2.1 cm above, margin 2 cm
    detail::ConvexShape near = box;
    near.xf.p.y = 0.25f + 0.015f;
    const auto c = collideOne(kGround, kAllConvex, near, true);
    ASSERT_EQ(c.size(), 4u);  // speculative
    for (const auto& k : c) EXPECT_NEAR(k.contact.depth, -0.015f, Real(1e-6));
    // One-sided: a box sunk with its centre under the triangle gets nothing.
    detail::ConvexShape under = box;
    under.xf.p.y = -0.01f;
    EXPECT_TRUE(collideOne(kGround, kAllConvex, under, true).empty());
}

// Random boxes and hulls around random triangles, both paths. Where either
// finds the shapes overlapping by 1 mm or more, both find a contact; with
// every edge convex (mask 7: no normal is rebuilt) the test's normal
// separates the shapes as well as the general path's (within 1e-4 m, by
// the support functions; a face axis may stand against an edge pair better
// by up to 5 mm + 5 %, kEdgeBias), and its deepest point is as deep as the
// shapes overlap along it (within 1e-4 m; a face contact's clipped points
// may all lie up to 1 mm shallower, as the general path allows,
// kClipDepthTolerance). The general path's own deepest point is not held to
// that: at an edge contact it clips a face up to 45 degrees off the normal,
// and its points came out up to 6 cm deeper than the overlap (when this test
// was written: 446 of the ~5,000 overlapping poses by more than 1e-4 m). With
// every edge internal (mask 0) the mesh path's rules give both the same
// normal (1e-3). Apart (speculative), the test's separation is a lower bound
// of the general path's distance.
TEST(TriangleSat, AgreesWithTheGeneralPathOnRandomPoses) {
    std::mt19937 rng(2111);
    std::uniform_real_distribution<Real> unit(-1, 1), size(0.5f, 2.5f), height(-0.3f, 0.6f);
    std::vector<Shape> shapes = {Shape::box({0.4f, 0.2f, 0.3f}), Shape::box({1.5f, 0.1f, 0.8f}), cubeHull(0.5f),
                                 hexPrism(0.35f, 1.2f), pyramid(0.5f, 0.8f)};
    for (int i = 0; i < 4; ++i) shapes.push_back(rock(rng));
    int compared = 0, overlapping = 0, apart = 0, generalDeeper = 0, sameAxis = 0;
    for (int trial = 0; trial < 6000; ++trial) {
        const Shape& shape = shapes[static_cast<std::size_t>(trial) % shapes.size()];
        // A random triangle, counter-clockwise about its normal.
        const Real r = size(rng);
        Vec3 w[3];
        randomTriangle(rng, r, w);
        const Vec3 nRaw = cross(w[1] - w[0], w[2] - w[0]);
        if (lengthSquared(nRaw) < Real(0.05) * r * r * r * r) continue;
        const Vec3 faceN = normalize(nRaw);
        // The shape's centre over a point near the triangle, at a height that brings its surface within reach.
        const Real a = std::fabs(unit(rng)), bb = std::fabs(unit(rng)) * (1 - a);
        const Vec3 onTri = w[0] + (w[1] - w[0]) * a + (w[2] - w[0]) * bb + Vec3{unit(rng), 0, unit(rng)} * Real(0.3);
        const Quat q = test::randomRotation(rng);
        detail::ConvexShape b = detail::makeConvexCore(shape, {onTri, q});
        Real lo, hi;
        b.extent(faceN, lo, hi);
        b.xf.p += faceN * (dot(faceN, onTri) - lo + height(rng) * (hi - lo) * Real(0.25));
        if (dot(faceN, b.center() - w[0]) < 0) continue;
        for (const std::uint8_t mask : {kAllConvex, std::uint8_t(0)}) {
            const auto general = collideOne(w, mask, b, false);
            const auto sat = collideOne(w, mask, b, true);
            ++compared;
            const Real dg = deepest(general), ds = deepest(sat);
            std::string where = "trial " + std::to_string(trial) + " mask " + std::to_string(mask) + " general " +
                                std::to_string(dg) + " sat " + std::to_string(ds);
            if ((!general.empty() && dg > Real(1e-3)) || (!sat.empty() && ds > Real(1e-3))) {
                ++overlapping;
                ASSERT_FALSE(sat.empty()) << where;
                ASSERT_FALSE(general.empty()) << where;
                const Real sepSat = separationAlong(w, b, sat[0].normal), sepGeneral = separationAlong(w, b, general[0].normal);
                where += " separation along the test's normal " + std::to_string(sepSat) + ", the general path's " +
                         std::to_string(sepGeneral);
                const bool same = std::fabs(sepSat - sepGeneral) <= Real(1e-4);
                if (mask == kAllConvex) {
                    // A face stands against an edge pair up to 5 mm + 5 % better (kEdgeBias).
                    EXPECT_LE(sepSat, sepGeneral + Real(1e-4)) << where;
                    EXPECT_GE(sepSat, sepGeneral - Real(1e-4) - Real(0.005) - Real(0.05) * std::fabs(sepSat)) << where;
                    EXPECT_LE(ds, -sepSat + Real(1e-4)) << where;
                    if (!same) continue;  // a face where the general path took the edge pair: its depths are along another normal
                    ++sameAxis;
                    if (dot(sat[0].normal, faceN) >= Real(1 - 1e-4)) {
                        // Along the face normal both keep only the points over the
                        // triangle; an edge contact within 1e-4 of the normal is
                        // one exact point here, clipped points there. As deep as
                        // the general path's, unless that one overstates the
                        // overlap along the normal (its clipped face up to 45
                        // degrees off: seen in the double build, 1.4 mm): then
                        // the whole overlap.
                        EXPECT_GE(ds, std::min(dg, -sepSat) - Real(1e-4)) << where;
                    } else {
                        EXPECT_GE(ds, -sepSat - Real(1e-3)) << where;
                    }
                    if (dg > -sepGeneral + Real(1e-4)) ++generalDeeper;
                } else if (same) {
                    expectVecNear(sat[0].normal, general[0].normal, Real(1e-3));
                }
            } else if (!general.empty() && !sat.empty() && mask == kAllConvex) {
                ++apart;
                where += " separation along the test's normal " + std::to_string(separationAlong(w, b, sat[0].normal)) +
                         ", the general path's " + std::to_string(separationAlong(w, b, general[0].normal)) + " n.faceN " +
                         std::to_string(dot(sat[0].normal, faceN)) + " " + std::to_string(dot(general[0].normal, faceN)) +
                         " points " + std::to_string(sat.size()) + " " + std::to_string(general.size());
                // -ds: a lower bound of the distance, where both took the same axis.
                if (separationAlong(w, b, sat[0].normal) >= separationAlong(w, b, general[0].normal) - Real(1e-4)) {
                    EXPECT_GE(ds, dg - Real(1e-4)) << where;
                }
            }
        }
    }
    EXPECT_GT(compared, 8000);
    EXPECT_GT(overlapping, 2000);
    EXPECT_GT(apart, 100);
    EXPECT_GT(sameAxis, overlapping * 4 / 10);  // of the overlapping poses' ~half with mask 7: nearly all on the same axis
    EXPECT_GT(generalDeeper, 0);  // the general path's over-stated depths are still there to compare with
}

// A box and a hull slid across the seams and diagonals of a flat mesh (every
// edge inside it flat) see only the face normal, at their depth, one manifold.
TEST(TriangleSat, BoxAndHullSlideAcrossAFlatMeshsInternalEdgesWithoutSnagging) {
    const TriangleMesh m = test::flatGrid(8, 1);
    const Shape grid = Shape::mesh(m.vertices, m.triangles);
    const Shape prism = hexPrism(0.35f, 0.6f);
    const Quat lying = Quat::fromAxisAngle({0, 0, 1}, Real(1.5707963));
    ManifoldBuffer out;
    for (int i = 0; i <= 80; ++i) {
        const Real x = -2 + Real(0.05) * static_cast<Real>(i);
        for (const Real yaw : {0.0f, 0.3f, 0.7853982f, 1.1f}) {
            const Quat turn = Quat::fromAxisAngle({0, 1, 0}, yaw);
            // The prism lying on a side face (its flats 0.35 cos 30 deg from the axis), sunk 5 mm.
            const Real flat = Real(0.35) * std::cos(Real(0.5235988));
            const Quat side = turn * lying * Quat::fromAxisAngle({0, 1, 0}, Real(0.5235988));
            collide(grid, {}, prism, {{x, flat - 0.005f, 0.37f}, side}, kMargin, out);
            ASSERT_EQ(out.size(), 1u) << "x " << x << " yaw " << yaw;
            expectVecNear(out[0].normal, {0, 1, 0}, Real(1e-3));
            for (const ContactPoint& c : out[0].contacts()) EXPECT_NEAR(c.depth, 0.005f, Real(1e-4));
            EXPECT_GE(out[0].pointCount, 2u);
        }
    }
}

// A box sunk 6 cm into a flat mesh, tilted 1 degree: the manifold keeps all
// four sunk corners (at least half as deep as the deepest), not only the two
// within the resting band of the deepest; with one edge to push on the solver
// tipped a sunk body from corner to corner instead of lifting it out
// (convex_vs_mesh's pyramid, docs/benchmarks.md).
TEST(TriangleSat, SunkBoxKeepsAllItsSunkCornersInTheManifold) {
    const TriangleMesh m = test::flatGrid(8, 1);
    const Shape grid = Shape::mesh(m.vertices, m.triangles);
    const Real tilt = Real(0.017453293), depth = Real(0.06);
    const Quat q = Quat::fromAxisAngle({0, 0, 1}, tilt);
    // The lowest corners, (-0.5, -0.25) rotated, at -depth.
    const Vec3 low = rotate(q, Vec3{-0.5f, -0.25f, 0});
    const Vec3 centre{0.13f, -depth - low.y, 0.21f};
    ManifoldBuffer out;
    collide(grid, {}, Shape::box({0.5f, 0.25f, 0.5f}), {centre, q}, kMargin, out);
    ASSERT_EQ(out.size(), 1u);
    expectVecNear(out[0].normal, {0, 1, 0}, Real(1e-6));
    ASSERT_EQ(out[0].pointCount, 4u);
    std::vector<Real> depths;
    for (const ContactPoint& c : out[0].contacts()) depths.push_back(c.depth);
    std::sort(depths.begin(), depths.end());
    const Real shallow = depth - Real(1) * std::sin(tilt);  // the corners 1 m away along x
    EXPECT_NEAR(depths[0], shallow, Real(1e-5));
    EXPECT_NEAR(depths[1], shallow, Real(1e-5));
    EXPECT_NEAR(depths[2], depth, Real(1e-5));
    EXPECT_NEAR(depths[3], depth, Real(1e-5));
}

// The hulls' edge tables kept across calls (PolytopeEdgeCache) give the
// polytope that deriving the table again gives: the same edges, faces and
// answer, whether the entry was filled by this hull, by another hull of
// other faces, or by one with open faces (no table), and after more hulls
// than the cache holds went through it.
TEST(TriangleSat, CachedEdgeTablesAreTheTablesDerivedAgain) {
    std::mt19937 rng(2113);
    std::vector<Shape> shapes = {cubeHull(0.5f), hexPrism(0.35f, 1.2f), pyramid(0.5f, 0.8f), Shape::box({0.4f, 0.2f, 0.3f})};
    for (int i = 0; i < 40; ++i) shapes.push_back(rock(rng));  // more hulls than the cache's 32 entries
    detail::PolytopeEdgeCache cache;
    const auto samePolytope = [](const detail::TrianglePolytope& x, const detail::TrianglePolytope& y) {
        if (x.vertexCount != y.vertexCount || x.faceCount != y.faceCount || x.edgeCount != y.edgeCount) return false;
        for (std::uint32_t v = 0; v < x.vertexCount; ++v) {
            if (!(x.vertices[v] == y.vertices[v])) return false;
        }
        for (std::uint32_t f = 0; f < x.faceCount; ++f) {
            if (!(x.faces[f].normal == y.faces[f].normal) || x.faces[f].offset != y.faces[f].offset) return false;
        }
        for (std::uint32_t e = 0; e < x.edgeCount; ++e) {
            const detail::PolytopeEdge a = x.edges[e], b = y.edges[e];
            if (a.from != b.from || a.to != b.to || a.faces[0] != b.faces[0] || a.faces[1] != b.faces[1]) return false;
        }
        return true;
    };
    int hits = 0;
    for (int round = 0; round < 3; ++round) {
        for (std::size_t i = 0; i < shapes.size(); ++i) {
            const detail::ConvexShape b = detail::makeConvexCore(shapes[i], {});
            std::vector<detail::PolytopeEdge> fresh;
            detail::TrianglePolytope derived, cached;
            const bool ok = derived.prepare(b, fresh);
            ASSERT_EQ(cached.prepare(b, cache), ok) << "shape " << i;
            ASSERT_TRUE(ok);
            EXPECT_TRUE(samePolytope(derived, cached)) << "shape " << i << " round " << round;
            // Twice in a row: the second from the entry the first filled.
            detail::TrianglePolytope again;
            ASSERT_TRUE(again.prepare(b, cache));
            EXPECT_TRUE(samePolytope(derived, again)) << "shape " << i;
            hits += again.edges == cached.edges ? 1 : 0;
        }
    }
    EXPECT_GT(hits, 100);
    // A hull whose faces do not close up (a face dropped) gets no table, from
    // the cache as from deriving it, and the whole hull afterwards its own.
    ConvexHull open = *detail::makeConvexCore(shapes[0], {}).hull;
    open.faces.pop_back();
    detail::ConvexShape openShape = detail::makeConvexCore(shapes[0], {});
    openShape.hull = &open;
    std::vector<detail::PolytopeEdge> fresh;
    detail::TrianglePolytope derived, cached;
    EXPECT_FALSE(derived.prepare(openShape, fresh));
    EXPECT_FALSE(cached.prepare(openShape, cache));
    EXPECT_FALSE(cached.prepare(openShape, cache));
    open = *detail::makeConvexCore(shapes[0], {}).hull;  // the same object, its faces closed again
    EXPECT_TRUE(cached.prepare(openShape, cache));
    EXPECT_TRUE(derived.prepare(openShape, fresh));
    EXPECT_TRUE(samePolytope(derived, cached));
}

// The separating-axis hints (collideTrianglePolytope's axisHint,
// SeparatingAxisCache): a piece drifting a few millimetres and a fraction of
// a degree a step beside a triangle, now and then jumping (beyond where the
// hinted axis still separates it: the hint misses and the test runs whole),
// gets bit for bit the answer of the test without a hint, and so does any
// hint at all (another pair's, hashed to the same slot, or garbage).
TEST(TriangleSat, SeparatingAxisHintsGiveTheFullTestsAnswer) {
    std::mt19937 rng(2117);
    std::uniform_real_distribution<Real> unit(-1, 1), size(0.5f, 2.5f), height(-0.2f, 1.2f);
    std::vector<Shape> shapes = boxHullsAndRocks(rng);
    const auto sameAnswer = [](bool hitA, const Manifold& a, bool hitB, const Manifold& b) {
        if (hitA != hitB) return false;
        if (!hitA) return true;
        if (!(a.normal == b.normal) || a.pointCount != b.pointCount) return false;
        for (std::uint32_t k = 0; k < a.pointCount; ++k) {
            if (!(a.points[k].position == b.points[k].position) || a.points[k].depth != b.points[k].depth ||
                a.points[k].featureId != b.points[k].featureId) {
                return false;
            }
        }
        return true;
    };
    int tests = 0, hits = 0, stale = 0, faceHints = 0, edgeHints = 0;
    for (int trial = 0; trial < 400; ++trial) {
        const Shape& shape = shapes[static_cast<std::size_t>(trial) % shapes.size()];
        const Real r = size(rng);
        Vec3 w[3];
        randomTriangle(rng, r, w);
        const Vec3 nRaw = cross(w[1] - w[0], w[2] - w[0]);
        if (lengthSquared(nRaw) < Real(0.05) * r * r * r * r) continue;
        const Vec3 faceN = normalize(nRaw);
        // Beside the triangle as often as over it, within reach or a little beyond.
        const Real a = std::fabs(unit(rng)), bb = std::fabs(unit(rng)) * (1 - a);
        Transform xf{w[0] + (w[1] - w[0]) * a + (w[2] - w[0]) * bb + Vec3{unit(rng), 0, unit(rng)} * r,
                     test::randomRotation(rng)};
        {
            detail::ConvexShape b = detail::makeConvexCore(shape, xf);
            Real lo, hi;
            b.extent(faceN, lo, hi);
            xf.p += faceN * (dot(faceN, w[0]) - lo + height(rng) * kMargin * 4);  // its lowest point that far above the plane
        }
        std::uint32_t hint = 0;
        for (int step = 0; step < 40; ++step) {
            if (step % 13 == 12) {
                xf.p += Vec3{unit(rng), unit(rng), unit(rng)} * Real(0.3);  // a jump
                xf.q = normalize(xf.q * Quat(1, unit(rng) * Real(0.3), unit(rng) * Real(0.3), unit(rng) * Real(0.3)));
            } else {
                xf.p += Vec3{unit(rng), unit(rng), unit(rng)} * Real(0.003);
                xf.q = normalize(xf.q * Quat(1, unit(rng) * Real(0.004), unit(rng) * Real(0.004), unit(rng) * Real(0.004)));
            }
            const detail::ConvexShape b = detail::makeConvexCore(shape, xf);
            std::vector<detail::PolytopeEdge> edges;
            detail::TrianglePolytope polytope;
            ASSERT_TRUE(polytope.prepare(b, edges));
            Manifold full, hinted, garbage;
            const bool fullHit = detail::collideTrianglePolytope(w, faceN, polytope, kMargin, full);
            const std::uint32_t before = hint;
            const bool hintedHit = detail::collideTrianglePolytope(w, faceN, polytope, kMargin, hinted, &hint);
            ++tests;
            ASSERT_TRUE(sameAnswer(fullHit, full, hintedHit, hinted)) << "trial " << trial << " step " << step;
            if (before != 0) (hint == before && !hintedHit ? hits : stale) += 1;
            if ((hint & ~detail::kAxisHintIndex) == detail::kFaceAxisHint) ++faceHints;
            if ((hint & ~detail::kAxisHintIndex) == detail::kEdgeAxisHint) ++edgeHints;
            // Any hint: every face and edge pair, and indices past the end.
            std::uint32_t any = (rng() % 2 == 0 ? detail::kFaceAxisHint : detail::kEdgeAxisHint) | static_cast<std::uint32_t>(rng() % 80);
            const bool garbageHit = detail::collideTrianglePolytope(w, faceN, polytope, kMargin, garbage, &any);
            ASSERT_TRUE(sameAnswer(fullHit, full, garbageHit, garbage)) << "trial " << trial << " step " << step;
        }
    }
    EXPECT_GT(tests, 10000);
    EXPECT_GT(hits, 1000);     // the drifting pieces' hints mostly stand
    EXPECT_GT(stale, 100);     // and the jumps' do not: the test ran whole
    EXPECT_GT(faceHints, 500);
    EXPECT_GT(edgeHints, 50);
}

// The mesh path with its hint table: a hull and a box drifting over a wave
// mesh get the same manifolds, bit for bit, from a buffer whose hints are
// warm from the poses before as from a fresh one.
TEST(TriangleSat, MeshManifoldsWithWarmHintsAreTheFreshOnes) {
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    constexpr std::uint32_t kCells = 24;
    for (std::uint32_t i = 0; i <= kCells; ++i) {
        for (std::uint32_t j = 0; j <= kCells; ++j) {
            const Real x = Real(0.25) * static_cast<Real>(j) - 3, z = Real(0.25) * static_cast<Real>(i) - 3;
            vertices.push_back({x, Real(0.1) * std::sin(Real(1.3) * x) * std::cos(Real(0.9) * z), z});
        }
    }
    for (std::uint32_t i = 0; i < kCells; ++i) {
        for (std::uint32_t j = 0; j < kCells; ++j) {
            const std::uint32_t v = i * (kCells + 1) + j;
            triangles.push_back({v, v + kCells + 1, v + 1});
            triangles.push_back({v + 1, v + kCells + 1, v + kCells + 2});
        }
    }
    const Shape ground = Shape::mesh(vertices, triangles);
    std::mt19937 rng(2119);
    std::uniform_real_distribution<Real> unit(-1, 1);
    const Shape pieces[] = {hexPrism(0.3f, 1.0f), Shape::box({0.3f, 0.2f, 0.5f})};
    ManifoldBuffer warm;
    int manifolds = 0;
    for (const Shape& piece : pieces) {
        Transform xf{{0, Real(0.32), 0}, normalize(Quat(1, 0, 0, Real(0.7)))};
        for (int step = 0; step < 300; ++step) {
            xf.p += Vec3{Real(0.01), unit(rng) * Real(0.004), Real(0.004) * unit(rng)};
            xf.q = normalize(xf.q * Quat(1, unit(rng) * Real(0.01), unit(rng) * Real(0.01), unit(rng) * Real(0.01)));
            const detail::ConvexShape b = detail::makeConvexCore(piece, xf);
            ManifoldBuffer fresh;
            warm.clear();
            detail::collideMeshConvex(ground.mesh(), Transform{}, b, piece.bounds(xf), Real(0.05), warm);
            detail::collideMeshConvex(ground.mesh(), Transform{}, b, piece.bounds(xf), Real(0.05), fresh);
            ASSERT_EQ(warm.size(), fresh.size()) << "step " << step;
            for (std::size_t i = 0; i < warm.size(); ++i) {
                const Manifold &x = warm[i], &y = fresh[i];
                ASSERT_TRUE(x.normal == y.normal && x.pointCount == y.pointCount && x.childA == y.childA) << "step " << step;
                for (std::uint32_t k = 0; k < x.pointCount; ++k) {
                    ASSERT_TRUE(x.points[k].position == y.points[k].position && x.points[k].depth == y.points[k].depth &&
                                x.points[k].featureId == y.points[k].featureId)
                        << "step " << step;
                }
            }
            manifolds += static_cast<int>(warm.size());
        }
    }
    EXPECT_GT(manifolds, 300);
    int hinted = 0;
    for (const detail::SeparatingAxisCache::Entry& e : warm.separatingAxisScratch().entries) hinted += e.axis != 0 ? 1 : 0;
    EXPECT_GT(hinted, 20);
}

// The contact's triangle axis cache (collideTrianglePolytope's `cached`,
// TriangleAxisCache in manifold.hpp): pieces drifting beside random
// triangles. Where the full test, run afresh, still picks the cached axis,
// the cached path's contact is the full test's (normal and points within
// 1e-5 m: the same expressions, so in practice the same bits); an entry
// whose separation moved by more than the tolerance, or one naming no axis
// of this polytope, runs the full test (the same bits). Where the cached
// axis is no longer the best, its contact differs (counted, not bounded
// here: the drift is the 5 mm tolerance's).
TEST(TriangleSat, CachedAxisGivesTheFullTestsContactWhileItStaysTheBest) {
    std::mt19937 rng(2123);
    std::uniform_real_distribution<Real> unit(-1, 1);
    const std::vector<Shape> shapes = boxHullsAndRocks(rng);
    const auto near = [](bool hitA, const Manifold& a, bool hitB, const Manifold& b, Real tol) {
        if (hitA != hitB) return false;
        if (!hitA) return true;
        if (length(a.normal - b.normal) > tol || a.pointCount != b.pointCount) return false;
        for (std::uint32_t k = 0; k < a.pointCount; ++k) {
            if (length(a.points[k].position - b.points[k].position) > tol || std::fabs(a.points[k].depth - b.points[k].depth) > tol ||
                a.points[k].featureId != b.points[k].featureId) {
                return false;
            }
        }
        return true;
    };
    const auto maxDepth = [](const Manifold& m) {
        Real d = -1e30f;
        for (std::uint32_t k = 0; k < m.pointCount; ++k) d = std::max(d, m.points[k].depth);
        return d;
    };
    int same = 0, kept = 0, shallower = 0, codes[4] = {0, 0, 0, 0};
    for (int trial = 0; trial < 400; ++trial) {
        const Shape& shape = shapes[static_cast<std::size_t>(trial) % shapes.size()];
        Vec3 w[3], faceN;
        Transform xf;
        if (!poseOverTriangle(rng, shape, Real(0.3), Real(-0.5), Real(0.9), w, faceN, xf)) continue;
        detail::TriangleAxisEntry entry;
        for (int step = 0; step < 40; ++step) {
            xf.p += Vec3{unit(rng), unit(rng), unit(rng)} * Real(0.002);
            xf.q = normalize(xf.q * Quat(1, unit(rng) * Real(0.003), unit(rng) * Real(0.003), unit(rng) * Real(0.003)));
            const detail::ConvexShape b = detail::makeConvexCore(shape, xf);
            std::vector<detail::PolytopeEdge> edges;
            detail::TrianglePolytope polytope;
            ASSERT_TRUE(polytope.prepare(b, edges));
            Manifold full, cachedM;
            detail::TriangleAxisEntry fresh;
            const bool fullHit = detail::collideTrianglePolytope(w, faceN, polytope, kMargin, full, nullptr, &fresh);
            const detail::TriangleAxisEntry prev = entry;
            const bool cachedHit = detail::collideTrianglePolytope(w, faceN, polytope, kMargin, cachedM, nullptr, &entry);
            const bool tookCache = prev.axis != 0 && entry.axis == prev.axis && entry.separation == prev.separation && cachedHit;
            if (tookCache) {
                ++kept;
                codes[prev.axis >> 30] += 1;
                if (fresh.axis == prev.axis) {
                    ASSERT_TRUE(near(fullHit, full, cachedHit, cachedM, Real(1e-5))) << "trial " << trial << " step " << step;
                    ++same;
                }
                if (fullHit) shallower += maxDepth(cachedM) < maxDepth(full) - Real(1e-5) ? 1 : 0;
            } else {
                // The full test ran: its answer and its entry.
                ASSERT_TRUE(near(fullHit, full, cachedHit, cachedM, 0)) << "trial " << trial << " step " << step;
                ASSERT_EQ(entry.axis, fresh.axis);
            }
            // A stale entry (its separation 1 cm off) and entries naming no axis of this polytope run the full test.
            for (const std::uint32_t code : {fresh.axis, detail::kFaceAxisHint | 999u, detail::kEdgeAxisHint | 9999u, 7u}) {
                detail::TriangleAxisEntry bogus{0, 0, code, fresh.separation + Real(0.01)};
                if (code != fresh.axis) bogus.separation = fresh.separation;
                Manifold m;
                const bool hit = detail::collideTrianglePolytope(w, faceN, polytope, kMargin, m, nullptr, &bogus);
                ASSERT_TRUE(near(fullHit, full, hit, m, 0)) << "trial " << trial << " step " << step << " code " << code;
            }
        }
    }
    EXPECT_GT(kept, 3000);   // drifting 2 mm a step, the cached axis mostly stands
    EXPECT_GT(same, 2000);   // and is mostly still the best
    EXPECT_GT(codes[3], 100);  // the triangle's normal
    EXPECT_GT(codes[1], 10);   // a polytope face (39 in the GCC build: pieces near triangles mostly take the triangle's normal or an edge pair)
    EXPECT_GT(codes[2], 100);  // an edge pair
    std::printf("cached %d, still the best %d, shallower than the full test's %d, by kind %d %d %d\n", kept, same, shallower,
                codes[3], codes[1], codes[2]);
}

// The hint and the contact's cached axis together, as the mesh path calls
// them: the hint table is a worker's, shared by every piece of one hull
// over a triangle, so it may hold any axis when a contact's cached axis is
// live. Whatever hint is given (none, each face and edge pair of the
// polytope, past the end), the answer and the entry left behind are the
// ones without a hint, bit for bit. Tried before the cached axis, a hint
// that separated the pair kept a stale entry alive where the cached axis
// alone gave a point or was dropped, and two copies of one world at three
// threads parted (ManifoldBits, about one run in thirty).
TEST(TriangleSat, HintsChangeNeitherTheAnswerNorTheCachedAxis) {
    std::mt19937 rng(2129);
    std::uniform_real_distribution<Real> unit(-1, 1);
    const std::vector<Shape> shapes = boxHullsAndRocks(rng);
    const auto sameBits = [](bool hitA, const Manifold& a, bool hitB, const Manifold& b) {
        if (hitA != hitB) return false;
        if (!hitA) return true;
        if (!(a.normal == b.normal) || a.pointCount != b.pointCount) return false;
        for (std::uint32_t k = 0; k < a.pointCount; ++k) {
            if (!(a.points[k].position == b.points[k].position) || a.points[k].depth != b.points[k].depth ||
                a.points[k].featureId != b.points[k].featureId) {
                return false;
            }
        }
        return true;
    };
    int liveAndSeparating = 0, calls = 0;
    for (int trial = 0; trial < 1000; ++trial) {
        const Shape& shape = shapes[static_cast<std::size_t>(trial) % shapes.size()];
        Vec3 w[3], faceN;
        Transform xf;
        if (!poseOverTriangle(rng, shape, Real(0.5), Real(-0.5), Real(2.0), w, faceN, xf)) continue;
        detail::TriangleAxisEntry entry;
        for (int step = 0; step < 30; ++step) {
            // Drifting, and now and then moving away faster than the
            // cached axis's tolerance or along it: the entry then outlives
            // the contact it came from.
            const Real stride = step % 7 == 6 ? Real(0.02) : Real(0.002);
            xf.p += Vec3{unit(rng), unit(rng), unit(rng)} * stride + faceN * (stride * std::fabs(unit(rng)));
            xf.q = normalize(xf.q * Quat(1, unit(rng) * Real(0.003), unit(rng) * Real(0.003), unit(rng) * Real(0.003)));
            const detail::ConvexShape b = detail::makeConvexCore(shape, xf);
            std::vector<detail::PolytopeEdge> edges;
            detail::TrianglePolytope polytope;
            ASSERT_TRUE(polytope.prepare(b, edges));
            // Without a hint: the reference, and the entry the contact keeps.
            detail::TriangleAxisEntry plain = entry;
            Manifold reference;
            const bool hit = detail::collideTrianglePolytope(w, faceN, polytope, kMargin, reference, nullptr, &plain);
            std::vector<std::uint32_t> hints = {detail::kFaceAxisHint | 999u, detail::kEdgeAxisHint | 9999u};
            for (std::uint32_t f = 0; f < polytope.faceCount; ++f) hints.push_back(detail::kFaceAxisHint | f);
            for (std::uint32_t e = 0; e < 3 * polytope.edgeCount; ++e) hints.push_back(detail::kEdgeAxisHint | e);
            for (const std::uint32_t given : hints) {
                detail::TriangleAxisEntry withHint = entry;
                std::uint32_t hint = given;
                Manifold m;
                const bool hinted = detail::collideTrianglePolytope(w, faceN, polytope, kMargin, m, &hint, &withHint);
                ++calls;
                // A hint that still separates the pair: the case where the
                // order of the two caches matters, counted when the entry
                // was live.
                std::uint32_t probe = given;
                Manifold unused;
                if (entry.axis != 0 && !detail::collideTrianglePolytope(w, faceN, polytope, kMargin, unused, &probe) &&
                    probe == given) {
                    ++liveAndSeparating;
                }
                ASSERT_TRUE(sameBits(hit, reference, hinted, m)) << "trial " << trial << " step " << step << " hint " << given;
                ASSERT_EQ(withHint.axis, plain.axis) << "trial " << trial << " step " << step << " hint " << given;
                if (plain.axis != 0) {
                    ASSERT_EQ(withHint.separation, plain.separation) << "trial " << trial << " step " << step;
                }
            }
            entry = plain;
        }
    }
    EXPECT_GT(calls, 100000);
    EXPECT_GT(liveAndSeparating, 50);  // hints that separate while the contact's cached axis is live
}

// The triangle test takes the triangle into the polytope's frame by the
// shape's rotation matrix, taken once per pair (toPieceFrame, branch
// trees11; the quaternion per point before): each point and the normal
// against R^T (w - p) in double precision, whatever the pose and
// coordinates (random rotations and places, far and tiny coordinates, signed
// zeros, unturned and quarter-turned shapes), within 1e-6 of the
// coordinates' size (float rounding, about 8 units in the last place).
TEST(TriangleSat, PieceFrameIsTheInverseTransformToRounding) {
    std::mt19937 rng(2026);
    std::uniform_real_distribution<Real> unit(-1, 1), logScale(-6, 4);
    const auto point = [&] {
        const Real s = std::pow(Real(10), logScale(rng));
        return Vec3{unit(rng) * s, unit(rng) * s, unit(rng) * s};
    };
    // R^T (x - p) in doubles, R the unit quaternion's matrix.
    const auto reference = [](const Quat& q, const Vec3& x, const Vec3& p, double out[3]) {
        const double qx = q.x, qy = q.y, qz = q.z, qw = q.w;
        const double r[3][3] = {{1 - 2 * (qy * qy + qz * qz), 2 * (qx * qy - qw * qz), 2 * (qx * qz + qw * qy)},
                                {2 * (qx * qy + qw * qz), 1 - 2 * (qx * qx + qz * qz), 2 * (qy * qz - qw * qx)},
                                {2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), 1 - 2 * (qx * qx + qy * qy)}};
        const double d[3] = {double(x.x) - double(p.x), double(x.y) - double(p.y), double(x.z) - double(p.z)};
        for (int i = 0; i < 3; ++i) out[i] = r[0][i] * d[0] + r[1][i] * d[1] + r[2][i] * d[2];
    };
    const auto within = [](const Vec3& v, const double ref[3], double scale) {
        const double tolerance = 1e-6 * scale + 1e-30;
        return std::fabs(double(v.x) - ref[0]) <= tolerance && std::fabs(double(v.y) - ref[1]) <= tolerance &&
               std::fabs(double(v.z) - ref[2]) <= tolerance;
    };
    const Shape box = Shape::box({0.5f, 0.25f, 0.75f});
    int compared = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        Transform xf{point(), test::randomRotation(rng)};
        Vec3 w[3] = {point(), point(), point()};
        Vec3 faceN = normalize(Vec3{unit(rng), unit(rng), unit(rng)});
        if (trial % 10 == 0) {
            w[trial / 10 % 3] = xf.p;
            if (trial % 20 == 0) xf.q = Quat{};
            if (trial % 30 == 0) xf.q = Quat::fromAxisAngle(Vec3{0, 1, 0}, Real(1.5707963));
            faceN = trial % 40 == 0 ? Vec3{Real(-0.0), 1, Real(0.0)} : faceN;
            w[(trial / 10 + 1) % 3] = Vec3{Real(-0.0), Real(0.0), xf.p.z};
        }
        const detail::ConvexShape b = detail::makeConvexCore(box, xf);
        std::vector<detail::PolytopeEdge> edges;
        detail::TrianglePolytope polytope;
        ASSERT_TRUE(polytope.prepare(b, edges));
        Vec3 v[3], n;
        detail::toPieceFrame(polytope, w, faceN, v, n);
        double ref[3];
        for (int i = 0; i < 3; ++i) {
            reference(xf.q, w[i], xf.p, ref);
            const double scale = std::max(double(length(w[i])), double(length(xf.p)));
            ASSERT_TRUE(within(v[i], ref, scale)) << "trial " << trial << " point " << i << ": " << v[i].x << " " << ref[0];
        }
        reference(xf.q, faceN, Vec3{}, ref);
        ASSERT_TRUE(within(n, ref, 1.0)) << "trial " << trial;
        // The lanes (the float build's, their matrix and position taken in
        // prepare) are the scalar dots of R^T (w - p), bit for bit.
        const auto sameBits = [](const Vec3& x, const Vec3& y) { return std::memcmp(&x, &y, sizeof(Vec3)) == 0; };
        for (int i = 0; i < 3; ++i) {
            ASSERT_TRUE(sameBits(v[i], transposeMul(polytope.rotation, w[i] - xf.p))) << "trial " << trial << " point " << i;
        }
        ASSERT_TRUE(sameBits(n, transposeMul(polytope.rotation, faceN))) << "trial " << trial;
        ++compared;
    }
    EXPECT_EQ(compared, 20000);
}

// The face contacts are built in the polytope's frame from its faces as
// stored (pieceSupportingFace), where supportingFace moved every point into
// the world: moved there, the face must be supportingFace's, the same id and
// count and each point within 1e-5 m (rounding of coordinates under 2 m),
// for boxes and hulls, turned at random and unturned with a direction along
// an axis (tied dots).
TEST(TriangleSat, PieceSupportingFaceIsTheWorldFaceMovedBack) {
    std::mt19937 rng(78);
    std::uniform_real_distribution<Real> unit(-1, 1);
    std::vector<Shape> shapes = boxHullsAndRocks(rng);
    const Vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int trial = 0; trial < 20000; ++trial) {
        const Shape& shape = shapes[static_cast<std::size_t>(trial) % shapes.size()];
        const bool aligned = trial % 3 == 0;
        const Transform xf{{unit(rng), unit(rng), unit(rng)}, aligned ? Quat{} : test::randomRotation(rng)};
        const Vec3 l = aligned ? axes[static_cast<std::size_t>(trial / 3) % 6] : normalize(Vec3{unit(rng), unit(rng), unit(rng)});
        const detail::ConvexShape b = detail::makeConvexCore(shape, xf);
        std::vector<detail::PolytopeEdge> edges;
        detail::TrianglePolytope polytope;
        ASSERT_TRUE(polytope.prepare(b, edges));
        // The vertex furthest along l, the first of equals (the axis search's scan).
        std::uint32_t top = 0;
        for (std::uint32_t i = 1; i < polytope.vertexCount; ++i) {
            if (dot(l, polytope.vertices[i]) > dot(l, polytope.vertices[top])) top = i;
        }
        detail::SupportFace local, world;
        detail::pieceSupportingFace(polytope, l, top, local);
        detail::supportingFace(b, rotate(xf.q, l), world, b.kind == detail::ConvexKind::Hull ? top : detail::kNoVertex);
        ASSERT_EQ(local.id, world.id) << "trial " << trial;
        ASSERT_EQ(local.count, world.count) << "trial " << trial;
        for (std::uint32_t i = 0; i < local.count; ++i) {
            expectVecNear(transformPoint(xf, local.points[i]), world.points[i], Real(1e-5));
        }
        expectVecNear(rotate(xf.q, local.normal), world.normal, Real(1e-5));
        if (::testing::Test::HasFailure()) FAIL() << "trial " << trial;
    }
}

// The whole contact (axis search, clipping, the points moved back) in the
// polytope's frame must be what the same test gives for the same pose
// expressed in the shape's own frame (the triangle moved there, the shape
// unturned at the origin, where the frame change is exact), moved into the
// world: a contact is a geometric fact, whatever the frame. Random poses of
// boxes and hulls against triangles, slivers among them (the third vertex
// 1e-2 of an edge's length off its line; at 1e-3 the mesh path's float
// barycentric tests, overTriangle and edgeNormalAllowed, lose six digits to
// cancellation and the contact flips between any two frames, the old
// quaternion's too), overlapping and apart within the margin, cached edge
// lanes and the scalar loop; face contacts on either shape and edge-edge and
// vertex contacts all occur. Each point within 0.02 mm and each depth within
// 0.01 mm (seen: 3 um, 2 um), the normal within 1e-4; a pose may tip a near
// tie the other way (a face kept against an edge pair within its bias, a
// point at a clipping plane), in at most 1 % of the poses (seen: none).
TEST(TriangleSat, ContactIsTheSameInTheShapesOwnFrame) {
    std::mt19937 rng(1129);
    std::uniform_real_distribution<Real> unit(-1, 1), size(0.5f, 2.5f), height(-0.3f, 0.6f);
    std::vector<Shape> shapes = {Shape::box({0.4f, 0.2f, 0.3f}), Shape::box({1.5f, 0.1f, 0.8f}), cubeHull(0.5f),
                                 hexPrism(0.35f, 1.2f), pyramid(0.5f, 0.8f)};
    for (int i = 0; i < 4; ++i) shapes.push_back(rock(rng));
    detail::PolytopeEdgeCache cache;
    const auto collide = [&](const Vec3 w[3], const detail::ConvexShape& b, bool lanes) {
        std::vector<detail::MeshContactCandidate> out;
        std::vector<detail::PolytopeEdge> edges;
        detail::TrianglePolytope polytope;
        const bool prepared = lanes ? polytope.prepare(b, cache) : polytope.prepare(b, edges);
        EXPECT_TRUE(prepared);
        detail::collideTriangleWithConvex(w, kAllConvex, 0, b, kMargin, out, &polytope);
        return out;
    };
    int compared = 0, differ = 0, faces = 0, polytopeFaces = 0, single = 0, slivers = 0;
    double worstPoint = 0, worstDepth = 0;
    for (int trial = 0; trial < 12000; ++trial) {
        const Shape& shape = shapes[static_cast<std::size_t>(trial) % shapes.size()];
        const Real r = size(rng);
        Vec3 w[3];
        randomTriangle(rng, r, w);
        if (trial % 5 == 0) {
            // A sliver: the third vertex 1e-2 of the first edge off its line.
            const Vec3 e = w[1] - w[0];
            w[2] = w[0] + e * Real(0.4) + normalize(cross(e, Vec3{0, 1, 0})) * (Real(1e-2) * length(e));
            ++slivers;
        }
        const Vec3 nRaw = cross(w[1] - w[0], w[2] - w[0]);
        if (!(lengthSquared(nRaw) > 0)) continue;
        const Vec3 faceN = normalize(nRaw);
        if (!(lengthSquared(faceN) > Real(0.5))) continue;
        const Real a = std::fabs(unit(rng)), bb = std::fabs(unit(rng)) * (1 - a);
        const Vec3 onTri = w[0] + (w[1] - w[0]) * a + (w[2] - w[0]) * bb + Vec3{unit(rng), 0, unit(rng)} * Real(0.3);
        const Quat q = trial % 7 == 0 ? Quat::fromAxisAngle(Vec3{0, 0, 1}, Real(1.5707963)) : test::randomRotation(rng);
        detail::ConvexShape b = detail::makeConvexCore(shape, {onTri, q});
        Real lo, hi;
        b.extent(faceN, lo, hi);
        b.xf.p += faceN * (dot(faceN, onTri) - lo + height(rng) * (hi - lo) * Real(0.25));
        if (dot(faceN, b.center() - w[0]) < 0) continue;
        const bool lanes = trial % 2 == 0;
        const auto world = collide(w, b, lanes);
        // The same pose in the shape's frame.
        const Transform xf = b.xf;
        Vec3 wl[3];
        for (int i = 0; i < 3; ++i) wl[i] = inverseTransformPoint(xf, w[i]);
        detail::ConvexShape bl = detail::makeConvexCore(shape, Transform{});
        const auto local = collide(wl, bl, lanes);
        if (world.empty() && local.empty()) continue;
        ++compared;
        bool same = world.size() == local.size();
        double point = 0, depth = 0;
        for (std::size_t i = 0; same && i < world.size(); ++i) {
            same = world[i].contact.featureId == local[i].contact.featureId &&
                   length(world[i].normal - rotate(xf.q, local[i].normal)) <= Real(1e-4);
            point = std::max(point, double(length(world[i].contact.position - transformPoint(xf, local[i].contact.position))));
            depth = std::max(depth, double(std::fabs(world[i].contact.depth - local[i].contact.depth)));
        }
        same = same && point <= 2e-5 && depth <= 1e-5;
        if (!same) {
            ++differ;
            continue;
        }
        worstPoint = std::max(worstPoint, point);
        worstDepth = std::max(worstDepth, depth);
        if (dot(world[0].normal, faceN) >= Real(1 - 1e-4)) {
            ++faces;
        } else if (world.size() == 1) {
            ++single;
        } else {
            ++polytopeFaces;
        }
    }
    std::printf("compared %d, differ %d, triangle faces %d, polytope faces %d, one point %d, slivers %d, worst point %.3g m, depth %.3g m\n",
                compared, differ, faces, polytopeFaces, single, slivers, worstPoint, worstDepth);
    EXPECT_GT(compared, 2500);
    EXPECT_LE(differ, compared / 100);
    EXPECT_GT(faces, 1000);
    EXPECT_GT(polytopeFaces, 80);
    EXPECT_GT(single, 1000);
}

// The mesh path's rebuild of a contact along the triangle's normal (the
// internal-edge rule refused the test's own normal) is built in the
// polytope's frame as well (collideTrianglePolytopeAlongFace); before, it
// was the world-frame clipping of the shape's supporting face along -faceN
// from its support point (support, supportingFace, buildFaceManifold with
// the triangle as the reference face), which this test keeps as the
// reference: at random poses of boxes and hulls over triangles (sunk, level,
// apart within the margin and beyond it, unturned shapes with tied
// vertices among them), the same answer, the same points (feature ids, in
// order) within 0.02 mm, depths within 0.01 mm (seen: 2 um, 1 um), the
// normal faceN exactly; a near tie (a point at the margin or at a clipping
// plane) may tip the other way in at most 1 % of the contacts (seen: none).
TEST(TriangleSat, FaceRebuildIsTheWorldFramesClipping) {
    std::mt19937 rng(1130);
    std::uniform_real_distribution<Real> unit(-1, 1), size(0.5f, 2.5f), height(-0.3f, 0.6f);
    std::vector<Shape> shapes = {Shape::box({0.4f, 0.2f, 0.3f}), Shape::box({1.5f, 0.1f, 0.8f}), cubeHull(0.5f),
                                 hexPrism(0.35f, 1.2f), pyramid(0.5f, 0.8f)};
    for (int i = 0; i < 4; ++i) shapes.push_back(rock(rng));
    int hits = 0, misses = 0, several = 0, differ = 0;
    double worstPoint = 0, worstDepth = 0;
    for (int trial = 0; trial < 6000; ++trial) {
        const Shape& shape = shapes[static_cast<std::size_t>(trial) % shapes.size()];
        const Real r = size(rng);
        Vec3 w[3];
        randomTriangle(rng, r, w);
        const Vec3 nRaw = cross(w[1] - w[0], w[2] - w[0]);
        if (lengthSquared(nRaw) < Real(0.05) * r * r * r * r) continue;
        const Vec3 faceN = normalize(nRaw);
        const Real a = std::fabs(unit(rng)), bb = std::fabs(unit(rng)) * (1 - a);
        const Vec3 onTri = w[0] + (w[1] - w[0]) * a + (w[2] - w[0]) * bb;
        const Quat q = trial % 4 == 0 ? Quat{} : test::randomRotation(rng);
        detail::ConvexShape b = detail::makeConvexCore(shape, {onTri, q});
        Real lo, hi;
        b.extent(faceN, lo, hi);
        b.xf.p += faceN * (dot(faceN, onTri) - lo + height(rng) * (hi - lo) * Real(0.25));
        std::vector<detail::PolytopeEdge> edges;
        detail::TrianglePolytope polytope;
        ASSERT_TRUE(polytope.prepare(b, edges));
        Manifold piece;
        const bool hit = detail::collideTrianglePolytopeAlongFace(w, faceN, polytope, kMargin, piece);
        // The world frame's rebuild (collideTriangleWithConvex before).
        Manifold world;
        std::uint32_t hullVertex = detail::kNoVertex;
        const Vec3 pb = b.support(-faceN, hullVertex);
        const Real depth = dot(w[0] - pb, faceN);
        bool worldHit = false;
        if (!(depth < -kMargin)) {
            detail::SupportFace faceB;
            if (hullVertex != detail::kNoVertex) detail::supportingFace(b, -faceN, faceB, hullVertex);
            detail::buildFaceManifold(detail::makeTriangle(w[0], w[1], w[2]), b, faceN, pb + faceN * depth, pb, kMargin, world, 1,
                                      false, nullptr, hullVertex != detail::kNoVertex ? &faceB : nullptr);
            worldHit = world.pointCount > 0;
        }
        const std::string where = "trial " + std::to_string(trial) + " depth " + std::to_string(depth);
        if (!hit && !worldHit) {
            ++misses;
            continue;
        }
        // The same points, or a near tie tipped (a point at the margin or at
        // a clipping plane, the shape's plane at the margin), counted.
        bool same = hit == worldHit && piece.pointCount == world.pointCount;
        for (std::uint32_t i = 0; same && i < piece.pointCount; ++i) same = piece.points[i].featureId == world.points[i].featureId;
        if (!same) {
            ++differ;
            continue;
        }
        ++hits;
        if (piece.pointCount > 1) ++several;
        ASSERT_EQ(piece.normal, faceN) << where;
        for (std::uint32_t i = 0; i < piece.pointCount; ++i) {
            const double dp = length(piece.points[i].position - world.points[i].position);
            const double dd = std::fabs(piece.points[i].depth - world.points[i].depth);
            ASSERT_LE(dp, 2e-5) << where << " point " << i;
            ASSERT_LE(dd, 1e-5) << where << " point " << i;
            worstPoint = std::max(worstPoint, dp);
            worstDepth = std::max(worstDepth, dd);
        }
    }
    std::printf("contacts %d (%d of several points), none %d, differing %d, worst point %.3g m, depth %.3g m\n", hits, several, misses,
                differ, worstPoint, worstDepth);
    EXPECT_LE(differ, hits / 100);
    EXPECT_GT(hits, 2000);
    EXPECT_GT(several, 500);
    EXPECT_GT(misses, 300);
}

// The triangle's face contact takes a hull's supporting face along -faceN
// from the vertex the axis search found lowest along faceN (the first of the
// lowest dots in the hull's frame) instead of a second support search: that
// face must be the one the search gives, point for point, also where dots
// tie (a face or an edge parallel to the triangle).
TEST(TriangleSat, LowestVertexGivesTheSupportSearchsFace) {
    std::mt19937 rng(77);
    std::uniform_real_distribution<Real> unit(-1, 1);
    std::vector<Shape> shapes = {cubeHull(0.5f), hexPrism(0.35f, 1.2f), pyramid(0.5f, 0.8f)};
    for (int i = 0; i < 6; ++i) shapes.push_back(rock(rng));
    // A bigger rock: more than eight vertices, the eight-lane search.
    {
        std::uniform_real_distribution<Real> u(-0.5f, 0.5f);
        std::vector<Vec3> p;
        for (int i = 0; i < 40; ++i) p.push_back({u(rng), u(rng), u(rng)});
        shapes.push_back(Shape::convexHull(p));
    }
    const Vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    int ties = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const Shape& shape = shapes[static_cast<std::size_t>(trial) % shapes.size()];
        const bool aligned = trial % 3 == 0;  // unturned, a normal along an axis: tied dots
        const Transform xf{{unit(rng), unit(rng), unit(rng)}, aligned ? Quat{} : test::randomRotation(rng)};
        const Vec3 faceN = aligned ? axes[static_cast<std::size_t>(trial / 3) % 6] : normalize(Vec3{unit(rng), unit(rng), unit(rng)});
        const detail::ConvexShape b = detail::makeConvex(shape, xf);
        const ConvexHull& h = *b.hull;
        // The axis search's scan (collideTrianglePolytope).
        const Vec3 n = inverseRotate(xf.q, faceN);
        Real lo = dot(n, h.vertices[0]);
        std::uint32_t lowest = 0;
        int atLowest = 1;
        for (std::uint32_t i = 1; i < h.vertices.size(); ++i) {
            const Real d = dot(n, h.vertices[i]);
            if (d < lo) {
                lo = d;
                lowest = i;
                atLowest = 1;
            } else if (d == lo) {
                ++atLowest;
            }
        }
        if (atLowest > 1) ++ties;
        detail::SupportFace known, searched;
        detail::supportingFace(b, -faceN, known, lowest);
        detail::supportingFace(b, -faceN, searched);
        ASSERT_EQ(known.id, searched.id) << "trial " << trial;
        ASSERT_EQ(known.count, searched.count) << "trial " << trial;
        for (std::uint32_t i = 0; i < known.count; ++i) ASSERT_EQ(known.points[i], searched.points[i]) << "trial " << trial;
        ASSERT_EQ(known.normal, searched.normal) << "trial " << trial;
        // And the support point itself.
        std::uint32_t vertex = detail::kNoVertex;
        b.support(-faceN, vertex);
        ASSERT_EQ(vertex, lowest) << "trial " << trial;
    }
    EXPECT_GT(ties, 1000);  // the tied cases are exercised
}

// The edge pairs' Gauss-map filter in lanes of four polytope edges
// (TrianglePolytope::edgeLanes, branch tri10): the sign of ca ((a x c) . n)
// in place of mid . s is the same test in exact arithmetic (mid . s = -(t . t)
// ((a x c) . n) / (ca - cc) for t . n = 0), and the pairs it passes still run
// the scalar test, so the contact is the scalar loop's. Compared with the
// scalar loop (edgeLaneGroups 0) over random poses of boxes and hulls against
// triangles (faces, edge pairs, near-parallel edges, slivers and tiny
// triangles): the same hit and the same manifold bit for bit, or, where the
// two tests could differ (a pair at the filter's zero, whose axis is then the
// triangle's normal), the same deepest depth within 0.1 mm, in at most one
// pose in a thousand.
TEST(TriangleSat, EdgeLanesGiveTheScalarLoopsContact) {
    std::mt19937 rng(2131);
    std::vector<Shape> shapes = {Shape::box({0.4f, 0.2f, 0.3f}), Shape::box({1.5f, 0.1f, 0.8f}), cubeHull(0.5f),
                                 hexPrism(0.35f, 1.2f), pyramid(0.5f, 0.8f)};
    for (int i = 0; i < 5; ++i) shapes.push_back(rock(rng));
    detail::PolytopeEdgeCache cache;
    int compared = 0, hits = 0, edgeContacts = 0, faceContacts = 0, slivers = 0, differing = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const Shape& shape = shapes[static_cast<std::size_t>(trial) % shapes.size()];
        Vec3 w[3], faceN;
        detail::ConvexShape b;
        if (!pieceBesideEdgeCaseTriangle(rng, shape, trial, w, faceN, b)) continue;
        slivers += trial % 5 == 0 ? 1 : 0;
        detail::TrianglePolytope lanes, scalar;
        ASSERT_TRUE(lanes.prepare(b, cache));
        ASSERT_TRUE(scalar.prepare(b, cache));
#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE
        ASSERT_GT(lanes.edgeLaneGroups, 0u);
#endif
        scalar.edgeLaneGroups = 0;
        Manifold ml, ms;
        const bool hl = detail::collideTrianglePolytope(w, faceN, lanes, kMargin, ml);
        const bool hs = detail::collideTrianglePolytope(w, faceN, scalar, kMargin, ms);
        ++compared;
        bool same = hl == hs && (!hl || (ml.normal == ms.normal && ml.pointCount == ms.pointCount));
        for (std::uint32_t k = 0; same && hl && k < ml.pointCount; ++k) {
            same = ml.points[k].position == ms.points[k].position && ml.points[k].depth == ms.points[k].depth &&
                   ml.points[k].featureId == ms.points[k].featureId;
        }
        if (hs) {
            ++hits;
            if (ms.pointCount == 1 && (ms.points[0].featureId & 0xFFC00000u) == 0x80400000u) {
                ++edgeContacts;
            } else {
                ++faceContacts;
            }
        }
        if (!same) {
            ++differing;
            ASSERT_EQ(hl, hs) << "trial " << trial;
            Real dl = -1e30f, ds = -1e30f;
            for (std::uint32_t k = 0; k < ml.pointCount; ++k) dl = std::max(dl, ml.points[k].depth);
            for (std::uint32_t k = 0; k < ms.pointCount; ++k) ds = std::max(ds, ms.points[k].depth);
            EXPECT_NEAR(dl, ds, Real(1e-4)) << "trial " << trial;
        }
    }
    EXPECT_GT(compared, 15000);
    EXPECT_GT(hits, 3000);  // 3,929 (GCC, float)
    EXPECT_GT(edgeContacts, 1000);
    EXPECT_GT(faceContacts, 1000);
    EXPECT_GT(slivers, 3000);
    EXPECT_LE(differing, compared / 1000);
    std::printf("compared %d, hits %d (edge pairs %d, faces %d), differing %d\n", compared, hits, edgeContacts, faceContacts,
                differing);
}

// The edge pairs the lanes' signs pass take edgePairAxis's tests, axis and
// separation in lanes too (TrianglePolytope::edgePairsInLanes, branch
// trees12): the same operations in the same order, so the same answer as one
// pair at a time. Over random poses of boxes and hulls against triangles
// (faces, edge pairs, near-parallel edges, slivers), with the pair's hint and
// triangle axis cache entry: the same hit, manifold, hint and entry, bit for
// bit, every time.
TEST(TriangleSat, EdgePairsInLanesArePairAtATimeBitForBit) {
    std::mt19937 rng(1207);
    std::vector<Shape> shapes = {Shape::box({0.4f, 0.2f, 0.3f}), Shape::box({1.5f, 0.1f, 0.8f}), cubeHull(0.5f),
                                 hexPrism(0.35f, 1.2f), hexPrism(0.75f, 1.5f), pyramid(0.5f, 0.8f)};
    for (int i = 0; i < 5; ++i) shapes.push_back(rock(rng));
    detail::PolytopeEdgeCache cache;
    const auto sameBits = [](const auto& x, const auto& y) { return std::memcmp(&x, &y, sizeof(x)) == 0; };
    int compared = 0, hits = 0, edgeContacts = 0, edgeRejections = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const Shape& shape = shapes[static_cast<std::size_t>(trial) % shapes.size()];
        Vec3 w[3], faceN;
        detail::ConvexShape b;
        if (!pieceBesideEdgeCaseTriangle(rng, shape, trial, w, faceN, b)) continue;
        detail::TrianglePolytope lanes, oneAtATime;
        ASSERT_TRUE(lanes.prepare(b, cache));
        ASSERT_TRUE(oneAtATime.prepare(b, cache));
#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE
        ASSERT_GT(lanes.edgeLaneGroups, 0u);
#endif
        oneAtATime.edgePairsInLanes = false;
        Manifold ml, ms;
        std::uint32_t hintL = 0, hintS = 0;
        detail::TriangleAxisEntry entryL{}, entryS{};
        const bool hl = detail::collideTrianglePolytope(w, faceN, lanes, kMargin, ml, &hintL, &entryL);
        const bool hs = detail::collideTrianglePolytope(w, faceN, oneAtATime, kMargin, ms, &hintS, &entryS);
        ++compared;
        ASSERT_EQ(hl, hs) << "trial " << trial;
        ASSERT_EQ(hintL, hintS) << "trial " << trial;
        ASSERT_TRUE(entryL.axis == entryS.axis && sameBits(entryL.separation, entryS.separation)) << "trial " << trial;
        if ((hintS & ~detail::kAxisHintIndex) == detail::kEdgeAxisHint) ++edgeRejections;
        if (!hs) continue;
        ++hits;
        if (ms.pointCount == 1 && (ms.points[0].featureId & 0xFFC00000u) == 0x80400000u) ++edgeContacts;
        ASSERT_TRUE(sameBits(ml.normal, ms.normal)) << "trial " << trial;
        ASSERT_EQ(ml.pointCount, ms.pointCount) << "trial " << trial;
        for (std::uint32_t k = 0; k < ml.pointCount; ++k) {
            ASSERT_TRUE(sameBits(ml.points[k].position, ms.points[k].position) && sameBits(ml.points[k].depth, ms.points[k].depth) &&
                        ml.points[k].featureId == ms.points[k].featureId)
                << "trial " << trial << " point " << k;
        }
    }
    EXPECT_GT(compared, 15000);
    EXPECT_GT(hits, 3000);
    EXPECT_GT(edgeContacts, 500);
    EXPECT_GT(edgeRejections, 500);
    std::printf("compared %d, hits %d (edge pairs %d), rejected by an edge pair %d\n", compared, hits, edgeContacts, edgeRejections);
}
