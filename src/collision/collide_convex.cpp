// The general convex-convex path and the face-clipping manifold builder.
//
// Penetration: GJK on the core shapes (spheres and capsules reduced to their
// point and segment) gives the distance and closest points whenever the
// cores are apart, which is the common case for rounded shapes and for every
// speculative contact. Only when the cores overlap does EPA run on the full
// shapes. The one contact GJK/EPA gives is then widened into a manifold by
// clipping the shapes' supporting faces along the normal (the approach of
// Jolt's ManifoldBetweenTwoFaces and of Gregorius's GDC 2015 talk): the
// reference face is the one most aligned with the normal, the incident
// feature (polygon, segment or point) is clipped against its side planes, and
// each clipped point's depth is measured along the normal to the reference plane.
#include <algorithm>
#include <cmath>

#include "collision/collide_pairs.hpp"
#include "collision/epa.hpp"
#include "collision/gjk.hpp"

namespace fulcrum::detail {

namespace {

// Below this cosine between the contact normal and both faces, the contact
// is edge-like and a single point is the honest answer. cos 45 deg keeps a box
// tipped on its edge (face at 45 deg to the normal) on the two-point path.
constexpr Real kMinFaceAlignment = Real(0.7);
// A's face is kept as reference unless B's is clearly better aligned, so the
// choice does not flip between frames when the two are nearly equal.
constexpr Real kReferenceBias = Real(0.02);
// Below this core distance the closest-point direction is numerical noise; EPA decides.
constexpr Real kCoreTouch = Real(1e-4);
constexpr std::uint32_t kMaxClip = 2 * kMaxFacePoints + 8;

struct ClipVertex {
    Vec3 p;
    std::uint32_t key;
};

// Sutherland-Hodgman clipping of a polygon against the side planes of `ref`
// (a counter-clockwise polygon with outward normal ref.normal). Keys record
// where each output vertex came from: an incident vertex (its index) or the
// crossing of an incident edge with a side plane (0x8000 | plane << 8 | edge).
std::uint32_t clipPolygon(const SupportFace& ref, ClipVertex* poly, std::uint32_t count, ClipVertex* scratch) {
    ClipVertex* in = poly;
    ClipVertex* out = scratch;
    for (std::uint32_t e = 0; e < ref.count && count > 0; ++e) {
        const Vec3 p0 = ref.points[e], p1 = ref.points[(e + 1) % ref.count];
        const Vec3 side = cross(p1 - p0, ref.normal);
        const Real off = dot(side, p0);
        std::uint32_t outCount = 0;
        for (std::uint32_t i = 0; i < count; ++i) {
            const ClipVertex& s = in[i];
            const ClipVertex& t = in[(i + 1) % count];
            const Real ds = dot(side, s.p) - off, dt = dot(side, t.p) - off;
            if (ds <= 0 && outCount < kMaxClip) out[outCount++] = s;
            if ((ds <= 0) != (dt <= 0) && outCount < kMaxClip) {
                const Real u = ds / (ds - dt);
                out[outCount++] = {s.p + (t.p - s.p) * u, 0x8000u | ((e & 0x7Fu) << 8) | (s.key & 0xFFu)};
            }
        }
        count = outCount;
        std::swap(in, out);
    }
    if (in != poly) {
        for (std::uint32_t i = 0; i < count; ++i) poly[i] = in[i];
    }
    return count;
}

// Clips the segment (a, b) to the side planes of `ref`; false when nothing is left.
bool clipSegment(const SupportFace& ref, ClipVertex& a, ClipVertex& b) {
    Real t0 = 0, t1 = 1;
    std::uint32_t k0 = a.key, k1 = b.key;
    const Vec3 d = b.p - a.p;
    for (std::uint32_t e = 0; e < ref.count; ++e) {
        const Vec3 p0 = ref.points[e], p1 = ref.points[(e + 1) % ref.count];
        const Vec3 side = cross(p1 - p0, ref.normal);
        const Real da = dot(side, a.p - p0), dd = dot(side, d);
        if (std::fabs(dd) < Real(1e-12)) {
            if (da > 0) return false;
            continue;
        }
        const Real t = -da / dd;
        const std::uint32_t key = 0x8000u | ((e & 0x7Fu) << 8);
        if (dd > 0) {  // leaving the inside as t grows
            if (t < t1) { t1 = t; k1 = key | 1u; }
        } else if (t > t0) {
            t0 = t; k0 = key;
        }
        if (t0 > t1) return false;
    }
    const Vec3 pa = a.p + d * t0, pb = a.p + d * t1;
    a = {pa, k0};
    b = {pb, k1};
    return true;
}

std::uint32_t packFeature(std::uint32_t refId, bool refIsB, std::uint32_t incId, std::uint32_t key) {
    return ((refId & 0xFFu) << 24) | (refIsB ? 1u << 23 : 0u) | ((incId & 0x7Fu) << 16) | (key & 0xFFFFu);
}

}  // namespace

void closestSegmentSegment(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2, Real& s, Real& t) {
    const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
    const Real a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
    constexpr Real kEps = Real(1e-12);
    if (a <= kEps && e <= kEps) { s = t = 0; return; }
    if (a <= kEps) {
        s = 0;
        t = std::clamp(f / e, Real(0), Real(1));
        return;
    }
    const Real c = dot(d1, r);
    if (e <= kEps) {
        t = 0;
        s = std::clamp(-c / a, Real(0), Real(1));
        return;
    }
    const Real b = dot(d1, d2), denom = a * e - b * b;
    s = denom > kEps * a * e ? std::clamp((b * f - c * e) / denom, Real(0), Real(1)) : Real(0);
    t = (b * s + f) / e;
    if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, Real(0), Real(1));
    } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, Real(0), Real(1));
    }
}

void buildFaceManifold(const ConvexShape& a, const ConvexShape& b, const Vec3& n, const Vec3& fallbackA,
                       const Vec3& fallbackB, Real margin, Manifold& m, int forceReference) {
    m.normal = n;
    m.pointCount = 0;
    SupportFace fa, fb;
    supportingFace(a, n, fa);
    supportingFace(b, -n, fb);
    const Real alignA = fa.count >= 3 ? dot(fa.normal, n) : Real(-1);
    const Real alignB = fb.count >= 3 ? -dot(fb.normal, n) : Real(-1);
    int ref = forceReference;
    if (ref == 0 && std::max(alignA, alignB) >= kMinFaceAlignment) ref = alignA >= alignB - kReferenceBias ? 1 : 2;
    if ((ref == 1 && fa.count < 3) || (ref == 2 && fb.count < 3)) ref = 0;

    ContactCandidate cand[kMaxClip];
    std::uint32_t candCount = 0;
    if (ref != 0) {
        const SupportFace& rf = ref == 1 ? fa : fb;
        const SupportFace& inc = ref == 1 ? fb : fa;
        const Real refD = dot(rf.normal, rf.points[0]);
        const Real denom = ref == 1 ? dot(rf.normal, n) : -dot(rf.normal, n);
        ClipVertex poly[kMaxClip], scratch[kMaxClip];
        std::uint32_t count = inc.count;
        for (std::uint32_t i = 0; i < count; ++i) poly[i] = {inc.points[i], i};
        if (count >= 3) {
            count = clipPolygon(rf, poly, count, scratch);
        } else if (count == 2) {
            count = clipSegment(rf, poly[0], poly[1]) ? 2u : 0u;
        } else {
            const Vec3 q = poly[0].p;
            for (std::uint32_t e = 0; e < rf.count && count > 0; ++e) {
                const Vec3 p0 = rf.points[e], p1 = rf.points[(e + 1) % rf.count];
                if (dot(cross(p1 - p0, rf.normal), q - p0) > 0) count = 0;
            }
        }
        for (std::uint32_t i = 0; i < count; ++i) {
            const Vec3 q = poly[i].p;
            const Real depth = (refD - dot(rf.normal, q)) / denom;
            const Vec3 pa = ref == 1 ? q + n * depth : q;
            const Vec3 pb = ref == 1 ? q : q - n * depth;
            cand[candCount++] = {(pa + pb) * Real(0.5), depth, packFeature(rf.id, ref == 2, inc.id, poly[i].key)};
        }
    } else if (fa.count == 2 && fb.count == 2) {
        // Two parallel segments (capsule or cylinder sides): the overlap of B's
        // segment projected on A's line.
        const Vec3 a0 = fa.points[0], a1 = fa.points[1], b0 = fb.points[0], b1 = fb.points[1];
        const Real la = length(a1 - a0);
        const Vec3 u = (a1 - a0) / la, ub = normalize(b1 - b0);
        if (std::fabs(dot(u, ub)) > Real(0.995)) {
            const Real tb0 = dot(b0 - a0, u), tb1 = dot(b1 - a0, u);
            const Real lo = std::max(Real(0), std::min(tb0, tb1)), hi = std::min(la, std::max(tb0, tb1));
            if (hi - lo > Real(1e-6) * la && std::fabs(tb1 - tb0) > Real(1e-9)) {
                const Real ts[2] = {lo, hi};
                for (std::uint32_t i = 0; i < 2; ++i) {
                    const Vec3 pa = a0 + u * ts[i];
                    const Vec3 pb = b0 + (b1 - b0) * ((ts[i] - tb0) / (tb1 - tb0));
                    const Real depth = dot(pa - pb, n);
                    cand[candCount++] = {(pa + pb) * Real(0.5), depth, 0x00400000u | i};
                }
            }
        }
    }
    if (candCount > 0) reduceContacts({cand, candCount}, margin, m);
    if (m.pointCount == 0) {
        addContact(m, fallbackA, fallbackB, dot(fallbackA - fallbackB, n), 0x00800000u | fa.id << 8 | fb.id, margin);
    }
}

bool collideConvexConvex(const ConvexShape& a, const ConvexShape& b, Real margin, Manifold& m) {
    const GjkResult g = gjkDistance(a, b, false);
    Vec3 n, pa, pb;
    if (!g.overlap && g.distance > kCoreTouch) {
        if (g.distance - a.radius - b.radius > margin) return false;
        n = (g.pointB - g.pointA) / g.distance;
        pa = g.pointA + n * a.radius;
        pb = g.pointB - n * b.radius;
    } else {
        const PenetrationResult p = epaPenetration(a, b);
        if (p.valid) {
            n = p.normal;
            pa = p.pointA;
            pb = p.pointB;
        } else {
            // EPA failed on a degenerate configuration: push apart along the
            // line of centres, measuring the depth with the support functions.
            n = normalize(b.center() - a.center());
            if (lengthSquared(n) == 0) n = {0, 1, 0};
            pa = a.support(n);
            pb = b.support(-n);
        }
        if (dot(pa - pb, n) < -margin) return false;
    }
    buildFaceManifold(a, b, n, pa, pb, margin, m);
    return m.pointCount > 0;
}

}  // namespace fulcrum::detail
