// Convex shapes against triangle meshes (built by Shape::mesh, so with the
// BVH and the convex-edge flags of the mesh builder). The key property:
// internal edges of a flat mesh never produce anything but the face normal
// (tolerance 1e-3 on the normal, as the brief asks), so a box sliding across
// seams gets no ghost bumps.
#include <gtest/gtest.h>

#include "collision/collide_mesh.hpp"
#include "collision/narrow_phase.hpp"
#include "helpers.hpp"

using namespace fulcrum;
using fulcrum::test::expectVecNear;

namespace {

constexpr Real kMargin = Real(0.02);

Shape gridShape(int n, Real cell) {
    const TriangleMesh m = test::flatGrid(n, cell);
    return Shape::mesh(m.vertices, m.triangles);
}

}  // namespace

TEST(Mesh, BoxSlidingAcrossFlatGridSeesOnlyTheFaceNormal) {
    const Shape grid = gridShape(8, 1);
    const Shape box = Shape::box({0.5f, 0.25f, 0.5f});
    ManifoldBuffer out;
    int manifolds = 0;
    // Slide over seams (x = integer) and diagonals, with a yaw so edges cross at angles, sunk 0.01.
    for (int i = 0; i <= 80; ++i) {
        const Real x = -2 + Real(0.05) * static_cast<Real>(i);
        for (const Real yaw : {0.0f, 0.3f, 0.7853982f}) {
            const Transform xb{{x, 0.24f, 0.37f}, Quat::fromAxisAngle({0, 1, 0}, yaw)};
            collide(grid, {}, box, xb, kMargin, out);
            ASSERT_GE(out.size(), 1u) << "x " << x;
            for (const Manifold& m : out) {
                ++manifolds;
                expectVecNear(m.normal, {0, 1, 0}, Real(1e-3));
                for (const ContactPoint& c : m.contacts()) EXPECT_NEAR(c.depth, 0.01f, Real(1e-4));
            }
            // All contacts share one normal, so they form one manifold of 4 points at the box corners.
            ASSERT_EQ(out.size(), 1u);
            EXPECT_EQ(out[0].pointCount, 4u);
        }
    }
    EXPECT_EQ(manifolds, 81 * 3);
}

TEST(Mesh, GhostNormalsWouldAppearWithoutEdgeFlags) {
    // Control: the same box on a hand-built grid whose edges are all flagged
    // convex gets sideways normals at seams, so the previous test really
    // exercises the internal-edge handling.
    TriangleMesh m = test::flatGrid(4, 1);
    for (auto& mask : m.convexEdgeMask) mask = 7;
    const detail::ConvexShape box = detail::makeConvex(Shape::box({0.5f, 0.25f, 0.5f}), {{0.02f, 0.24f, 0.3f}, {}});
    bool sideways = false;
    ManifoldBuffer out;
    // Every 5 mm: some positions reach past a seam by less than the box's 1 cm
    // depth, where a sideways (edge) axis overlaps least. The 10 cm steps this
    // used to take found one in the float build but none in the double build.
    for (int i = 0; i < 400; ++i) {
        detail::ConvexShape b = box;
        b.xf.p.x = Real(-1.02) + Real(0.005) * static_cast<Real>(i);
        out.clear();
        detail::collideMeshConvex(m, {}, b, Shape::box({0.5f, 0.25f, 0.5f}).bounds(b.xf), kMargin, out);
        for (const Manifold& mf : out) sideways = sideways || mf.normal.y < Real(0.999);
    }
    EXPECT_TRUE(sideways);
}

TEST(Mesh, SphereOnVertexEdgeAndFace) {
    const Shape grid = gridShape(4, 1);
    ManifoldBuffer out;
    // On a grid vertex (0,0,0), on an edge (0.5, 0, 0) and inside a face: all face normal, depth 0.02.
    for (const Vec3 p : {Vec3{0, 0.48f, 0}, Vec3{0.5f, 0.48f, 0}, Vec3{0.5f, 0.48f, 0.5f}, Vec3{0.3f, 0.48f, 0.6f}}) {
        collide(Shape::sphere(0.5f), {p, {}}, grid, {}, kMargin, out);
        ASSERT_EQ(out.size(), 1u);
        expectVecNear(out[0].normal, {0, -1, 0}, Real(1e-4));  // sphere (A) -> mesh (B)
        ASSERT_EQ(out[0].pointCount, 1u);
        EXPECT_NEAR(out[0].points[0].depth, 0.02f, Real(1e-4));
        expectVecNear(out[0].points[0].position, {p.x, -0.01f, p.z}, Real(1e-4));
    }
}

TEST(Mesh, CapsuleAcrossSeamGetsTwoPointsAndTheFaceNormal) {
    const Shape grid = gridShape(4, 1);
    ManifoldBuffer out;
    // Lying along x across the seam at x = 0 and the diagonals.
    const Transform xc{{0.1f, 0.19f, 0.3f}, Quat::fromAxisAngle({0, 0, 1}, 1.5707963f)};
    collide(Shape::capsule(0.2f, 0.8f), xc, grid, {}, kMargin, out);
    ASSERT_EQ(out.size(), 1u);
    expectVecNear(out[0].normal, {0, -1, 0}, Real(1e-3));
    ASSERT_EQ(out[0].pointCount, 2u);
    Real xs[2] = {out[0].points[0].position.x, out[0].points[1].position.x};
    if (xs[0] > xs[1]) std::swap(xs[0], xs[1]);
    EXPECT_NEAR(xs[0], -0.7f, Real(1e-3));
    EXPECT_NEAR(xs[1], 0.9f, Real(1e-3));
    for (const ContactPoint& c : out[0].contacts()) EXPECT_NEAR(c.depth, 0.01f, Real(1e-4));
}

TEST(Mesh, ConvexEdgeKeepsItsEdgeNormal) {
    // A ridge: two slopes meeting at x = 0 (convex edge along z). A sphere
    // right above the ridge touches the edge; its normal must point straight
    // up from the edge (the edge normal), not along either face.
    const std::vector<Vec3> v = {{-1, -1, -1}, {0, 0, -1}, {1, -1, -1}, {-1, -1, 1}, {0, 0, 1}, {1, -1, 1}};
    const std::vector<std::array<std::uint32_t, 3>> t = {{0, 3, 4}, {0, 4, 1}, {1, 4, 5}, {1, 5, 2}};
    const Shape ridge = Shape::mesh(v, t);
    ManifoldBuffer out;
    collide(ridge, {}, Shape::sphere(0.5f), {{0, 0.49f, 0}, {}}, kMargin, out);
    ASSERT_GE(out.size(), 1u);
    expectVecNear(out[0].normal, {0, 1, 0}, Real(1e-4));
    EXPECT_NEAR(out[0].points[0].depth, 0.01f, Real(1e-4));
}

TEST(Mesh, HullOnTiltedMesh) {
    // A mesh plane tilted 0.3 rad about z through a transform; a box hull resting on it.
    const Shape grid = gridShape(4, 1);
    const Vec3 pts[8] = {{-0.5f, -0.5f, -0.5f}, {0.5f, -0.5f, -0.5f}, {-0.5f, 0.5f, -0.5f}, {0.5f, 0.5f, -0.5f},
                         {-0.5f, -0.5f, 0.5f},  {0.5f, -0.5f, 0.5f},  {-0.5f, 0.5f, 0.5f},  {0.5f, 0.5f, 0.5f}};
    const Shape hull = Shape::convexHull(pts);
    const Quat tilt = Quat::fromAxisAngle({0, 0, 1}, 0.3f);
    const Transform xm{{0, 0, 0}, tilt};
    const Transform xh{rotate(tilt, Vec3{0.2f, 0.49f, 0.1f}), tilt};
    ManifoldBuffer out;
    collide(grid, xm, hull, xh, kMargin, out);
    ASSERT_EQ(out.size(), 1u);
    expectVecNear(out[0].normal, rotate(tilt, Vec3{0, 1, 0}), Real(1e-3));
    EXPECT_EQ(out[0].pointCount, 4u);
    for (const ContactPoint& c : out[0].contacts()) EXPECT_NEAR(c.depth, 0.01f, Real(1e-3));
}
