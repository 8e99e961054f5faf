// Capsule-capsule: closest points of the two core segments (Ericson RTCD
// 5.1.9) plus the radii. Parallel capsules (axes within ~3.6 degrees) get two
// points, the ends of the segments' overlap, so a capsule lying on another
// doesn't rock about a single point.
#include <algorithm>
#include <cmath>

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
    if (dist2 > reach * reach) return false;
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

}  // namespace fulcrum::detail
