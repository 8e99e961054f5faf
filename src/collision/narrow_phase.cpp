// The narrow phase dispatcher. Convex pairs go through a table indexed by the
// two convex kinds; pairs of different kinds always run in one canonical
// order (lower kind first) and are flipped afterwards, so collide(b, a) is
// bit-for-bit the mirror of collide(a, b). Planes, meshes, heightfields and
// compounds are unwrapped here; anchors are computed last, in the top-level frames.
#include "collision/narrow_phase.hpp"

#include <algorithm>
#include <limits>

#include "collision/collide_mesh.hpp"
#include "collision/collide_pairs.hpp"

namespace fulcrum {

namespace {

using namespace detail;

constexpr std::size_t kKinds = 5;  // Point, Segment, Box, Hull, Cylinder (triangles only inside meshes)

// Entries for kind(a) <= kind(b); the dispatcher swaps to reach them.
constexpr ConvexPairFn kPairTable[kKinds][kKinds] = {
    /* Point    */ {collideSphereSphere, collideSphereCapsule, collideSphereBox, collideConvexConvex, collideConvexConvex},
    /* Segment  */ {nullptr, collideCapsuleCapsule, collideConvexConvex, collideConvexConvex, collideConvexConvex},
    /* Box      */ {nullptr, nullptr, collideBoxBox, collideConvexConvex, collideConvexConvex},
    /* Hull     */ {nullptr, nullptr, nullptr, collideConvexConvex, collideConvexConvex},
    /* Cylinder */ {nullptr, nullptr, nullptr, nullptr, collideConvexConvex},
};

bool isConvex(ShapeType t) {
    return t == ShapeType::Sphere || t == ShapeType::Box || t == ShapeType::Capsule || t == ShapeType::Cylinder ||
           t == ShapeType::ConvexHull;
}

// The pairs collideConvexConvex takes a GJK warm start for (GjkWarmStart,
// manifold.hpp): two hulls, or a box and a hull (two boxes have their own path).
bool warmStartable(ConvexKind a, ConvexKind b) {
    const bool hullA = a == ConvexKind::Hull, hullB = b == ConvexKind::Hull;
    return (hullA && (hullB || b == ConvexKind::Box)) || (hullB && a == ConvexKind::Box);
}

// Inlined into collideLeaf, as it was into collideRecursive before rounded
// shapes split the leaf out (GCC stopped inlining it on its own).
[[gnu::always_inline]] inline void collideConvexPair(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb,
                                                     Real margin, ManifoldBuffer& out, std::uint32_t childA,
                                                     std::uint32_t childB) {
    const ConvexShape ca = makeConvexCore(a, xa), cb = makeConvexCore(b, xb);
    const std::size_t ka = static_cast<std::size_t>(ca.kind), kb = static_cast<std::size_t>(cb.kind);
    Manifold& m = out.push();
    m.childA = childA;
    m.childB = childB;
    bool hit;
    if (out.gjkWarmStart() != nullptr && warmStartable(ca.kind, cb.kind)) {
        // Two hulls or a box and a hull, with the pair's GJK warm start (in
        // the canonical order, as always for the pair).
        if (ka <= kb) {
            hit = collideConvexConvex(ca, cb, margin, m, out.gjkWarmStart());
        } else {
            hit = collideConvexConvex(cb, ca, margin, m, out.gjkWarmStart());
            flipManifold(m);
        }
    } else if (ka <= kb) {
        hit = kPairTable[ka][kb](ca, cb, margin, m);
    } else {
        hit = kPairTable[kb][ka](cb, ca, margin, m);
        flipManifold(m);
    }
    if (!hit) {
        out.setApartBy(m.apartBy);
        out.pop();
    }
}

void collidePlane(const Shape& plane, const Transform& xp, const Shape& b, const Transform& xb, Real margin,
                  ManifoldBuffer& out, std::uint32_t childB) {
    const Vec3 n = rotate(xp.q, plane.planeNormal());
    const Real offset = plane.planeOffset() + dot(n, xp.p);
    Manifold& m = out.push();
    m.childB = childB;
    if (!collidePlaneConvex(n, offset, makeConvexCore(b, xb), margin, m)) out.pop();
}

// Two shapes that are not compounds, rounded shapes as their cores. Inlined
// into collideRecursive: a call there cost 0.2 % of box_pile(500)'s step.
[[gnu::always_inline]] inline void collideLeaf(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb,
                                               Real margin, ManifoldBuffer& out, std::uint32_t childA, std::uint32_t childB) {
    const ShapeType ta = a.type(), tb = b.type();
    const bool staticA = ta == ShapeType::Plane || ta == ShapeType::Mesh || ta == ShapeType::HeightField;
    const bool staticB = tb == ShapeType::Plane || tb == ShapeType::Mesh || tb == ShapeType::HeightField;
    if (staticA && staticB) return;
    if (ta == ShapeType::Plane) {
        collidePlane(a, xa, b, xb, margin, out, childB);
        return;
    }
    if (tb == ShapeType::Plane) {
        const std::size_t first = out.size();
        collidePlane(b, xb, a, xa, margin, out, childA);
        for (std::size_t i = first; i < out.size(); ++i) {
            flipManifold(out[i]);
            out[i].childA = childA;
            out[i].childB = childB;
        }
        return;
    }
    if (ta == ShapeType::Mesh || ta == ShapeType::HeightField) {
        const std::size_t first = out.size();
        if (ta == ShapeType::Mesh) {
            out.triangleAxes().piece = childB ^ (childA << 16);  // the triangle axis cache's key (manifold.hpp)
            collideMeshConvex(a.mesh(), xa, makeConvexCore(b, xb), b.bounds(xb), margin, out);
        } else {
            collideHeightFieldConvex(a.heightField(), xa, makeConvexCore(b, xb), b.bounds(xb), margin, out);
        }
        for (std::size_t i = first; i < out.size(); ++i) out[i].childB = childB;
        return;
    }
    if (tb == ShapeType::Mesh || tb == ShapeType::HeightField) {
        const std::size_t first = out.size();
        if (tb == ShapeType::Mesh) {
            out.triangleAxes().piece = childA ^ (childB << 16);
            collideMeshConvex(b.mesh(), xb, makeConvexCore(a, xa), a.bounds(xa), margin, out);
        } else {
            collideHeightFieldConvex(b.heightField(), xb, makeConvexCore(a, xa), a.bounds(xa), margin, out);
        }
        for (std::size_t i = first; i < out.size(); ++i) {
            flipManifold(out[i]);
            out[i].childB = out[i].childA;  // the triangle
            out[i].childA = childA;
        }
        return;
    }
    if (isConvex(ta) && isConvex(tb)) collideConvexPair(a, xa, b, xb, margin, out, childA, childB);
}

// Rounded shapes (docs/narrow-phase.md, "Rounded shapes"): the manifold of
// the cores, found with the margin grown by both convex radii, then each
// point's surface points moved out by the radii along the normal: A's by r_a
// along n, B's by r_b against it. The depth grows by r_a + r_b, the midpoint
// moves by (r_a - r_b) / 2, so a core point within margin + r_a + r_b is a
// rounded point within the margin. Exact wherever the core manifold is: the
// rounded surfaces' closest points are the cores' closest points moved along
// the normal. Plain shapes never come here.
[[gnu::noinline]] void collideRounded(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb,
                                      Real margin, ManifoldBuffer& out, std::uint32_t childA, std::uint32_t childB) {
    const Real ra = a.convexRadius(), rb = b.convexRadius();
    const std::size_t first = out.size();
    collideLeaf(a, xa, b, xb, margin + ra + rb, out, childA, childB);
    const Real shift = Real(0.5) * (ra - rb);
    for (std::size_t i = first; i < out.size(); ++i) {
        Manifold& m = out[i];
        for (std::uint32_t k = 0; k < m.pointCount; ++k) {
            m.points[k].position += m.normal * shift;
            m.points[k].depth += ra + rb;
        }
    }
}

// A compound child's r for the speculative margin (narrow_phase.hpp,
// SpeculativeReach): the farthest corner of its bounds at this pose from the
// body's centre of mass, and never more than the body's extent (also a bound:
// the child is inside the body's local box). With the spin's axis known, also
// never more than the distance of the bounds' centre from the line through
// the centre of mass along that axis plus the bounds' half diagonal: a point
// x of the child moves at |w x (x - c)| <= |w| (|axis x (mid - c)| + |x - mid|)
// from the spin. A trunk segment of a tree rolling about its trunk then looks
// as far as its own girth can turn in a step, not as far as its distance from
// the centre of mass (up to 30 m on the trees: margins of 0.5 m, every
// triangle within them tested; docs/benchmarks.md, "Why the trees' step").
Real childReach(const AABB& childBounds, const Vec3& centre, Real extent, const Vec3& axis) {
    const Real corner = std::min(extent, length(max(abs(childBounds.min - centre), abs(childBounds.max - centre))));
    if (!(lengthSquared(axis) > 0)) return corner;  // no axis given: the bound over every axis
    const Vec3 mid = (childBounds.min + childBounds.max) * Real(0.5);
    const Real aroundAxis = length(cross(axis, mid - centre)) + length(childBounds.max - mid);
    return aroundAxis < corner ? aroundAxis : corner;  // a NaN (an infinite spin) keeps the corner
}

// How far apart two boxes are along the axis that parts them most: a lower
// bound of the distance between anything inside them (0 when they overlap).
Real boxGap(const AABB& a, const AABB& b) {
    Real gap = 0;
    for (int k = 0; k < 3; ++k) gap = std::max({gap, a.min[k] - b.max[k], b.min[k] - a.max[k]});
    return gap;
}

bool isPlainConvexShape(const Shape& s) { return isConvex(s.type()) && s.convexRadius() == 0; }

// Shapes whose every point lies within a bounded reach of their origin, as
// a moving body's: convex shapes and compounds (the contact manager's apart
// cache needs it).
bool hasReach(const Shape& s) { return isConvex(s.type()) || s.type() == ShapeType::Compound; }

}  // namespace

AABB compoundChildReaches(const Shape& s, const Transform& xf, const Vec3& centre, Real extent, const Vec3& axis,
                          ChildReach* out) {
    // The union as Shape::bounds grows it, so the same bits as s.bounds(xf).
    AABB all;
    const auto children = s.children();
    for (std::size_t i = 0; i < children.size(); ++i) {
        const AABB bc = children[i].shape.bounds(xf * children[i].transform);
        out[i].bounds = bc;
        out[i].reach = childReach(bc, centre, extent, axis);
        all.grow(bc);
    }
    return all;
}

namespace {

// `margin` is reach->margin(ra, rb) (or, with kPerChild false, the caller's
// one margin, reach null: the plain collide(), which this instance keeps
// exactly as it was): at the top level of a compound on a spinning body each
// child gets the margin of its own r; deeper levels keep their top-level child's.
template <bool kPerChild>
void collideRecursive(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb, Real margin,
                      const SpeculativeReach* reach, Real ra, Real rb, ManifoldBuffer& out, std::uint32_t childA,
                      std::uint32_t childB, int depthA, int depthB) {
    const ShapeType ta = a.type(), tb = b.type();
    if (ta == ShapeType::Compound) {
        const AABB boundsB = b.bounds(xb);
        const AABB bb = boundsB.fattened(margin);
        const bool ownMargin = kPerChild && depthA == 0 && reach->spinA > 0;
        // The children's bounds and r at this pose, once per body and step
        // (the contact manager's), or computed here; the pose of a child
        // only for those the bounds let through.
        const ChildReach* known = kPerChild && depthA == 0 ? reach->childrenA : nullptr;
        const auto children = a.children();
        // At the top level, a distance the whole pair is proved apart when no
        // child gives a point (the contact manager's apart cache, as for
        // plain convex pairs): the least over the children of their boxes' gap
        // or, for a plain convex child against a plain convex shape, the
        // distance its pair function proved; 0 when any child proves none.
        // Only against a shape of finite reach (the cache bounds its motion
        // by how far its points lie from its origin: not a plane's, a mesh's).
        const bool proveApart = kPerChild && depthA == 0 && hasReach(b);
        const bool plainOther = proveApart && isPlainConvexShape(b);
        Real apart = std::numeric_limits<Real>::max();
        const std::uint8_t* skip = kPerChild && depthA == 0 ? reach->skipA : nullptr;
        for (std::size_t i = 0; i < children.size(); ++i) {
            if (skip != nullptr && skip[i] != 0) continue;  // recycled (only against a mesh: no apart proof)
            Transform xc;
            AABB bc;
            if (known != nullptr) {
                bc = known[i].bounds;
            } else {
                xc = xa * children[i].transform;
                bc = children[i].shape.bounds(xc);
            }
            const std::uint32_t child = depthA == 0 ? static_cast<std::uint32_t>(i) : childA;
            // The whole body's margin is at least any child's (r at most the
            // extent, each sum monotone in it, rounding too): most children of a
            // big compound fail this one test.
            if (!overlaps(bc, bb)) {
                if (proveApart) apart = std::min(apart, boxGap(bc, boundsB));
                continue;
            }
            const std::size_t before = out.size();
            if (proveApart) out.setApartBy(0);
            if (ownMargin) {
                const Real rc = known != nullptr ? known[i].reach : childReach(bc, reach->centreA, reach->extentA, reach->axisA);
                const Real mc = reach->margin(rc, rb);
                if (!overlaps(bc, boundsB.fattened(mc))) {
                    if (proveApart) apart = std::min(apart, boxGap(bc, boundsB));
                    continue;
                }
                if (known != nullptr) xc = xa * children[i].transform;
                collideRecursive<kPerChild>(children[i].shape, xc, b, xb, mc, reach, rc, rb, out, child, childB, depthA + 1, depthB);
            } else {
                if (known != nullptr) xc = xa * children[i].transform;
                collideRecursive<kPerChild>(children[i].shape, xc, b, xb, margin, reach, ra, rb, out, child, childB, depthA + 1, depthB);
            }
            if (proveApart) {
                const bool proved = plainOther && out.size() == before && isPlainConvexShape(children[i].shape);
                apart = proved ? std::min(apart, out.apartBy()) : Real(0);
            }
        }
        if (proveApart) out.setApartBy(out.empty() && apart < std::numeric_limits<Real>::max() ? apart : Real(0));
        return;
    }
    if (tb == ShapeType::Compound) {
        const AABB boundsA = a.bounds(xa);
        const AABB ba = boundsA.fattened(margin);
        const bool ownMargin = kPerChild && depthB == 0 && reach->spinB > 0;
        // The children's bounds and r at this pose, once per body and step
        // (the contact manager's), or computed here; the pose of a child
        // only for those the bounds let through.
        const ChildReach* known = kPerChild && depthB == 0 ? reach->childrenB : nullptr;
        const auto children = b.children();
        // At the top level, a distance the whole pair is proved apart when no
        // child gives a point (the contact manager's apart cache, as for
        // plain convex pairs): the least over the children of their boxes' gap
        // or, for a plain convex child against a plain convex shape, the
        // distance its pair function proved; 0 when any child proves none.
        const bool proveApart = kPerChild && depthB == 0 && hasReach(a);
        const bool plainOther = proveApart && isPlainConvexShape(a);
        Real apart = std::numeric_limits<Real>::max();
        const std::uint8_t* skip = kPerChild && depthB == 0 ? reach->skipB : nullptr;
        for (std::size_t i = 0; i < children.size(); ++i) {
            if (skip != nullptr && skip[i] != 0) continue;  // recycled (only against a mesh: no apart proof)
            Transform xc;
            AABB bc;
            if (known != nullptr) {
                bc = known[i].bounds;
            } else {
                xc = xb * children[i].transform;
                bc = children[i].shape.bounds(xc);
            }
            const std::uint32_t child = depthB == 0 ? static_cast<std::uint32_t>(i) : childB;
            // The whole body's margin is at least any child's (r at most the
            // extent, each sum monotone in it, rounding too): most children of a
            // big compound fail this one test.
            if (!overlaps(bc, ba)) {
                if (proveApart) apart = std::min(apart, boxGap(bc, boundsA));
                continue;
            }
            const std::size_t before = out.size();
            if (proveApart) out.setApartBy(0);
            if (ownMargin) {
                const Real rc = known != nullptr ? known[i].reach : childReach(bc, reach->centreB, reach->extentB, reach->axisB);
                const Real mc = reach->margin(ra, rc);
                if (!overlaps(bc, boundsA.fattened(mc))) {
                    if (proveApart) apart = std::min(apart, boxGap(bc, boundsA));
                    continue;
                }
                if (known != nullptr) xc = xb * children[i].transform;
                collideRecursive<kPerChild>(a, xa, children[i].shape, xc, mc, reach, ra, rc, out, childA, child, depthA, depthB + 1);
            } else {
                if (known != nullptr) xc = xb * children[i].transform;
                collideRecursive<kPerChild>(a, xa, children[i].shape, xc, margin, reach, ra, rb, out, childA, child, depthA, depthB + 1);
            }
            if (proveApart) {
                const bool proved = plainOther && out.size() == before && isPlainConvexShape(children[i].shape);
                apart = proved ? std::min(apart, out.apartBy()) : Real(0);
            }
        }
        if (proveApart) out.setApartBy(out.empty() && apart < std::numeric_limits<Real>::max() ? apart : Real(0));
        return;
    }
    if (a.convexRadius() > 0 || b.convexRadius() > 0) {
        collideRounded(a, xa, b, xb, margin, out, childA, childB);
        return;
    }
    collideLeaf(a, xa, b, xb, margin, out, childA, childB);
}

// The anchors, last, in the top-level frames (inlined into both collide()s,
// as it was into the one before).
[[gnu::always_inline]] inline void computeAnchors(const Transform& xa, const Transform& xb, ManifoldBuffer& out) {
    for (std::size_t i = 0; i < out.size(); ++i) {
        Manifold& m = out[i];
        for (std::uint32_t k = 0; k < m.pointCount; ++k) {
            ContactPoint& c = m.points[k];
            const Vec3 half = m.normal * (Real(0.5) * c.depth);
            c.localAnchorA = inverseTransformPoint(xa, c.position + half);
            c.localAnchorB = inverseTransformPoint(xb, c.position - half);
        }
    }
}

}  // namespace

void collide(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb, Real speculativeMargin,
             ManifoldBuffer& out) {
    out.clear();
    if (a.type() == ShapeType::Sphere && b.type() == ShapeType::Sphere) {
        // Sphere against sphere, nearly every pair of a sphere pile, straight
        // to its pair function: no recursion, no ConvexShapes, no dispatch table.
        // collideSphereSphere is this same call (kinds equal: no flip), so the
        // same bits. Measured on a settled 600-sphere pile: collideRecursive
        // was 1.6 % of the step's instructions (docs/solver.md).
        Manifold& m = out.push();
        if (!collideSphereCentres(xa.p, a.radius(), xb.p, b.radius(), speculativeMargin, m)) out.pop();
    } else {
        collideRecursive<false>(a, xa, b, xb, speculativeMargin, nullptr, 0, 0, out, 0, 0, 0, 0);
    }
    computeAnchors(xa, xb, out);
}

void collide(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb, const SpeculativeReach& reach,
             ManifoldBuffer& out) {
    const bool compound = a.type() == ShapeType::Compound || b.type() == ShapeType::Compound;
    if (!compound) {
        collide(a, xa, b, xb, reach.margin(reach.extentA, reach.extentB), out);
        return;
    }
    out.clear();
    collideRecursive<true>(a, xa, b, xb, reach.margin(reach.extentA, reach.extentB), &reach, reach.extentA, reach.extentB, out,
                     0, 0, 0, 0);
    computeAnchors(xa, xb, out);
}

}  // namespace fulcrum
