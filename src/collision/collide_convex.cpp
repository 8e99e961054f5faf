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
#include <array>
#include <cmath>
#include <limits>

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
// A box face normal replaces GJK/EPA's normal when it separates the pair at
// least as well, less this: a face contact is preferred to an edge contact
// that is deeper by less than 0.1 mm (GJK's own resolution near a large box),
// so a resting contact keeps its face.
constexpr Real kFaceAxisTolerance = Real(1e-4);
constexpr std::uint32_t kMaxClip = 2 * kMaxFacePoints + 8;
// GJK's early stop needs the shapes this much farther apart than the margin
// allows: far above the rounding of a support plane's distance (1e-7 of the
// points' size, a few micrometres even for the cut-down ground box), so a
// pair it stops on is one the full run rejects too.
constexpr Real kBeyondPad = Real(1e-3);
// A clipped manifold shallower than GJK/EPA's deepest point by more than this
// missed the touching features (buildFaceManifold).
constexpr Real kClipDepthTolerance = Real(1e-3);

struct ClipVertex {
    Vec3 p;
    std::uint32_t key;
};

// Scratch of N elements that its constructor leaves uninitialised: the
// clipping and candidate arrays are sized for a 32-point face and zeroing
// them (their Vec3s zero themselves) cost more per pair than the few entries
// a rock's triangles use; only the first `count` are ever read.
template <class T, std::uint32_t N>
struct Scratch {
    union {
        T items[N];
    };
    Scratch() {}  // NOLINT: uninitialised on purpose
    T& operator[](std::uint32_t i) { return items[i]; }
    const T& operator[](std::uint32_t i) const { return items[i]; }
};

// Sutherland-Hodgman clipping of a polygon against the side planes of `ref`
// (a counter-clockwise polygon with outward normal ref.normal). Keys record
// where each output vertex came from: an incident vertex (its index) or the
// crossing of an incident edge with a side plane (0x8000 | plane << 8 | edge).
std::uint32_t clipPolygon(const SupportFace& ref, ClipVertex* poly, std::uint32_t count, ClipVertex* scratch) {
    ClipVertex* in = poly;
    ClipVertex* out = scratch;
    for (std::uint32_t e = 0; e < ref.count && count > 0; ++e) {
        const Vec3 p0 = ref.points[e], p1 = ref.points[e + 1 == ref.count ? 0 : e + 1];
        const Vec3 side = cross(p1 - p0, ref.normal);
        const Real off = dot(side, p0);
        std::uint32_t outCount = 0;
        // Each vertex's distance once, carried from an edge's end to the
        // next edge's start (the same expression: the same bits).
        const Real first = dot(side, in[0].p) - off;
        Real dt = first;
        for (std::uint32_t i = 0; i < count; ++i) {
            const ClipVertex& s = in[i];
            const bool last = i + 1 == count;
            const ClipVertex& t = in[last ? 0 : i + 1];  // not % count: a division per vertex
            const Real ds = dt;
            dt = last ? first : dot(side, t.p) - off;
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
        const Vec3 p0 = ref.points[e], p1 = ref.points[e + 1 == ref.count ? 0 : e + 1];
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
    // In double precision whatever Real is: for two nearly parallel segments
    // denom = a e - b^2 cancels, and in single precision two parallel capsules
    // crossing at one centre got s = 0.45 from rounding and closest points
    // 0.16 mm apart in a made-up direction (depths 4.70 and 4.87 cm in the two
    // orders; found by fuzz/narrowphase_fuzz.cpp).
    const auto sub = [](const Vec3& u, const Vec3& v) {
        return std::array<double, 3>{double(u.x) - double(v.x), double(u.y) - double(v.y), double(u.z) - double(v.z)};
    };
    const auto dotD = [](const std::array<double, 3>& u, const std::array<double, 3>& v) {
        return u[0] * v[0] + u[1] * v[1] + u[2] * v[2];
    };
    const std::array<double, 3> d1 = sub(q1, p1), d2 = sub(q2, p2), r = sub(p1, p2);
    const double a = dotD(d1, d1), e = dotD(d2, d2), f = dotD(d2, r);
    constexpr double kEps = 1e-12;
    double ss = 0, tt = 0;
    if (a <= kEps && e <= kEps) {
        ss = tt = 0;
    } else if (a <= kEps) {
        ss = 0;
        tt = std::clamp(f / e, 0.0, 1.0);
    } else {
        const double c = dotD(d1, r);
        if (e <= kEps) {
            tt = 0;
            ss = std::clamp(-c / a, 0.0, 1.0);
        } else {
            const double b = dotD(d1, d2), denom = a * e - b * b;
            ss = denom > kEps * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
            tt = (b * ss + f) / e;
            if (tt < 0) {
                tt = 0;
                ss = std::clamp(-c / a, 0.0, 1.0);
            } else if (tt > 1) {
                tt = 1;
                ss = std::clamp((b - c) / a, 0.0, 1.0);
            }
        }
    }
    s = static_cast<Real>(ss);
    t = static_cast<Real>(tt);
}

namespace {

// buildFaceManifold's body. `fallback(pa, pb)` gives the fallback points; it
// is called only when they are used: always with fallbackIsDeepest, else only
// when clipping left no point within the margin.
template <class Fallback>
void buildFaceManifoldWith(const ConvexShape& a, const ConvexShape& b, const Vec3& n, Fallback&& fallback, Real margin,
                           Manifold& m, int forceReference, bool fallbackIsDeepest, const SupportFace* knownFaceA,
                           const SupportFace* knownFaceB) {
    m.normal = n;
    m.pointCount = 0;
    SupportFace ownA, ownB;
    if (knownFaceA == nullptr) supportingFace(a, n, ownA);
    if (knownFaceB == nullptr) supportingFace(b, -n, ownB);
    const SupportFace& fa = knownFaceA != nullptr ? *knownFaceA : ownA;
    const SupportFace& fb = knownFaceB != nullptr ? *knownFaceB : ownB;
    const Real alignA = fa.count >= 3 ? dot(fa.normal, n) : Real(-1);
    const Real alignB = fb.count >= 3 ? -dot(fb.normal, n) : Real(-1);
    int ref = forceReference;
    if (ref == 0 && std::max(alignA, alignB) >= kMinFaceAlignment) ref = alignA >= alignB - kReferenceBias ? 1 : 2;
    if ((ref == 1 && fa.count < 3) || (ref == 2 && fb.count < 3)) ref = 0;

    Scratch<ContactCandidate, kMaxClip + 1> cand;  // + the deepest point
    std::uint32_t candCount = 0;
    if (ref != 0) {
        const SupportFace& rf = ref == 1 ? fa : fb;
        const SupportFace& inc = ref == 1 ? fb : fa;
        const Real refD = dot(rf.normal, rf.points[0]);
        const Real denom = ref == 1 ? dot(rf.normal, n) : -dot(rf.normal, n);
        Scratch<ClipVertex, kMaxClip> polyStore, scratchStore;
        ClipVertex* poly = polyStore.items;
        ClipVertex* scratch = scratchStore.items;
        std::uint32_t count = inc.count;
        for (std::uint32_t i = 0; i < count; ++i) poly[i] = {inc.points[i], i};
        if (count >= 3) {
            count = clipPolygon(rf, poly, count, scratch);
        } else if (count == 2) {
            count = clipSegment(rf, poly[0], poly[1]) ? 2u : 0u;
        } else {
            const Vec3 q = poly[0].p;
            for (std::uint32_t e = 0; e < rf.count && count > 0; ++e) {
                const Vec3 p0 = rf.points[e], p1 = rf.points[e + 1 == rf.count ? 0 : e + 1];
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
    const std::uint32_t fallbackId = 0x00800000u | fa.id << 8 | fb.id;
    if (fallbackIsDeepest) {
        Vec3 fallbackA, fallbackB;
        fallback(fallbackA, fallbackB);
        // Clipping measures depth to the reference face's plane over the
        // prism of its polygon; at an edge-like contact (normal up to 45
        // degrees off the face) the touching edges can lie outside that
        // prism, so every clipped point came out centimetres apart while
        // the shapes overlapped: the manifold then depended on the margin
        // (the points within it, or else the fallback) and a fast pair's
        // larger margin hid its penetration. The deepest point joins them.
        const Real deepest = dot(fallbackA - fallbackB, n);
        Real clipped = -1e30f;
        for (std::uint32_t i = 0; i < candCount; ++i) clipped = std::max(clipped, cand[i].depth);
        if (clipped < deepest - kClipDepthTolerance) cand[candCount++] = {(fallbackA + fallbackB) * Real(0.5), deepest, fallbackId};
    }
    if (candCount > 0) reduceContacts({cand.items, candCount}, margin, m);
    if (m.pointCount == 0) {
        Vec3 fallbackA, fallbackB;
        fallback(fallbackA, fallbackB);
        addContact(m, fallbackA, fallbackB, dot(fallbackA - fallbackB, n), fallbackId, margin);
    }
}

}  // namespace

void buildFaceManifold(const ConvexShape& a, const ConvexShape& b, const Vec3& n, const Vec3& fallbackA,
                       const Vec3& fallbackB, Real margin, Manifold& m, int forceReference, bool fallbackIsDeepest,
                       const SupportFace* knownFaceA, const SupportFace* knownFaceB) {
    buildFaceManifoldWith(
        a, b, n,
        [&](Vec3& pa, Vec3& pb) {
            pa = fallbackA;
            pb = fallbackB;
        },
        margin, m, forceReference, fallbackIsDeepest, knownFaceA, knownFaceB);
}

void buildFaceManifold(const ConvexShape& a, const ConvexShape& b, const Vec3& n, Real margin, Manifold& m,
                       int forceReference) {
    buildFaceManifoldWith(
        a, b, n,
        [&](Vec3& pa, Vec3& pb) {
            pa = a.support(n);
            pb = b.support(-n);
        },
        margin, m, forceReference, false, nullptr, nullptr);
}

namespace {

// How far B lies beyond A along the unit axis n (A to B): B's lowest point
// along n minus A's highest; negative when they overlap along n. Every axis
// gives a lower bound of the true separation and the best axis gives it
// exactly (Minkowski), so of two candidate normals the one separating more
// is the better.
Real separationAlong(const ConvexShape& a, const ConvexShape& b, const Vec3& n) {
    return dot(b.support(-n) - a.support(n), n);
}

// The supports separationAlong looks at (A's along n, B's along -n), with the
// hulls' vertices they are: the supporting faces along the same n start from
// those vertices, so each pair's search runs once (docs/narrow-phase.md,
// "Hull support").
struct AxisSupports {
    Vec3 a, b;
    std::uint32_t vertexA = kNoVertex, vertexB = kNoVertex;
};

AxisSupports supportsAlong(const ConvexShape& a, const ConvexShape& b, const Vec3& n) {
    AxisSupports s;
    s.a = a.support(n, s.vertexA);
    s.b = b.support(-n, s.vertexB);
    return s;
}

// At most s.boundingRadius(), as rounded: for a hull one vertex's distance
// (boundingRadius scans them all), so a test that passes below it needs no scan.
Real boundingRadiusAtMost(const ConvexShape& s) {
    if (s.kind != ConvexKind::Hull || s.hull->vertices.empty()) return s.boundingRadius();
    return std::sqrt(lengthSquared(s.hull->vertices[0])) + s.radius;
}

// A box against another convex shape, seen from the box's frame: the other
// shape's extent along each box axis, the box's best face normal and the
// region of the box that can touch the other shape.
struct BoxView {
    Vec3 faceNormal;        // from A to B, of the box face along which the pair separates most
    Real faceSeparation;    // along it (negative: overlap)
    ConvexShape nearPart;   // the box cut down to the other shape's extent plus a pad (or the box itself)
    // The distance to nearPart is the box's own below this (every point of
    // the box within it of the other shape is in nearPart), at least this above.
    Real exactWithin = std::numeric_limits<Real>::infinity();
};

// Large boxes (a 500 m ground under 2 m bodies) break GJK and EPA in float:
// their simplex vertices are the box's corners, hundreds of metres out, whose
// rounding (~1e-5 m) and the cancellation in the closest-point weights are
// larger than the contact's millimetres. GJK then reported a resting hull 5 cm
// apart (no contact) and normals tens of degrees off (clipped against a side
// face 250 m away: a 300 m deep contact). So GJK and EPA run on the part of the
// box within `pad` of the other shape's extent along each box axis (a smaller
// box, exact: every point of the box within pad of the other shape is in it),
// and a box face normal, exact whatever the box's size, is preferred when it
// separates at least as well (docs/narrow-phase.md, "Large boxes").
BoxView viewBox(const ConvexShape& box, const ConvexShape& other, bool boxIsA, Real margin) {
    BoxView view;
    view.faceSeparation = -1e30f;
    const Vec3 h = box.halfExtents;
    Real lo[3], hi[3], width = 0;
    for (std::size_t k = 0; k < 3; ++k) {
        Vec3 axis;
        axis[k] = 1;
        axis = rotate(box.xf.q, axis);
        const Real centre = dot(axis, box.xf.p);
        other.extent(axis, lo[k], hi[k]);
        lo[k] -= centre;
        hi[k] -= centre;
        width = std::max(width, hi[k] - lo[k]);
        const Real gaps[2] = {lo[k] - h[k], -h[k] - hi[k]};  // beyond the box's +k and -k faces
        for (int side = 0; side < 2; ++side) {
            if (gaps[side] <= view.faceSeparation) continue;
            view.faceSeparation = gaps[side];
            const Vec3 outward = side == 0 ? axis : -axis;
            view.faceNormal = boxIsA ? outward : -outward;
        }
    }
    view.nearPart = box;
    // Twice the other shape's size beyond it: a way out through a cut face
    // costs at least that, more than any contact the shapes can have through
    // a real face short of one swallowing the other.
    const Real pad = margin + 2 * width;
    Vec3 centre, half = h;
    bool cut = false;
    for (std::size_t k = 0; k < 3; ++k) {
        const Real from = std::max(-h[k], lo[k] - pad), to = std::min(h[k], hi[k] + pad);
        if (from == -h[k] && to == h[k]) continue;
        if (!(to > from)) return view;  // apart along this axis by more than pad: the caller stops
        centre[k] = Real(0.5) * (from + to);
        half[k] = Real(0.5) * (to - from);
        cut = true;
    }
    if (cut) {
        view.nearPart.xf.p = transformPoint(box.xf, centre);
        view.nearPart.halfExtents = half;
        view.exactWithin = pad;
    }
    return view;
}

// GJK/EPA's direction is poorly conditioned when hulls nearly touch: the
// origin then lies on the Minkowski difference's boundary, and poses 0.1
// degree apart gave normals 1.6 degrees apart that separated the pair up to
// 8 cm less than the best axis, rarely metres (Box3D's hulls resting on each
// other; tests HullNormal.* and PersistentManifold.HullPile*). A face
// contact's best axis is a face normal, exact to rounding. So a face normal
// replaces n when it separates the pair at least as well (less
// kFaceAxisTolerance), as the box path does with its face normals: the
// supporting faces' along n, or every face of the hulls when n separates the
// pair worse than GJK/EPA's own points say by more than kNormalInconsistency
// (the gap `gap` between them along n): then n is off, by up to metres, and
// faces along it are no better (docs/narrow-phase.md, "Hull face axes").
// Every face always would double the hull pile's step cost.
constexpr Real kNormalInconsistency = Real(1e-3);

// The supporting faces along n that bestHullFaceAxis found on its way, for
// buildFaceManifold when n stands (the same calls: the same faces).
struct FacesAlongNormal {
    SupportFace a, b;
    bool knownA = false, knownB = false;
};

// faceOfA: whether the axis returned is a face of a (false: of b, or n itself);
// bestSupports: the supports along the axis returned when it is not n.
Vec3 bestHullFaceAxis(const ConvexShape& a, const ConvexShape& b, const Vec3& n, Real gap, FacesAlongNormal& faces,
                      bool& faceOfA, AxisSupports& bestSupports) {
    Vec3 best = n;
    const AxisSupports alongN = supportsAlong(a, b, n);
    const Real separation = dot(alongN.b - alongN.a, n);
    const bool everyFace = separation < gap - kNormalInconsistency;
    Real bestSeparation = separation - kFaceAxisTolerance;
    const auto consider = [&](const Vec3& axis, bool ofA) {
        const AxisSupports along = supportsAlong(a, b, axis);
        const Real s = dot(along.b - along.a, axis);
        if (s > bestSeparation) {
            best = axis;
            bestSeparation = s;
            faceOfA = ofA;
            bestSupports = along;
        }
    };
    if (a.kind == ConvexKind::Hull) {
        if (everyFace) {
            for (const HullFace& f : a.hull->faces) consider(rotate(a.xf.q, f.normal), true);
        } else {
            supportingFace(a, n, faces.a, alongN.vertexA);
            faces.knownA = true;
            consider(faces.a.normal, true);
        }
    }
    if (b.kind == ConvexKind::Hull) {
        if (everyFace) {
            for (const HullFace& f : b.hull->faces) consider(-rotate(b.xf.q, f.normal), false);
        } else {
            supportingFace(b, -n, faces.b, alongN.vertexB);
            faces.knownB = true;
            consider(-faces.b.normal, false);
        }
    }
    return best;
}

}  // namespace

bool collideConvexConvex(const ConvexShape& shapeA, const ConvexShape& shapeB, Real margin, Manifold& m) {
    return collideConvexConvex(shapeA, shapeB, margin, m, nullptr);
}

bool collideConvexConvex(const ConvexShape& shapeA, const ConvexShape& shapeB, Real margin, Manifold& m,
                         GjkWarmStart* warm) {
    const bool boxA = shapeA.kind == ConvexKind::Box, boxB = shapeB.kind == ConvexKind::Box;
    BoxView box;
    if (boxA || boxB) {
        box = boxA ? viewBox(shapeA, shapeB, true, margin) : viewBox(shapeB, shapeA, false, margin);
        if (box.faceSeparation > margin) {
            m.apartBy = box.faceSeparation;  // along a box axis: never more than the distance
            return false;
        }
    }
    // From here on a box is its part near the other shape.
    const ConvexShape& a = boxA ? box.nearPart : shapeA;
    const ConvexShape& b = boxB && !boxA ? box.nearPart : shapeB;
    // GJK may stop once a support plane shows the cores farther apart than
    // the margin (plus the radii) by kBeyondPad: the full run would reject the
    // pair below, so the answer is the same, without GJK's remaining
    // iterations. Most pairs of a pile are such pairs (fat bounds overlapping,
    // shapes apart: 83 % of the hull pile's), docs/narrow-phase.md "GJK's early stop".
    const GjkResult g = gjkDistance(a, b, false, margin + a.radius + b.radius + kBeyondPad, warm);
    if (g.beyond) {
        m.apartBy = std::min(g.distance - a.radius - b.radius, box.exactWithin);
        return false;
    }
    Vec3 n, pa, pb;
    const bool separated = !g.overlap && g.distance > kCoreTouch;
    if (separated) {
        if (g.distance - a.radius - b.radius > margin) return false;
        n = g.normal;
        pa = g.pointA + n * a.radius;
        pb = g.pointB - n * b.radius;
    } else {
        const PenetrationResult p = epaPenetration(a, b, &g);
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
        // GJK's direction at a touch below kCoreTouch is noisy, but EPA's
        // for shapes that do not overlap can be far worse (the origin is
        // outside the polytope it expands): the better separating one stands.
        if (!g.overlap && g.distance > 0) {
            const Vec3 gn = g.normal;
            if (separationAlong(a, b, gn) > separationAlong(a, b, n)) {
                n = gn;
                pa = g.pointA + n * a.radius;
                pb = g.pointB - n * b.radius;
            }
        }
        if (dot(pa - pb, n) < -margin) return false;
    }
    int reference = 0;
    bool deepestKnown = true;  // pa, pb: GJK/EPA's closest or deepest points along n
    const Vec3 closestA = pa, closestB = pb;
    if ((boxA || boxB) && box.faceSeparation >= separationAlong(a, b, n) - kFaceAxisTolerance) {
        n = box.faceNormal;
        reference = boxA ? 1 : 2;
        // The other shape's deepest point along the face normal, and its
        // projection on the face plane: a contact when it is over the face
        // (a cylinder's tilted rim reaches deeper than its four cap points).
        const ConvexShape& other = boxA ? b : a;
        const Vec3 down = boxA ? -n : n;
        const Vec3 deep = other.support(down);
        const Vec3 onFace = deep + down * box.faceSeparation;
        pa = boxA ? onFace : deep;
        pb = boxA ? deep : onFace;
        const ConvexShape& boxShape = boxA ? shapeA : shapeB;
        const Vec3 local = abs(inverseTransformPoint(boxShape.xf, onFace));
        const Vec3 h = boxShape.halfExtents * Real(1.0001);
        deepestKnown = local.x <= h.x && local.y <= h.y && local.z <= h.z;
        if (!deepestKnown && separated) {
            // The other shape's nearest part along the face normal lies
            // beyond the face, so the clipped points, over the face, may all
            // be farther than the distance the shapes can close along the
            // normal before they touch (a cylinder's rim just past a face
            // edge, its cap clipped as a square: 9 cm too far; a speculative
            // contact that over-states it lets them overlap for a step).
            // GJK's closest points join them: their gap along the face
            // normal lies between the face axis's separation and their
            // distance, and that distance never exceeds the travel.
            pa = closestA;
            pb = closestB;
            deepestKnown = true;
        }
    }
    FacesAlongNormal faces;
    if (reference == 0 && (a.kind == ConvexKind::Hull || b.kind == ConvexKind::Hull)) {
        bool faceOfA = false;
        AxisSupports along;
        const Vec3 faceAxis = bestHullFaceAxis(a, b, n, dot(pb - pa, n), faces, faceOfA, along);
        if (!(faceAxis == n)) {
            // GJK/EPA's points are closest or deepest along their own normal,
            // not along the face axis: the deepest points along it are the
            // supports. (A small hull deep inside a large cylinder: EPA's
            // normal and a hull face 45 degrees from it; EPA's points, 3.57 m
            // deep along EPA's normal, were 1.66 m apart along the face axis,
            // the clipped face missed the cylinder's side and the pair got no
            // contact at all; found by fuzz/narrowphase_fuzz.cpp.)
            n = faceAxis;
            pa = along.a;
            pb = along.b;
            // The faces along the old n are not these.
            supportingFace(a, n, faces.a, along.vertexA);
            supportingFace(b, -n, faces.b, along.vertexB);
            faces.knownA = faces.knownB = true;
            // The face's own support is only the first vertex of that face,
            // anywhere on it; the other shape's is the feature reaching
            // deepest. When their midpoint lies beyond the other shape's
            // reach (a cube by a drum's 20 m wall: the midpoint of the cube's
            // corner and the wall's far corner was a contact point 4 m from
            // the cube, whose impulse spun it, and the speculative contact
            // became a 16 cm overlap), both points go to the other shape's
            // feature, on either side of the same depth. Shapes of one size
            // (a hull pile) keep the midpoint.
            const Real depth = dot(pa - pb, n);
            const Vec3 lateral = pa - pb - n * depth;
            const ConvexShape& other = faceOfA ? b : a;
            const Real lateral2 = lengthSquared(lateral);
            const Real reachAtMost = boundingRadiusAtMost(other);
            bool beyondReach = lateral2 > 4 * reachAtMost * reachAtMost;
            if (beyondReach) {
                const Real reach = other.boundingRadius();
                beyondReach = lateral2 > 4 * reach * reach;
            }
            if (beyondReach) {
                if (faceOfA) {
                    pa = pb + n * depth;
                } else {
                    pb = pa - n * depth;
                }
            }
        }
    }
    buildFaceManifold(a, b, n, pa, pb, margin, m, reference, deepestKnown, faces.knownA ? &faces.a : nullptr,
                      faces.knownB ? &faces.b : nullptr);
    return m.pointCount > 0;
}

}  // namespace fulcrum::detail
