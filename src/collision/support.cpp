// Support mappings and supporting faces of the convex shapes.
#include "collision/support.hpp"

#include <algorithm>
#include <cmath>

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

}  // namespace

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
        case ConvexKind::Hull: {
            const Vec3 l = inverseRotate(xf.q, d);
            const std::vector<Vec3>& v = hull->vertices;
            std::size_t best = 0;
            Real bestDot = dot(v[0], l);
            for (std::size_t i = 1; i < v.size(); ++i) {
                const Real dd = dot(v[i], l);
                if (dd > bestDot) { bestDot = dd; best = i; }
            }
            return transformPoint(xf, v[best]);
        }
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

void supportingFace(const ConvexShape& s, const Vec3& n, SupportFace& out) {
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
            const std::size_t k = static_cast<std::size_t>(axis), u = (k + 1) % 3, v = (k + 2) % 3;
            const Vec3 e = s.halfExtents;
            Vec3 c[4];
            const Real su[4] = {1, -1, -1, 1}, sv[4] = {1, 1, -1, -1};
            for (int i = 0; i < 4; ++i) {
                Vec3 p;
                p[k] = sign * e[k];
                p[u] = su[i] * e[u];
                p[v] = sv[i] * e[v] * sign;  // mirror the winding on the negative face
                c[i] = p;
            }
            for (int i = 0; i < 4; ++i) out.points[i] = transformPoint(s.xf, c[i]);
            out.count = 4;
            out.id = static_cast<std::uint32_t>(2 * axis + (sign > 0 ? 0 : 1));
            Vec3 fn;
            fn[k] = sign;
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
            std::uint32_t top = 0;
            Real topDot = dot(h.vertices[0], l);
            for (std::uint32_t i = 1; i < h.vertices.size(); ++i) {
                const Real d = dot(h.vertices[i], l);
                if (d > topDot) { topDot = d; top = i; }
            }
            std::size_t best = 0;
            Real bestDot = -2;
            for (std::size_t f = 0; f < h.faces.size(); ++f) {
                const HullFace& face = h.faces[f];
                const Real d = dot(face.normal, l);
                if (d <= bestDot) continue;
                const auto first = h.faceVertices.begin() + face.firstIndex;
                if (std::find(first, first + face.indexCount, top) == first + face.indexCount) continue;
                bestDot = d;
                best = f;
            }
            const HullFace& face = h.faces[best];
            const std::uint32_t count = face.indexCount < kMaxFacePoints ? face.indexCount : kMaxFacePoints;
            for (std::uint32_t i = 0; i < count; ++i) {
                out.points[i] = transformPoint(s.xf, h.vertices[h.faceVertices[face.firstIndex + i]]);
            }
            out.count = count;
            out.id = static_cast<std::uint32_t>(best);
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
