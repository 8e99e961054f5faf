// GJK with Ericson's Voronoi-region simplex solver (RTCD 5.1.5 and 9.5): the
// closest point of a segment, triangle or tetrahedron to the origin, with the
// barycentric weights kept so the closest points on A and B follow directly.
#include "collision/gjk.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "collision/manifold.hpp"

namespace fulcrum::detail {

namespace {

void keep(Simplex& s, std::initializer_list<std::uint32_t> idx, std::initializer_list<Real> w) {
    SimplexVertex v[4];
    Real b[4];
    std::uint32_t n = 0;
    auto wi = w.begin();
    for (std::uint32_t i : idx) {
        v[n] = s.v[i];
        b[n] = *wi++;
        ++n;
    }
    for (std::uint32_t i = 0; i < n; ++i) {
        s.v[i] = v[i];
        s.bary[i] = b[i];
    }
    s.count = n;
}

// The sub-simplex solver works in double precision, whatever Real is. Its
// inputs are vertices of A - B metres from the origin, its answer a point
// millimetres from it, and on the thin simplices GJK builds against parallel
// faces and capsules (a triangle 10 m long and 0.3 mm wide) the single-
// precision formulas cancel to nonsense: Ericson's va, vb, vc (differences of
// products of dot products) left the closest point 0.15 mm from an origin
// that lay in the triangle, so two capsules 3.5 cm deep in each other were
// "apart" (fuzz/corpus/narrowphase/parallel_thin_capsules); a sliver's normal,
// off by 2e-3 rad, gave weights of +-19000 and a distance of 1.6 cm for
// capsules 3.3 cm apart; a nearly flat tetrahedron "held" an origin 12 cm
// outside it. The vertices are exact in double, and these few products
// cost next to nothing beside the support functions.
struct D3 {
    double x, y, z;
};
D3 toD(const Vec3& v) { return {v.x, v.y, v.z}; }
D3 operator-(const D3& a, const D3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator+(const D3& a, const D3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator*(const D3& a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dotD(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 crossD(const D3& a, const D3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
Vec3 toReal(const D3& v) { return {static_cast<Real>(v.x), static_cast<Real>(v.y), static_cast<Real>(v.z)}; }
// A vertex of A - B from its support points: exact in double, where the
// single-precision w carries rounding of 1e-7 of the points' distance from
// the origin (3e-7 m at 3 m, a tenth of a gap of a few micrometres).
D3 wOf(const SimplexVertex& v) { return toD(v.a) - toD(v.b); }

// Closest point to the origin on triangle (s.v[i0], s.v[i1], s.v[i2]) (RTCD 5.1.5),
// written into `out` as (indices, weights).
struct Sub {
    std::uint32_t idx[3];
    Real w[3];
    std::uint32_t n;
    Vec3 p;
};

Sub closestTriangle(const Simplex& s, std::uint32_t ia, std::uint32_t ib, std::uint32_t ic) {
    const D3 a = wOf(s.v[ia]), b = wOf(s.v[ib]), c = wOf(s.v[ic]);
    const D3 ab = b - a, ac = c - a;
    const double d1 = -dotD(ab, a), d2 = -dotD(ac, a);
    if (d1 <= 0 && d2 <= 0) return {{ia}, {1}, 1, toReal(a)};
    const double d3 = -dotD(ab, b), d4 = -dotD(ac, b);
    if (d3 >= 0 && d4 <= d3) return {{ib}, {1}, 1, toReal(b)};
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const double v = d1 / (d1 - d3);
        return {{ia, ib}, {static_cast<Real>(1 - v), static_cast<Real>(v)}, 2, toReal(a + ab * v)};
    }
    const double d5 = -dotD(ab, c), d6 = -dotD(ac, c);
    if (d6 >= 0 && d5 <= d6) return {{ic}, {1}, 1, toReal(c)};
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const double w = d2 / (d2 - d6);
        return {{ia, ic}, {static_cast<Real>(1 - w), static_cast<Real>(w)}, 2, toReal(a + ac * w)};
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {{ib, ic}, {static_cast<Real>(1 - w), static_cast<Real>(w)}, 2, toReal(b + (c - b) * w)};
    }
    // The origin projects inside: its projection on the plane, with the
    // signed sub-triangle areas as weights.
    const D3 n = crossD(ab, ac);
    const double nn = dotD(n, n);
    if (!(nn > 0)) return {{ia}, {1}, 1, toReal(a)};  // degenerate (zero-area) triangle
    const D3 p = n * (dotD(n, a) / nn);
    const double wa = dotD(crossD(b - p, c - p), n) / nn;
    const double wb = dotD(crossD(c - p, a - p), n) / nn;
    return {{ia, ib, ic}, {static_cast<Real>(wa), static_cast<Real>(wb), static_cast<Real>(1 - wa - wb)}, 3, toReal(p)};
}

void apply(Simplex& s, const Sub& sub) {
    SimplexVertex v[3];
    for (std::uint32_t i = 0; i < sub.n; ++i) v[i] = s.v[sub.idx[i]];
    for (std::uint32_t i = 0; i < sub.n; ++i) {
        s.v[i] = v[i];
        s.bary[i] = sub.w[i];
    }
    s.count = sub.n;
}

// Warm starts name a simplex's points by the vertices they are: a hull's
// vertex index, or a box's corner (bit k set: + along axis k). The support
// searches below give the points coreSupport gives, bit for bit, with their
// indices (a box's sign test is coreSupport's sgn: + at zero).
bool indexable(const ConvexShape& s) { return s.kind == ConvexKind::Hull || s.kind == ConvexKind::Box; }
std::size_t vertexCount(const ConvexShape& s) { return s.kind == ConvexKind::Hull ? s.hull->vertices.size() : 8; }
Vec3 vertexOf(const ConvexShape& s, std::uint32_t i) {
    if (s.kind == ConvexKind::Hull) return transformPoint(s.xf, s.hull->vertices[i]);
    const Vec3& h = s.halfExtents;
    return transformPoint(s.xf, {(i & 1u) ? h.x : -h.x, (i & 2u) ? h.y : -h.y, (i & 4u) ? h.z : -h.z});
}
std::uint32_t supportIndex(const ConvexShape& s, const Vec3& d) {
    const Vec3 l = inverseRotate(s.xf.q, d);
    if (s.kind == ConvexKind::Hull) return hullSupportIndex(*s.hull, l);
    return (l.x >= 0 ? 1u : 0u) | (l.y >= 0 ? 2u : 0u) | (l.z >= 0 ? 4u : 0u);
}

}  // namespace

bool closestOnSimplex(Simplex& s, Vec3& closest) {
    switch (s.count) {
        case 1:
            s.bary[0] = 1;
            closest = toReal(wOf(s.v[0]));
            return true;
        case 2: {
            const D3 a = wOf(s.v[0]), b = wOf(s.v[1]), ab = b - a;
            const double denom = dotD(ab, ab);
            const double t = denom > 0 ? -dotD(a, ab) / denom : 0;
            if (t <= 0) { closest = toReal(a); keep(s, {0}, {1}); return true; }
            if (t >= 1) { closest = toReal(b); keep(s, {1}, {1}); return true; }
            s.bary[0] = static_cast<Real>(1 - t);
            s.bary[1] = static_cast<Real>(t);
            closest = toReal(a + ab * t);
            return true;
        }
        case 3: {
            const Sub sub = closestTriangle(s, 0, 1, 2);
            apply(s, sub);
            closest = sub.p;
            return true;
        }
        case 4: {
            // Test each face whose plane separates the origin from the opposite vertex.
            static constexpr std::uint32_t faces[4][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}};
            bool outsideAny = false;
            Sub best{};
            Real bestD2 = 0;
            for (const auto& f : faces) {
                const D3 a = wOf(s.v[f[0]]), b = wOf(s.v[f[1]]), c = wOf(s.v[f[2]]), d = wOf(s.v[f[3]]);
                const D3 n = crossD(b - a, c - a);
                const double sideO = -dotD(a, n), sideD = dotD(d - a, n);
                // Origin strictly on the other side of the face from d (with a
                // small tolerance so a flat tetrahedron does not claim containment).
                if (sideO * sideD < 0 || sideD == 0) {
                    const Sub sub = closestTriangle(s, f[0], f[1], f[2]);
                    const Real d2 = lengthSquared(sub.p);
                    if (!outsideAny || d2 < bestD2) { best = sub; bestD2 = d2; }
                    outsideAny = true;
                }
            }
            if (!outsideAny) {
                closest = Vec3::zero();
                return false;
            }
            apply(s, best);
            closest = best.p;
            return true;
        }
        default: return true;
    }
}

GjkResult gjkDistance(const ConvexShape& a, const ConvexShape& b, bool withRadius, Real stopBeyond, GjkWarmStart* warm,
                      const Vec3* guess) {
    GjkResult r;
    Simplex& s = r.simplex;
    auto supportA = [&](const Vec3& d) { return withRadius ? a.support(d) : a.coreSupport(d); };
    auto supportB = [&](const Vec3& d) { return withRadius ? b.support(d) : b.coreSupport(d); };
    // A run that keeps a warm start finds a hull's or a box's supports by
    // index: the points coreSupport gives, bit for bit, with their indices.
    const bool indexed = warm != nullptr && !withRadius && indexable(a) && indexable(b);
    // The vertex of A - B farthest along -v (A's support along -v, B's along v).
    const auto vertexAgainst = [&](const Vec3& v, SimplexVertex& sv) {
        if (indexed) {
            sv.indexA = supportIndex(a, -v);
            sv.indexB = supportIndex(b, v);
            sv.a = vertexOf(a, sv.indexA);
            sv.b = vertexOf(b, sv.indexB);
        } else {
            sv.a = supportA(-v);
            sv.b = supportB(v);
        }
        sv.w = sv.a - sv.b;
    };
    // The simplex the run ends on is the next run's start (at most a
    // triangle: after an overlap, the tetrahedron's first three vertices;
    // the next run adds the fourth by one search, through the checks below).
    const auto keepStart = [&] {
        if (!indexed) return;
        warm->count = std::min<std::uint32_t>(s.count, 3);
        for (std::uint32_t i = 0; i < warm->count; ++i) {
            warm->indexA[i] = s.v[i].indexA;
            warm->indexB[i] = s.v[i].indexB;
        }
    };

    Vec3 v;
    bool warmStarted = false;
    if (indexed && warm->count > 0 && warm->count <= 3) {
        // The last run's simplex at the shapes' new poses: points of A - B
        // like any other (a snapshot's indices beyond the shapes: a cold start).
        const std::size_t na = vertexCount(a), nb = vertexCount(b);
        bool fits = true;
        for (std::uint32_t i = 0; i < warm->count; ++i) fits = fits && warm->indexA[i] < na && warm->indexB[i] < nb;
        if (fits) {
            for (std::uint32_t i = 0; i < warm->count; ++i) {
                SimplexVertex& sv = s.v[i];
                sv.indexA = warm->indexA[i];
                sv.indexB = warm->indexB[i];
                sv.a = vertexOf(a, sv.indexA);
                sv.b = vertexOf(b, sv.indexB);
                sv.w = sv.a - sv.b;
            }
            s.count = warm->count;
            closestOnSimplex(s, v);  // at most a triangle: never "inside"
            warmStarted = true;
        }
    }
    if (!warmStarted) {
        v = guess != nullptr ? -*guess : a.center() - b.center();
        if (lengthSquared(v) < Real(1e-12)) v = {1, 0, 0};
        SimplexVertex& sv = s.v[0];
        vertexAgainst(v, sv);
        s.count = 1;
        s.bary[0] = 1;
        // The line of centres is a support direction like any other (w is
        // A - B's lowest point along it): when its plane already shows the
        // shapes beyond stopBeyond, stop before the first iteration (two
        // support calls fewer; for round hulls apart in a pile, most pairs).
        const Real plane = dot(v, sv.w), vv = dot(v, v);
        if (plane > 0 && plane * plane > stopBeyond * stopBeyond * vv) {
            r.beyond = true;
            r.distance = plane / std::sqrt(vv);
            keepStart();
            return r;
        }
        v = sv.w;
    }
    constexpr std::uint32_t kMaxIterations = 64;
    // Relative convergence tolerance on |v|^2 - v.w (van den Bergen 2004, 4.3.4).
    constexpr Real kRelTol = Real(1e-6);
    Real prevD2 = 1e30f;
    for (r.iterations = 0; r.iterations < kMaxIterations; ++r.iterations) {
        const Real vv = dot(v, v);
        if (vv < Real(1e-14)) { r.overlap = true; break; }
        SimplexVertex nv;
        vertexAgainst(v, nv);
        // Every point x of A - B has v.x >= v.w: the shapes are at least
        // v.w / |v| apart, and the full run's |v| never ends below that.
        const Real plane = dot(v, nv.w);
        if (plane > 0 && plane * plane > stopBeyond * stopBeyond * vv) {
            r.beyond = true;
            r.distance = plane / std::sqrt(vv);
            keepStart();
            return r;
        }
        // No progress possible: w is not closer to the origin along v than v itself.
        if (vv - dot(v, nv.w) <= kRelTol * vv) break;
        bool duplicate = false;
        for (std::uint32_t i = 0; i < s.count; ++i) {
            if (lengthSquared(s.v[i].w - nv.w) < Real(1e-14)) duplicate = true;
        }
        if (duplicate) break;
        const Simplex saved = s;
        s.v[s.count++] = nv;
        Vec3 closest;
        if (!closestOnSimplex(s, closest)) {
            // A tetrahedron holding the origin means overlap, unless w's
            // support plane already separates A - B from the origin: every
            // point x of A - B has v.x >= v.w > 0. Then the tetrahedron is
            // one GJK built almost flat (w lands between two earlier points
            // on a curved rim) and rounding put the origin inside it (with
            // single-precision side tests, a cylinder 12 cm from a thin
            // plate "overlapped" it: fuzz/corpus/narrowphase/
            // cylinder_near_thin_plate). The previous simplex and its
            // distance stand, as at the no-progress stop.
            if (dot(v, nv.w) > kRelTol * std::sqrt(vv * lengthSquared(nv.w))) {
                s = saved;
                break;
            }
            r.overlap = true;
            break;
        }
        const Real d2 = lengthSquared(closest);
        if (d2 >= prevD2 || d2 >= vv) {
            // Float noise made no progress: keep the previous, better simplex.
            s = saved;
            break;
        }
        prevD2 = d2;
        v = closest;
    }
    // Stopped for lack of progress with v within single precision's noise of
    // the origin, relative to the size of A - B: the origin is on or inside
    // the simplex as far as floats can tell, so the shapes overlap. (Two
    // concentric cylinders: the first segment runs through the origin, the
    // next triangle too, and the closest point stays at ~1e-6 m; reported as
    // separated, EPA then trusted it and gave a depth of 0 for shapes 5 m
    // deep in each other; found by fuzz/narrowphase_fuzz.cpp.)
    if (!r.overlap) {
        Real size2 = 0;
        for (std::uint32_t i = 0; i < s.count; ++i) size2 = std::max(size2, lengthSquared(s.v[i].w));
        if (dot(v, v) <= Real(1e-12) * size2) r.overlap = true;
    }
    Vec3 pa, pb;
    for (std::uint32_t i = 0; i < s.count; ++i) {
        pa += s.v[i].a * s.bary[i];
        pb += s.v[i].b * s.bary[i];
    }
    r.pointA = pa;
    r.pointB = pb;
    // Distance and direction from v, the closest point of A - B worked out
    // in double: pb - pa, a difference of two weighted sums of points metres
    // from the origin, carries their rounding (1e-7 m at a few metres), which
    // for hulls a few micrometres apart turned the normal by tens of degrees.
    const Real vLength = length(v);
    r.distance = r.overlap ? 0 : vLength;
    r.normal = !r.overlap && vLength > 0 ? v * (-1 / vLength) : Vec3{};
    keepStart();
    return r;
}

}  // namespace fulcrum::detail
