// Ray casts and closest points for every shape type. Each query moves the ray
// or point into the shape's frame, solves there in closed form, and moves the
// answer back. Conventions are documented in shape_queries.hpp.
#include "collision/shape_queries.hpp"

#include <algorithm>
#include <cmath>

#include "collision/heightfield.hpp"
#include "collision/mesh_bvh.hpp"

namespace fulcrum {

namespace {

constexpr Real kInf = std::numeric_limits<Real>::infinity();

struct LocalHit {
    Real fraction = 0;
    Vec3 normal;          // shape-local, unit
    bool inside = false;  // started inside a solid: fraction 0, normal from the ray
    std::uint32_t child = kNoSubShape;
    std::uint32_t triangle = kNoSubShape;
};

// Sphere of radius r at the origin. Assumes the origin is outside (c > 0).
// The root is taken as c / (-b + sqrt(disc)), which avoids the cancellation
// of (-b - sqrt(disc)) / a when the ray passes close to the centre's side.
std::optional<LocalHit> raySphere(const Vec3& o, const Vec3& d, Real r, Real maxFraction) {
    const Real c = dot(o, o) - r * r;
    if (c <= 0) return LocalHit{0, {}, true};
    const Real b = dot(o, d);
    if (b >= 0) return std::nullopt;  // outside and moving away
    const Real a = dot(d, d);
    // disc = b^2 - a c, computed as a |o x d|-style difference would lose
    // precision; for the sizes used in games float is adequate here.
    const Real disc = b * b - a * c;
    if (disc < 0) return std::nullopt;
    const Real t = c / (-b + std::sqrt(disc));
    if (t > maxFraction) return std::nullopt;
    return LocalHit{t, normalize(o + d * t)};
}

std::optional<LocalHit> rayBox(const Vec3& o, const Vec3& d, const Vec3& h, Real maxFraction) {
    if (std::fabs(o.x) <= h.x && std::fabs(o.y) <= h.y && std::fabs(o.z) <= h.z) return LocalHit{0, {}, true};
    Real tEnter = -kInf, tExit = maxFraction;
    std::size_t axis = 0;
    for (std::size_t i = 0; i < 3; ++i) {
        if (d[i] == 0) {
            if (std::fabs(o[i]) > h[i]) return std::nullopt;
            continue;
        }
        const Real inv = 1 / d[i];
        Real t1 = (-h[i] - o[i]) * inv, t2 = (h[i] - o[i]) * inv;
        if (t1 > t2) std::swap(t1, t2);
        if (t1 > tEnter) { tEnter = t1; axis = i; }
        tExit = std::min(tExit, t2);
        if (tEnter > tExit) return std::nullopt;
    }
    if (tEnter < 0 || tEnter > maxFraction) return std::nullopt;
    Vec3 n;
    n[axis] = d[axis] > 0 ? Real(-1) : Real(1);
    return LocalHit{tEnter, n};
}

std::optional<LocalHit> rayCapsule(const Vec3& o, const Vec3& d, Real r, Real h, Real maxFraction) {
    const Vec3 onAxis{0, std::clamp(o.y, -h, h), 0};
    if (lengthSquared(o - onAxis) <= r * r) return LocalHit{0, {}, true};
    // The capsule is the union of a finite cylinder and two spheres; from
    // outside, the first entry into a union is the first entry into any piece.
    std::optional<LocalHit> best;
    const Real a = d.x * d.x + d.z * d.z;
    const Real c = o.x * o.x + o.z * o.z - r * r;
    const Real b = o.x * d.x + o.z * d.z;
    if (a > 0 && c > 0 && b < 0) {
        const Real disc = b * b - a * c;
        if (disc >= 0) {
            const Real t = c / (-b + std::sqrt(disc));
            const Real y = o.y + t * d.y;
            if (t <= maxFraction && std::fabs(y) <= h) {
                best = LocalHit{t, normalize(Vec3{o.x + t * d.x, 0, o.z + t * d.z})};
            }
        }
    }
    for (const Real cy : {h, -h}) {
        const Vec3 center{0, cy, 0};
        const auto hit = raySphere(o - center, d, r, best ? best->fraction : maxFraction);
        if (hit && !hit->inside && (!best || hit->fraction < best->fraction)) best = hit;
    }
    return best;
}

std::optional<LocalHit> rayCylinder(const Vec3& o, const Vec3& d, Real r, Real h, Real maxFraction) {
    const Real c = o.x * o.x + o.z * o.z - r * r;
    if (std::fabs(o.y) <= h && c <= 0) return LocalHit{0, {}, true};
    // Clip the ray against the slab |y| <= h and the infinite cylinder x^2 + z^2 <= r^2.
    Real tEnter = -kInf, tExit = maxFraction;
    bool capEntry = false;
    if (d.y == 0) {
        if (std::fabs(o.y) > h) return std::nullopt;
    } else {
        Real t1 = (-h - o.y) / d.y, t2 = (h - o.y) / d.y;
        if (t1 > t2) std::swap(t1, t2);
        tEnter = t1;
        capEntry = true;
        tExit = std::min(tExit, t2);
    }
    const Real a = d.x * d.x + d.z * d.z;
    if (a == 0) {
        if (c > 0) return std::nullopt;
    } else {
        const Real b = o.x * d.x + o.z * d.z;
        const Real disc = b * b - a * c;
        if (disc < 0) return std::nullopt;
        const Real s = std::sqrt(disc);
        // Stable roots: one from -(b + sign(b) s) / a, the other from c / that.
        const Real q = -(b + (b >= 0 ? s : -s));
        Real t1 = q / a, t2 = q != 0 ? c / q : t1;
        if (t1 > t2) std::swap(t1, t2);
        if (t1 > tEnter) { tEnter = t1; capEntry = false; }
        tExit = std::min(tExit, t2);
    }
    if (tEnter > tExit || tEnter < 0 || tEnter > maxFraction) return std::nullopt;
    if (capEntry) return LocalHit{tEnter, {0, d.y > 0 ? Real(-1) : Real(1), 0}};
    return LocalHit{tEnter, normalize(Vec3{o.x + tEnter * d.x, 0, o.z + tEnter * d.z})};
}

std::optional<LocalHit> rayHull(const ConvexHull& hull, const Vec3& o, const Vec3& d, Real maxFraction) {
    Real tEnter = 0, tExit = maxFraction;
    std::size_t enterFace = hull.faces.size();
    for (std::size_t i = 0; i < hull.faces.size(); ++i) {
        const HullFace& f = hull.faces[i];
        const Real num = f.offset - dot(f.normal, o);  // >= 0: origin behind the plane
        const Real den = dot(f.normal, d);
        if (den == 0) {
            if (num < 0) return std::nullopt;
            continue;
        }
        const Real t = num / den;
        if (den < 0) {
            if (t > tEnter) { tEnter = t; enterFace = i; }
        } else {
            tExit = std::min(tExit, t);
        }
        if (tEnter > tExit) return std::nullopt;
    }
    if (enterFace == hull.faces.size()) return LocalHit{0, {}, true};  // behind every plane: inside
    return LocalHit{tEnter, hull.faces[enterFace].normal};
}

std::optional<LocalHit> rayRounded(const Shape& shape, const Vec3& o, const Vec3& d, Real maxFraction);

std::optional<LocalHit> rayLocal(const Shape& shape, const Vec3& o, const Vec3& d, Real maxFraction) {
    if (shape.convexRadius() > 0) return rayRounded(shape, o, d, maxFraction);
    switch (shape.type()) {
        case ShapeType::Sphere: return raySphere(o, d, shape.radius(), maxFraction);
        case ShapeType::Box: return rayBox(o, d, shape.halfExtents(), maxFraction);
        case ShapeType::Capsule: return rayCapsule(o, d, shape.radius(), shape.halfHeight(), maxFraction);
        case ShapeType::Cylinder: return rayCylinder(o, d, shape.radius(), shape.halfHeight(), maxFraction);
        case ShapeType::ConvexHull: return rayHull(shape.hull(), o, d, maxFraction);
        case ShapeType::Plane: {
            const Vec3 n = shape.planeNormal();
            const Real s = dot(n, o) - shape.planeOffset();
            if (s <= 0) return LocalHit{0, {}, true};
            const Real den = dot(n, d);
            if (den >= 0) return std::nullopt;
            const Real t = -s / den;
            if (t > maxFraction) return std::nullopt;
            return LocalHit{t, n};
        }
        case ShapeType::Mesh: {
            const auto hit = rayCastMesh(shape.mesh(), o, d, maxFraction);
            if (!hit) return std::nullopt;
            LocalHit h{hit->fraction, hit->normal};
            h.triangle = hit->triangle;
            return h;
        }
        case ShapeType::HeightField: {
            const auto hit = detail::rayCastHeightField(shape.heightField(), o, d, maxFraction);
            if (!hit) return std::nullopt;
            LocalHit h{hit->fraction, hit->normal};
            h.triangle = hit->triangle;
            return h;
        }
        case ShapeType::Compound: {
            std::optional<LocalHit> best;
            const auto children = shape.children();
            for (std::size_t i = 0; i < children.size(); ++i) {
                const Transform& ct = children[i].transform;
                const Real limit = best ? best->fraction : maxFraction;
                auto hit = rayLocal(children[i].shape, inverseTransformPoint(ct, o), inverseRotate(ct.q, d), limit);
                if (!hit || (best && hit->fraction >= best->fraction)) continue;
                hit->normal = rotate(ct.q, hit->normal);
                hit->child = static_cast<std::uint32_t>(i);
                best = hit;
                if (best->inside) break;
            }
            return best;
        }
    }
    return std::nullopt;
}

struct LocalPoint {
    Vec3 point;
    Real distance = 0;
    Vec3 normal;
    std::uint32_t child = kNoSubShape;
    std::uint32_t triangle = kNoSubShape;
};

LocalPoint pointSphere(const Vec3& p, Real r) {
    const Real len = length(p);
    const Vec3 n = len > 0 ? p / len : Vec3::unitY();
    return {n * r, len - r, n};
}

LocalPoint pointBox(const Vec3& p, const Vec3& h) {
    const Vec3 q = max(-h, min(p, h));
    const Vec3 delta = p - q;
    const Real dist = length(delta);
    if (dist > 0) return {q, dist, delta / dist};
    // Inside or on the surface: the nearest face (lowest axis on ties).
    std::size_t axis = 0;
    Real gap = h.x - std::fabs(p.x);
    for (std::size_t i = 1; i < 3; ++i) {
        const Real g = h[i] - std::fabs(p[i]);
        if (g < gap) { gap = g; axis = i; }
    }
    const Real sign = p[axis] >= 0 ? Real(1) : Real(-1);
    LocalPoint r{p, -gap, {}};
    r.point[axis] = sign * h[axis];
    r.normal[axis] = sign;
    return r;
}

LocalPoint pointCapsule(const Vec3& p, Real r, Real h) {
    const Vec3 c{0, std::clamp(p.y, -h, h), 0};
    const Vec3 v = p - c;
    const Real len = length(v);
    const Vec3 n = len > 0 ? v / len : Vec3::unitX();
    return {c + n * r, len - r, n};
}

LocalPoint pointCylinder(const Vec3& p, Real r, Real h) {
    const Real rho = std::sqrt(p.x * p.x + p.z * p.z);
    const Vec3 radial = rho > 0 ? Vec3{p.x / rho, 0, p.z / rho} : Vec3::unitX();
    const Real sy = p.y >= 0 ? Real(1) : Real(-1);
    const bool withinRadius = rho <= r, withinHeight = std::fabs(p.y) <= h;
    if (withinRadius && withinHeight) {
        const Real gapCap = h - std::fabs(p.y), gapSide = r - rho;
        if (gapCap <= gapSide) return {{p.x, sy * h, p.z}, -gapCap, {0, sy, 0}};
        return {radial * r + Vec3{0, p.y, 0}, -gapSide, radial};
    }
    if (withinRadius) return {{p.x, sy * h, p.z}, std::fabs(p.y) - h, {0, sy, 0}};
    if (withinHeight) return {radial * r + Vec3{0, p.y, 0}, rho - r, radial};
    const Vec3 rim = radial * r + Vec3{0, sy * h, 0};
    const Vec3 delta = p - rim;
    const Real dist = length(delta);
    return {rim, dist, delta / dist};
}

Vec3 closestOnSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const Real len2 = lengthSquared(ab);
    const Real t = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, Real(0), Real(1)) : Real(0);
    return a + ab * t;
}

LocalPoint pointHull(const ConvexHull& hull, const Vec3& p) {
    std::size_t nearestFace = 0;
    Real maxSep = -kInf;
    for (std::size_t i = 0; i < hull.faces.size(); ++i) {
        const Real s = dot(hull.faces[i].normal, p) - hull.faces[i].offset;
        if (s > maxSep) { maxSep = s; nearestFace = i; }
    }
    if (maxSep <= 0) {
        // Inside: the ball of radius |maxSep| fits inside every half-space, so
        // the projection onto the nearest plane is on the boundary.
        const Vec3 n = hull.faces[nearestFace].normal;
        return {p - n * maxSep, maxSep, n};
    }
    // Outside: the closest point lies on a face whose plane p is in front of.
    Real bestSq = kInf;
    Vec3 best;
    for (const HullFace& f : hull.faces) {
        const Real s = dot(f.normal, p) - f.offset;
        if (s <= 0 || s * s >= bestSq) continue;
        const Vec3 q = p - f.normal * s;
        bool insidePolygon = true;
        Real edgeBestSq = kInf;
        Vec3 edgeBest;
        for (std::uint32_t i = 0; i < f.indexCount; ++i) {
            const Vec3& a = hull.vertices[hull.faceVertices[f.firstIndex + i]];
            const Vec3& b = hull.vertices[hull.faceVertices[f.firstIndex + (i + 1) % f.indexCount]];
            if (dot(cross(b - a, q - a), f.normal) < 0) {
                insidePolygon = false;
                const Vec3 c = closestOnSegment(p, a, b);
                const Real dSq = lengthSquared(p - c);
                if (dSq < edgeBestSq) { edgeBestSq = dSq; edgeBest = c; }
            }
        }
        if (insidePolygon) {
            bestSq = s * s;
            best = q;
        } else if (edgeBestSq < bestSq) {
            bestSq = edgeBestSq;
            best = edgeBest;
        }
    }
    const Vec3 delta = p - best;
    const Real dist = std::sqrt(bestSq);
    return {best, dist, dist > 0 ? delta / dist : hull.faces[nearestFace].normal};
}

// ---- Rounded shapes (docs/shapes.md, "Rounded shapes"): the closest point
// of the core moved out along its normal by the convex radius. Exact inside
// and out: the rounded surface is the set of points at distance r from the
// convex core, and a point inside the core is r deeper than under the core's
// surface.
LocalPoint pointRounded(const Shape& shape, const Vec3& p) {
    const Real r = shape.convexRadius();
    LocalPoint c;
    switch (shape.type()) {
        case ShapeType::Box: c = pointBox(p, shape.halfExtents() - Vec3::splat(r)); break;
        case ShapeType::Cylinder: c = pointCylinder(p, shape.radius() - r, shape.halfHeight() - r); break;
        default: c = pointHull(shape.hull(), p); break;
    }
    c.point += c.normal * r;
    c.distance -= r;
    return c;
}

// A ray against a rounded shape by conservative advancement on the exact
// distance: each step goes to the tangent plane at the closest surface point,
// which the convex shape lies behind, so the steps never pass the hit and
// converge on it (in one step on a flat face, a few on the round parts).
// A ray that only grazes the surface (closing speed ~0 for kMaxSteps steps) misses.
std::optional<LocalHit> rayRounded(const Shape& shape, const Vec3& o, const Vec3& d, Real maxFraction) {
    constexpr int kMaxSteps = 64;
    const Real tolerance = std::numeric_limits<Real>::epsilon() * 64 * (1 + length(o) + length(d) * maxFraction);
    Real t = 0;
    for (int step = 0; step < kMaxSteps; ++step) {
        const LocalPoint c = pointRounded(shape, o + d * t);
        if (c.distance <= tolerance) {
            if (step == 0 && c.distance <= 0) return LocalHit{0, {}, true};
            return LocalHit{t, c.normal};
        }
        const Real closing = -dot(d, c.normal);
        if (closing <= 0) return std::nullopt;
        t += c.distance / closing;
        if (t > maxFraction) return std::nullopt;
    }
    return std::nullopt;
}

LocalPoint pointLocal(const Shape& shape, const Vec3& p) {
    if (shape.convexRadius() > 0) return pointRounded(shape, p);
    switch (shape.type()) {
        case ShapeType::Sphere: return pointSphere(p, shape.radius());
        case ShapeType::Box: return pointBox(p, shape.halfExtents());
        case ShapeType::Capsule: return pointCapsule(p, shape.radius(), shape.halfHeight());
        case ShapeType::Cylinder: return pointCylinder(p, shape.radius(), shape.halfHeight());
        case ShapeType::ConvexHull: return pointHull(shape.hull(), p);
        case ShapeType::Plane: {
            const Vec3 n = shape.planeNormal();
            const Real s = dot(n, p) - shape.planeOffset();
            return {p - n * s, s, n};
        }
        case ShapeType::Mesh: {
            const MeshClosestPoint m = closestPointOnMesh(shape.mesh(), p);
            LocalPoint r{m.point, m.distance, m.normal};
            r.triangle = m.triangle;
            return r;
        }
        case ShapeType::HeightField: {
            const MeshClosestPoint m = detail::closestPointOnHeightField(shape.heightField(), p);
            LocalPoint r{m.point, m.distance, m.normal};
            r.triangle = m.triangle;
            return r;
        }
        case ShapeType::Compound: {
            LocalPoint best;
            best.distance = kInf;
            const auto children = shape.children();
            for (std::size_t i = 0; i < children.size(); ++i) {
                const Transform& ct = children[i].transform;
                LocalPoint c = pointLocal(children[i].shape, inverseTransformPoint(ct, p));
                if (c.distance >= best.distance) continue;
                c.point = transformPoint(ct, c.point);
                c.normal = rotate(ct.q, c.normal);
                c.child = static_cast<std::uint32_t>(i);
                best = c;
            }
            return best;
        }
    }
    return {};
}

}  // namespace

std::optional<RayHit> rayCastShape(const Shape& shape, const Transform& xf, const Vec3& origin, const Vec3& direction,
                                   Real maxFraction) {
    if (lengthSquared(direction) == 0) return std::nullopt;
    const auto local = rayLocal(shape, inverseTransformPoint(xf, origin), inverseRotate(xf.q, direction), maxFraction);
    if (!local) return std::nullopt;
    RayHit hit;
    hit.fraction = local->inside ? 0 : local->fraction;
    hit.point = origin + direction * hit.fraction;
    hit.normal = local->inside ? -normalize(direction) : rotate(xf.q, local->normal);
    hit.child = local->child;
    hit.triangle = local->triangle;
    return hit;
}

PointQuery closestPoint(const Shape& shape, const Transform& xf, const Vec3& point) {
    const LocalPoint local = pointLocal(shape, inverseTransformPoint(xf, point));
    PointQuery q;
    q.point = transformPoint(xf, local.point);
    q.distance = local.distance;
    q.normal = rotate(xf.q, local.normal);
    q.child = local.child;
    q.triangle = local.triangle;
    return q;
}

}  // namespace fulcrum
