#pragma once
// A box or convex hull against one triangle by the separating-axis test
// (collide_triangle.cpp): what collideTriangleWithConvex (collide_mesh.cpp)
// runs for boxes and hulls instead of GJK, EPA and face clipping.
#include <array>
#include <cstdint>
#include <vector>

#include "collision/manifold.hpp"
#include "collision/support.hpp"

namespace fulcrum::detail {

// A box or hull in its own frame as the triangle test reads it: vertices,
// faces (outward normal, plane offset) and edges with their two faces. A
// hull's edge-face adjacency is not part of ConvexHull, so it is derived once
// per mesh pair (a sort of the faces' edges) and kept in `edgeScratch`; a
// box's comes from a fixed table.
class TrianglePolytope {
public:
    TrianglePolytope() = default;
    // A box's arrays live in the object itself.
    TrianglePolytope(const TrianglePolytope&) = delete;
    TrianglePolytope& operator=(const TrianglePolytope&) = delete;

    // False when b is neither a box nor a hull (or is rounded), or a hull
    // whose faces do not close up (each edge in exactly two faces, once each
    // way round): the caller keeps the general path for it.
    bool prepare(const ConvexShape& b, std::vector<PolytopeEdge>& edgeScratch);
    // The same, a hull's edge table taken from `cache` when it holds one
    // derived from the same faces (else derived there): the same polytope.
    bool prepare(const ConvexShape& b, PolytopeEdgeCache& cache);

    const ConvexShape* shape = nullptr;
    const Vec3* vertices = nullptr;
    std::uint32_t vertexCount = 0;
    const HullFace* faces = nullptr;
    std::uint32_t faceCount = 0;
    const PolytopeEdge* edges = nullptr;
    std::uint32_t edgeCount = 0;

private:
    std::array<Vec3, 8> boxVertices_;
    std::array<HullFace, 6> boxFaces_;
};

// The contact of world-space triangle w (counter-clockwise front, unit normal
// faceN) with the prepared polytope, as collideConvexConvex(triangle, b)
// gives it: normal from the triangle to b, points with depth and feature ids,
// at most 4. The axes are the triangle's normal (both sides), the polytope's
// face normals and the cross products of edges whose arcs cross on the Gauss
// map. A face axis gives the reference face's clipped manifold
// (buildFaceManifold), an edge axis the closest points of the two edges.
// False when the two are farther apart than `margin` or no point is within it.
bool collideTrianglePolytope(const Vec3 w[3], const Vec3& faceN, const TrianglePolytope& p, Real margin, Manifold& m);

}  // namespace fulcrum::detail
