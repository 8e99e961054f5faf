#pragma once
// The one place where particles ask "where is the surface of this shape?".
//
// It calls the collision module's shared point query,
//   PointQuery closestPoint(const Shape&, const Transform&, const Vec3&)
// (src/collision/shape_queries.hpp, branch `shapes`): closest surface point,
// signed distance (negative inside) and outward unit normal. Particles never
// carry their own copy of the shape geometry.
//
// NOTE (integration): while branch `shapes` has not landed, that header does
// not exist; then this file declares the same signature and the definition
// must come from elsewhere (the particle tests and benchmark provide an
// analytic sphere/plane/box/capsule version under the same
// `!__has_include` guard). Once shape_queries.hpp exists it is used
// automatically; if its PointQuery spells its fields differently, adjust the
// three lines of surfaceQuery() below.
#include "fulcrum/math.hpp"
#include "fulcrum/shape.hpp"

#if __has_include("collision/shape_queries.hpp")
#include "collision/shape_queries.hpp"
#define FULCRUM_HAS_SHAPE_QUERIES 1
#else
#define FULCRUM_HAS_SHAPE_QUERIES 0
namespace fulcrum {
struct PointQuery {
    Vec3 point;        // closest point on the surface, world space
    Real distance = 0; // signed: negative inside the shape
    Vec3 normal;       // outward unit normal at `point`
};
PointQuery closestPoint(const Shape& shape, const Transform& transform, const Vec3& point);
}  // namespace fulcrum
#endif

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
