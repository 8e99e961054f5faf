#pragma once
// The narrow phase dispatcher: exact contact manifolds for any pair of shapes.
#include <cmath>

#include "collision/manifold.hpp"
#include "fulcrum/shape.hpp"

namespace fulcrum {

// Clears `out` and fills it with the manifolds between shape a at xa and
// shape b at xb: zero or more (several for compounds and meshes), each with up
// to 4 points, normals from a to b. Points are reported while the shapes are
// within `speculativeMargin` of touching (depth >= -speculativeMargin).
// Symmetric: collide(b, a) gives the same points with the normal flipped.
// Pairs of two static-only shapes (plane/mesh against plane/mesh) give nothing.
// No heap allocation once `out` has grown to its working size.
void collide(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb, Real speculativeMargin,
             ManifoldBuffer& out);

// How far two moving bodies' surfaces can approach in one step: the contact
// manager's speculative margin, base + (linear + spinA r_a + spinB r_b) dt,
// where r is the distance from a body's centre of mass to its farthest point
// that can touch (a point at r moves by at most |v| dt + |w| r dt: the chord
// of its arc). For the whole body r is its extent; a compound's child has its
// own, smaller r (docs/narrow-phase.md, "Speculative margin"), so a long
// spinning body's near-centre children look for contacts only as far as they
// can move. Static bodies have spin 0.
// A compound's top-level child at its body's pose: its world bounds
// (Shape::bounds at the body transform times the child's) and its r for the
// speculative margin (the farthest corner of those bounds from the centre of
// mass, at most the body's extent).
struct ChildReach {
    AABB bounds;
    Real reach = 0;
};

// Fills out[i] for each top-level child i of compound `s` at `xf` (centre of
// mass `centre`, extent `extent`, spin axis `axis` or zero: childReach) and returns the union of the children's
// bounds: s.bounds(xf), the same bits. The contact manager computes these
// once per moving compound body and step (collide() then reads them for
// every pair of the body instead of recomputing them per pair).
AABB compoundChildReaches(const Shape& s, const Transform& xf, const Vec3& centre, Real extent, const Vec3& axis,
                          ChildReach* out);

struct SpeculativeReach {
    Real base = 0;              // the world's speculative margin
    Real linear = 0;            // |v_b - v_a| (centres of mass)
    Real spinA = 0, spinB = 0;  // |w_a|, |w_b|
    Vec3 axisA, axisB;          // w_a / |w_a|, w_b / |w_b|; zero: not given (a child's r is then its farthest corner)
    Real dt = 0;
    Vec3 centreA, centreB;      // centres of mass, world
    Real extentA = 0, extentB = 0;  // the whole bodies' r (BodyParams::extent)
    // A compound body's top-level children at this pose (compoundChildReaches
    // with this centre, extent and axis), or null: computed per pair. The same bits either way.
    const ChildReach* childrenA = nullptr;
    const ChildReach* childrenB = nullptr;
    // Per top-level child of a compound, nonzero: leave it out (the contact
    // manager recycles its manifolds; contact.hpp, PiecePose). Null: none.
    const std::uint8_t* skipA = nullptr;
    const std::uint8_t* skipB = nullptr;

    // The sums in the order the contact manager has always made them (the
    // same bits for a pair without compounds).
    Real margin(Real ra, Real rb) const {
        Real approach = linear;
        approach += spinA * ra;
        approach += spinB * rb;
        return base + approach * dt;
    }
};

// collide() with the margin of `reach`: reach.margin(extentA, extentB) for
// the pair, and for each child of a compound (at its top level) the margin of
// that child's own r: the farthest corner of its bounds at this pose from the
// centre of mass, at most the body's extent. When a compound against a convex
// shape or a compound gives no manifold, out.apartBy() is a distance the
// pair is proved apart (0: none), as for plain convex pairs.
void collide(const Shape& a, const Transform& xa, const Shape& b, const Transform& xb, const SpeculativeReach& reach,
             ManifoldBuffer& out);

// The contact geometry of two spheres (centres ca, cb; radii ra, rb): the
// normal from a to b along the centres (`fallbackNormal` when they coincide),
// the surface points and the depth. False, with nothing computed, when the
// surfaces are more than `margin` apart. The one formula of the narrow
// phase's sphere pairs and of the contact manager's sphere fast path.
struct SphereContact {
    Vec3 normal, pointA, pointB;
    Real depth = 0;
};
inline bool sphereContact(const Vec3& ca, Real ra, const Vec3& cb, Real rb, const Vec3& fallbackNormal, Real margin,
                          SphereContact& out) {
    const Vec3 d = cb - ca;
    const Real d2 = lengthSquared(d);
    const Real reach = ra + rb + margin;
    if (d2 > reach * reach) return false;
    const Real dist = std::sqrt(d2);
    out.normal = dist > Real(1e-9) ? d / dist : fallbackNormal;
    out.pointA = ca + out.normal * ra;
    out.pointB = cb - out.normal * rb;
    out.depth = ra + rb - dist;
    return true;
}

}  // namespace fulcrum
