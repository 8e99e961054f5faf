// Support mappings and supporting faces of the convex shapes.
#include "collision/support.hpp"

#include <algorithm>
#include <cmath>
#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE
#include <emmintrin.h>
#endif

namespace fulcrum::detail {

namespace {

inline Real sgn(Real v) { return v >= 0 ? Real(1) : Real(-1); }

// Below this |cos| between a direction and a capsule/cylinder axis the side is
// "flat" against the direction; above kAxisAligned a cylinder cap is. A 0.05
// band (about 3 degrees) is wide enough to keep a resting capsule's two points
// from flickering to one under solver jitter, narrow enough that a visibly
// tilted capsule gets the single end point it really touches with.
constexpr Real kSideFlat = Real(0.05);
constexpr Real kAxisAligned = Real(0.95);

// The reference scan: the first vertex of the largest dot (NaNs never win).
std::uint32_t scanSupportIndex(const std::vector<Vec3>& v, const Vec3& d) {
    std::uint32_t best = 0;
    Real bestDot = dot(v[0], d);
    for (std::uint32_t i = 1; i < v.size(); ++i) {
        const Real dd = dot(v[i], d);
        if (dd > bestDot) {
            bestDot = dd;
            best = i;
        }
    }
    return best;
}

#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE
bool detectAvx2SupportSearch() {
#if (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || defined(__i386__))
    // cpu_init first: this may run before libgcc's own initialiser has
    // (as solver/contact_wide.cpp).
    __builtin_cpu_init();
    return hullSupportAvx2Compiled() && __builtin_cpu_supports("avx2");
#else
    return false;
#endif
}

// A plain flag, read by every search: a function-local static's guard (and
// its initialiser inlined) made each search save and restore six registers,
// 35 of the eight-lane path's 180 instructions. A hull searched from another
// file's static constructor before this initialiser has run reads false and
// takes the four lanes: the same answer.
const bool avx2SupportSearch = detectAvx2SupportSearch();
#endif

}  // namespace

void deriveHullTables(ConvexHull& hull) {
    const std::size_t n = hull.vertices.size();
    hull.vertexRows.resize(3 * n);
    for (std::size_t i = 0; i < n; ++i) {
        hull.vertexRows[i] = hull.vertices[i].x;
        hull.vertexRows[n + i] = hull.vertices[i].y;
        hull.vertexRows[2 * n + i] = hull.vertices[i].z;
    }
    // Counted over the faces' index ranges, not over faceVertices: a loaded
    // snapshot's faces are each checked to lie in range, but may overlap or
    // leave gaps (found by fuzz/snapshot_fuzz.cpp), and a built hull's
    // partition it, where both counts agree.
    hull.vertexFaceStart.assign(n + 1, 0);
    std::size_t total = 0;
    for (const HullFace& face : hull.faces) {
        for (std::uint32_t i = 0; i < face.indexCount; ++i) ++hull.vertexFaceStart[hull.faceVertices[face.firstIndex + i] + 1];
        total += face.indexCount;
    }
    for (std::size_t v = 0; v < n; ++v) hull.vertexFaceStart[v + 1] += hull.vertexFaceStart[v];
    hull.vertexFaces.assign(total, 0);
    std::vector<std::uint32_t> next(hull.vertexFaceStart.begin(), hull.vertexFaceStart.end() - 1);
    // Faces in ascending order, so each vertex's list is ascending too.
    for (std::uint32_t f = 0; f < hull.faces.size(); ++f) {
        const HullFace& face = hull.faces[f];
        for (std::uint32_t i = 0; i < face.indexCount; ++i) {
            hull.vertexFaces[next[hull.faceVertices[face.firstIndex + i]]++] = f;
        }
    }
}

// The support search was half of Box3D's hull pile's instructions as a scalar
// scan (docs/narrow-phase.md, "Hull support"). With SSE2 it runs four vertices
// at a time, straight from the vertex array (x y z x | y z x y | z x y z,
// transposed in registers): each lane scans its own vertices as the scalar
// scan does (the same dot, (x dx + y dy) + z dz, rounded the same way, and
// only a strictly larger one wins), and the lanes' winners and the last few
// vertices are merged by value, then by the smaller index: the scalar
// answer, bit for bit. A NaN (a non-finite direction) takes the scalar scan,
// whose answer with NaNs the merge would not reproduce.
#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE
namespace {

// The four-lane search, and the scan for fewer than eight vertices or a NaN;
// out of line, so the eight-lane path saves no registers for it.
[[gnu::noinline]] std::uint32_t fourLaneSupportIndex(const std::vector<Vec3>& v, const Vec3& d) {
    static_assert(sizeof(Vec3) == 3 * sizeof(float), "the vertices are read as packed floats");
    const std::uint32_t n = static_cast<std::uint32_t>(v.size());
    const std::uint32_t blocks = n / 4;
    if (blocks >= 2) {
        const float* p = &v[0].x;
        const __m128 dx = _mm_set1_ps(d.x), dy = _mm_set1_ps(d.y), dz = _mm_set1_ps(d.z);
        __m128 best = _mm_set1_ps(0), nan = _mm_setzero_ps();
        __m128i bestIndex = _mm_setzero_si128(), index = _mm_setr_epi32(0, 1, 2, 3);
        const __m128i four = _mm_set1_epi32(4);
        for (std::uint32_t b = 0; b < blocks; ++b, p += 12) {
            const __m128 r0 = _mm_loadu_ps(p), r1 = _mm_loadu_ps(p + 4), r2 = _mm_loadu_ps(p + 8);
            const __m128 t0 = _mm_shuffle_ps(r1, r2, _MM_SHUFFLE(2, 1, 3, 2));  // x2 y2 x3 y3
            const __m128 t1 = _mm_shuffle_ps(r0, r1, _MM_SHUFFLE(1, 0, 2, 1));  // y0 z0 y1 z1
            const __m128 x = _mm_shuffle_ps(r0, t0, _MM_SHUFFLE(2, 0, 3, 0));
            const __m128 y = _mm_shuffle_ps(t1, t0, _MM_SHUFFLE(3, 1, 2, 0));
            const __m128 z = _mm_shuffle_ps(t1, r2, _MM_SHUFFLE(3, 0, 3, 1));
            const __m128 dd = _mm_add_ps(_mm_add_ps(_mm_mul_ps(x, dx), _mm_mul_ps(y, dy)), _mm_mul_ps(z, dz));
            nan = _mm_or_ps(nan, _mm_cmpunord_ps(dd, dd));
            if (b == 0) {
                best = dd;
                bestIndex = index;
            } else {
                const __m128i larger = _mm_castps_si128(_mm_cmpgt_ps(dd, best));
                best = _mm_max_ps(dd, best);  // dd > best ? dd : best, NaN-free here
                bestIndex = _mm_or_si128(_mm_and_si128(larger, index), _mm_andnot_si128(larger, bestIndex));
            }
            index = _mm_add_epi32(index, four);
        }
        if (_mm_movemask_ps(nan) == 0) {
            alignas(16) float value[4];
            alignas(16) std::uint32_t at[4];
            _mm_store_ps(value, best);
            _mm_store_si128(reinterpret_cast<__m128i*>(at), bestIndex);
            std::uint32_t top = at[0];
            float topDot = value[0];
            for (int k = 1; k < 4; ++k) {
                if (value[k] > topDot || (value[k] == topDot && at[k] < top)) {
                    topDot = value[k];
                    top = at[k];
                }
            }
            for (std::uint32_t i = 4 * blocks; i < n; ++i) {  // later than every lane's: only a larger one wins
                const float dd = dot(v[i], d);
                if (dd > topDot) {
                    topDot = dd;
                    top = i;
                }
            }
            return top;
        }
    }
    return scanSupportIndex(v, d);
}

}  // namespace
#endif

std::uint32_t hullSupportIndex(const ConvexHull& hull, const Vec3& d) {
#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE
    const std::uint32_t n = static_cast<std::uint32_t>(hull.vertices.size());
    // Eight lanes over the hull's coordinate rows where the CPU has AVX2:
    // the same merge, so the same answer (docs/narrow-phase.md, "Hull
    // support"); a NaN (top == n) is left to the scan.
    if (n >= 8 && hull.vertexRows.size() == 3 * std::size_t{n} && avx2SupportSearch) {
        const float* rows = hull.vertexRows.data();
        const std::uint32_t top = hullSupportIndexAvx2(rows, rows + n, rows + 2 * n, n, d);
        if (top < n) return top;
    }
    return fourLaneSupportIndex(hull.vertices, d);
#else
    return scanSupportIndex(hull.vertices, d);
#endif
}

void boxFaceCorners(const Vec3& e, int axis, Real sign, Vec3 corners[4]) {
    // The corners (k, u, v) = (axis, axis + 1, axis + 2) mod 3: k at sign e_k,
    // u at +-e_u, v at +-e_v mirrored by the sign (the winding on the
    // negative face), written out per axis so no component is indexed
    // at run time (the same values as a loop over p[k], p[u], p[v]).
    const Real ek = sign * e[static_cast<std::size_t>(axis)];
    const auto corner = [&](Real su, Real sv) {
        switch (axis) {
            case 0: return Vec3{ek, su * e.y, sv * e.z * sign};
            case 1: return Vec3{sv * e.x * sign, ek, su * e.z};
            default: return Vec3{su * e.x, sv * e.y * sign, ek};
        }
    };
    corners[0] = corner(1, 1);
    corners[1] = corner(-1, 1);
    corners[2] = corner(-1, -1);
    corners[3] = corner(1, -1);
}

std::uint32_t hullFaceAtVertex(const ConvexHull& hull, std::uint32_t top, const Vec3& d) {
    std::uint32_t best = 0;
    Real bestDot = -2;
    if (hull.vertexFaceStart.size() == hull.vertices.size() + 1) {
        // The faces at the vertex from the hull's adjacency, in face order:
        // the same choice as the scan below.
        for (std::uint32_t k = hull.vertexFaceStart[top]; k < hull.vertexFaceStart[top + 1]; ++k) {
            const std::uint32_t f = hull.vertexFaces[k];
            const Real dd = dot(hull.faces[f].normal, d);
            if (dd <= bestDot) continue;
            bestDot = dd;
            best = f;
        }
    } else {
        for (std::uint32_t f = 0; f < hull.faces.size(); ++f) {
            const HullFace& face = hull.faces[f];
            const Real dd = dot(face.normal, d);
            if (dd <= bestDot) continue;
            const auto first = hull.faceVertices.begin() + face.firstIndex;
            if (std::find(first, first + face.indexCount, top) == first + face.indexCount) continue;
            bestDot = dd;
            best = f;
        }
    }
    return best;
}

Vec3 ConvexShape::coreSupport(const Vec3& d) const {
    switch (kind) {
        case ConvexKind::Point: return xf.p;
        case ConvexKind::Segment: {
            const Vec3 axis = rotate(xf.q, Vec3{0, halfHeight, 0});
            return dot(axis, d) >= 0 ? xf.p + axis : xf.p - axis;
        }
        case ConvexKind::Box: {
            const Vec3 l = inverseRotate(xf.q, d);
            return transformPoint(xf, {sgn(l.x) * halfExtents.x, sgn(l.y) * halfExtents.y, sgn(l.z) * halfExtents.z});
        }
        case ConvexKind::Hull: return transformPoint(xf, hull->vertices[hullSupportIndex(*hull, inverseRotate(xf.q, d))]);
        case ConvexKind::Cylinder: {
            const Vec3 l = inverseRotate(xf.q, d);
            const Real r = std::sqrt(l.x * l.x + l.z * l.z);
            Vec3 p{0, sgn(l.y) * halfHeight, 0};
            if (r > Real(1e-12)) {
                p.x = cylinderRadius * l.x / r;
                p.z = cylinderRadius * l.z / r;
            }
            return transformPoint(xf, p);
        }
        case ConvexKind::Triangle: {
            const Real d0 = dot(triangle[0], d), d1 = dot(triangle[1], d), d2 = dot(triangle[2], d);
            if (d0 >= d1 && d0 >= d2) return triangle[0];
            return d1 >= d2 ? triangle[1] : triangle[2];
        }
    }
    return xf.p;
}

Vec3 ConvexShape::support(const Vec3& d) const {
    const Vec3 c = coreSupport(d);
    if (radius == 0) return c;
    return c + normalize(d) * radius;
}

Vec3 ConvexShape::support(const Vec3& d, std::uint32_t& hullVertex) const {
    if (kind != ConvexKind::Hull) {
        hullVertex = kNoVertex;
        return support(d);
    }
    // coreSupport's hull case, keeping the index.
    hullVertex = hullSupportIndex(*hull, inverseRotate(xf.q, d));
    const Vec3 c = transformPoint(xf, hull->vertices[hullVertex]);
    if (radius == 0) return c;
    return c + normalize(d) * radius;
}

void ConvexShape::extent(const Vec3& d, Real& lo, Real& hi) const {
    if (kind != ConvexKind::Hull) {
        lo = dot(d, support(-d));
        hi = dot(d, support(d));
        return;
    }
    const Vec3 l = inverseRotate(xf.q, d);
    const std::vector<Vec3>& v = hull->vertices;
    Real low = dot(v[0], l), high = low;
    for (std::size_t i = 1; i < v.size(); ++i) {
        const Real dd = dot(v[i], l);
        low = std::min(low, dd);
        high = std::max(high, dd);
    }
    const Real offset = dot(d, xf.p);
    lo = low + offset;
    hi = high + offset;
    if (radius > 0) {  // a rounded hull
        const Real grow = radius * length(d);
        lo -= grow;
        hi += grow;
    }
}

Vec3 ConvexShape::center() const {
    if (kind == ConvexKind::Triangle) return (triangle[0] + triangle[1] + triangle[2]) * (Real(1) / 3);
    if (kind == ConvexKind::Hull) return transformPoint(xf, hull->centroid);
    return xf.p;
}

Real ConvexShape::boundingRadius() const {
    switch (kind) {
        case ConvexKind::Point: return radius;
        case ConvexKind::Segment: return halfHeight + radius;
        case ConvexKind::Box: return length(halfExtents) + radius;
        case ConvexKind::Hull: {
            Real r2 = 0;
            for (const Vec3& v : hull->vertices) r2 = std::max(r2, lengthSquared(v));
            return std::sqrt(r2) + radius;
        }
        case ConvexKind::Cylinder: return std::sqrt(cylinderRadius * cylinderRadius + halfHeight * halfHeight) + radius;
        case ConvexKind::Triangle: {
            const Vec3 c = center();
            return std::sqrt(std::max({lengthSquared(triangle[0] - c), lengthSquared(triangle[1] - c), lengthSquared(triangle[2] - c)}));
        }
    }
    return 0;
}

ConvexShape makeConvexCore(const Shape& shape, const Transform& xf) {
    ConvexShape s;
    s.xf = xf;
    switch (shape.type()) {
        case ShapeType::Sphere:
            s.kind = ConvexKind::Point;
            s.radius = shape.radius();
            break;
        case ShapeType::Capsule:
            s.kind = ConvexKind::Segment;
            s.radius = shape.radius();
            s.halfHeight = shape.halfHeight();
            break;
        case ShapeType::Box:
            s.kind = ConvexKind::Box;
            s.halfExtents = shape.halfExtents();
            // Rounded: the core is the outer size minus the convex radius.
            if (const Real r = shape.convexRadius(); r > 0) s.halfExtents -= Vec3::splat(r);
            break;
        case ShapeType::Cylinder:
            s.kind = ConvexKind::Cylinder;
            s.cylinderRadius = shape.radius();
            s.halfHeight = shape.halfHeight();
            if (const Real r = shape.convexRadius(); r > 0) {
                s.cylinderRadius -= r;
                s.halfHeight -= r;
            }
            break;
        case ShapeType::ConvexHull:  // a rounded hull's points are already its core
            s.kind = ConvexKind::Hull;
            s.hull = &shape.hull();
            break;
        default: break;  // planes, meshes and compounds never reach here (dispatcher)
    }
    return s;
}

ConvexShape makeConvex(const Shape& shape, const Transform& xf) {
    ConvexShape s = makeConvexCore(shape, xf);
    // A rounded shape's radius is added back like a sphere's or capsule's.
    if (const Real r = shape.convexRadius(); r > 0) s.radius = r;
    return s;
}

ConvexShape makeTriangle(const Vec3& a, const Vec3& b, const Vec3& c) {
    ConvexShape s;
    s.kind = ConvexKind::Triangle;
    s.triangle[0] = a;
    s.triangle[1] = b;
    s.triangle[2] = c;
    return s;
}

void supportingFace(const ConvexShape& s, const Vec3& n, SupportFace& out, std::uint32_t hullVertex) {
    out.count = 0;
    out.id = 0;
    out.normal = n;
    auto single = [&] {
        out.points[0] = s.support(n);
        out.count = 1;
    };
    switch (s.kind) {
        case ConvexKind::Point: single(); return;
        case ConvexKind::Segment: {
            const Vec3 axis = rotate(s.xf.q, Vec3{0, 1, 0});
            if (std::fabs(dot(axis, n)) > kSideFlat) { single(); return; }
            const Vec3 off = n * s.radius;
            out.points[0] = s.xf.p + axis * s.halfHeight + off;
            out.points[1] = s.xf.p - axis * s.halfHeight + off;
            out.count = 2;
            return;
        }
        case ConvexKind::Box: {
            const Vec3 l = inverseRotate(s.xf.q, n);
            const Vec3 a = abs(l);
            const int axis = maxAxis(a);
            const Real sign = sgn(l[static_cast<std::size_t>(axis)]);
            // Face axis k with sign: corners counter-clockwise seen from outside.
            const Vec3 e = s.halfExtents;
            boxFaceCorners(e, axis, sign, out.points);
            for (std::uint32_t i = 0; i < 4; ++i) out.points[i] = transformPoint(s.xf, out.points[i]);
            out.count = 4;
            out.id = static_cast<std::uint32_t>(2 * axis + (sign > 0 ? 0 : 1));
            const Vec3 fn = axis == 0 ? Vec3{sign, 0, 0} : axis == 1 ? Vec3{0, sign, 0} : Vec3{0, 0, sign};
            out.normal = rotate(s.xf.q, fn);
            return;
        }
        case ConvexKind::Hull: {
            const ConvexHull& h = *s.hull;
            const Vec3 l = inverseRotate(s.xf.q, n);
            // The face most aligned with n among the faces at the support
            // vertex, not among all faces: the face whose normal is nearest to
            // n need not touch the vertex farthest along n (a hull resting on a
            // vertex of a long, narrow Gauss-map cell), and clipping that face
            // would lose the deepest point (docs/narrow-phase.md, "Hull
            // supporting face").
            const std::uint32_t top = hullVertex != kNoVertex ? hullVertex : hullSupportIndex(h, l);
            const std::uint32_t best = hullFaceAtVertex(h, top, l);
            const HullFace& face = h.faces[best];
            const std::uint32_t count = face.indexCount < kMaxFacePoints ? face.indexCount : kMaxFacePoints;
            for (std::uint32_t i = 0; i < count; ++i) {
                out.points[i] = transformPoint(s.xf, h.vertices[h.faceVertices[face.firstIndex + i]]);
            }
            out.count = count;
            out.id = best;
            out.normal = rotate(s.xf.q, face.normal);
            return;
        }
        case ConvexKind::Cylinder: {
            const Vec3 axis = rotate(s.xf.q, Vec3{0, 1, 0});
            const Real c = dot(axis, n);
            if (std::fabs(c) >= kAxisAligned) {
                const Real sign = sgn(c);
                // The cap as a square of rim points (see kCylinderCapPoints),
                // counter-clockwise about the cap's outward normal (t1 x t2 = axis * sign).
                // Rim points fixed in the cylinder's own frame, so the manifold
                // moves with the body (invariant under rigid motions) and the
                // feature ids of the rim points stay put.
                const Vec3 t1 = rotate(s.xf.q, Vec3{1, 0, 0});
                const Vec3 t2 = rotate(s.xf.q, Vec3{0, 0, 1}) * -sign;
                const Vec3 capCenter = s.xf.p + axis * (sign * s.halfHeight);
                for (std::uint32_t i = 0; i < kCylinderCapPoints; ++i) {
                    const Real ang = Real(2 * 3.14159265358979) * static_cast<Real>(i) / static_cast<Real>(kCylinderCapPoints);
                    out.points[i] = capCenter + (t1 * dmath::cos(ang) + t2 * dmath::sin(ang)) * s.cylinderRadius;
                }
                out.count = kCylinderCapPoints;
                out.id = sign > 0 ? 0u : 1u;
                out.normal = axis * sign;
                return;
            }
            if (std::fabs(c) <= kSideFlat) {
                const Vec3 radial = normalize(n - axis * c) * s.cylinderRadius;
                out.points[0] = s.xf.p + axis * s.halfHeight + radial;
                out.points[1] = s.xf.p - axis * s.halfHeight + radial;
                out.count = 2;
                out.id = 2;
                return;
            }
            single();
            out.id = 3;
            return;
        }
        case ConvexKind::Triangle: {
            const Vec3* t = s.triangle;
            const Vec3 tn = normalize(cross(t[1] - t[0], t[2] - t[0]));
            const Real c = dot(tn, n);
            if (c >= 0) {
                out.points[0] = t[0]; out.points[1] = t[1]; out.points[2] = t[2];
                out.normal = tn;
                out.id = 0;
            } else {
                out.points[0] = t[0]; out.points[1] = t[2]; out.points[2] = t[1];
                out.normal = -tn;
                out.id = 1;
            }
            out.count = 3;
            return;
        }
    }
}

}  // namespace fulcrum::detail
