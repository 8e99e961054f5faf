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
    // The shape's rotation as a matrix (columns: its axes in the world),
    // taken once per prepare: the triangle test moves every triangle into the
    // shape's frame and its contact back by it (cheaper than the quaternion
    // per point; docs/narrow-phase.md, "Box and hull against a triangle").
    Mat3 rotation;
    // The same matrix and the shape's position as toPieceFrame's four SSE
    // lanes take them (the float build with SSE2; unset otherwise): rows 0-8
    // each entry of the rotation (c0.x, c0.y, c0.z, c1.x, ..., c2.z) in all
    // four lanes, rows 9-11 a coordinate of the position in the three point
    // lanes and zero in the normal's. Set once per prepare, where each
    // triangle broadcast them again (about 28 of toPieceFrame's 106
    // instructions; branch trees12).
    alignas(16) float frameLanes[12][4];
    const Vec3* vertices = nullptr;
    std::uint32_t vertexCount = 0;
    const HullFace* faces = nullptr;
    std::uint32_t faceCount = 0;
    const PolytopeEdge* edges = nullptr;
    std::uint32_t edgeCount = 0;

    // The edges' two face normals and their cross product in lanes of four
    // edges (PolytopeEdgeLanes; collideTrianglePolytope's Gauss-map filter),
    // edgeLaneGroups of them; none (0) in the double build, for a polytope
    // prepared without a cache, or for one of more than kMaxLaneEdges edges:
    // the scalar loop.
    static constexpr std::uint32_t kMaxLaneEdges = 64;
    const PolytopeEdgeLanes* edgeLanes = nullptr;
    std::uint32_t edgeLaneGroups = 0;
    // With the lanes: the pairs the signs pass take edgePairAxis's further
    // tests and their axes in lanes too (true), or one pair at a time by
    // edgePairAxis (false: the path before, the same bits, kept as the
    // lanes' reference in tests/collision/triangle_sat_test.cpp).
    bool edgePairsInLanes = true;

private:
    // shape, rotation and frameLanes for b.
    void setFrame(const ConvexShape& b);

    std::array<Vec3, 8> boxVertices_;
    std::array<HullFace, 6> boxFaces_;
};

// The triangle's vertices w and unit normal faceN in the frame of the
// prepared polytope's shape: inverseTransformPoint(xf, w[i]) and
// inverseRotate(xf.q, faceN) to rounding, by p.rotation (four SSE lanes in
// the float build).
void toPieceFrame(const TrianglePolytope& p, const Vec3 w[3], const Vec3& faceN, Vec3 v[3], Vec3& n);

// The prepared polytope's supporting face along l, a direction of its own
// frame, in that frame: the face supportingFace(shape, rotate(xf.q, l),
// face, top) gives in the world, not moved there (the same id and points in
// the same order). `top` is a hull's vertex furthest along l (support's
// answer, or the first of the furthest); a box ignores it.
void pieceSupportingFace(const TrianglePolytope& p, const Vec3& l, std::uint32_t top, SupportFace& out);

// The contact of world-space triangle w (counter-clockwise front, unit normal
// faceN, computed as normalize(cross(w[1] - w[0], w[2] - w[0])), as
// collideTriangleWithConvex does: the triangle's supporting face takes it
// as its own) with the prepared polytope, as collideConvexConvex(triangle, b)
// gives it: normal from the triangle to b, points with depth and feature ids,
// at most 4. The axes are the triangle's normal (both sides), the polytope's
// face normals and the cross products of edges whose arcs cross on the Gauss
// map. A face axis gives the reference face's clipped manifold
// (buildFaceManifold), an edge axis the closest points of the two edges.
// False when the two are farther apart than `margin` or no point is within it.
//
// `axisHint`, when given, is the pair's separating-axis hint
// (SeparatingAxisCache, manifold.hpp): tried before the other axes, and left
// naming the polytope face or edge pair that rejected the pair this time, or
// 0 (none: the triangle's own normal, tested first anyway, or no rejection).
// The answer is the same with or without it.
//
// `cached`, when given, is the pair's entry of the contact's triangle axis
// cache (TriangleAxisCache, manifold.hpp): its axis (0: none) is taken alone
// while its separation is within 5 mm of the entry's and it gives a point
// (the entry then unchanged); otherwise the full test runs and the entry is
// left naming the axis of its contact and that axis's separation, or 0 when
// there is none (or the contact's axis is the triangle's back face). Unlike
// the hint, this changes results: the kept axis is not proven the best.
bool collideTrianglePolytope(const Vec3 w[3], const Vec3& faceN, const TrianglePolytope& p, Real margin, Manifold& m,
                             std::uint32_t* axisHint = nullptr, TriangleAxisEntry* cached = nullptr);

// The hint of a polytope face f or of the polytope's edge e against the
// triangle's edge j (from vertex j to j + 1), as collideTrianglePolytope
// stores them; 0 is no hint.
constexpr std::uint32_t kFaceAxisHint = 1u << 30;
constexpr std::uint32_t kEdgeAxisHint = 2u << 30;
constexpr std::uint32_t kAxisHintIndex = (1u << 30) - 1;
// The triangle axis cache's code of the triangle's own (front) normal.
constexpr std::uint32_t kTriangleFaceAxis = 3u << 30;

// The contact of the triangle's face (normal faceN, the triangle as
// collideTrianglePolytope takes it) with the prepared polytope, whatever axis
// would separate them best: the polytope's face at its lowest vertex along
// faceN clipped against the triangle in the polytope's frame, or the lowest
// vertex itself when no clipped point lies within the margin (the mesh
// path's rebuild of a contact the internal-edge rule refused: what
// buildFaceManifold(makeTriangle(w), b, faceN, ...) from b's support along
// -faceN gives, built as the triangle test builds its face contacts). False
// when the polytope lies beyond the margin above the triangle's plane.
bool collideTrianglePolytopeAlongFace(const Vec3 w[3], const Vec3& faceN, const TrianglePolytope& p, Real margin, Manifold& m);

}  // namespace fulcrum::detail
