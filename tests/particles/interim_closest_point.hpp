#pragma once
// Analytic closestPoint for sphere, plane, box and capsule - ONLY while the
// shared query (src/collision/shape_queries.hpp, branch `shapes`) has not
// landed. Include from exactly one translation unit per executable (the test
// double's .cpp, bench/cloth.cpp). Once shape_queries.hpp exists this whole
// file compiles to nothing and the engine's query is used.
#include "particles/shape_query_adapter.hpp"

#if !FULCRUM_HAS_SHAPE_QUERIES
#include <algorithm>
#include <cmath>

namespace fulcrum {

PointQuery closestPoint(const Shape& shape, const Transform& xf, const Vec3& worldPoint) {
    const Vec3 p = inverseTransformPoint(xf, worldPoint);
    Vec3 point, normal{0, 1, 0};
    Real dist = 0;
    const auto aroundSegmentPoint = [&](const Vec3& c, Real r) {
        const Vec3 d = p - c;
        const Real len = length(d);
        normal = len > Real(1e-12) ? d / len : Vec3{0, 1, 0};
        dist = len - r;
        point = c + normal * r;
    };
    switch (shape.type()) {
        case ShapeType::Sphere: aroundSegmentPoint(Vec3::zero(), shape.radius()); break;
        case ShapeType::Capsule: {
            const Real hh = shape.halfHeight();
            aroundSegmentPoint({0, std::clamp(p.y, -hh, hh), 0}, shape.radius());
            break;
        }
        case ShapeType::Plane: {
            normal = shape.planeNormal();
            dist = dot(normal, p) - shape.planeOffset();
            point = p - normal * dist;
            break;
        }
        case ShapeType::Box: {
            const Vec3 h = shape.halfExtents();
            const Vec3 q{std::clamp(p.x, -h.x, h.x), std::clamp(p.y, -h.y, h.y), std::clamp(p.z, -h.z, h.z)};
            if (q != p) {
                const Vec3 d = p - q;
                dist = length(d);
                normal = d / dist;
                point = q;
            } else {  // inside: leave through the nearest face
                std::size_t axis = 0;
                Real best = h.x - std::fabs(p.x);
                for (std::size_t a = 1; a < 3; ++a) {
                    const Real gap = h[a] - std::fabs(p[a]);
                    if (gap < best) { best = gap; axis = a; }
                }
                normal = Vec3::zero();
                normal[axis] = p[axis] >= 0 ? Real(1) : Real(-1);
                point = p;
                point[axis] = normal[axis] * h[axis];
                dist = -best;
            }
            break;
        }
        default: break;  // the test worlds use only the shapes above
    }
    return {transformPoint(xf, point), dist, transformVector(xf, normal)};
}

}  // namespace fulcrum
#endif
