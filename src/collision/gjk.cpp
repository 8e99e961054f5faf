// GJK with Ericson's Voronoi-region simplex solver (RTCD 5.1.5 and 9.5): the
// closest point of a segment, triangle or tetrahedron to the origin, with the
// barycentric weights kept so the closest points on A and B follow directly.
#include "collision/gjk.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>

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

// Closest point to the origin on triangle (s.v[i0], s.v[i1], s.v[i2]) (RTCD 5.1.5),
// written into `out` as (indices, weights).
struct Sub {
    std::uint32_t idx[3];
    Real w[3];
    std::uint32_t n;
    Vec3 p;
};

Sub closestTriangle(const Simplex& s, std::uint32_t ia, std::uint32_t ib, std::uint32_t ic) {
    const Vec3 a = s.v[ia].w, b = s.v[ib].w, c = s.v[ic].w;
    const Vec3 ab = b - a, ac = c - a, ap = -a;
    const Real d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return {{ia}, {1}, 1, a};
    const Vec3 bp = -b;
    const Real d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return {{ib}, {1}, 1, b};
    const Real vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) {
        const Real v = d1 / (d1 - d3);
        return {{ia, ib}, {1 - v, v}, 2, a + ab * v};
    }
    const Vec3 cp = -c;
    const Real d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return {{ic}, {1}, 1, c};
    const Real vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) {
        const Real w = d2 / (d2 - d6);
        return {{ia, ic}, {1 - w, w}, 2, a + ac * w};
    }
    const Real va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
        const Real w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return {{ib, ic}, {1 - w, w}, 2, b + (c - b) * w};
    }
    const Real denom = va + vb + vc;
    if (!(std::fabs(denom) > Real(0))) return {{ia}, {1}, 1, a};  // degenerate (zero-area) triangle
    const Real inv = 1 / denom;
    const Real v = vb * inv, w = vc * inv;
    return {{ia, ib, ic}, {1 - v - w, v, w}, 3, a + ab * v + ac * w};
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

}  // namespace

bool closestOnSimplex(Simplex& s, Vec3& closest) {
    switch (s.count) {
        case 1:
            s.bary[0] = 1;
            closest = s.v[0].w;
            return true;
        case 2: {
            const Vec3 a = s.v[0].w, b = s.v[1].w, ab = b - a;
            const Real denom = dot(ab, ab);
            Real t = denom > 0 ? -dot(a, ab) / denom : 0;
            if (t <= 0) { keep(s, {0}, {1}); closest = a; return true; }
            if (t >= 1) { keep(s, {1}, {1}); closest = b; return true; }
            s.bary[0] = 1 - t;
            s.bary[1] = t;
            closest = a + ab * t;
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
                const Vec3 a = s.v[f[0]].w, b = s.v[f[1]].w, c = s.v[f[2]].w, d = s.v[f[3]].w;
                const Vec3 n = cross(b - a, c - a);
                const Real sideO = dot(-a, n), sideD = dot(d - a, n);
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

GjkResult gjkDistance(const ConvexShape& a, const ConvexShape& b, bool withRadius) {
    GjkResult r;
    Simplex& s = r.simplex;
    auto supportA = [&](const Vec3& d) { return withRadius ? a.support(d) : a.coreSupport(d); };
    auto supportB = [&](const Vec3& d) { return withRadius ? b.support(d) : b.coreSupport(d); };

    Vec3 v = a.center() - b.center();
    if (lengthSquared(v) < Real(1e-12)) v = {1, 0, 0};
    {
        SimplexVertex& sv = s.v[0];
        sv.a = supportA(-v);
        sv.b = supportB(v);
        sv.w = sv.a - sv.b;
        s.count = 1;
        s.bary[0] = 1;
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
        nv.a = supportA(-v);
        nv.b = supportB(v);
        nv.w = nv.a - nv.b;
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
        if (!closestOnSimplex(s, closest)) { r.overlap = true; break; }
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
    r.distance = r.overlap ? 0 : length(pa - pb);
    return r;
}

}  // namespace fulcrum::detail
