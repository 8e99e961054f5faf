// EPA with fixed-capacity storage. Horizon by the edge-list method: every
// face visible from the new support point is removed, its edges are pushed
// to a list, and an edge found twice (shared by two removed faces) cancels
// out; what remains is the horizon, which is fanned to the new point.
#include "collision/epa.hpp"

#include <cmath>

namespace fulcrum::detail {

namespace {

constexpr std::uint32_t kMaxVerts = 128;
constexpr std::uint32_t kMaxFaces = 256;
constexpr std::uint32_t kMaxEdges = 384;
constexpr std::uint32_t kMaxIterations = 96;
// Stop when the support plane is within this (relative) distance of the
// closest face. On curved shapes (cylinders) the normal error is about
// sqrt(2 tol / radius): 1e-6 gives ~2e-3 rad on a 0.5 m cylinder, 1e-5 gave 6e-3.
constexpr Real kTolerance = Real(1e-6);

struct Face {
    std::uint32_t i[3];
    Vec3 n;
    Real d;
    bool alive;
};

struct Polytope {
    SimplexVertex v[kMaxVerts];
    std::uint32_t vertCount = 0;
    Face f[kMaxFaces];
    std::uint32_t faceCount = 0;

    bool addFace(std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        if (faceCount == kMaxFaces) return false;
        Face& face = f[faceCount++];
        face.i[0] = a; face.i[1] = b; face.i[2] = c;
        const Vec3 n = cross(v[b].w - v[a].w, v[c].w - v[a].w);
        const Real len = length(n);
        face.alive = true;
        if (len < Real(1e-12)) {
            face.n = Vec3::zero();
            face.d = 1e30f;  // degenerate: never chosen as closest, removed when visible
            return true;
        }
        face.n = n / len;
        face.d = dot(face.n, v[a].w);
        return true;
    }
};

struct ClosestFace {
    SimplexVertex v[3];
    Vec3 n;
    Real d = 0;
    bool found = false;
};

// Which sets EPA expands: the full shapes, or their cores (radii left out).
enum class Sets : bool { Full, Cores };

SimplexVertex supportVertex(const ConvexShape& a, const ConvexShape& b, const Vec3& d, Sets sets) {
    SimplexVertex sv;
    sv.a = sets == Sets::Cores ? a.coreSupport(d) : a.support(d);
    sv.b = sets == Sets::Cores ? b.coreSupport(-d) : b.support(-d);
    sv.w = sv.a - sv.b;
    return sv;
}

// Grow GJK's simplex (fewer than 4 vertices when the origin sits on a face,
// edge or vertex of it) to a tetrahedron that encloses the origin.
bool buildTetrahedron(const ConvexShape& a, const ConvexShape& b, Sets sets, Simplex& s) {
    static const Vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    if (s.count == 0) {
        s.v[0] = supportVertex(a, b, {1, 0, 0}, sets);
        s.count = 1;
    }
    if (s.count == 1) {
        for (const Vec3& d : axes) {
            const SimplexVertex sv = supportVertex(a, b, d, sets);
            if (lengthSquared(sv.w - s.v[0].w) > Real(1e-10)) { s.v[1] = sv; s.count = 2; break; }
        }
        if (s.count < 2) return false;
    }
    if (s.count == 2) {
        const Vec3 dir = s.v[1].w - s.v[0].w;
        Vec3 t1, t2;
        orthonormalBasis(normalize(dir), t1, t2);
        const Vec3 tries[4] = {t1, -t1, t2, -t2};
        for (const Vec3& d : tries) {
            const SimplexVertex sv = supportVertex(a, b, d, sets);
            if (lengthSquared(cross(dir, sv.w - s.v[0].w)) > Real(1e-12)) { s.v[2] = sv; s.count = 3; break; }
        }
        if (s.count < 3) return false;
    }
    if (s.count == 3) {
        const Vec3 n = cross(s.v[1].w - s.v[0].w, s.v[2].w - s.v[0].w);
        const Vec3 tries[2] = {n, -n};
        for (const Vec3& d : tries) {
            const SimplexVertex sv = supportVertex(a, b, d, sets);
            if (std::fabs(dot(n, sv.w - s.v[0].w)) > Real(1e-9) * length(n)) { s.v[3] = sv; s.count = 4; break; }
        }
        if (s.count < 4) return false;
    }
    return true;
}

// EPA on the full shapes or on the cores; for the cores only when they
// overlap (false otherwise, and when their difference is flat). `coreRun`:
// see epaPenetration.
bool expandPolytope(const ConvexShape& a, const ConvexShape& b, Sets sets, PenetrationResult& out,
                    const GjkResult* coreRun) {
    // The caller's run on the cores is this run when it is on the cores, or
    // on full shapes without radii (their supports are the cores').
    const bool reuse = coreRun != nullptr && (sets == Sets::Cores || (a.radius == 0 && b.radius == 0));
    const GjkResult g = reuse ? *coreRun : gjkDistance(a, b, sets == Sets::Full);
    if (sets == Sets::Cores && !g.overlap) return false;
    if (!g.overlap && g.distance > Real(1e-6)) {
        // Touching or separated after all (the caller's core test was conservative).
        out.valid = true;
        out.normal = g.normal;
        out.depth = -g.distance;
        out.pointA = g.pointA;
        out.pointB = g.pointB;
        return true;
    }
    Simplex s = g.simplex;
    if (!buildTetrahedron(a, b, sets, s)) return false;

    static thread_local Polytope poly;  // ~20 KB; thread_local keeps it off small stacks
    Polytope& p = poly;
    p.vertCount = 0;
    p.faceCount = 0;
    for (std::uint32_t i = 0; i < 4; ++i) p.v[p.vertCount++] = s.v[i];
    // Orient the tetrahedron so its faces wind outward.
    if (dot(cross(p.v[1].w - p.v[0].w, p.v[2].w - p.v[0].w), p.v[3].w - p.v[0].w) > 0) {
        const SimplexVertex t = p.v[1]; p.v[1] = p.v[2]; p.v[2] = t;
    }
    p.addFace(0, 1, 2);
    p.addFace(0, 3, 1);
    p.addFace(0, 2, 3);
    p.addFace(1, 3, 2);

    std::uint32_t edges[kMaxEdges][2];
    // The closest face of the last polytope known to be sound: the answer.
    // Kept by value, because an expansion that goes wrong (below) has already
    // rewritten the face list when it is found out.
    ClosestFace closest;
    for (std::uint32_t iter = 0; iter < kMaxIterations; ++iter) {
        const Face* best = nullptr;
        for (std::uint32_t i = 0; i < p.faceCount; ++i) {
            if (p.f[i].alive && (best == nullptr || p.f[i].d < best->d)) best = &p.f[i];
        }
        if (best == nullptr || best->d >= 1e29f) break;
        closest = {{p.v[best->i[0]], p.v[best->i[1]], p.v[best->i[2]]}, best->n, best->d, true};
        const SimplexVertex w = supportVertex(a, b, best->n, sets);
        const Real gain = dot(w.w, best->n) - best->d;
        // Converged: the support plane is at the face (absolute + relative tolerance).
        const Real tolerance = kTolerance * (Real(1) + std::fabs(best->d));
        if (gain < tolerance || p.vertCount == kMaxVerts) break;
        const std::uint32_t wi = p.vertCount;
        p.v[p.vertCount++] = w;

        std::uint32_t edgeCount = 0;
        bool overflow = false;
        for (std::uint32_t i = 0; i < p.faceCount; ++i) {
            Face& f = p.f[i];
            if (!f.alive) continue;
            const bool visible = f.d >= 1e29f ? dot(cross(p.v[f.i[1]].w - p.v[f.i[0]].w, p.v[f.i[2]].w - p.v[f.i[0]].w),
                                                    w.w - p.v[f.i[0]].w) > 0
                                              : dot(f.n, w.w - p.v[f.i[0]].w) > 0;
            if (!visible) continue;
            f.alive = false;
            for (std::uint32_t e = 0; e < 3; ++e) {
                const std::uint32_t e0 = f.i[e], e1 = f.i[(e + 1) % 3];
                bool cancelled = false;
                for (std::uint32_t k = 0; k < edgeCount; ++k) {
                    if (edges[k][0] == e1 && edges[k][1] == e0) {
                        edges[k][0] = edges[edgeCount - 1][0];
                        edges[k][1] = edges[edgeCount - 1][1];
                        --edgeCount;
                        cancelled = true;
                        break;
                    }
                }
                if (cancelled) continue;
                if (edgeCount == kMaxEdges) { overflow = true; break; }
                edges[edgeCount][0] = e0;
                edges[edgeCount][1] = e1;
                ++edgeCount;
            }
        }
        if (overflow) break;
        // Compact dead faces so the array does not fill up with them.
        std::uint32_t live = 0;
        for (std::uint32_t i = 0; i < p.faceCount; ++i) {
            if (p.f[i].alive) p.f[live++] = p.f[i];
        }
        p.faceCount = live;
        if (p.faceCount + edgeCount > kMaxFaces) break;
        // The new polytope holds the old one, so none of its faces can be
        // nearer the origin than the face just expanded. One that is shows
        // that the visibility tests, on a point almost in the plane of the
        // faces around it, cut a horizon that is not a loop: the polytope is
        // no longer convex and its faces no longer enclose the origin. On a
        // cylinder's rim, where every support point lands a few micrometres
        // off the faces it replaces, that gave faces metres behind the
        // origin and depths of -1.6 m for cylinders 2.6 m deep in each other
        // (fuzz/corpus/narrowphase/crossed_cylinders_same_point). The face
        // chosen before this expansion stands: a lower bound of the depth,
        // as every EPA answer, within `gain` of the support plane.
        const std::uint32_t firstNew = p.faceCount;
        for (std::uint32_t k = 0; k < edgeCount; ++k) p.addFace(edges[k][0], edges[k][1], wi);
        bool sound = true;
        for (std::uint32_t i = firstNew; i < p.faceCount; ++i) {
            if (p.f[i].d < closest.d - tolerance) sound = false;
        }
        if (!sound) break;
    }
    if (!closest.found) return false;

    // Barycentric coordinates of the origin's projection on the closest face.
    const Vec3 proj = closest.n * closest.d;
    const SimplexVertex &v0 = closest.v[0], &v1 = closest.v[1], &v2 = closest.v[2];
    const Vec3 e0 = v1.w - v0.w, e1 = v2.w - v0.w, e2 = proj - v0.w;
    const Real d00 = dot(e0, e0), d01 = dot(e0, e1), d11 = dot(e1, e1), d20 = dot(e2, e0), d21 = dot(e2, e1);
    const Real den = d00 * d11 - d01 * d01;
    Real bv = 0, bw = 0;
    if (std::fabs(den) > Real(1e-20)) {
        bv = (d11 * d20 - d01 * d21) / den;
        bw = (d00 * d21 - d01 * d20) / den;
    }
    const Real bu = 1 - bv - bw;
    out.valid = true;
    // The closest face's outward normal n: A - B shifted by -n*d no longer
    // holds the origin, i.e. moving B by +n*d separates the shapes, so n points
    // from A to B; pointA - pointB = n*d.
    out.normal = closest.n;
    out.depth = closest.d;
    out.pointA = v0.a * bu + v1.a * bv + v2.a * bw;
    out.pointB = v0.b * bu + v1.b * bv + v2.b * bw;
    return true;
}

}  // namespace

PenetrationResult epaPenetration(const ConvexShape& a, const ConvexShape& b, const GjkResult* coreRun) {
    PenetrationResult out;
    // A rounded shape is its core grown by its radius, so A - B is the cores'
    // difference grown by the sum of the radii, and when the cores overlap
    // the depth is theirs plus the radii, along the same normal: exact. The
    // cores are polytopes or segments, which EPA resolves exactly in a few
    // steps; the full shapes are curved, and EPA's polytope, out of vertices
    // long before it fits a sphere of metres, stopped 1.7 mm short of the
    // depth of a capsule of radius 3.2 m around a small hull
    // (fuzz/corpus/narrowphase/small_hull_inside_capsule).
    if ((a.radius > 0 || b.radius > 0) && expandPolytope(a, b, Sets::Cores, out, coreRun)) {
        out.depth += a.radius + b.radius;
        out.pointA += out.normal * a.radius;
        out.pointB -= out.normal * b.radius;
        return out;
    }
    out = PenetrationResult{};
    if (!expandPolytope(a, b, Sets::Full, out, coreRun)) out.valid = false;
    return out;
}

}  // namespace fulcrum::detail
