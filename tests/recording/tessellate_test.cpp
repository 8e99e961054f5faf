// Render meshes against geometry: a closed, outward-wound mesh encloses the
// shape's volume (exactly for flat-faced shapes; for curved ones the inscribed
// polyhedron's volume, below the true one by a bounded fraction), every edge
// joins exactly two triangles in opposite directions, and normals point out.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <tuple>

#include "io/tessellate.hpp"

using namespace fulcrum;
using namespace fulcrum::io;

namespace {

constexpr double kPi = std::numbers::pi;

// Edges keyed by welded positions: a closed 2-manifold uses each directed edge
// exactly once and its reverse exactly once.
void expectClosed(const RenderMesh& mesh) {
    using Key = std::tuple<float, float, float>;
    std::map<std::pair<Key, Key>, int> directed;
    auto key = [&](std::uint32_t i) { const Vec3& p = mesh.positions[i]; return Key{p.x, p.y, p.z}; };
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
        for (int e = 0; e < 3; ++e) {
            const Key a = key(mesh.indices[t + static_cast<std::size_t>(e)]);
            const Key b = key(mesh.indices[t + static_cast<std::size_t>((e + 1) % 3)]);
            ++directed[{a, b}];
        }
    }
    int bad = 0;
    for (const auto& [edge, count] : directed) {
        const auto reverse = directed.find({edge.second, edge.first});
        if (count != 1 || reverse == directed.end() || reverse->second != 1) ++bad;
    }
    EXPECT_EQ(bad, 0) << "edges not shared by exactly two opposite triangles";
}

// For a shape convex about the origin, every face's normal points away from the origin.
void expectOutwardNormals(const RenderMesh& mesh) {
    ASSERT_EQ(mesh.positions.size(), mesh.normals.size());
    for (std::size_t t = 0; t < mesh.indices.size(); t += 3) {
        const Vec3 a = mesh.positions[mesh.indices[t]], b = mesh.positions[mesh.indices[t + 1]],
                   c = mesh.positions[mesh.indices[t + 2]];
        const Vec3 faceNormal = cross(b - a, c - a);
        const Vec3 centroid = (a + b + c) / Real(3);
        EXPECT_GT(dot(faceNormal, centroid), 0) << "triangle " << t / 3 << " wound inwards";
        for (int k = 0; k < 3; ++k) {
            const Vec3 n = mesh.normals[mesh.indices[t + static_cast<std::size_t>(k)]];
            EXPECT_NEAR(length(n), 1, 1e-5);
            EXPECT_GT(dot(n, normalize(faceNormal)), 0) << "vertex normal against its face";
        }
    }
}

TEST(Tessellate, BoxEnclosesExactVolume) {
    const Vec3 h{0.5f, 1.5f, 0.25f};
    const RenderMesh mesh = tessellateBox(h);
    EXPECT_EQ(mesh.indices.size(), 36u);
    EXPECT_NEAR(enclosedVolume(mesh), 8.0 * 0.5 * 1.5 * 0.25, 1e-6);
    expectClosed(mesh);
    expectOutwardNormals(mesh);
}

// An inscribed UV sphere with m segments and k rings under-estimates the volume;
// with 32 x 16 the deficit is about 1.6% (area of a regular 32-gon: 0.6% less
// than the circle's, times the ring discretisation); we allow (0, 3%].
TEST(Tessellate, SphereApproachesBallVolumeFromBelow) {
    const Real r = 0.7f;
    const RenderMesh mesh = tessellateSphere(r);
    const double exact = 4.0 / 3.0 * kPi * r * r * r;
    const double v = enclosedVolume(mesh);
    EXPECT_LT(v, exact);
    EXPECT_GT(v, 0.97 * exact);
    expectClosed(mesh);
    expectOutwardNormals(mesh);
    for (const Vec3& p : mesh.positions) EXPECT_NEAR(length(p), r, 1e-5);
    // Finer tessellation converges: the deficit shrinks roughly 4x per doubling.
    const double fine = enclosedVolume(tessellateSphere(r, TessellationOptions{.segments = 64, .rings = 32, .planeCenter = {}, .planeHalfSize = 20}));
    EXPECT_LT(exact - fine, 0.3 * (exact - v));
}

TEST(Tessellate, CapsuleAndCylinderVolumes) {
    const Real r = 0.3f, h = 0.8f;
    const RenderMesh capsule = tessellateCapsule(r, h);
    const double capsuleExact = kPi * r * r * 2 * h + 4.0 / 3.0 * kPi * r * r * r;
    EXPECT_LT(enclosedVolume(capsule), capsuleExact);
    EXPECT_GT(enclosedVolume(capsule), 0.97 * capsuleExact);
    expectClosed(capsule);
    expectOutwardNormals(capsule);

    // A prism over a regular 32-gon: area (m/2) r^2 sin(2 pi / m), exact.
    const RenderMesh cylinder = tessellateCylinder(r, h);
    const double prism = 32.0 / 2.0 * r * r * std::sin(2 * kPi / 32) * 2 * h;
    EXPECT_NEAR(enclosedVolume(cylinder), prism, 1e-6);
    expectClosed(cylinder);
    expectOutwardNormals(cylinder);
}

// A hull given as faces (a unit cube, as quickhull would report it, with merged quads).
TEST(Tessellate, HullFacesEncloseTheHullVolume) {
    ConvexHull hull;
    for (int i = 0; i < 8; ++i) {
        hull.vertices.push_back({static_cast<Real>(i & 1), static_cast<Real>((i >> 1) & 1), static_cast<Real>((i >> 2) & 1)});
    }
    // Vertex index = x + 2y + 4z; each face counter-clockwise seen from outside.
    const std::uint32_t faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    const Vec3 normals[6] = {{-1, 0, 0}, {1, 0, 0}, {0, -1, 0}, {0, 1, 0}, {0, 0, -1}, {0, 0, 1}};
    for (int f = 0; f < 6; ++f) {
        HullFace face;
        face.normal = normals[f];
        face.firstIndex = static_cast<std::uint32_t>(hull.faceVertices.size());
        face.indexCount = 4;
        for (std::uint32_t v : faces[f]) hull.faceVertices.push_back(v);
        hull.faces.push_back(face);
    }
    const RenderMesh mesh = tessellateHull(hull);
    EXPECT_NEAR(enclosedVolume(mesh), 1.0, 1e-6);
    expectClosed(mesh);
    for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        // Flat shading: each vertex carries its face's normal, which points away from the cube's centre.
        EXPECT_GT(dot(mesh.normals[i], mesh.positions[i] - Vec3::splat(0.5f)), 0);
    }
}

TEST(Tessellate, PlaneQuadLiesInThePlaneUnderTheCentre) {
    const Vec3 n = normalize(Vec3{0.2f, 1, -0.1f});
    TessellationOptions options;
    options.planeCenter = {3, 7, -2};
    options.planeHalfSize = 15;
    const RenderMesh quad = tessellatePlane(n, 0.5f, options);
    ASSERT_EQ(quad.positions.size(), 4u);
    Vec3 centre;
    for (const Vec3& p : quad.positions) {
        EXPECT_NEAR(dot(n, p), 0.5f, 1e-4);
        centre += p / Real(4);
    }
    // The centre is the foot of the perpendicular from planeCenter.
    const Vec3 foot = options.planeCenter - n * (dot(n, options.planeCenter) - Real(0.5));
    EXPECT_NEAR(distance(centre, foot), 0, 1e-4);
    EXPECT_NEAR(distance(quad.positions[0], quad.positions[1]), 30, 1e-3);
    // Wound counter-clockwise seen from the normal's side.
    EXPECT_GT(dot(cross(quad.positions[1] - quad.positions[0], quad.positions[2] - quad.positions[0]), n), 0);
    EXPECT_TRUE(quad.doubleSided);
}

TEST(Tessellate, CompoundFlattensWithChildFrames) {
    const Transform inner{{0, 1, 0}, Quat::fromAxisAngle({0, 0, 1}, 0.5f)};
    const CompoundChild nested[] = {{Shape::sphere(0.1f), inner}};
    const CompoundChild children[] = {{Shape::box({0.1f, 0.2f, 0.3f}), Transform{{1, 0, 0}, Quat::identity()}},
                                      {Shape::compound(nested), Transform{{0, 0, 2}, Quat::identity()}}};
    const auto parts = tessellate(Shape::compound(children));
    ASSERT_EQ(parts.size(), 2u);
    EXPECT_EQ(parts[0].local.p, (Vec3{1, 0, 0}));
    EXPECT_NEAR(distance(parts[1].local.p, Vec3{0, 1, 2}), 0, 1e-6);
    EXPECT_NEAR(enclosedVolume(parts[0].mesh), 8 * 0.1 * 0.2 * 0.3, 1e-6);
}

}  // namespace

namespace {

// Shapes built by the engine's own factories: the hull's render mesh encloses
// exactly the hull's volume, and a triangle mesh keeps its triangles.
TEST(Tessellate, EngineHullAndMesh) {
    const Vec3 points[] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.2f, 0.2f, 0.2f}, {1, 1, 1}};
    const Shape hull = Shape::convexHull(points);
    const auto parts = tessellate(hull);
    ASSERT_EQ(parts.size(), 1u);
    EXPECT_NEAR(enclosedVolume(parts[0].mesh), hull.volume(), 1e-5);
    expectClosed(parts[0].mesh);

    const Vec3 vertices[] = {{0, 0, 0}, {1, 0, 0}, {1, 0, 1}, {0, 0, 1}};
    const std::array<std::uint32_t, 3> triangles[] = {{0, 2, 1}, {0, 3, 2}};
    const auto meshParts = tessellate(Shape::mesh(vertices, triangles));
    ASSERT_EQ(meshParts.size(), 1u);
    EXPECT_EQ(meshParts[0].mesh.indices.size(), 6u);
    for (const Vec3& n : meshParts[0].mesh.normals) EXPECT_NEAR(n.y, 1, 1e-6);  // (0,2,1) is counter-clockwise from +y
}

}  // namespace
