#pragma once
// Convex shapes against static triangle meshes, with internal-edge handling.
#include "collision/manifold.hpp"
#include "collision/support.hpp"

namespace fulcrum::detail {

// Appends the manifolds of convex `b` (world space, world bounds `bBounds`)
// against `mesh` placed at `meshXf`. The mesh is shape A: normals point from
// the mesh to b. childA of each manifold is the triangle of its deepest point.
void collideMeshConvex(const TriangleMesh& mesh, const Transform& meshXf, const ConvexShape& b, const AABB& bBounds,
                       Real margin, ManifoldBuffer& out);

// Calls fn(triangleIndex) for each triangle whose bounds overlap `localBox`
// (mesh-local coordinates).
template <class Fn>
void forEachTriangleOverlapping(const TriangleMesh& mesh, const AABB& localBox, Fn&& fn) {
    // Brute force over the triangles until the mesh BVH (mesh_bvh.hpp, branch
    // `shapes`) lands; then this becomes MeshBvh::queryTriangles.
    const std::size_t n = mesh.triangles.size();
    for (std::size_t t = 0; t < n; ++t) {
        const auto& tri = mesh.triangles[t];
        const Vec3 &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &c = mesh.vertices[tri[2]];
        const AABB tb{min(a, min(b, c)), max(a, max(b, c))};
        if (overlaps(tb, localBox)) fn(static_cast<std::uint32_t>(t));
    }
}

}  // namespace fulcrum::detail
