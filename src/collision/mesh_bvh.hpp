#pragma once
// The static bounding volume hierarchy of a triangle mesh, and the queries the
// narrow phase, ray casts and point queries run against it.
//
// Layout: one flat array of 32-byte nodes in depth-first order. An internal
// node's left child is the next node and its right child is stored; a leaf
// owns a contiguous range of `triangleOrder` (at most kMaxLeafTriangles). The
// build is binned SAH (Wald 2007, "On fast Construction of SAH-based Bounding
// Volume Hierarchies") with kSahBins bins on each of the three axes.
//
// Alongside the tree the BVH keeps per-triangle unit normals and per-vertex
// angle-weighted pseudo-normals (Baerentzen & Aanaes 2005, "Signed distance
// computation using the angle weighted pseudonormal"), which give the sign of
// the distance to a closed mesh exactly even when the closest point is on an
// edge or a vertex.
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <type_traits>
#include <vector>

#include "collision/manifold.hpp"
#include "fulcrum/shape.hpp"

namespace fulcrum {

struct MeshBvhNode {
    AABB bounds;
    std::uint32_t index = 0;  // leaf: first slot in MeshBvh::triangleOrder; internal: the right child
    std::uint32_t count = 0;  // leaf: number of triangles (> 0); internal: 0
    constexpr bool isLeaf() const { return count > 0; }
};

struct MeshBvh {
    static constexpr std::uint32_t kSahBins = 12;
    static constexpr std::uint32_t kMaxLeafTriangles = 4;
    // Traversal stacks hold at most the tree depth; the build switches to
    // median splits past kSahDepthLimit, so the depth stays below
    // kSahDepthLimit + 32 for any mesh that fits 32-bit indices.
    static constexpr std::uint32_t kSahDepthLimit = 40;
    static constexpr std::uint32_t kStackSize = 80;

    std::vector<MeshBvhNode> nodes;
    std::vector<std::uint32_t> triangleOrder;  // triangle indices grouped by leaf
    // triangleBounds of triangleOrder[i], at i: a query's leaf test reads its
    // triangles' boxes in a row where it gathered three vertices through the
    // triangle's indices (cache misses that took a fifth of trees100's step;
    // 24 bytes a triangle).
    std::vector<AABB> slotBounds;
    std::vector<Vec3> triangleNormals;         // unit, on the counter-clockwise (front) side
    std::vector<Vec3> vertexNormals;           // angle-weighted pseudo-normals, unit (zero for unused vertices)
    std::uint32_t depth = 0;                   // levels below the root
    Real rayEpsilon = 0;                       // node boxes are widened by this for ray traversal
};

// True when the edge edgeStart -> edgeEnd of a triangle with unit normal
// `faceNormal` is convex (or a knife edge) given the neighbour triangle's far
// vertex; flat (within 1e-3 rad) and concave edges are internal. Meshes and
// heightfields set their convex-edge flags with it (mesh.cpp).
bool isConvexEdge(const Vec3& faceNormal, const Vec3& edgeStart, const Vec3& edgeEnd, const Vec3& farVertex);

// How the SAH build bins a node's triangles: all three axes in one pass over
// them (the default), or a pass per axis (the reference the test compares it
// with: the same tree, bit for bit).
enum class MeshBvhBinning { AxesTogether, AxisByAxis };

// Builds the BVH and the normals of a mesh whose vertices, triangles and
// adjacency are already set and validated.
MeshBvh buildMeshBvh(const TriangleMesh& mesh, MeshBvhBinning binning = MeshBvhBinning::AxesTogether);

inline AABB triangleBounds(const TriangleMesh& mesh, std::uint32_t t) {
    const auto& tri = mesh.triangles[t];
    AABB b;
    b.grow(mesh.vertices[tri[0]]);
    b.grow(mesh.vertices[tri[1]]);
    b.grow(mesh.vertices[tri[2]]);
    return b;
}

// Calls callback(triangleIndex) for every triangle whose bounding box overlaps
// `box` (mesh-local coordinates), in tree order. The callback may return void,
// or bool where false stops the query.
template <class F>
void queryTriangles(const TriangleMesh& mesh, const AABB& box, F&& callback);

// queryTriangles with each triangle's bounds: callback(triangleIndex, bounds).
template <class F>
void queryTriangleSlots(const TriangleMesh& mesh, const AABB& box, F&& callback) {
    const MeshBvh& bvh = *mesh.bvh;
    const MeshBvhNode* nodes = bvh.nodes.data();
    if (bvh.nodes.empty() || !overlaps(nodes[0].bounds, box)) return;
    // Depth first, left child first, as a stack of every node would visit
    // them; a child is tested before it is pushed, and the overlapping left
    // one is descended into directly (a small body's query on a large mesh
    // goes down one path, where pushing both children popped and rejected
    // one at every level).
    std::array<std::uint32_t, MeshBvh::kStackSize> stack;
    std::uint32_t top = 0;
    std::uint32_t current = 0;
    for (;;) {
        const MeshBvhNode& node = nodes[current];
        if (!node.isLeaf()) {
            const std::uint32_t left = current + 1, right = node.index;
            const bool inLeft = overlaps(nodes[left].bounds, box), inRight = overlaps(nodes[right].bounds, box);
            if (inLeft) {
                if (inRight) stack[top++] = right;
                current = left;
                continue;
            }
            if (inRight) {
                current = right;
                continue;
            }
        } else {
            for (std::uint32_t i = node.index; i < node.index + node.count; ++i) {
                const AABB& bounds = bvh.slotBounds[i];
                if (!overlaps(bounds, box)) continue;
                if constexpr (std::is_same_v<std::invoke_result_t<F&, std::uint32_t, const AABB&>, bool>) {
                    if (!callback(bvh.triangleOrder[i], bounds)) return;
                } else {
                    callback(bvh.triangleOrder[i], bounds);
                }
            }
        }
        if (top == 0) return;
        current = stack[--top];
    }
}

template <class F>
void queryTriangles(const TriangleMesh& mesh, const AABB& box, F&& callback) {
    queryTriangleSlots(mesh, box, [&callback](std::uint32_t t, const AABB&) { return callback(t); });
}

// queryTriangles through a contact's candidate list (MeshCandidateCache,
// collision/manifold.hpp): the same triangles in the same order. When `box`
// is not inside the list's box, or the list is of another mesh or none, the
// list is made again from a query of `box` grown by `grow` on every side.
// The answer is exact: a triangle whose bounds overlap `box` overlaps every
// box that holds `box`, so it is on the list; the list is in tree order, as
// the query visits; and the filter is the query's own leaf test. (A NaN box
// is never inside the list's box: the query runs, and finds nothing, as the
// plain query does.)
template <class F>
void queryTrianglesCached(const TriangleMesh& mesh, const AABB& box, Real grow, detail::MeshCandidateCache& near,
                          F&& callback) {
    if (near.mesh != &mesh || !near.box.contains(box)) {
        near.mesh = &mesh;
        near.box = box.fattened(grow);
        near.triangles.clear();
        queryTriangleSlots(mesh, near.box, [&](std::uint32_t t, const AABB& bounds) { near.triangles.push_back({bounds, t}); });
    }
    for (const detail::MeshCandidateCache::Candidate& c : near.triangles) {
        if (overlaps(c.bounds, box)) callback(c.triangle);
    }
}

// Ray p + t d against one triangle, both sides (Moeller & Trumbore 1997,
// "Fast, minimum storage ray-triangle intersection"). Returns t in
// [0, maxFraction] or nothing.
std::optional<Real> rayTriangle(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p, const Vec3& d,
                                Real maxFraction);

// Entry fraction in [0, maxFraction] of the ray p + t d into box b, or a
// negative value for a miss (slab test with the reciprocal direction invD; an
// axis `parallel` to the box compares the origin).
Real rayBox(const AABB& b, const Vec3& p, const Vec3& invD, const std::array<bool, 3>& parallel, Real maxFraction);

struct MeshRayHit {
    Real fraction = 0;
    std::uint32_t triangle = 0;
    Vec3 normal;  // unit, facing against the ray (front normal, or its reverse when the back side was hit)
};

// Closest hit of the ray p + t d, t in [0, maxFraction], with the mesh (mesh-local coordinates).
std::optional<MeshRayHit> rayCastMesh(const TriangleMesh& mesh, const Vec3& p, const Vec3& d, Real maxFraction);

// Which part of a triangle a closest point lies on.
enum class TriangleFeature : std::uint8_t { Face, Vertex0, Vertex1, Vertex2, Edge01, Edge12, Edge20 };

// Closest point on triangle abc to p, and its feature (Ericson, "Real-Time
// Collision Detection" 5.1.5, Voronoi regions).
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, TriangleFeature& feature);

struct MeshClosestPoint {
    Vec3 point;
    Real distance = 0;  // signed by the pseudo-normal: negative behind the surface
    Vec3 normal;        // unit, outward at `point`
    std::uint32_t triangle = 0;
};

// The nearest point of the mesh to p (mesh-local coordinates).
MeshClosestPoint closestPointOnMesh(const TriangleMesh& mesh, const Vec3& p);

}  // namespace fulcrum
