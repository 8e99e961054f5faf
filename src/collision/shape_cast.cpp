// Conservative advancement. For a pure translation the closing speed along
// the current normal n is exactly dot(translation, n), so each step lands on
// the plane of the current closest features: one step for a face contact, a
// few for curved ones. With rotation the bound adds |w| * (largest distance
// from the centre of rotation to the surface) for each body (Mirtich's bound).
#include "collision/shape_cast.hpp"

#include <cmath>
#include <string>

#include "collision/collide_mesh.hpp"
#include "collision/epa.hpp"
#include "collision/gjk.hpp"
#include "collision/heightfield.hpp"

namespace fulcrum {

namespace {

using namespace detail;

constexpr std::uint32_t kMaxIterations = 64;

bool isConvex(ShapeType t) {
    return t == ShapeType::Sphere || t == ShapeType::Box || t == ShapeType::Capsule || t == ShapeType::Cylinder ||
           t == ShapeType::ConvexHull;
}

// Distance between full convex shapes with the A->B normal and midway point;
// a negative distance means overlap (depth from EPA).
struct Proximity {
    Real distance;
    Vec3 normal;
    Vec3 point;
};

Proximity proximity(const ConvexShape& a, const ConvexShape& b) {
    const GjkResult g = gjkDistance(a, b, false);
    const Real rs = a.radius + b.radius;
    if (!g.overlap && g.distance > Real(1e-6)) {
        const Vec3 n = g.normal;
        const Vec3 pa = g.pointA + n * a.radius, pb = g.pointB - n * b.radius;
        return {g.distance - rs, n, (pa + pb) * Real(0.5)};
    }
    const PenetrationResult p = epaPenetration(a, b);
    if (!p.valid) return {-1, {0, 1, 0}, (a.center() + b.center()) * Real(0.5)};
    return {-p.depth, p.normal, (p.pointA + p.pointB) * Real(0.5)};
}

ShapeCastResult castConvexConvex(const ConvexShape& a0, const Vec3& translation, const ConvexShape& b, Real tol) {
    ShapeCastResult r;
    ConvexShape a = a0;
    Real t = 0;
    for (r.iterations = 0; r.iterations < kMaxIterations; ++r.iterations) {
        a.xf.p = a0.xf.p + translation * t;
        if (a.kind == ConvexKind::Triangle) {
            for (int k = 0; k < 3; ++k) a.triangle[k] = a0.triangle[k] + translation * t;
        }
        const Proximity p = proximity(a, b);
        if (p.distance < tol) {
            r.hit = true;
            r.fraction = t;
            r.normal = p.normal;
            r.point = p.point;
            return r;
        }
        const Real closing = dot(translation, p.normal);
        if (closing <= Real(1e-12) * (1 + p.distance)) return r;  // moving apart or parallel
        t += p.distance / closing;
        if (t > 1) return r;
    }
    return r;
}

ShapeCastResult castConvexPlane(const ConvexShape& a, const Vec3& translation, const Shape& plane, const Transform& xp,
                                Real tol) {
    ShapeCastResult r;
    const Vec3 n = rotate(xp.q, plane.planeNormal());
    const Real offset = plane.planeOffset() + dot(n, xp.p);
    const Vec3 s = a.support(-n);
    const Real gap = dot(n, s) - offset;
    const Real closing = -dot(n, translation);
    // The plane is shape B, so the A->B normal is -n.
    if (gap < tol) {
        r.hit = true;
        r.fraction = 0;
    } else if (closing > 0 && gap < closing) {
        r.hit = true;
        r.fraction = gap / closing;
    } else {
        return r;
    }
    r.normal = -n;
    r.point = s + translation * r.fraction;
    return r;
}

void keepEarliest(ShapeCastResult& best, const ShapeCastResult& c) {
    if (c.hit && (!best.hit || c.fraction < best.fraction)) {
        const std::uint32_t it = best.iterations + c.iterations;
        best = c;
        best.iterations = it;
    } else {
        best.iterations += c.iterations;
    }
}

ShapeCastResult castRecursive(const Shape& a, const Transform& xa, const Vec3& translation, const Shape& b,
                              const Transform& xb, Real tol) {
    ShapeCastResult best;
    if (a.type() == ShapeType::Compound) {
        for (const CompoundChild& c : a.children()) keepEarliest(best, castRecursive(c.shape, xa * c.transform, translation, b, xb, tol));
        return best;
    }
    if (!isConvex(a.type())) {
        throw Error(std::string("shapeCast: the moving shape must be convex or a compound of convex shapes, got a ") +
                    toString(a.type()));
    }
    if (b.type() == ShapeType::Compound) {
        for (const CompoundChild& c : b.children()) keepEarliest(best, castRecursive(a, xa, translation, c.shape, xb * c.transform, tol));
        return best;
    }
    const ConvexShape ca = makeConvex(a, xa);
    if (b.type() == ShapeType::Plane) return castConvexPlane(ca, translation, b, xb, tol);
    if (b.type() == ShapeType::HeightField) {
        const HeightField& hf = b.heightField();
        AABB swept = a.bounds(xa);
        swept.grow(a.bounds({xa.p + translation, xa.q}));
        const AABB local = transformBounds(inverse(xb), swept.fattened(tol));
        forEachHeightFieldTriangle(hf, local, [&](std::uint32_t t) {
            Vec3 w[3];
            hf.triangle(t, w);
            const ConvexShape tri = makeTriangle(transformPoint(xb, w[0]), transformPoint(xb, w[1]), transformPoint(xb, w[2]));
            keepEarliest(best, castConvexConvex(ca, translation, tri, tol));
        });
        return best;
    }
    if (b.type() == ShapeType::Mesh) {
        const TriangleMesh& mesh = b.mesh();
        AABB swept = a.bounds(xa);
        swept.grow(a.bounds({xa.p + translation, xa.q}));
        const AABB local = transformBounds(inverse(xb), swept.fattened(tol));
        forEachTriangleOverlapping(mesh, local, [&](std::uint32_t t) {
            const auto& idx = mesh.triangles[t];
            const ConvexShape tri = makeTriangle(transformPoint(xb, mesh.vertices[idx[0]]), transformPoint(xb, mesh.vertices[idx[1]]),
                                                 transformPoint(xb, mesh.vertices[idx[2]]));
            keepEarliest(best, castConvexConvex(ca, translation, tri, tol));
        });
        return best;
    }
    return castConvexConvex(ca, translation, makeConvex(b, xb), tol);
}

}  // namespace

ShapeCastResult shapeCast(const Shape& a, const Transform& xa, const Vec3& translationA, const Shape& b,
                          const Transform& xb, Real tolerance) {
    return castRecursive(a, xa, translationA, b, xb, tolerance);
}

Transform Sweep::at(Real t) const {
    const Quat q = integrateRotation(start.q, angularVelocity, t);
    const Vec3 com = transformPoint(start, localCenter) + linearVelocity * t;
    return {com - rotate(q, localCenter), q};
}

ToiResult timeOfImpact(const Shape& a, const Sweep& sa, const Shape& b, const Sweep& sb, Real duration,
                       Real targetSeparation, Real tolerance) {
    if (!isConvex(a.type()) || !isConvex(b.type())) {
        throw Error(std::string("timeOfImpact: both shapes must be convex, got a ") + toString(a.type()) + " and a " +
                    toString(b.type()));
    }
    ToiResult r;
    ConvexShape ca = makeConvex(a, sa.start), cb = makeConvex(b, sb.start);
    const Real reachA = ca.boundingRadius() + length(sa.localCenter);
    const Real reachB = cb.boundingRadius() + length(sb.localCenter);
    const Real angular = length(sa.angularVelocity) * reachA + length(sb.angularVelocity) * reachB;
    Real t = 0;
    for (r.iterations = 0; r.iterations < kMaxIterations; ++r.iterations) {
        ca.xf = sa.at(t);
        cb.xf = sb.at(t);
        const Proximity p = proximity(ca, cb);
        const Real gap = p.distance - targetSeparation;
        if (gap < tolerance) {
            r.state = (t == 0 && gap < -tolerance) ? ToiResult::State::Overlapping : ToiResult::State::Hit;
            r.time = t;
            r.normal = p.normal;
            r.point = p.point;
            return r;
        }
        // Upper bound of how fast the gap can shrink: relative velocity along n plus rotation.
        const Real bound = dot(sa.linearVelocity - sb.linearVelocity, p.normal) + angular;
        if (bound <= Real(1e-9)) break;
        // Aim a little inside the tolerance band so the loop ends on a hit, not a crawl.
        t += (gap - Real(0.5) * tolerance) / bound;
        if (t >= duration) break;
    }
    r.state = r.iterations >= kMaxIterations ? ToiResult::State::Failed : ToiResult::State::Separated;
    r.time = duration;
    return r;
}

}  // namespace fulcrum
