#pragma once
// Convex shapes against static triangle meshes, with internal-edge handling.
#include "collision/manifold.hpp"
#include "collision/mesh_bvh.hpp"
#include "collision/support.hpp"

namespace fulcrum::detail {

// Appends the manifolds of convex `b` (world space, world bounds `bBounds`)
// against `mesh` placed at `meshXf`. The mesh is shape A: normals point from
// the mesh to b. childA of each manifold is the triangle of its deepest point.
void collideMeshConvex(const TriangleMesh& mesh, const Transform& meshXf, const ConvexShape& b, const AABB& bBounds,
                       Real margin, ManifoldBuffer& out);

// Convex b against a heightfield placed at `xf`, the same way
// (collide_heightfield.cpp); childA of each manifold is its triangle.
void collideHeightFieldConvex(const HeightField& hf, const Transform& xf, const ConvexShape& b, const AABB& bBounds,
                              Real margin, ManifoldBuffer& out);

// The two halves every triangle surface (meshes, heightfields) shares.
// collideTriangleWithConvex appends the contacts of world-space triangle w
// (counter-clockwise front, index t, convex-edge flags `convexMask` as
// TriangleMesh::convexEdgeMask) with b to `scratch`, internal edges resolved;
// false when they do not touch. groupTriangleContacts then turns the
// candidates into manifolds, one per normal direction, at most 4 points each
// (it uses up `scratch`: what is left there afterwards means nothing);
// `flatFaces` (b is a box or hull) also lets a group keep its speculative
// points where they widen the manifold (collide_mesh.cpp, kTouchingPreference).
// `polytope`, when given, is b prepared for the separating-axis test
// (collide_triangle.hpp: boxes and hulls); without it the triangle runs the
// general convex path (GJK, EPA, face clipping), as cylinders always do
// (spheres and capsules: their own closest points, collide_pairs.hpp).
class TrianglePolytope;
// `axisHint` (with `polytope` only) is the pair's separating-axis hint for
// collideTrianglePolytope (collide_triangle.hpp); `bCentre`, when given, is
// b.center(), computed once for all of a shape's triangles; `cachedAxis`
// (with `polytope` only) the pair's triangle axis cache entry
// (collideTrianglePolytope).
bool collideTriangleWithConvex(const Vec3 w[3], std::uint8_t convexMask, std::uint32_t t, const ConvexShape& b, Real margin,
                               std::vector<MeshContactCandidate>& scratch, const TrianglePolytope* polytope,
                               std::uint32_t* axisHint = nullptr, const Vec3* bCentre = nullptr,
                               TriangleAxisEntry* cachedAxis = nullptr);
void groupTriangleContacts(std::vector<MeshContactCandidate>& scratch, Real margin, ManifoldBuffer& out, bool flatFaces = false);
// True when p, projected along the triangle's normal, falls on triangle w
// (within 1e-3 of its edges, in barycentric terms).
bool overTriangle(const Vec3 w[3], const Vec3& p);

// Calls fn(triangleIndex) for each triangle whose bounds overlap `localBox`
// (mesh-local coordinates).
template <class Fn>
void forEachTriangleOverlapping(const TriangleMesh& mesh, const AABB& localBox, Fn&& fn) {
    if (mesh.bvh) {
        queryTriangles(mesh, localBox, fn);
        return;
    }
    // A mesh assembled by hand without its BVH (internal tests): brute force.
    const std::size_t n = mesh.triangles.size();
    for (std::size_t t = 0; t < n; ++t) {
        if (overlaps(triangleBounds(mesh, static_cast<std::uint32_t>(t)), localBox)) fn(static_cast<std::uint32_t>(t));
    }
}

}  // namespace fulcrum::detail
