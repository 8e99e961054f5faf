#pragma once
// World queries: the input and result types of World::castRay, castRayAll,
// overlapAABB / overlapSphere / overlapBox / overlapShape, castShape and closestPoints
// (declared in world.hpp; docs/queries.md describes each one).
//
// Queries are read-only, may run at any time between steps (bodies created
// since the last step included), and report bodies by BodyId in a
// deterministic order that does not depend on the broad phase's tree shape.
#include <cstdint>
#include <limits>

#include "fulcrum/body.hpp"
#include "fulcrum/math.hpp"

namespace fulcrum {

// The value of RayCastHit::child / triangle when the body's shape has no such part.
inline constexpr std::uint32_t kNoSubShapeIndex = std::numeric_limits<std::uint32_t>::max();

// Which bodies a query sees. A body passes when
//   (body.filter.category & mask) != 0 and (category & body.filter.mask) != 0,
// it is not `excludeBody`, and it is not a sensor unless `includeSensors`.
// Collision groups play no part in queries. The defaults see every body that
// collides with anything (a body with mask 0 is invisible to them too) except
// sensors.
struct QueryFilter {
    std::uint32_t category = 0xFFFFFFFFu;  // what the query counts as, for the bodies' masks
    std::uint32_t mask = 0xFFFFFFFFu;      // the body categories the query sees
    BodyId excludeBody;                    // null: none (e.g. the character casting the ray)
    bool includeSensors = false;
};

// The segment origin + t * translation, t in [0, maxFraction]. `translation`
// need not be unit length: a hit's fraction is that t, so with a unit
// direction it is a distance, and with translation = end - origin it is the
// fraction of the way to `end`.
struct Ray {
    Vec3 origin;
    Vec3 translation;
    Real maxFraction = 1;  // in [0, 1]
};

struct RayCastHit {
    BodyId body;
    Vec3 point;           // world space: origin + fraction * translation
    Vec3 normal;          // unit, outward from the body's surface at `point` (against the ray for meshes)
    Real fraction = 0;    // 0 when the ray starts inside a solid shape (normal = -unit(translation))
    std::uint32_t child = kNoSubShapeIndex;     // compound: the top-level child hit
    std::uint32_t triangle = kNoSubShapeIndex;  // mesh (also inside a compound): the triangle hit
};

// The first contact of a convex shape swept along a translation.
struct ShapeCastHit {
    BodyId body;
    Real fraction = 0;    // of the translation, in [0, 1]: the shape's frame is then at start.p + fraction * translation
    Vec3 point;           // world contact point at that time
    Vec3 normal;          // unit, outward from the body hit (against the cast)
};

// The closest points of two shapes (World::closestPoints, World::distanceBetween).
struct ClosestPoints {
    Real distance = 0;  // m between the surfaces; negative when they overlap (minus the penetration depth)
    Vec3 pointA;        // world: on the first shape's surface (when overlapping, its deepest point inside the second)
    Vec3 pointB;        // world: on the second shape's surface
    Vec3 normal;        // unit, from the first shape towards the second (moving the second along it separates them)
};

}  // namespace fulcrum
