#pragma once
// Ray casts and closest-point queries against a single shape placed in the
// world by a Transform. Used by world ray casts, by the particle system (cloth
// and rope particles colliding with rigid shapes), and as an exact reference
// in the collision tests.
//
// Conventions
// - A ray is the segment origin + t * direction, t in [0, maxFraction]; the
//   direction need not be unit length, and `fraction` is that t.
// - Solid shapes (sphere, box, capsule, cylinder, hull, plane's half-space,
//   compounds of them): a ray that starts inside or on the surface hits at
//   fraction 0, at the origin, with normal -normalize(direction) (as Box2D v3
//   and Jolt's solid convex casts report it), so a caller can tell "already
//   inside" from a miss.
// - Meshes are two-sided surfaces with no inside: a ray hits the first
//   triangle it crosses from either side, and the normal faces against the ray.
// - Signed distance is negative inside a solid. For meshes the sign comes from
//   the angle-weighted pseudo-normal of the closest feature, which is exact
//   for closed, consistently wound meshes and follows the front side of open
//   ones. For compounds the closest point belongs to the child with the
//   smallest signed distance: exact outside all children, and the deepest
//   child's surface when the point is inside overlapping children.
#include <cstdint>
#include <limits>
#include <optional>

#include "fulcrum/shape.hpp"

namespace fulcrum {

inline constexpr std::uint32_t kNoSubShape = std::numeric_limits<std::uint32_t>::max();

struct RayHit {
    Real fraction = 0;                 // hit at origin + fraction * direction
    Vec3 point;                        // world space
    Vec3 normal;                       // world space, unit, outward at the hit
    std::uint32_t child = kNoSubShape;     // compound: index of the child hit
    std::uint32_t triangle = kNoSubShape;  // mesh (or mesh inside a compound): triangle hit
};

struct PointQuery {
    Vec3 point;                        // closest point on the surface, world space
    Real distance = 0;                 // signed: negative inside
    Vec3 normal;                       // unit outward surface normal at `point`, world space
    std::uint32_t child = kNoSubShape;
    std::uint32_t triangle = kNoSubShape;
};

std::optional<RayHit> rayCastShape(const Shape& shape, const Transform& xf, const Vec3& origin, const Vec3& direction,
                                   Real maxFraction = 1);

PointQuery closestPoint(const Shape& shape, const Transform& xf, const Vec3& point);

}  // namespace fulcrum
