// Capsule-capsule: closest points of the two core segments (Ericson RTCD
// 5.1.9) plus the radii. Parallel capsules (axes within ~3.6 degrees) get two
// points, the ends of the segments' overlap, so a capsule lying on another
// doesn't rock about a single point.
//
// Triangle-capsule (the mesh path's triangles): the closest points of the
// core segment and the triangle, exact, in place of GJK's iterations; the
// manifold is then built by the face clipping the general path uses, so the
// contact is the general path's up to GJK's rounding.
#include <algorithm>
#include <cmath>
#include <limits>

#include "collision/collide_pairs.hpp"

namespace fulcrum::detail {

bool collideCapsuleCapsule(const ConvexShape& a, const ConvexShape& b, Real margin, Manifold& m) {
    const Vec3 ua = rotate(a.xf.q, Vec3{0, 1, 0}), ub = rotate(b.xf.q, Vec3{0, 1, 0});
    const Vec3 a0 = a.xf.p - ua * a.halfHeight, a1 = a.xf.p + ua * a.halfHeight;
    const Vec3 b0 = b.xf.p - ub * b.halfHeight, b1 = b.xf.p + ub * b.halfHeight;
    Real s, t;
    closestSegmentSegment(a0, a1, b0, b1, s, t);
    const Vec3 ca = a0 + (a1 - a0) * s, cb = b0 + (b1 - b0) * t;
    const Vec3 d = cb - ca;
    const Real dist2 = lengthSquared(d);
    const Real reach = a.radius + b.radius + margin;
    if (dist2 > reach * reach) {
        // The segments' distance less the radii: what the apart cache keeps
        // (docs/narrow-phase.md, "Pairs proved apart").
        m.apartBy = std::sqrt(dist2) - a.radius - b.radius;
        return false;
    }
    const Real dist = std::sqrt(dist2);
    Vec3 n;
    // Below 0.1 mm the closest points' offset is rounding, not a direction
    // (as kCoreTouch in collide_convex.cpp): two capsules crossing at one
    // centre got offsets of 1e-7 m pointing anywhere, and depths measured
    // along them that differed with the order (4.70 and 4.87 cm, found by
    // fuzz/narrowphase_fuzz.cpp). The common normal separates intersecting
    // segments by ra + rb, the least there is.
    if (dist > Real(1e-4)) {
        n = d / dist;
    } else {
        // Core segments intersect: any direction perpendicular to both works;
        // take the common normal, or a perpendicular of A's axis when parallel.
        n = cross(ua, ub);
        if (lengthSquared(n) < Real(1e-12)) {
            Vec3 t2;
            orthonormalBasis(ua, n, t2);
        }
        n = normalize(n);
        if (dot(n, b.xf.p - a.xf.p) < 0) n = -n;
    }
    m.normal = n;
    m.pointCount = 0;
    const Real ra = a.radius, rb = b.radius;
    if (std::fabs(dot(ua, ub)) > Real(0.998)) {
        // Parallel: B's end points projected on A's segment, clipped to it.
        const Real la = 2 * a.halfHeight;
        const Real tb0 = dot(b0 - a0, ua), tb1 = dot(b1 - a0, ua);
        const Real lo = std::max(Real(0), std::min(tb0, tb1)), hi = std::min(la, std::max(tb0, tb1));
        if (hi - lo > Real(1e-4) * (la + Real(1e-3))) {
            const Real ts[2] = {lo, hi};
            for (std::uint32_t i = 0; i < 2; ++i) {
                const Vec3 pa = a0 + ua * ts[i];
                const Real tb = std::clamp(dot(pa - b0, ub), Real(0), 2 * b.halfHeight);
                const Vec3 pb = b0 + ub * tb;
                const Real depth = ra + rb - dot(pb - pa, n);
                // Feature: which end of the overlap (A's end cap, or B's end point).
                const std::uint32_t id = 0x10u | (i << 1) | ((ts[i] == lo ? lo > 0 : hi < la) ? 1u : 0u);
                addContact(m, pa + n * ra, pb - n * rb, depth, id, margin);
            }
            if (m.pointCount > 0) return true;
        }
    }
    addContact(m, ca + n * ra, cb - n * rb, ra + rb - dist, 0, margin);
    return m.pointCount > 0;
}

namespace {

// The closest point of triangle (a, b, c) to p when p's projection on the
// triangle's plane falls inside it (barycentric coordinates >= 0): true and q.
bool projectsInside(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& p, Vec3& q) {
    const Vec3 e0 = b - a, e1 = c - a, ep = p - a;
    const Real d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1), d20 = dot(ep, e0), d21 = dot(ep, e1);
    const Real den = d00 * d11 - d01 * d01;
    if (!(den > 0)) return false;
    const Real v = (d11 * d20 - d01 * d21) / den, w = (d00 * d21 - d01 * d20) / den;
    if (v < 0 || w < 0 || v + w > 1) return false;
    q = a + e0 * v + e1 * w;
    return true;
}

}  // namespace

bool closestSegmentTriangle(const Vec3& p0, const Vec3& p1, const Vec3 tri[3], Vec3& onSegment, Vec3& onTriangle) {
    // The segment through the triangle: no closest pair apart.
    const Vec3 n = cross(tri[1] - tri[0], tri[2] - tri[0]);
    const Real s0 = dot(n, p0 - tri[0]), s1 = dot(n, p1 - tri[0]);
    if ((s0 <= 0 && s1 >= 0) || (s0 >= 0 && s1 <= 0)) {
        if (s0 == s1) {
            // In the plane (both zero): apart only when no edge crossing and
            // no end point inside, which the candidates below find as a
            // positive distance; an overlap shows as a zero one.
        } else {
            const Vec3 x = p0 + (p1 - p0) * (s0 / (s0 - s1));
            Vec3 q;
            if (projectsInside(tri[0], tri[1], tri[2], x, q)) return false;
        }
    }
    // Otherwise the closest pair has an end of the segment over the
    // triangle's inside, or a point of one of the triangle's edges: the
    // smallest of those candidates.
    Real best = std::numeric_limits<Real>::infinity();
    const auto consider = [&](const Vec3& a, const Vec3& b) {
        const Real d2 = lengthSquared(a - b);
        if (d2 < best) {
            best = d2;
            onSegment = a;
            onTriangle = b;
        }
    };
    Vec3 q;
    if (projectsInside(tri[0], tri[1], tri[2], p0, q)) consider(p0, q);
    if (projectsInside(tri[0], tri[1], tri[2], p1, q)) consider(p1, q);
    for (std::uint32_t k = 0; k < 3; ++k) {
        const Vec3& e0 = tri[k];
        const Vec3& e1 = tri[k == 2 ? 0 : k + 1];
        Real s, t;
        closestSegmentSegment(p0, p1, e0, e1, s, t);
        consider(p0 + (p1 - p0) * s, e0 + (e1 - e0) * t);
    }
    return best > 0;
}

bool collideTriangleCapsule(const ConvexShape& tri, const ConvexShape& b, Real margin, Manifold& m) {
    const Vec3 axis = rotate(b.xf.q, Vec3{0, b.halfHeight, 0});
    Vec3 onSegment, onTriangle;
    const bool apart = closestSegmentTriangle(b.xf.p - axis, b.xf.p + axis, tri.triangle, onSegment, onTriangle);
    const Vec3 d = onSegment - onTriangle;
    const Real dist2 = lengthSquared(d);
    // Cores touching or overlapping (below the general path's kCoreTouch,
    // 0.1 mm, its closest-point direction is noise): EPA's case, the
    // general path's answer.
    if (!apart || dist2 <= Real(1e-8)) return collideConvexConvex(tri, b, margin, m);
    const Real dist = std::sqrt(dist2);
    if (dist - b.radius > margin) return false;
    const Vec3 n = d / dist;
    // The general path's manifold from GJK's closest points: the triangle's
    // face and the capsule's side (or end) clipped along n, the closest
    // points joining them when clipping found nothing as deep.
    buildFaceManifold(tri, b, n, onTriangle, onSegment - n * b.radius, margin, m, 0, true);
    return m.pointCount > 0;
}

}  // namespace fulcrum::detail
