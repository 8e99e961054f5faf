// Dedicated paths for spheres: against spheres, capsules (the closest point
// of the segment), boxes (the closest point of the box, or the nearest face
// when the centre is inside) and triangles (Ericson RTCD 5.1.5). All exact,
// one point each.
#include <algorithm>
#include <cmath>

#include "collision/collide_pairs.hpp"
#include "collision/narrow_phase.hpp"

namespace fulcrum::detail {

namespace {

// Contact between spheres centred at ca (radius ra) and cb (rb); `fallbackN`
// is used when the centres coincide.
bool spherePoints(const Vec3& ca, Real ra, const Vec3& cb, Real rb, const Vec3& fallbackN, std::uint32_t id, Real margin,
                  Manifold& m) {
    SphereContact c;
    if (!sphereContact(ca, ra, cb, rb, fallbackN, margin, c)) return false;
    m.normal = c.normal;
    m.pointCount = 0;
    addContact(m, c.pointA, c.pointB, c.depth, id, margin);
    return m.pointCount > 0;
}

}  // namespace

bool collideSphereCentres(const Vec3& ca, Real ra, const Vec3& cb, Real rb, Real margin, Manifold& m) {
    return spherePoints(ca, ra, cb, rb, {0, 1, 0}, 0, margin, m);
}

bool collideSphereSphere(const ConvexShape& a, const ConvexShape& b, Real margin, Manifold& m) {
    return collideSphereCentres(a.xf.p, a.radius, b.xf.p, b.radius, margin, m);
}

bool collideSphereCapsule(const ConvexShape& a, const ConvexShape& b, Real margin, Manifold& m) {
    const Vec3 axis = rotate(b.xf.q, Vec3{0, b.halfHeight, 0});
    const Vec3 p0 = b.xf.p - axis;
    const Vec3 seg = axis * Real(2);
    const Real len2 = lengthSquared(seg);
    const Real t = len2 > 0 ? std::clamp(dot(a.xf.p - p0, seg) / len2, Real(0), Real(1)) : Real(0);
    // Feature: capsule end cap 0/1 or the cylindrical side 2.
    const std::uint32_t id = t <= 0 ? 0u : (t >= 1 ? 1u : 2u);
    Vec3 t1, t2;
    orthonormalBasis(normalize(axis), t1, t2);
    const Vec3 onAxis = p0 + seg * t;
    if (spherePoints(a.xf.p, a.radius, onAxis, b.radius, t1, id, margin, m)) return true;
    // Rejected: the centre's distance to the segment less the radii is what
    // the apart cache keeps (docs/narrow-phase.md, "Pairs proved apart").
    m.apartBy = std::max(Real(0), length(a.xf.p - onAxis) - a.radius - b.radius);
    return false;
}

bool collideSphereBox(const ConvexShape& a, const ConvexShape& b, Real margin, Manifold& m) {
    const Vec3 c = inverseTransformPoint(b.xf, a.xf.p);
    const Vec3 e = b.halfExtents;
    const Vec3 q = max(-e, min(e, c));
    // Feature: the Voronoi region of the box (3 states per axis: -, inside, +).
    std::uint32_t id = 0;
    for (std::size_t i = 0; i < 3; ++i) id = id * 3 + (c[i] < -e[i] ? 0u : (c[i] > e[i] ? 2u : 1u));
    const Real r = a.radius;
    m.pointCount = 0;
    if (q != c) {
        const Vec3 d = c - q;  // box -> sphere
        const Real d2 = lengthSquared(d);
        if (d2 > (r + margin) * (r + margin)) {
            m.apartBy = std::sqrt(d2) - r;  // the apart cache's distance, as above
            return false;
        }
        const Real dist = std::sqrt(d2);
        const Vec3 nLocal = d / dist;
        m.normal = -rotate(b.xf.q, nLocal);  // sphere (A) -> box (B)
        const Vec3 pb = transformPoint(b.xf, q);
        addContact(m, a.xf.p + m.normal * r, pb, r - dist, id, margin);
        return m.pointCount > 0;
    }
    // Centre inside the box: push out through the nearest face.
    std::size_t axis = 0;
    Real best = e[0] - std::fabs(c[0]);
    for (std::size_t i = 1; i < 3; ++i) {
        const Real gap = e[i] - std::fabs(c[i]);
        if (gap < best) { best = gap; axis = i; }
    }
    Vec3 nLocal, face = c;
    nLocal[axis] = c[axis] >= 0 ? Real(1) : Real(-1);
    face[axis] = nLocal[axis] * e[axis];
    m.normal = -rotate(b.xf.q, nLocal);
    addContact(m, a.xf.p + m.normal * r, transformPoint(b.xf, face), r + best, 27 + static_cast<std::uint32_t>(axis), margin);
    return m.pointCount > 0;
}

bool collideTriangleSphere(const ConvexShape& tri, const ConvexShape& b, Real margin, Manifold& m) {
    const Vec3 p = b.xf.p;
    const Vec3 a = tri.triangle[0], bb = tri.triangle[1], c = tri.triangle[2];
    // Ericson RTCD 5.1.5, with the region kept as the feature id
    // (0-2 vertices, 3-5 edges ab, bc, ca, 6 face).
    const Vec3 ab = bb - a, ac = c - a, ap = p - a;
    Vec3 q;
    std::uint32_t id;
    const Real d1 = dot(ab, ap), d2 = dot(ac, ap);
    const Vec3 bp = p - bb;
    const Real d3 = dot(ab, bp), d4 = dot(ac, bp);
    const Vec3 cp = p - c;
    const Real d5 = dot(ab, cp), d6 = dot(ac, cp);
    const Real vc = d1 * d4 - d3 * d2, vb = d5 * d2 - d1 * d6, va = d3 * d6 - d5 * d4;
    if (d1 <= 0 && d2 <= 0) { q = a; id = 0; }
    else if (d3 >= 0 && d4 <= d3) { q = bb; id = 1; }
    else if (d6 >= 0 && d5 <= d6) { q = c; id = 2; }
    else if (vc <= 0 && d1 >= 0 && d3 <= 0) { q = a + ab * (d1 / (d1 - d3)); id = 3; }
    else if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) { q = bb + (c - bb) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))); id = 4; }
    else if (vb <= 0 && d2 >= 0 && d6 <= 0) { q = a + ac * (d2 / (d2 - d6)); id = 5; }
    else {
        const Real denom = 1 / (va + vb + vc);
        q = a + ab * (vb * denom) + ac * (vc * denom);
        id = 6;
    }
    const Vec3 faceN = normalize(cross(ab, ac));
    const Vec3 d = p - q;
    const Real d2q = lengthSquared(d);
    const Real r = b.radius;
    if (d2q > (r + margin) * (r + margin)) return false;
    const Real dist = std::sqrt(d2q);
    const Vec3 n = dist > Real(1e-9) ? d / dist : faceN;
    m.normal = n;
    m.pointCount = 0;
    addContact(m, q, p - n * r, r - dist, id, margin);
    return m.pointCount > 0;
}

}  // namespace fulcrum::detail
