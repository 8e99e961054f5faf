#pragma once
// GJK distance (Gilbert, Johnson, Keerthi 1988; van den Bergen, "Collision
// Detection in Interactive 3D Environments", 2004; Ericson, "Real-Time
// Collision Detection", ch. 9): closest points of two convex shapes by
// walking a simplex of the Minkowski difference A - B towards the origin.
#include <cstdint>
#include <limits>

#include "collision/support.hpp"

namespace fulcrum::detail {

struct SimplexVertex {
    Vec3 a;  // support point on A
    Vec3 b;  // support point on B
    Vec3 w;  // a - b
    // The vertices a and b are (a hull's index, a box's corner), in a run
    // with a warm start (else unset).
    std::uint32_t indexA = 0, indexB = 0;
};

struct GjkWarmStart;  // collision/manifold.hpp

struct Simplex {
    SimplexVertex v[4];
    Real bary[4] = {0, 0, 0, 0};
    std::uint32_t count = 0;
};

struct GjkResult {
    bool overlap = false;   // the origin is inside (or within float noise of) A - B
    Real distance = 0;      // between the shapes GJK ran on (cores or full shapes)
    Vec3 pointA, pointB;    // closest points
    Vec3 normal;            // unit, from A to B, when apart: the direction of pointB - pointA, but exact to rounding
    Simplex simplex;        // final simplex (for EPA when overlapping)
    std::uint32_t iterations = 0;
    // Stopped early: a support plane showed the shapes farther apart than
    // `stopBeyond`; `distance` is then that lower bound, the points and the
    // normal are not filled in.
    bool beyond = false;
};

// Distance between the cores of a and b (radii ignored) when `withRadius` is
// false, or between the full shapes when true. With a finite `stopBeyond` GJK
// stops as soon as a support plane proves the shapes more than that far
// apart (a caller that only needs to know that they are: the narrow phase
// beyond its margin). The full run's distance is never below that bound, so
// a caller that would reject the pair on the full distance rejects it the
// same; with the default every result is as before. A non-null `guess` (a
// unit normal from A to B, say a nearby pose's result) starts a cold search
// along it instead of along the line of centres: the same distance to the
// tolerance, in fewer iterations when the guess is close.
//
// `warm`: a pair's warm start (collision/manifold.hpp, GjkWarmStart), for
// the cores of two shapes that are each a hull or a box (else ignored). The
// run starts from its simplex when it holds one whose indices fit the
// shapes (then `guess` is not used), and leaves in it the simplex the run
// ended on (its first three vertices after an overlap).
GjkResult gjkDistance(const ConvexShape& a, const ConvexShape& b, bool withRadius,
                      Real stopBeyond = std::numeric_limits<Real>::infinity(), GjkWarmStart* warm = nullptr,
                      const Vec3* guess = nullptr);

// Closest point to the origin on the simplex; shrinks it to the vertices that
// support that point and stores their barycentric weights. Returns false when
// the origin lies inside a tetrahedron.
bool closestOnSimplex(Simplex& s, Vec3& closest);

}  // namespace fulcrum::detail
