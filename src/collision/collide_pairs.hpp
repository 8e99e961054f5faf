#pragma once
// Internal interface of the narrow phase: one function per convex shape pair
// family, all in world space, filling one manifold (normal A->B, points with
// position and depth and feature id; anchors are filled by the dispatcher).
// Each returns true when it produced at least one point within `margin`.
#include "collision/manifold.hpp"
#include "collision/support.hpp"

namespace fulcrum::detail {

using ConvexPairFn = bool (*)(const ConvexShape& a, const ConvexShape& b, Real margin, Manifold& m);

// collide_sphere.cpp
bool collideSphereSphere(const ConvexShape& a, const ConvexShape& b, Real margin, Manifold& m);
// The same for spheres given by centre and radius (the dispatcher's fast path).
bool collideSphereCentres(const Vec3& ca, Real ra, const Vec3& cb, Real rb, Real margin, Manifold& m);
bool collideSphereCapsule(const ConvexShape& a, const ConvexShape& b, Real margin, Manifold& m);
bool collideSphereBox(const ConvexShape& a, const ConvexShape& b, Real margin, Manifold& m);
bool collideTriangleSphere(const ConvexShape& tri, const ConvexShape& b, Real margin, Manifold& m);
// collide_capsule.cpp
bool collideCapsuleCapsule(const ConvexShape& a, const ConvexShape& b, Real margin, Manifold& m);
// A triangle (makeTriangle) against a capsule: the general path's contact
// (collideConvexConvex) with the cores' closest points found exactly instead
// of by GJK; cores within 0.1 mm go through the general path (EPA).
bool collideTriangleCapsule(const ConvexShape& tri, const ConvexShape& b, Real margin, Manifold& m);
// Closest points of segment p0-p1 and triangle tri; false (and no points)
// when the segment touches or crosses the triangle.
bool closestSegmentTriangle(const Vec3& p0, const Vec3& p1, const Vec3 tri[3], Vec3& onSegment, Vec3& onTriangle);
// collide_box.cpp: SAT over the 15 axes with face clipping and edge-edge.
bool collideBoxBox(const ConvexShape& a, const ConvexShape& b, Real margin, Manifold& m);
// collide_convex.cpp: GJK (+ EPA when the cores overlap) and face clipping;
// every pair without a dedicated path (capsule-box, hulls, cylinders, triangles).
bool collideConvexConvex(const ConvexShape& a, const ConvexShape& b, Real margin, Manifold& m);
// The same with the pair's GJK warm start (collision/manifold.hpp,
// GjkWarmStart; null: none), read and rewritten when both are hulls or boxes.
bool collideConvexConvex(const ConvexShape& a, const ConvexShape& b, Real margin, Manifold& m, GjkWarmStart* warm);

// The face-clipping manifold builder: given the contact normal n (A->B), clip
// the supporting features of A (along n) and B (along -n) against each other.
// `fallback*` is the single contact (surface points on A and B) used when no
// face pair is usable. forceReference: 0 = choose, 1 = A's face, 2 = B's face.
// fallbackIsDeepest: the fallback points are the shapes' deepest (or closest)
// points along n (GJK/EPA's); they join the clipped points when clipping found
// none as deep. knownFaceA / knownFaceB: supportingFace(a, n) and
// supportingFace(b, -n) when the caller already has them (else found here).
void buildFaceManifold(const ConvexShape& a, const ConvexShape& b, const Vec3& n, const Vec3& fallbackA,
                       const Vec3& fallbackB, Real margin, Manifold& m, int forceReference = 0,
                       bool fallbackIsDeepest = false, const SupportFace* knownFaceA = nullptr,
                       const SupportFace* knownFaceB = nullptr);
// The same with the fallback points a.support(n) and b.support(-n), found
// only when clipping leaves no point (box-box: the supports cost 6 % of a
// face contact, and a face axis's clipping nearly always keeps a point).
void buildFaceManifold(const ConvexShape& a, const ConvexShape& b, const Vec3& n, Real margin, Manifold& m,
                       int forceReference);

// Closest points of segments p1-q1 and p2-q2 (Ericson RTCD 5.1.9); returns
// the parameters s, t in [0, 1].
void closestSegmentSegment(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2, Real& s, Real& t);

// Adds one point (surface points pa on A, pb on B) to m if depth >= -margin.
inline void addContact(Manifold& m, const Vec3& pa, const Vec3& pb, Real depth, std::uint32_t id, Real margin) {
    if (depth < -margin || m.pointCount == Manifold::kMaxPoints) return;
    ContactPoint& c = m.points[m.pointCount++];
    c.position = (pa + pb) * Real(0.5);
    c.depth = depth;
    c.featureId = id;
}

// Reverses a manifold computed for (B, A) into one for (A, B).
inline void flipManifold(Manifold& m) { m.normal = -m.normal; }

// collide_plane.cpp: plane (as shape A) against a convex shape B.
bool collidePlaneConvex(const Vec3& planeNormal, Real planeOffset, const ConvexShape& b, Real margin, Manifold& m);

}  // namespace fulcrum::detail
