#include "collision/swept_impact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "collision/collide_mesh.hpp"
#include "collision/epa.hpp"
#include "collision/gjk.hpp"
#include "collision/heightfield.hpp"
#include "collision/support.hpp"
#include "fulcrum/math/deterministic_math.hpp"

namespace fulcrum::detail {

namespace {

// A pair that has not settled after this many advances stops where it is
// (every advance is safe, so that is short of its target, never past it).
// Reached only by pieces spinning much faster than they approach (the angular
// bound then overstates the closing speed), which then lose the rest of the step.
constexpr std::uint32_t kMaxAdvances = 64;

bool isConvex(ShapeType t) {
    return t == ShapeType::Sphere || t == ShapeType::Box || t == ShapeType::Capsule || t == ShapeType::Cylinder ||
           t == ShapeType::ConvexHull;
}

bool moves(const Sweep& s) {
    return lengthSquared(s.linearVelocity) > 0 || lengthSquared(s.angularVelocity) > 0;
}

// A child's sweep: the same motion seen from the child's frame.
Sweep childSweep(const Sweep& s, const Transform& child) {
    return {s.start * child, inverseTransformPoint(child, s.localCenter), s.linearVelocity, s.angularVelocity};
}

// How far any point of `shape` moves at most over the sweep over [0, 1]
// (shape frame = the sweep's frame): its bounds' centre's displacement, plus
// how far that centre's arc strays from the chord (at most half the turn
// squared times its distance from the centre of rotation, for a turn below
// 1 rad), plus the turn times the shape's reach from its bounds' centre.
// Infinite for a turn of 1 rad or more.
Real pieceMotion(const Shape& shape, const Sweep& sweep) {
    const Real angle = length(sweep.angularVelocity);
    if (!(angle < Real(1))) return std::numeric_limits<Real>::infinity();
    const AABB local = shape.localBounds();
    const Vec3 centre = Real(0.5) * (local.min + local.max);
    const Vec3 chord = transformPoint(sweep.at(1), centre) - transformPoint(sweep.start, centre);
    return length(chord) + Real(0.5) * angle * angle * length(centre - sweep.localCenter) +
           angle * coreReach(shape, centre);
}

// One convex piece of a pair: a shape (or a triangle, still, in world space)
// or a plane (still), with its sweep.
struct Piece {
    ConvexShape shape;
    const Sweep* sweep = nullptr;  // null: still
    Real reach = 0;                // of its core from its centre of rotation
    Vec3 arm;                      // from its centre of rotation to its bounds' centre, shape frame
    Real armLength = 0;
    Real spread = 0;               // of its core from its bounds' centre
    bool plane = false;
    Vec3 planeNormal;              // world, unit (plane)
    Real planeOffset = 0;          // dot(planeNormal, x) = planeOffset on the plane

    void place(Real t) {
        if (sweep != nullptr) shape.xf = sweep->at(t);
    }
};

Piece movingPiece(const Shape& s, const Sweep& sweep) {
    Piece p;
    p.shape = makeConvex(s, sweep.start);
    if (moves(sweep)) {
        p.sweep = &sweep;
        // The tighter of two bounds on the core's reach from the centre of
        // rotation: through the shape's frame origin, or its bounds' corners.
        // A compound's child keeps the body's frame (a tree's top piece lies
        // 60 m from its origin, 40 m from its centre of mass), so the first
        // overstated the closing speed of a turning piece and a piece resting
        // on a mesh took dozens of advances per triangle.
        p.reach = std::min((p.shape.boundingRadius() - p.shape.radius) + length(sweep.localCenter),
                           coreReach(s, sweep.localCenter));
        const AABB local = s.localBounds();
        const Vec3 centre = Real(0.5) * (local.min + local.max);
        p.arm = centre - sweep.localCenter;
        p.armLength = length(p.arm);
        p.spread = coreReach(s, centre);
    }
    return p;
}

// The signed distance of two pieces (negative: the depth of their overlap)
// with the normal from a to b; false when it cannot be measured. `warm`:
// `normal` holds the pair's normal at a nearby time of the same sweeps, where
// GJK starts its search.
bool gapOf(const Piece& a, const Piece& b, Real& distance, Vec3& normal, bool warm = false) {
    if (b.plane) {
        const Vec3 s = a.shape.support(-b.planeNormal);
        distance = dot(b.planeNormal, s) - b.planeOffset;
        normal = -b.planeNormal;
        return true;
    }
    const GjkResult g = gjkDistance(a.shape, b.shape, false, std::numeric_limits<Real>::infinity(), nullptr,
                                    warm ? &normal : nullptr);
    if (!g.overlap && g.distance > Real(1e-6)) {
        distance = g.distance - a.shape.radius - b.shape.radius;
        normal = g.normal;
        return true;
    }
    const PenetrationResult p = epaPenetration(a.shape, b.shape);
    if (!p.valid) return false;
    distance = -p.depth;
    normal = p.normal;
    return true;
}

// Conservative advancement of one pair from time `t` (placed there, with its
// distance and normal at t) towards `target`, over [t, limit]: true with t at
// the time the distance comes within the tolerance above the target (or where
// it could no longer be measured, or after kMaxAdvances: both short of the
// target), false when the target is not reached before `limit`.
bool advance(Piece& a, Piece& b, Real target, Real limit, Real& t, Real& distance, Vec3& normal, const ImpactRules& rules,
             std::uint32_t& advances) {
    const Vec3 va = a.sweep != nullptr ? a.sweep->linearVelocity : Vec3::zero();
    const Vec3 vb = b.sweep != nullptr ? b.sweep->linearVelocity : Vec3::zero();
    const Vec3 relative = va - vb;
    const Vec3 wa = a.sweep != nullptr ? a.sweep->angularVelocity : Vec3::zero();
    const Vec3 wb = b.sweep != nullptr ? b.sweep->angularVelocity : Vec3::zero();
    const Real spinA = length(wa), spinB = length(wb);
    for (std::uint32_t k = 1;; ++k) {
        const Real gap = distance - target;
        if (gap < rules.tolerance) return true;
        // Only the spin across the normal moves a point along it: a point r
        // from its piece's centre of rotation moves along the (fixed) normal
        // n at n.(w x r) = r.(n x w), at most |w x n| |r|. Each sweep turns
        // about a fixed axis at a constant rate, so |w x n| holds over the
        // whole advance; for a spin about the normal (a bar spinning flat
        // against a wall) the bound is the translation's alone.
        const Real acrossA = spinA > 0 ? length(cross(wa, normal)) : Real(0);
        const Real acrossB = spinB > 0 ? length(cross(wb, normal)) : Real(0);
        const Real angular = acrossA * a.reach + acrossB * b.reach;
        // The second bound's growth: a piece's arm turns at its spin, so the
        // velocity of its bounds' centre along n changes at most by
        // (n x w).(w x arm) <= |w x n| |w| |arm| per unit time.
        const Real growth = acrossA * spinA * a.armLength + acrossB * spinB * b.armLength;
        const Real spread = acrossA * a.spread + acrossB * b.spread;
        // How fast the gap can close: along the fixed normal the separation
        // (or the overlap) changes by no more than this, and the distance is
        // at least the separation along any fixed axis (the depth at most the
        // overlap along it), so the advance never passes the target.
        const Real closing = dot(relative, normal) + angular;
        // A second bound, from the velocities of the pieces' bounds' centres
        // now (their spin times their arm, along the normal) plus their spin
        // times their own spread, growing by `growth` per unit time: over a
        // step h the pair closes at most rate h + growth h^2 / 2. A piece
        // near the foot of a toppling tree moves slowly while its spin times
        // its reach from the tree's centre of mass is large: this bound took
        // one advance where the first took dozens. Each bound alone never
        // passes the target, so the longer step of the two is safe.
        Vec3 centreVelocity = relative;
        if (a.sweep != nullptr) centreVelocity += cross(a.sweep->angularVelocity, rotate(a.shape.xf.q, a.arm));
        if (b.sweep != nullptr) centreVelocity -= cross(b.sweep->angularVelocity, rotate(b.shape.xf.q, b.arm));
        const Real rate = dot(centreVelocity, normal) + spread;
        const Real budget = gap - Real(0.5) * rules.tolerance;
        Real step = closing > 0 ? budget / closing : std::numeric_limits<Real>::infinity();
        if (growth > 0) {
            step = std::max(step, 2 * budget / (rate + std::sqrt(rate * rate + 2 * growth * budget)));
        } else if (rate <= 0 || closing <= 0) {
            return false;
        } else {
            step = std::max(step, budget / rate);
        }
        if (!(step < std::numeric_limits<Real>::infinity())) return false;
        t += step;
        if (t >= limit) return false;
        if (k >= kMaxAdvances) return true;
        a.place(t);
        b.place(t);
        ++advances;
        if (!gapOf(a, b, distance, normal, true)) return true;
    }
}

// How deep point p (world) lies inside the full shape s (its distance to
// the outside; negative: outside by that much), for a sphere, a capsule or a
// (rounded) box; -infinity for the other kinds (not measured here).
Real pointDepth(const ConvexShape& s, const Vec3& p) {
    switch (s.kind) {
        case ConvexKind::Point: return s.radius - length(p - s.xf.p);
        case ConvexKind::Segment: {
            const Vec3 l = inverseTransformPoint(s.xf, p);
            const Real y = std::clamp(l.y, -s.halfHeight, s.halfHeight);
            return s.radius - length(Vec3{l.x, l.y - y, l.z});
        }
        case ConvexKind::Box: {
            // A point d inside the core is d + radius inside the rounded box:
            // every point within that distance is a core point plus at most
            // the radius.
            const Vec3 q = abs(inverseTransformPoint(s.xf, p)) - s.halfExtents;
            const Real out = std::max(std::max(q.x, q.y), q.z);
            if (out <= 0) return s.radius - out;
            return s.radius - length(max(q, Vec3::zero()));
        }
        default: return -std::numeric_limits<Real>::infinity();
    }
}

// Whether the sweeps, after time t (the pieces placed there, `distance`
// apart along `normal`), take the pair more than `depth` into each other,
// shown cheaply: the point of a deepest along the normal, at the one later
// time the translation alone would take it 2 depth in, lies more than
// `depth` inside b. That suffices: the depth of an overlap is at least the
// depth of any point of one shape inside the other (a shorter move of the
// shape leaves that point inside), and the distance is continuous, so the
// conservative advance would reach -depth by then too. False when not shown
// (the caller advances as before). Leaves the pieces placed at t.
bool shownGoingIn(Piece& a, Piece& b, Real depth, Real t, Real distance, const Vec3& normal) {
    if (b.plane) return false;
    const Vec3 va = a.sweep != nullptr ? a.sweep->linearVelocity : Vec3::zero();
    const Vec3 vb = b.sweep != nullptr ? b.sweep->linearVelocity : Vec3::zero();
    const Real approach = dot(va - vb, normal);
    if (!(approach > 0)) return false;
    const Real later = t + (std::max(distance, Real(0)) + 2 * depth) / approach;
    if (!(later <= 1)) return false;
    a.place(later);
    b.place(later);
    const bool shown = pointDepth(b.shape, a.shape.support(normal)) > depth;
    a.place(t);
    b.place(t);
    return shown;
}

// One pair of pieces. Apart at the start: the time they come within stopGap,
// if the sweeps then take them more than passDepth into each other (a body
// that touches and rolls or slides on was held by its contact and is left
// alone; one whose path goes on into or through the other stops where it
// touched). Touching at the start: the time they are sinkAllowance deeper
// than they started.
void advancePair(Piece& a, Piece& b, const ImpactRules& rules, Real limit, SweptImpact& out) {
    limit = std::min(limit, out.time);
    Real distance = 0;
    Vec3 normal;
    Real t = 0;
    ++out.advances;
    bool stops = !gapOf(a, b, distance, normal);
    Real stopTime = 0;
    if (!stops && distance > rules.touchBand) {
        if (!advance(a, b, rules.stopGap, limit, t, distance, normal, rules, out.advances)) return;
        stopTime = t;
        stops = shownGoingIn(a, b, rules.passDepth, t, distance, normal) ||
                advance(a, b, -rules.passDepth, 1, t, distance, normal, rules, out.advances);
    } else if (!stops) {
        stops = advance(a, b, std::min(distance, Real(0)) - rules.sinkAllowance, limit, t, distance, normal, rules, out.advances);
        stopTime = t;
    }
    if (stops && stopTime < out.time) {
        out.hit = true;
        out.time = stopTime;
    }
}

void impactRecursive(const Shape& a, const Sweep& sa, const Shape& b, const Sweep& sb, const ImpactRules& rules,
                     Real limit, SweptImpact& out) {
    if (a.type() == ShapeType::Compound) {
        for (const CompoundChild& c : a.children()) {
            const Sweep cs = childSweep(sa, c.transform);
            if (rules.pieceThickness != nullptr &&
                pieceMotion(c.shape, cs) <= rules.slowPieceFraction * rules.pieceThickness(c.shape)) {
                continue;
            }
            impactRecursive(c.shape, cs, b, sb, rules, limit, out);
        }
        return;
    }
    if (!isConvex(a.type())) {
        throw Error(std::string("sweptImpact: the moving shape must be convex or a compound of convex shapes, got a ") +
                    toString(a.type()));
    }
    if (b.type() == ShapeType::Compound) {
        for (const CompoundChild& c : b.children()) impactRecursive(a, sa, c.shape, childSweep(sb, c.transform), rules, limit, out);
        return;
    }
    const bool bStill = !moves(sb);
    if (!isConvex(b.type()) && !bStill) {
        throw Error(std::string("sweptImpact: a ") + toString(b.type()) + " must be still");
    }
    Piece pa = movingPiece(a, sa);
    if (b.type() == ShapeType::Plane) {
        Piece pb;
        pb.plane = true;
        pb.planeNormal = rotate(sb.start.q, b.planeNormal());
        pb.planeOffset = b.planeOffset() + dot(pb.planeNormal, sb.start.p);
        return advancePair(pa, pb, rules, limit, out);
    }
    if (b.type() == ShapeType::Mesh || b.type() == ShapeType::HeightField) {
        const Transform xb = sb.start;
        const AABB local = transformBounds(inverse(xb), sweptBounds(a, sa).fattened(rules.touchBand));
        // A triangle whose plane keeps the piece farther than the touch band
        // plus the most any point of it moves can neither touch it at the
        // start nor come within stopGap of it: skipped with one extent of the
        // piece, where conservative advancement takes a GJK distance or more.
        // (Most triangles under a falling piece's swept box lie below it.)
        const Real motion = pieceMotion(a, sa);
        const Real clearance = motion + std::max(rules.touchBand, rules.stopGap) + rules.tolerance;
        const auto triangle = [&](const Vec3& v0, const Vec3& v1, const Vec3& v2) {
            const Vec3 w0 = transformPoint(xb, v0), w1 = transformPoint(xb, v1), w2 = transformPoint(xb, v2);
            pa.place(0);
            const Vec3 faceN = normalize(cross(w1 - w0, w2 - w0));
            Real lo, hi;
            pa.shape.extent(faceN, lo, hi);
            const Real plane = dot(faceN, w0);
            if (std::max(lo - plane, plane - hi) > clearance) return;
            Piece pb;
            pb.shape = makeTriangle(w0, w1, w2);
            advancePair(pa, pb, rules, limit, out);
        };
        if (b.type() == ShapeType::Mesh) {
            const TriangleMesh& mesh = b.mesh();
            forEachTriangleOverlapping(mesh, local, [&](std::uint32_t t) {
                const auto& idx = mesh.triangles[t];
                triangle(mesh.vertices[idx[0]], mesh.vertices[idx[1]], mesh.vertices[idx[2]]);
            });
        } else {
            const HeightField& hf = b.heightField();
            forEachHeightFieldTriangle(hf, local, [&](std::uint32_t t) {
                Vec3 v[3];
                hf.triangle(t, v);
                triangle(v[0], v[1], v[2]);
            });
        }
        return;
    }
    // The pieces' swept boxes first: a compound's children each meet only
    // some of what the whole body's swept box found.
    const AABB bBox = bStill ? b.bounds(sb.start) : sweptBounds(b, sb);
    if (!overlaps(sweptBounds(a, sa).fattened(rules.touchBand), bBox)) return;
    Piece pb = movingPiece(b, sb);
    advancePair(pa, pb, rules, limit, out);
}

}  // namespace

SweptImpact sweptImpact(const Shape& a, const Sweep& sa, const Shape& b, const Sweep& sb, const ImpactRules& rules,
                        Real limit) {
    SweptImpact out;
    out.time = limit;
    impactRecursive(a, sa, b, sb, rules, limit, out);
    return out;
}

Real coreReach(const Shape& shape, const Vec3& centre) {
    switch (shape.type()) {
        case ShapeType::Sphere: return length(centre);
        case ShapeType::Capsule: {
            const Vec3 end{0, shape.halfHeight(), 0};
            return std::max(length(end - centre), length(-end - centre));
        }
        case ShapeType::Box: return length(abs(centre) + shape.halfExtents());
        case ShapeType::Compound: {
            Real r = 0;
            for (const CompoundChild& c : shape.children()) r = std::max(r, coreReach(c.shape, inverseTransformPoint(c.transform, centre)));
            return r;
        }
        default: {
            const AABB b = shape.localBounds();
            return length(max(abs(b.min - centre), abs(b.max - centre)));
        }
    }
}

AABB sweptBounds(const Shape& shape, const Sweep& sweep) {
    if (lengthSquared(sweep.angularVelocity) == 0 || coreReach(shape, sweep.localCenter) == 0) {
        return merge(shape.bounds(sweep.start), shape.bounds({sweep.start.p + sweep.linearVelocity, sweep.start.q}));
    }
    const AABB local = shape.localBounds();
    const Real r = length(max(abs(local.min - sweep.localCenter), abs(local.max - sweep.localCenter)));
    const Vec3 c0 = transformPoint(sweep.start, sweep.localCenter), c1 = c0 + sweep.linearVelocity;
    const Real angle = length(sweep.angularVelocity);
    if (angle < Real(3)) {
        // The turn is about one axis (Sweep::at: the exponential map), by at
        // most `angle` below pi, so every point d from the centre runs along
        // an arc that stays within its sagitta |d| (1 - cos(angle / 2)) =
        // 2 |d| sin^2(angle / 4) of the chord from d to its end. The turned
        // shape is thus inside the box of its start and turned-in-place
        // bounds grown by that, and the whole sweep inside that box swept
        // along the centre's path. A tumbling tree's hull is boxed by its
        // own path, not by a sphere of the tree's height around the centre
        // (which met every triangle under the tree, each advanced by GJK).
        const Real s = dmath::sin(angle * Real(0.25));
        const Real sagitta = 2 * r * s * s + r * Real(1e-5);  // and the rounding of the bounds' poses
        const Quat q1 = sweep.at(1).q;
        const AABB turned = merge(shape.bounds(sweep.start), shape.bounds({c0 - rotate(q1, sweep.localCenter), q1}))
                                .fattened(sagitta);
        return merge(turned, {turned.min + sweep.linearVelocity, turned.max + sweep.linearVelocity});
    }
    return {min(c0, c1) - Vec3::splat(r), max(c0, c1) + Vec3::splat(r)};
}

Sweep sweepBetween(const Vec3& com0, const Quat& q0, const Vec3& com1, const Quat& q1, const Vec3& localCenter) {
    return {{com0 - rotate(q0, localCenter), q0}, localCenter, com1 - com0, toRotationVector(q1 * conjugate(q0))};
}

}  // namespace fulcrum::detail
