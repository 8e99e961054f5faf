// Triangle meshes: validation, adjacency and convex-edge flags, and the BVH
// queries against brute force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <utility>
#include <vector>

#include "collision/mesh_bvh.hpp"
#include "fulcrum/shape.hpp"
#include "test_util.hpp"

namespace fulcrum {
namespace {

using Tri = std::array<std::uint32_t, 3>;
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// n x n quads in the plane y = height, front faces up (+y).
void flatGrid(int n, Real spacing, std::vector<Vec3>& v, std::vector<Tri>& t, Real bump = 0) {
    const auto id = [n](int i, int j) { return static_cast<std::uint32_t>(i * (n + 1) + j); };
    for (int i = 0; i <= n; ++i)
        for (int j = 0; j <= n; ++j) v.push_back({Real(i) * spacing, (i == n / 2 && j == n / 2) ? bump : 0, Real(j) * spacing});
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            t.push_back({id(i, j), id(i, j + 1), id(i + 1, j)});
            t.push_back({id(i + 1, j), id(i, j + 1), id(i + 1, j + 1)});
        }
}

// A closed box, outward-facing triangles.
void boxMesh(const Vec3& h, std::vector<Vec3>& v, std::vector<Tri>& t) {
    for (int i = 0; i < 8; ++i) v.push_back({(i & 1) ? h.x : -h.x, (i & 2) ? h.y : -h.y, (i & 4) ? h.z : -h.z});
    const std::array<std::array<std::uint32_t, 4>, 6> quads{{{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}}};
    for (const auto& q : quads) {
        t.push_back({q[0], q[1], q[2]});
        t.push_back({q[0], q[2], q[3]});
    }
}

TEST(Mesh, FlatGridEdgesAreInternalBoundaryEdgesAreFlagged) {
    std::vector<Vec3> v;
    std::vector<Tri> t;
    flatGrid(6, Real(0.5), v, t);
    const Shape s = Shape::mesh(v, t);
    const TriangleMesh& m = s.mesh();
    int boundary = 0;
    for (std::size_t i = 0; i < t.size(); ++i) {
        for (std::uint32_t k = 0; k < 3; ++k) {
            const bool isBoundary = m.adjacency[i][k] == kNone;
            const bool convex = (m.convexEdgeMask[i] >> k) & 1u;
            boundary += isBoundary;
            EXPECT_EQ(convex, isBoundary) << "flat internal edges must not be convex, boundaries must be";
            if (!isBoundary) {
                // Adjacency is symmetric.
                const auto& back = m.adjacency[m.adjacency[i][k]];
                EXPECT_NE(std::find(back.begin(), back.end(), static_cast<std::uint32_t>(i)), back.end());
            }
        }
    }
    EXPECT_EQ(boundary, 4 * 6);
}

TEST(Mesh, ClosedBoxCubeEdgesConvexDiagonalsFlat) {
    std::vector<Vec3> v;
    std::vector<Tri> t;
    boxMesh({1, 2, Real(0.5)}, v, t);
    const Shape shape = Shape::mesh(v, t);
        const TriangleMesh& m = shape.mesh();
    for (std::size_t i = 0; i < t.size(); ++i) {
        for (std::uint32_t k = 0; k < 3; ++k) {
            ASSERT_NE(m.adjacency[i][k], kNone) << "a closed box has no boundary";
            const bool diagonal = m.adjacency[i][k] == (i ^ 1u);  // the other half of the same quad
            EXPECT_EQ(((m.convexEdgeMask[i] >> k) & 1u) != 0, !diagonal);
        }
    }
}

TEST(Mesh, ValleyIsConcaveRidgeIsConvex) {
    // Two triangles sharing the edge x = 0 along z, front faces up.
    for (const Real tip : {Real(1), Real(-1)}) {
        const std::vector<Vec3> v{{0, 0, 0}, {0, 0, 1}, {-1, tip, 0}, {1, tip, 0}};
        const std::vector<Tri> t{{0, 2, 1}, {0, 1, 3}};
        const Shape shape = Shape::mesh(v, t);
        const TriangleMesh& m = shape.mesh();
        EXPECT_EQ(m.adjacency[0][2], 1u);
        const bool convex = (m.convexEdgeMask[0] >> 2) & 1u;
        EXPECT_EQ(convex, tip < 0) << (tip > 0 ? "valley (V): concave, internal" : "ridge: convex");
        EXPECT_EQ(((m.convexEdgeMask[1] >> 0) & 1u) != 0, tip < 0);
    }
}

TEST(Mesh, SlightlyBentEdgeBeyondToleranceIsConvex) {
    // A 0.5 degree fold downward: convex (above the 0.06 degree flat tolerance).
    std::vector<Vec3> v;
    std::vector<Tri> t;
    flatGrid(2, 1, v, t, Real(-0.0087));
    const Shape shape = Shape::mesh(v, t);
        const TriangleMesh& m = shape.mesh();
    int convexInternal = 0;
    for (std::size_t i = 0; i < t.size(); ++i)
        for (std::uint32_t k = 0; k < 3; ++k) convexInternal += m.adjacency[i][k] != kNone && ((m.convexEdgeMask[i] >> k) & 1u);
    EXPECT_GT(convexInternal, 0);
}

void expectMeshError(std::span<const Vec3> v, std::span<const Tri> t, const std::string& fragment) {
    try {
        (void)Shape::mesh(v, t);
        ADD_FAILURE() << "expected an error containing '" << fragment << "'";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}

TEST(Mesh, InvalidInputIsAnError) {
    const std::vector<Vec3> v{{0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {2, 0, 0}};
    expectMeshError({}, std::vector<Tri>{{0, 1, 2}}, "mesh: vertices must not be empty");
    expectMeshError(v, {}, "mesh: triangles must not be empty");
    expectMeshError(v, std::vector<Tri>{{0, 2, 1}, {0, 1, 7}}, "mesh: triangles[1][2] = 7 is out of range (4 vertices)");
    expectMeshError(v, std::vector<Tri>{{0, 2, 1}, {0, 1, 3}}, "mesh: triangles[1] is degenerate (zero area)");
    expectMeshError(v, std::vector<Tri>{{0, 0, 1}}, "mesh: triangles[0] is degenerate");
    std::vector<Vec3> bad = v;
    bad[2].z = std::nanf("");
    expectMeshError(bad, std::vector<Tri>{{0, 2, 1}}, "mesh: vertices[2] is not finite");
}

// A random triangle soup: small triangles scattered in a box.
Shape randomSoup(test::Rng& rng, int count, std::vector<Vec3>& v, std::vector<Tri>& t) {
    for (int i = 0; i < count; ++i) {
        const Vec3 c = rng.inBox(Vec3::splat(-10), Vec3::splat(10));
        const auto base = static_cast<std::uint32_t>(v.size());
        for (int k = 0; k < 3; ++k) v.push_back(c + rng.inBox(Vec3::splat(-1), Vec3::splat(1)));
        t.push_back({base, base + 1, base + 2});
    }
    return Shape::mesh(v, t);
}

TEST(MeshBvh, StructureCoversEveryTriangleOnce) {
    test::Rng rng(21);
    std::vector<Vec3> v;
    std::vector<Tri> t;
    const Shape s = randomSoup(rng, 3000, v, t);
    const MeshBvh& bvh = *s.mesh().bvh;
    std::vector<std::uint32_t> order = bvh.triangleOrder;
    std::sort(order.begin(), order.end());
    for (std::uint32_t i = 0; i < order.size(); ++i) ASSERT_EQ(order[i], i);
    std::size_t leafTriangles = 0;
    for (std::size_t n = 0; n < bvh.nodes.size(); ++n) {
        const MeshBvhNode& node = bvh.nodes[n];
        if (node.isLeaf()) {
            EXPECT_LE(node.count, MeshBvh::kMaxLeafTriangles * 2);
            leafTriangles += node.count;
            for (std::uint32_t i = node.index; i < node.index + node.count; ++i) {
                EXPECT_TRUE(node.bounds.contains(triangleBounds(s.mesh(), bvh.triangleOrder[i])));
            }
        } else {
            EXPECT_TRUE(node.bounds.contains(bvh.nodes[n + 1].bounds));
            EXPECT_TRUE(node.bounds.contains(bvh.nodes[node.index].bounds));
        }
    }
    EXPECT_EQ(leafTriangles, t.size());
    EXPECT_LT(bvh.depth, MeshBvh::kStackSize);
}

TEST(MeshBvh, AabbQueryEqualsBruteForce) {
    test::Rng rng(22);
    std::vector<Vec3> v;
    std::vector<Tri> t;
    const Shape s = randomSoup(rng, 2000, v, t);
    for (int q = 0; q < 200; ++q) {
        const Vec3 c = rng.inBox(Vec3::splat(-12), Vec3::splat(12));
        const AABB box = AABB::fromCenterHalf(c, rng.inBox(Vec3::splat(0.1f), Vec3::splat(4)));
        std::vector<std::uint32_t> found;
        queryTriangles(s.mesh(), box, [&](std::uint32_t i) { found.push_back(i); });
        std::vector<std::uint32_t> expected;
        for (std::uint32_t i = 0; i < t.size(); ++i) {
            if (overlaps(triangleBounds(s.mesh(), i), box)) expected.push_back(i);
        }
        std::sort(found.begin(), found.end());
        ASSERT_EQ(found, expected);
    }
    // Early exit: a callback returning false stops after the first triangle.
    int calls = 0;
    queryTriangles(s.mesh(), s.mesh().bounds, [&](std::uint32_t) { ++calls; return false; });
    EXPECT_EQ(calls, 1);
}

// A contact's candidate list (MeshCandidateCache) gives the query's own
// answer: the same triangles in the same order, bit for bit, whether the
// list is made again or reused, over random walks of boxes that grow and
// shrink (turning bodies), jump, and change mesh.
TEST(MeshBvh, CachedQueryEqualsQueryOverMotions) {
    test::Rng rng(31);
    std::vector<Vec3> v1, v2;
    std::vector<Tri> t1, t2;
    flatGrid(40, Real(1.5), v1, t1);
    for (Vec3& p : v1) p.y = rng.uniform(-1, 1);  // hills: boxes meet several triangles
    const Shape terrain = Shape::mesh(v1, t1);
    const Shape soup = randomSoup(rng, 2000, v2, t2);
    std::size_t reused = 0, remade = 0, found = 0;
    for (int body = 0; body < 40; ++body) {
        detail::MeshCandidateCache near;
        Vec3 c = rng.inBox(Vec3{0, -2, 0}, Vec3{60, 2, 60});
        Vec3 h = rng.inBox(Vec3::splat(0.1f), Vec3::splat(2));
        const Real grow = rng.uniform(0, 1) * std::max(h.x, std::max(h.y, h.z));
        const Real speed = body % 4 == 0 ? Real(0.01) : body % 4 == 1 ? Real(0.1) : Real(0.5);
        for (int step = 0; step < 300; ++step) {
            c += rng.inBox(Vec3::splat(-speed), Vec3::splat(speed));
            h = max(Vec3::splat(0.05f), h + rng.inBox(Vec3::splat(-0.02f), Vec3::splat(0.02f)));
            if (step % 97 == 96) c = rng.inBox(Vec3{0, -2, 0}, Vec3{60, 2, 60});  // a jump (a teleport)
            const Shape& s = (step / 100) % 2 == 0 ? terrain : soup;  // the list of another mesh is never used
            const AABB box = AABB::fromCenterHalf(c, h);
            std::vector<std::uint32_t> expected, got;
            queryTriangles(s.mesh(), box, [&](std::uint32_t i) { expected.push_back(i); });
            const AABB listBox = near.box;
            const TriangleMesh* listMesh = near.mesh;
            queryTrianglesCached(s.mesh(), box, grow, near, [&](std::uint32_t i) { got.push_back(i); });
            ASSERT_EQ(got, expected) << "body " << body << " step " << step;
            if (near.mesh == listMesh && near.box == listBox) ++reused; else ++remade;
            found += got.size();
        }
    }
    // Both ways were taken many times, on boxes that met triangles.
    EXPECT_GT(reused, 1000u);
    EXPECT_GT(remade, 1000u);
    EXPECT_GT(found, 5000u);
    // A NaN box finds nothing either way, and leaves no list that a later box could take.
    detail::MeshCandidateCache near;
    const Real nan = std::numeric_limits<Real>::quiet_NaN();
    std::size_t calls = 0;
    queryTrianglesCached(terrain.mesh(), AABB{Vec3{nan, 0, 0}, Vec3{nan, 1, 1}}, 1, near, [&](std::uint32_t) { ++calls; });
    EXPECT_EQ(calls, 0u);
    const AABB box = AABB::fromCenterHalf(Vec3{30, 0, 30}, Vec3::splat(1));
    std::vector<std::uint32_t> expected, got;
    queryTriangles(terrain.mesh(), box, [&](std::uint32_t i) { expected.push_back(i); });
    queryTrianglesCached(terrain.mesh(), box, 1, near, [&](std::uint32_t i) { got.push_back(i); });
    EXPECT_FALSE(expected.empty());
    EXPECT_EQ(got, expected);
}

TEST(MeshBvh, RayCastEqualsBruteForce) {
    test::Rng rng(23);
    std::vector<Vec3> v;
    std::vector<Tri> t;
    const Shape s = randomSoup(rng, 2000, v, t);
    int hits = 0;
    for (int q = 0; q < 500; ++q) {
        const Vec3 p = rng.inBox(Vec3::splat(-15), Vec3::splat(15));
        Vec3 d = rng.inBox(Vec3::splat(-30), Vec3::splat(30));
        if (q % 10 == 0) d = Vec3{0, 0, d.z};  // axis-parallel rays exercise the slab special case
        const auto hit = rayCastMesh(s.mesh(), p, d, 1);
        Real best = 1;
        std::uint32_t bestTri = kNone;
        for (std::uint32_t i = 0; i < t.size(); ++i) {
            const auto h = rayTriangle(v[t[i][0]], v[t[i][1]], v[t[i][2]], p, d, best);
            if (h && (*h < best || bestTri == kNone)) { best = *h; bestTri = i; }
        }
        ASSERT_EQ(hit.has_value(), bestTri != kNone);
        if (!hit) continue;
        ++hits;
        EXPECT_EQ(hit->fraction, best);  // the same triangle test: bit-identical
        EXPECT_EQ(hit->triangle, bestTri);
        EXPECT_LE(dot(hit->normal, d), 0);
    }
    EXPECT_GT(hits, 50);
}

TEST(MeshBvh, ClosestPointEqualsBruteForce) {
    // Tolerance: 1e-5 of the soup's size (float rounding of the projections).
    test::Rng rng(24);
    std::vector<Vec3> v;
    std::vector<Tri> t;
    const Shape s = randomSoup(rng, 1000, v, t);
    for (int q = 0; q < 300; ++q) {
        const Vec3 p = rng.inBox(Vec3::splat(-14), Vec3::splat(14));
        const MeshClosestPoint c = closestPointOnMesh(s.mesh(), p);
        Real best = std::numeric_limits<Real>::max();
        for (const Tri& tri : t) best = std::min(best, length(p - test::closestOnTriangle(p, v[tri[0]], v[tri[1]], v[tri[2]])));
        EXPECT_NEAR(std::fabs(c.distance), best, 1e-4);
        EXPECT_NEAR(length(p - c.point), best, 1e-4);
    }
}

// Box3D's trees mesh at a small size: a wave grid, columns x rows cells of 1 m.
void waveGrid(int columns, int rows, std::vector<Vec3>& v, std::vector<Tri>& t) {
    const auto id = [rows](int i, int j) { return static_cast<std::uint32_t>(i * (rows + 1) + j); };
    for (int i = 0; i <= columns; ++i) {
        for (int j = 0; j <= rows; ++j) {
            v.push_back({Real(i), Real(0.4) * std::sin(Real(0.6) * Real(i)) * std::sin(Real(0.3) * Real(j)), Real(j)});
        }
    }
    for (int i = 0; i < columns; ++i) {
        for (int j = 0; j < rows; ++j) {
            t.push_back({id(i, j), id(i, j + 1), id(i + 1, j + 1)});
            t.push_back({id(i + 1, j + 1), id(i + 1, j), id(i, j)});
        }
    }
}

bool sameBits(Real a, Real b) { return std::memcmp(&a, &b, sizeof(Real)) == 0; }
bool sameBits(const Vec3& a, const Vec3& b) { return sameBits(a.x, b.x) && sameBits(a.y, b.y) && sameBits(a.z, b.z); }

// The build bins a node's triangles on the three axes in one pass over them;
// the reference makes a pass per axis. The same tree, bit for bit: every
// node's bounds, child or range, the triangle order and the depth. Meshes:
// random soups, a wave grid (Box3D's trees), a flat grid (no extent along y:
// that axis is skipped), and a soup of stacked copies (coincident centroids:
// the median fallback).
TEST(MeshBvh, AxesTogetherBinningBuildsTheAxisByAxisTreeBitForBit) {
    std::vector<std::pair<std::vector<Vec3>, std::vector<Tri>>> meshes;
    for (std::uint32_t seed = 31; seed < 35; ++seed) {
        test::Rng rng(seed);
        std::vector<Vec3> v;
        std::vector<Tri> t;
        randomSoup(rng, 500 + 1000 * int(seed - 31), v, t);
        meshes.emplace_back(v, t);
    }
    {
        std::vector<Vec3> v;
        std::vector<Tri> t;
        waveGrid(60, 80, v, t);
        meshes.emplace_back(v, t);
    }
    {
        std::vector<Vec3> v;
        std::vector<Tri> t;
        flatGrid(40, Real(0.5), v, t);
        meshes.emplace_back(v, t);
    }
    {
        test::Rng rng(36);
        std::vector<Vec3> v;
        std::vector<Tri> t;
        randomSoup(rng, 40, v, t);
        const std::vector<Tri> once = t;
        for (int copy = 0; copy < 30; ++copy) t.insert(t.end(), once.begin(), once.end());
        meshes.emplace_back(v, t);
    }
    for (std::size_t m = 0; m < meshes.size(); ++m) {
        const Shape s = Shape::mesh(meshes[m].first, meshes[m].second);
        const MeshBvh together = buildMeshBvh(s.mesh(), MeshBvhBinning::AxesTogether);
        const MeshBvh byAxis = buildMeshBvh(s.mesh(), MeshBvhBinning::AxisByAxis);
        ASSERT_EQ(together.nodes.size(), byAxis.nodes.size()) << "mesh " << m;
        for (std::size_t n = 0; n < together.nodes.size(); ++n) {
            const MeshBvhNode &a = together.nodes[n], &b = byAxis.nodes[n];
            ASSERT_TRUE(sameBits(a.bounds.min, b.bounds.min) && sameBits(a.bounds.max, b.bounds.max)) << "mesh " << m << " node " << n;
            ASSERT_EQ(a.index, b.index) << "mesh " << m << " node " << n;
            ASSERT_EQ(a.count, b.count) << "mesh " << m << " node " << n;
        }
        EXPECT_EQ(together.triangleOrder, byAxis.triangleOrder) << "mesh " << m;
        EXPECT_EQ(together.depth, byAxis.depth) << "mesh " << m;
        // And Shape::mesh's own tree is the default's.
        EXPECT_EQ(s.mesh().bvh->triangleOrder, together.triangleOrder) << "mesh " << m;
        EXPECT_EQ(s.mesh().bvh->nodes.size(), together.nodes.size()) << "mesh " << m;
    }
}

// A leaf's triangle boxes are stored in tree order (MeshBvh::slotBounds) for
// the queries' leaf test: each the triangle's own bounds, bit for bit.
TEST(MeshBvh, SlotBoundsAreTheTrianglesBoundsBitForBit) {
    test::Rng rng(37);
    std::vector<Vec3> v;
    std::vector<Tri> t;
    const Shape s = randomSoup(rng, 2000, v, t);
    const MeshBvh& bvh = *s.mesh().bvh;
    ASSERT_EQ(bvh.slotBounds.size(), bvh.triangleOrder.size());
    for (std::size_t i = 0; i < bvh.slotBounds.size(); ++i) {
        const AABB expected = triangleBounds(s.mesh(), bvh.triangleOrder[i]);
        ASSERT_TRUE(sameBits(bvh.slotBounds[i].min, expected.min) && sameBits(bvh.slotBounds[i].max, expected.max)) << "slot " << i;
    }
}

// Adjacency against its definition, an edge map: two triangles are
// neighbours across an edge when exactly they two use it, with opposite
// windings; an edge of one triangle, or of three or more, or of two with the
// same winding, is a boundary. Random meshes over few vertices make every
// case; then the grids and the closed box.
TEST(Mesh, AdjacencyIsTheEdgeMapReference) {
    const auto reference = [](const std::vector<Tri>& t) {
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::pair<std::uint32_t, std::uint32_t>>> users;
        for (std::uint32_t i = 0; i < t.size(); ++i) {
            for (std::uint32_t k = 0; k < 3; ++k) {
                const std::uint32_t a = t[i][k], b = t[i][(k + 1) % 3];
                users[{std::min(a, b), std::max(a, b)}].push_back({i, k});
            }
        }
        std::vector<std::array<std::uint32_t, 3>> adjacency(t.size(), {kNone, kNone, kNone});
        for (const auto& [edge, list] : users) {
            if (list.size() != 2) continue;
            const auto [t0, k0] = list[0];
            const auto [t1, k1] = list[1];
            if ((t[t0][k0] == edge.first) == (t[t1][k1] == edge.first)) continue;  // the same winding
            adjacency[t0][k0] = t1;
            adjacency[t1][k1] = t0;
        }
        return adjacency;
    };
    int neighbours = 0, sameWinding = 0, crowded = 0;
    for (std::uint32_t seed = 41; seed < 61; ++seed) {
        test::Rng rng(seed);
        std::vector<Vec3> v;
        for (int i = 0; i < 12 + int(seed % 7) * 5; ++i) v.push_back(rng.inBox(Vec3::splat(-1), Vec3::splat(1)));
        std::vector<Tri> t;
        while (t.size() < 150) {
            const auto pick = [&] { return static_cast<std::uint32_t>(static_cast<std::size_t>(rng.uniform() * double(v.size())) % v.size()); };
            const Tri tri{pick(), pick(), pick()};
            if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0]) continue;
            const Vec3 e1 = v[tri[1]] - v[tri[0]], e2 = v[tri[2]] - v[tri[0]], e3 = v[tri[2]] - v[tri[1]];
            const Real longest2 = std::max({lengthSquared(e1), lengthSquared(e2), lengthSquared(e3)});
            if (!(length(cross(e1, e2)) > Real(1e-2) * longest2)) continue;  // far from Shape::mesh's degenerate limit
            t.push_back(tri);
        }
        const Shape s = Shape::mesh(v, t);
        const auto expected = reference(t);
        ASSERT_EQ(s.mesh().adjacency.size(), expected.size());
        for (std::size_t i = 0; i < t.size(); ++i) {
            for (std::size_t k = 0; k < 3; ++k) {
                ASSERT_EQ(s.mesh().adjacency[i][k], expected[i][k]) << "seed " << seed << " triangle " << i << " edge " << k;
                neighbours += expected[i][k] != kNone;
            }
        }
        std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<bool>> forward;
        for (const Tri& tri : t) {
            for (std::uint32_t k = 0; k < 3; ++k) {
                const std::uint32_t a = tri[k], b = tri[(k + 1) % 3];
                forward[{std::min(a, b), std::max(a, b)}].push_back(a < b);
            }
        }
        for (const auto& [edge, list] : forward) {
            crowded += list.size() > 2;
            sameWinding += list.size() == 2 && list[0] == list[1];
        }
    }
    // The random meshes made every case.
    EXPECT_GT(neighbours, 100);
    EXPECT_GT(sameWinding, 10);
    EXPECT_GT(crowded, 10);
    std::vector<std::pair<std::vector<Vec3>, std::vector<Tri>>> meshes(3);
    flatGrid(7, Real(0.5), meshes[0].first, meshes[0].second);
    waveGrid(9, 13, meshes[1].first, meshes[1].second);
    boxMesh({1, 2, 3}, meshes[2].first, meshes[2].second);
    for (const auto& [v, t] : meshes) EXPECT_EQ(Shape::mesh(v, t).mesh().adjacency, reference(t));
}

}  // namespace
}  // namespace fulcrum
