#pragma once
// Shape casts (a convex shape swept along a translation) and time of impact
// between two moving convex bodies, both by conservative advancement on the
// GJK distance (Mirtich 1996; van den Bergen 2004, ch. 5; Catto, "Continuous
// Collision", GDC 2013). Each step moves time forward by distance / (upper
// bound of the closing speed), which can never step past the first contact.
#include <cstdint>

#include "fulcrum/shape.hpp"

namespace fulcrum {

struct ShapeCastResult {
    bool hit = false;
    Real fraction = 1;   // of the translation, in [0, 1], at first contact
    Vec3 point;          // world contact point at that time (midway between the surfaces)
    Vec3 normal;         // unit, from A (the moving shape) to B, at that time
    std::uint32_t iterations = 0;
};

// Sweeps shape a from xa along `translationA` against the still shape b at xb.
// b may be any shape (convex, plane, mesh, compound); a may be convex or a
// compound of convex shapes. Starting in contact (within `tolerance`) gives
// fraction 0. Throws fulcrum::Error when a is a plane or mesh.
ShapeCastResult shapeCast(const Shape& a, const Transform& xa, const Vec3& translationA, const Shape& b,
                          const Transform& xb, Real tolerance = Real(1e-4));

// The motion of a body over a time interval [0, duration]: constant linear
// velocity of the centre of mass and constant angular velocity.
struct Sweep {
    Transform start;          // body frame (the shape's frame) at t = 0
    Vec3 localCenter;         // centre of mass in the body frame (the centre of rotation)
    Vec3 linearVelocity;      // of the centre of mass
    Vec3 angularVelocity;     // world space, rad/s

    Transform at(Real t) const;
};

struct ToiResult {
    enum class State : std::uint8_t { Hit, Separated, Overlapping, Failed };
    State state = State::Failed;
    Real time = 0;       // seconds from the start; `duration` when separated
    Vec3 point;
    Vec3 normal;         // from A to B
    std::uint32_t iterations = 0;
};

// First time in [0, duration] at which convex shapes a and b, moving by their
// sweeps, come within `targetSeparation` (+- tolerance) of each other.
// Overlapping: already closer than the target at t = 0.
ToiResult timeOfImpact(const Shape& a, const Sweep& sa, const Shape& b, const Sweep& sb, Real duration,
                       Real targetSeparation = Real(0), Real tolerance = Real(1e-4));

}  // namespace fulcrum
