// Quickhull: topology, robustness and exact mass properties.
#include <gtest/gtest.h>

#include <vector>

#include "fulcrum/shape.hpp"
#include "test_util.hpp"

namespace fulcrum {
namespace {

using test::Rng;

// Structural invariants every hull must satisfy. `tol` is the distance slack
// for points that must lie on or behind every face plane.
void expectValidHull(const ConvexHull& h, std::span<const Vec3> input, Real tol) {
    const std::size_t v = h.vertices.size(), e = h.edges.size(), f = h.faces.size();
    EXPECT_EQ(static_cast<long>(v) - static_cast<long>(e) + static_cast<long>(f), 2) << "Euler's formula V - E + F = 2";
    for (const HullFace& face : h.faces) {
        EXPECT_NEAR(length(face.normal), 1, 1e-5);
        ASSERT_GE(face.indexCount, 3u);
        // Every hull vertex behind or on the plane (convexity), the face's own on it.
        for (const Vec3& p : h.vertices) EXPECT_LE(dot(face.normal, p), face.offset + tol);
        Vec3 newell;
        for (std::uint32_t i = 0; i < face.indexCount; ++i) {
            const Vec3& a = h.vertices[h.faceVertices[face.firstIndex + i]];
            const Vec3& b = h.vertices[h.faceVertices[face.firstIndex + (i + 1) % face.indexCount]];
            EXPECT_NEAR(dot(face.normal, a), face.offset, tol);
            newell += cross(a, b);
        }
        EXPECT_GT(dot(normalize(newell), face.normal), Real(0.999)) << "face vertices must be CCW seen from outside";
    }
    // Every input point inside or on the hull.
    for (const Vec3& p : input) {
        for (const HullFace& face : h.faces) ASSERT_LE(dot(face.normal, p), face.offset + tol);
    }
    // Every hull vertex is one of the input points.
    for (const Vec3& hv : h.vertices) {
        bool found = false;
        for (const Vec3& p : input) found = found || p == hv;
        EXPECT_TRUE(found);
    }
    // Each undirected edge borders exactly two faces.
    for (const auto& edge : h.edges) {
        int uses = 0;
        for (const HullFace& face : h.faces) {
            for (std::uint32_t i = 0; i < face.indexCount; ++i) {
                const std::uint32_t a = h.faceVertices[face.firstIndex + i];
                const std::uint32_t b = h.faceVertices[face.firstIndex + (i + 1) % face.indexCount];
                if ((a == edge[0] && b == edge[1]) || (a == edge[1] && b == edge[0])) ++uses;
            }
        }
        EXPECT_EQ(uses, 2);
    }
}

std::vector<Vec3> boxCorners(const Vec3& h) {
    std::vector<Vec3> pts;
    for (int i = 0; i < 8; ++i) pts.push_back({(i & 1) ? h.x : -h.x, (i & 2) ? h.y : -h.y, (i & 4) ? h.z : -h.z});
    return pts;
}

TEST(ConvexHull, BoxCornersEqualTheBox) {
    const Vec3 he{1, Real(0.5), 2};
    const std::vector<Vec3> pts = boxCorners(he);
    const Shape hull = Shape::convexHull(pts);
    const ConvexHull& h = hull.hull();
    EXPECT_EQ(h.vertices.size(), 8u);
    EXPECT_EQ(h.faces.size(), 6u);
    EXPECT_EQ(h.edges.size(), 12u);
    for (const HullFace& f : h.faces) EXPECT_EQ(f.indexCount, 4u) << "coplanar triangles merge into quads";
    expectValidHull(h, pts, 1e-6f);
    // Tolerance: float rounding of the exact double computation, 1e-5 relative.
    const MassProperties a = hull.massProperties(3), b = Shape::box(he).massProperties(3);
    EXPECT_NEAR(a.mass, b.mass, 1e-5 * b.mass);
    EXPECT_NEAR(length(a.centerOfMass), 0, 1e-6);
    EXPECT_LT(test::maxAbsDiff(a.inertia, b.inertia), 1e-5 * b.inertia(2, 2));
    EXPECT_EQ(hull.localBounds(), AABB(-he, he));
}

TEST(ConvexHull, RegularTetrahedronInertia) {
    // Regular tetrahedron of edge a: I = m a^2 / 20 about any axis through the centroid.
    Rng rng(7);
    const Quat q = rng.rotation();
    const Vec3 offset{3, -2, 1};
    std::vector<Vec3> pts;
    for (const Vec3& v : {Vec3{1, 1, 1}, Vec3{1, -1, -1}, Vec3{-1, 1, -1}, Vec3{-1, -1, 1}}) pts.push_back(rotate(q, v) + offset);
    const Shape hull = Shape::convexHull(pts);
    const Real edge = std::sqrt(Real(8)), volume = Real(8) / 3;
    EXPECT_EQ(hull.hull().faces.size(), 4u);
    EXPECT_EQ(hull.hull().edges.size(), 6u);
    EXPECT_NEAR(hull.volume(), volume, 1e-5);
    const MassProperties mp = hull.massProperties(2);
    const Real expected = 2 * volume * edge * edge / 20;
    EXPECT_LT(length(mp.centerOfMass - offset), 1e-5);
    EXPECT_LT(test::maxAbsDiff(mp.inertia, Mat3::diagonal(expected)), 1e-5 * expected);
}

TEST(ConvexHull, RandomHullsMatchAVoxelEstimate) {
    // A 96^3 grid of cell centres over the bounds, counted inside by the face
    // planes: the discretisation error is ~1/96 of a cell layer over the
    // surface, well under the 1% (volume), 1% of size (centroid) and 2%
    // (inertia) tolerances.
    Rng rng(11);
    for (int trial = 0; trial < 3; ++trial) {
        std::vector<Vec3> pts;
        for (int i = 0; i < 40; ++i) pts.push_back(mul(rng.inBall(1), Vec3{1, Real(0.7), Real(1.3)}));
        const Shape hull = Shape::convexHull(pts);
        const ConvexHull& h = hull.hull();
        const int n = 96;
        const Vec3 lo = h.bounds.min, size = h.bounds.max - h.bounds.min;
        const double cell = double(size.x) * size.y * size.z / (double(n) * n * n);
        double vol = 0, cx = 0, cy = 0, cz = 0, xx = 0, yy = 0, zz = 0, xy = 0;
        for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j)
                for (int k = 0; k < n; ++k) {
                    const Real fn = static_cast<Real>(n);
                    const Vec3 p = lo + mul(size, Vec3{(Real(i) + Real(0.5)) / fn, (Real(j) + Real(0.5)) / fn, (Real(k) + Real(0.5)) / fn});
                    bool inside = true;
                    for (const HullFace& f : h.faces) {
                        if (dot(f.normal, p) > f.offset) { inside = false; break; }
                    }
                    if (!inside) continue;
                    vol += cell;
                    cx += cell * p.x; cy += cell * p.y; cz += cell * p.z;
                    xx += cell * p.x * p.x; yy += cell * p.y * p.y; zz += cell * p.z * p.z; xy += cell * p.x * p.y;
                }
        cx /= vol; cy /= vol; cz /= vol;
        // Second moments about the centroid.
        const double sxx = xx - vol * cx * cx, syy = yy - vol * cy * cy, szz = zz - vol * cz * cz, sxy = xy - vol * cx * cy;
        EXPECT_NEAR(h.volume, vol, 0.01 * vol);
        EXPECT_LT(length(h.centroid - Vec3{Real(cx), Real(cy), Real(cz)}), 0.01);
        const Mat3& I = h.unitDensityInertia;
        EXPECT_NEAR(I(0, 0), syy + szz, 0.02 * (syy + szz));
        EXPECT_NEAR(I(1, 1), sxx + szz, 0.02 * (sxx + szz));
        EXPECT_NEAR(I(2, 2), sxx + syy, 0.02 * (sxx + syy));
        EXPECT_NEAR(I(0, 1), -sxy, 0.02 * (sxx + syy));
        EXPECT_NEAR(I(0, 1), I(1, 0), 1e-6);
        expectValidHull(h, pts, 1e-5f);
    }
}

TEST(ConvexHull, RandomPointsInASphere) {
    Rng rng(3);
    for (int trial = 0; trial < 5; ++trial) {
        std::vector<Vec3> pts;
        for (int i = 0; i < 300; ++i) pts.push_back(rng.inBall(2) + Vec3{5, 0, -1});
        const Shape hull = Shape::convexHull(pts);
        // Slack: 1e-5 x the cloud's size, above the hull tolerance (2e-6 x extent sum).
        expectValidHull(hull.hull(), pts, 2e-4f);
        EXPECT_GT(hull.hull().vertices.size(), 20u);
        EXPECT_LT(hull.volume(), Real(4) / 3 * 3.1415927f * 8);
    }
}

TEST(ConvexHull, DuplicatedPoints) {
    std::vector<Vec3> pts;
    for (int copy = 0; copy < 5; ++copy) {
        for (const Vec3& v : boxCorners({1, 1, 1})) pts.push_back(v);
    }
    pts.push_back({0, 0, 0});
    const Shape hull = Shape::convexHull(pts);
    EXPECT_EQ(hull.hull().vertices.size(), 8u);
    EXPECT_EQ(hull.hull().faces.size(), 6u);
    EXPECT_NEAR(hull.volume(), 8, 1e-5);
    expectValidHull(hull.hull(), pts, 1e-6f);
}

// Corners of a cube plus points on its faces and edges, optionally with noise.
std::vector<Vec3> cubeSurfaceCloud(Rng& rng, Real noise) {
    std::vector<Vec3> pts = boxCorners({1, 1, 1});
    for (int i = 0; i < 400; ++i) {
        Vec3 p = rng.inBox(Vec3::splat(-1), Vec3::splat(1));
        const std::size_t axis = static_cast<std::size_t>(i % 3);
        p[axis] = (i / 3) % 2 ? 1 : -1;                   // on a face
        if (i % 4 == 0) p[(axis + 1) % 3] = (i / 7) % 2 ? 1 : -1;  // on an edge
        pts.push_back(p + rng.inBox(Vec3::splat(-noise), Vec3::splat(noise)));
    }
    return pts;
}

TEST(ConvexHull, PointsOnCubeFacesAndEdges) {
    Rng rng(5);
    const std::vector<Vec3> pts = cubeSurfaceCloud(rng, 0);
    const Shape hull = Shape::convexHull(pts);
    EXPECT_EQ(hull.hull().vertices.size(), 8u);
    EXPECT_EQ(hull.hull().faces.size(), 6u);
    EXPECT_EQ(hull.hull().edges.size(), 12u);
    EXPECT_NEAR(hull.volume(), 8, 1e-5);
    expectValidHull(hull.hull(), pts, 1e-6f);
}

TEST(ConvexHull, NearlyCoplanarNoise) {
    // Noise of 1e-6 of the cube's size on every point (corners included): the
    // hull tolerance (6e-6 here) treats it as flat, so the faces still merge.
    Rng rng(9);
    const std::vector<Vec3> pts = cubeSurfaceCloud(rng, 2e-6f);
    const Shape hull = Shape::convexHull(pts);
    EXPECT_EQ(hull.hull().faces.size(), 6u);
    EXPECT_EQ(hull.hull().vertices.size(), 8u);
    EXPECT_NEAR(hull.volume(), 8, 1e-4);
    expectValidHull(hull.hull(), pts, 2e-5f);
}

TEST(ConvexHull, LargeCloudOnASphere) {
    Rng rng(13);
    std::vector<Vec3> pts;
    for (int i = 0; i < 2000; ++i) pts.push_back(rng.onSphere());
    const Shape hull = Shape::convexHull(pts);
    expectValidHull(hull.hull(), pts, 1e-5f);
    // Volume of the inscribed polyhedron approaches the ball's from below; with
    // 2000 vertices it is within 1%.
    const Real ball = Real(4) / 3 * 3.14159265f;
    EXPECT_LT(hull.volume(), ball);
    EXPECT_GT(hull.volume(), 0.99f * ball);
}

void expectError(std::span<const Vec3> pts, const std::string& fragment) {
    try {
        (void)Shape::convexHull(pts);
        ADD_FAILURE() << "expected an error containing '" << fragment << "'";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}

TEST(ConvexHull, DegenerateInputIsAnError) {
    const std::vector<Vec3> three{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    expectError(three, "convex_hull: needs at least 4 points, got 3");
    std::vector<Vec3> flat;
    for (int i = 0; i < 20; ++i) flat.push_back({Real(i % 5), Real(i / 5), 0});
    expectError(flat, "convex_hull: points are coplanar");
    expectError(flat, "a hull needs volume");
    std::vector<Vec3> line;
    for (int i = 0; i < 10; ++i) line.push_back(Vec3{1, 2, 3} * Real(i));
    expectError(line, "points are coplanar (they all lie on a line)");
    const std::vector<Vec3> same(6, Vec3{1, 1, 1});
    expectError(same, "points are coplanar (they all coincide)");
    std::vector<Vec3> nan = boxCorners({1, 1, 1});
    nan[5].y = std::nanf("");
    expectError(nan, "convex_hull: points[5] is not finite");
    nan[5].y = INFINITY;
    expectError(nan, "points[5]");
}

}  // namespace
}  // namespace fulcrum
