#pragma once
// Support mappings of the convex shapes, in world space, for GJK, EPA, shape
// casts and the face-clipping manifold builder.
//
// A convex shape is split into a *core* and a *radius* (van den Bergen's
// "core shapes"): a sphere is a point core with radius r, a capsule a segment
// core with radius r; a rounded box, hull or cylinder its core with its convex
// radius; plain boxes, hulls, cylinders and triangles have radius 0.
// GJK runs on the cores, which is exact and fast for the rounded shapes and
// keeps GJK away from the badly conditioned curved surfaces; the radius is
// added back afterwards.
#include <cstdint>

#include "fulcrum/shape.hpp"

namespace fulcrum::detail {

enum class ConvexKind : std::uint8_t { Point, Segment, Box, Hull, Cylinder, Triangle };

struct ConvexShape {
    ConvexKind kind = ConvexKind::Point;
    Transform xf;                  // shape frame -> world (triangles: identity, vertices already in world)
    Vec3 halfExtents;              // box
    Real halfHeight = 0;           // segment (capsule) and cylinder, along local y
    Real cylinderRadius = 0;       // cylinder
    Real radius = 0;               // rounding radius added to the core (sphere, capsule)
    const ConvexHull* hull = nullptr;
    Vec3 triangle[3];              // triangle vertices, world space

    // Support point of the core in world direction `d` (need not be unit).
    Vec3 coreSupport(const Vec3& d) const;
    // Support point of the full (rounded) shape in world direction `d`.
    Vec3 support(const Vec3& d) const;
    // support(d), bit for bit, and for a hull the index of the vertex it
    // found (kNoVertex for the other kinds): supportingFace(d) of a hull
    // starts from the same vertex, so a caller holding it skips one search.
    Vec3 support(const Vec3& d, std::uint32_t& hullVertex) const;
    // The full shape's extent along world direction `d` (need not be unit):
    // lo = min and hi = max of dot(d, p) over its points; for a hull one pass
    // over the vertices instead of two supports.
    void extent(const Vec3& d, Real& lo, Real& hi) const;
    // A point inside the core (for EPA/GJK seeds and triangle orientation).
    Vec3 center() const;
    // Largest distance from the shape's origin to any point of the full shape (for TOI bounds).
    Real boundingRadius() const;
};

// Fills the hull's derived tables (vertexFaceStart, vertexFaces, vertexRows)
// from its vertices and faces.
void deriveHullTables(ConvexHull& hull);

// support_avx2.cpp: whether it was compiled with AVX2, and its search: the
// first index of the largest (x[i] dx + y[i] dy) + z[i] dz over n >= 8
// vertices (rows x, y, z of n floats each), or n when a dot is NaN.
bool hullSupportAvx2Compiled();
std::uint32_t hullSupportIndexAvx2(const float* x, const float* y, const float* z, std::uint32_t n, const Vec3& d);

// The index of the hull vertex farthest along `d` (hull frame): the first of
// the largest dot(vertex, d), exactly as a scan in vertex order finds it.
std::uint32_t hullSupportIndex(const ConvexHull& hull, const Vec3& d);

// The face of `hull` most aligned with `d` (hull frame) among the faces at
// vertex `top`: the first of the largest dot(normal, d) in face order, from
// the adjacency tables deriveHullTables fills (a scan of every face when they
// are absent). A NaN dot passes every face at the vertex, so the last stays.
std::uint32_t hullFaceAtVertex(const ConvexHull& hull, std::uint32_t top, const Vec3& d);

// The four corners of a box's face (half extents `e`, face along axis `axis`
// with sign `sign`, +-1) in the box's frame, counter-clockwise seen from
// outside.
void boxFaceCorners(const Vec3& e, int axis, Real sign, Vec3 corners[4]);

// The convex shape of `shape` placed at `xf`; `shape` must not be a plane, mesh or compound.
ConvexShape makeConvex(const Shape& shape, const Transform& xf);
// The same without a rounded shape's convex radius (box, cylinder, hull): the
// core the narrow phase collides (a sphere's or capsule's radius stays).
ConvexShape makeConvexCore(const Shape& shape, const Transform& xf);
ConvexShape makeTriangle(const Vec3& a, const Vec3& b, const Vec3& c);

// The supporting feature of the full shape in world direction `n` (unit): the
// face of a box or hull most aligned with n, a cylinder cap (as a polygon of
// kCylinderCapPoints rim points) when n is near its axis or else the side line,
// a capsule's two end points when n is near perpendicular to its axis, or the
// single support point. Polygons wind counter-clockwise seen from outside.
// A rounded box, hull or cylinder's feature is its core's (the radius is not
// added): the narrow phase hands only cores (makeConvexCore) to it.
// `id` numbers the feature (face index) for feature ids.
inline constexpr std::uint32_t kMaxFacePoints = 32;
// Four rim points: the cap is a square inscribed in the rim, aligned with the
// cylinder's local x and z axes. Tried 8 (an octagon): the reduction to 4
// points then picks a different half of the rim whenever a small tilt moves
// the deepest point, so the feature ids (and warm starting) flicker for a
// cylinder resting on its cap; 4 points are kept as they are. The cost is a
// support polygon of 64% of the cap's area.
inline constexpr std::uint32_t kCylinderCapPoints = 4;
struct SupportFace {
    // Only the first `count` points are ever written or read. Left
    // uninitialised (a Vec3 zeroes itself): a hull pair's narrow phase builds
    // up to four faces, and zeroing their 384 bytes each cost more than
    // filling in the few points used (docs/benchmarks.md, "Hull pairs' scratch").
    union {
        Vec3 points[kMaxFacePoints];
    };
    SupportFace() {}  // NOLINT: the points stay uninitialised on purpose
    std::uint32_t count = 0;
    std::uint32_t id = 0;
    Vec3 normal;  // outward normal of a polygon face (count >= 3)
};
// No hull vertex known (supportingFace searches for it).
inline constexpr std::uint32_t kNoVertex = 0xFFFFFFFFu;
// `hullVertex`: for a hull, the index support(n, hullVertex) gave for this
// very n (the same answer as the search, without it), or kNoVertex.
void supportingFace(const ConvexShape& s, const Vec3& n, SupportFace& out, std::uint32_t hullVertex = kNoVertex);

}  // namespace fulcrum::detail
