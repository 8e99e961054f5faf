#pragma once
// EPA, the Expanding Polytope Algorithm (van den Bergen 2001, "Proximity
// Queries and Penetration Depth Computation on 3D Game Objects"): grows a
// polytope inside the Minkowski difference A - B from GJK's final simplex
// until its face closest to the origin is on the boundary; that face's
// normal and distance are the penetration direction and depth.
#include "collision/gjk.hpp"

namespace fulcrum::detail {

struct PenetrationResult {
    bool valid = false;
    Vec3 normal;   // unit, from A to B: moving B by normal*depth separates the shapes
    Real depth = 0;
    Vec3 pointA;   // deepest point of A inside B (on A's surface)
    Vec3 pointB;   // deepest point of B inside A (on B's surface)
};

// Penetration of the full (rounded) shapes. Runs GJK itself: when a shape has
// a radius and the cores overlap, EPA expands the cores and adds the radii
// (exact), else the full shapes; fixed-size storage, no allocation.
// `coreRun`: gjkDistance(a, b, false) on these shapes, when the caller has
// run it (run to the end: not stopped early); EPA then starts from it instead
// of running GJK again (the same run, so the same answer).
PenetrationResult epaPenetration(const ConvexShape& a, const ConvexShape& b, const GjkResult* coreRun = nullptr);

}  // namespace fulcrum::detail
