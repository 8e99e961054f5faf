#pragma once
// The geometric half of continuous collision (src/contacts/continuous.cpp):
// the first time at which a body moving over a step meets another body's
// shape. Each body's motion is its sweep (shape_cast.hpp): the centre of mass
// on the straight line from its start to its end, the orientation turning at
// a constant rate about one axis (the shortest rotation from the start
// orientation to the end one), so the sweep runs exactly from the pose the
// body had to the pose the solver gave it, whatever it turned in between.
//
// Conservative advancement (Mirtich 1996) on every pair of convex pieces:
// the moving body's compound children against the other's convex shape, its
// compound children, the mesh or heightfield triangles under the swept
// bounds, or its plane. Each advance is the gap over an upper bound of how
// fast it can close (the relative velocity along the current normal plus,
// for each moving piece, its angular speed times the reach of its core from
// the centre of rotation), so it never steps past the target; a rotation is
// therefore never missed, unlike a cast along the translation alone.
//
// Where a pair of pieces starts matters (ImpactRules). Apart at the start,
// the pair stops `stopGap` short of touching if the sweeps go on to take it
// more than `passDepth` into each other (so a body its contact held at the
// surface, or that touched and rolled on, is not stopped). Touching or
// overlapping at the start (a body resting or sliding on a floor, or put back
// at a wall by the last step), it stops only when `sinkAllowance` deeper than
// it started, so a body may slide along what it touches, never through it: a
// piece straddling the mid-plane of anything thin is deeper than its own half
// thickness, which the allowance stays well below.
#include <cstdint>

#include "collision/shape_cast.hpp"

namespace fulcrum::detail {

struct ImpactRules {
    Real touchBand = Real(0.01);       // a pair closer than this at the start counts as touching
    Real stopGap = Real(0.005);        // apart at the start: stop this far from touching...
    Real passDepth = Real(0.01);       // ...if the sweeps take the pair this deep into each other
    Real sinkAllowance = Real(0.01);   // touching at the start: stop this much deeper than at the start
    Real tolerance = Real(0.001);      // the stop is within this of its target (never past it)
    // When set, a compound child of the moving shape none of whose points
    // moves farther than slowPieceFraction times pieceThickness(child) over
    // the sweep is not swept: it cannot pass through anything (its
    // speculative contact holds it), as the caller's own trigger for whole
    // bodies assumes. A toppling tree turns about its foot: the pieces near
    // the foot barely move while its top swings far.
    Real (*pieceThickness)(const Shape&) = nullptr;
    Real slowPieceFraction = 0;
};

struct SweptImpact {
    Real time = 1;                 // fraction of the sweeps at the first stop; 1 (the limit) when none
    bool hit = false;
    std::uint32_t advances = 0;    // distance evaluations (GJK, with EPA when overlapping) over all pairs
};

// The first stop in [0, limit] of shape a moving by sa against shape b moving
// by sb; sweeps run over [0, 1] (their velocities are the whole step's
// displacement and rotation vector). a: convex or a compound of convex
// shapes (else fulcrum::Error); b: any shape, but a plane, mesh or
// heightfield must be still (sb's velocities zero; else fulcrum::Error).
// A pair whose distance cannot be measured (EPA failing on a degenerate
// overlap) stops where it is: never a pass-through.
SweptImpact sweptImpact(const Shape& a, const Sweep& sa, const Shape& b, const Sweep& sb, const ImpactRules& rules,
                        Real limit = 1);

// How far from `centre` (shape frame) a point of the shape's core can be: its
// points move at most this times the angular speed when it turns about
// `centre`. The core leaves out a sphere's and capsule's radius (turning does
// not move a sphere's surface about its own centre); the other shapes count
// whole (their bounds' corners for hulls, cylinders, compounds' children).
Real coreReach(const Shape& shape, const Vec3& centre);

// A box holding the whole shape at every pose of the sweep over [0, 1]: the
// start and end bounds when it does not turn; when it turns by less than
// 3 rad, its start and turned bounds grown by the arcs' sagitta and swept
// along the centre's path; else the box around the centre's path grown by
// the shape's farthest point from the centre.
AABB sweptBounds(const Shape& shape, const Sweep& sweep);

// The sweep from pose (com0, q0) to pose (com1, q1) of a body whose centre of
// mass is `localCenter` in its frame, over [0, 1].
Sweep sweepBetween(const Vec3& com0, const Quat& q0, const Vec3& com1, const Quat& q1, const Vec3& localCenter);

}  // namespace fulcrum::detail
