#pragma once
// The one place where particles ask "where is the surface of this shape?".
//
// It calls the collision module's shared point query,
//   PointQuery closestPoint(const Shape&, const Transform&, const Vec3&)
// (src/collision/shape_queries.hpp): closest surface point, signed distance
// (negative inside) and outward unit normal. Particles never carry their own
// copy of the shape geometry.
#include "collision/shape_queries.hpp"
#include "fulcrum/math.hpp"
#include "fulcrum/shape.hpp"

namespace fulcrum::detail {

struct SurfacePoint {
    Vec3 point;
    Real distance = 0;
    Vec3 normal;
};

inline SurfacePoint surfaceQuery(const Shape& shape, const Transform& transform, const Vec3& point) {
    const PointQuery q = closestPoint(shape, transform, point);
    return {q.point, q.distance, q.normal};
}

}  // namespace fulcrum::detail
