#pragma once
// Test helpers for the narrow phase: hand-built hulls and meshes (so these
// tests do not depend on quickhull or the mesh builder), random rotations.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <random>
#include <utility>
#include <vector>

#include "collision/manifold.hpp"
#include "collision/support.hpp"
#include "fulcrum/shape.hpp"

namespace fulcrum::test {

inline void expectVecNear(const Vec3& a, const Vec3& b, Real tol) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

inline Quat randomRotation(std::mt19937& rng) {
    std::normal_distribution<Real> n(0, 1);
    // Drawn in an explicit order (the last component first, as GCC evaluated
    // the former constructor's arguments): the same cases with every compiler.
    const Real z = n(rng), y = n(rng), x = n(rng), w = n(rng);
    return normalize(Quat(w, x, y, z));
}

// A box as a ConvexHull: 8 vertices, 6 quads counter-clockwise from outside, 12 edges.
inline ConvexHull boxHull(const Vec3& e) {
    ConvexHull h;
    for (int i = 0; i < 8; ++i) h.vertices.push_back({(i & 1) ? e.x : -e.x, (i & 2) ? e.y : -e.y, (i & 4) ? e.z : -e.z});
    // Vertex index = x + 2y + 4z bits.
    const std::uint32_t quads[6][4] = {{1, 3, 7, 5}, {0, 4, 6, 2}, {2, 6, 7, 3}, {0, 1, 5, 4}, {4, 5, 7, 6}, {0, 2, 3, 1}};
    const Vec3 normals[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (int f = 0; f < 6; ++f) {
        HullFace face;
        face.normal = normals[f];
        face.offset = dot(normals[f], h.vertices[quads[f][0]]);
        face.firstIndex = static_cast<std::uint32_t>(h.faceVertices.size());
        face.indexCount = 4;
        for (std::uint32_t v : quads[f]) h.faceVertices.push_back(v);
        h.faces.push_back(face);
    }
    for (std::uint32_t i = 0; i < 8; ++i) {
        for (std::uint32_t bit = 1; bit < 8; bit <<= 1) {
            if (!(i & bit)) h.edges.push_back({i, i | bit});
        }
    }
    h.centroid = Vec3::zero();
    h.volume = 8 * e.x * e.y * e.z;
    h.bounds = AABB::fromCenterHalf(Vec3::zero(), e);
    return h;
}

// A triangle mesh with adjacency and convex-edge flags computed here the way
// the mesh builder is specified to (bit k set for convex or boundary edges).
inline TriangleMesh buildMesh(std::vector<Vec3> vertices, std::vector<std::array<std::uint32_t, 3>> triangles) {
    TriangleMesh m;
    m.vertices = std::move(vertices);
    m.triangles = std::move(triangles);
    const std::size_t n = m.triangles.size();
    m.adjacency.assign(n, {UINT32_MAX, UINT32_MAX, UINT32_MAX});
    m.convexEdgeMask.assign(n, 0);
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::pair<std::uint32_t, std::uint32_t>> edgeOwner;
    for (std::uint32_t t = 0; t < n; ++t) {
        for (std::uint32_t k = 0; k < 3; ++k) {
            edgeOwner[{m.triangles[t][k], m.triangles[t][(k + 1) % 3]}] = {t, k};
        }
    }
    auto normalOf = [&](std::uint32_t t) {
        const auto& tr = m.triangles[t];
        return normalize(cross(m.vertices[tr[1]] - m.vertices[tr[0]], m.vertices[tr[2]] - m.vertices[tr[0]]));
    };
    for (std::uint32_t t = 0; t < n; ++t) {
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t a = m.triangles[t][k], b = m.triangles[t][(k + 1) % 3];
            auto it = edgeOwner.find({b, a});
            if (it == edgeOwner.end()) {
                m.convexEdgeMask[t] |= static_cast<std::uint8_t>(1u << k);
                continue;
            }
            const std::uint32_t other = it->second.first;
            m.adjacency[t][k] = other;
            // Convex when the neighbour's far vertex is below this triangle's plane (by more than a flat tolerance).
            const auto& ot = m.triangles[other];
            std::uint32_t far = ot[0];
            for (std::uint32_t v : ot) {
                if (v != a && v != b) far = v;
            }
            const Real side = dot(normalOf(t), m.vertices[far] - m.vertices[a]);
            if (side < -Real(1e-5)) m.convexEdgeMask[t] |= static_cast<std::uint8_t>(1u << k);
        }
    }
    for (const Vec3& v : m.vertices) m.bounds.grow(v);
    return m;
}

// A flat n x n grid of squares of side `cell` in the plane y = 0, two triangles per square.
inline TriangleMesh flatGrid(int n, Real cell) {
    std::vector<Vec3> v;
    std::vector<std::array<std::uint32_t, 3>> t;
    const Real half = static_cast<Real>(n) * cell / 2;
    for (int j = 0; j <= n; ++j) {
        for (int i = 0; i <= n; ++i) v.push_back({static_cast<Real>(i) * cell - half, 0, static_cast<Real>(j) * cell - half});
    }
    auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * (n + 1) + i); };
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            // Counter-clockwise seen from +y: (i,j) -> (i,j+1) -> (i+1,j+1).
            t.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
            t.push_back({id(i, j), id(i + 1, j + 1), id(i + 1, j)});
        }
    }
    return buildMesh(std::move(v), std::move(t));
}

inline detail::ConvexShape hullShape(const ConvexHull& h, const Transform& xf) {
    detail::ConvexShape s;
    s.kind = detail::ConvexKind::Hull;
    s.hull = &h;
    s.xf = xf;
    return s;
}

}  // namespace fulcrum::test
