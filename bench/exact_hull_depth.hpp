// The exact separation of two convex hulls, in double, for checking the narrow
// phase (bench_convex_pile_probe, tests/collision/hull_pile_pair_test.cpp).
//
// The separation along a unit axis n is B's lowest vertex along n less A's
// highest; the shapes' true separation (negative: the penetration depth) is
// its maximum over all axes, attained at a face normal of the Minkowski
// difference A - B. For polytopes those normals are A's face normals, B's,
// and the cross products of an edge of A with an edge of B, so trying all of
// them gives the maximum exactly (up to double rounding), with no search.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "fulcrum/fulcrum.hpp"

namespace bench {

struct ExactSeparation {
    double separation = -1e300;  // negative: the penetration depth
    double axis[3] = {0, 1, 0};  // from A to B
};

namespace exact_detail {

struct D3 {
    double x = 0, y = 0, z = 0;
};
inline D3 sub(const D3& a, const D3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline double dot(const D3& a, const D3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline D3 cross(const D3& a, const D3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }

// The hull's vertices in world coordinates, rotated and moved in double.
inline std::vector<D3> worldVertices(const fulcrum::ConvexHull& hull, const fulcrum::Transform& xf) {
    const double w = xf.q.w, qx = xf.q.x, qy = xf.q.y, qz = xf.q.z;
    const double n = std::sqrt(w * w + qx * qx + qy * qy + qz * qz);
    const D3 u{qx / n, qy / n, qz / n};
    const double s = w / n;
    std::vector<D3> out;
    out.reserve(hull.vertices.size());
    for (const fulcrum::Vec3& v : hull.vertices) {
        const D3 p{double(v.x), double(v.y), double(v.z)};
        // v' = v + 2 s (u x v) + 2 u x (u x v)
        const D3 t = cross(u, p);
        const D3 t2 = cross(u, t);
        out.push_back({p.x + 2 * s * t.x + 2 * t2.x + double(xf.p.x), p.y + 2 * s * t.y + 2 * t2.y + double(xf.p.y),
                       p.z + 2 * s * t.z + 2 * t2.z + double(xf.p.z)});
    }
    return out;
}

}  // namespace exact_detail

inline ExactSeparation exactHullSeparation(const fulcrum::ConvexHull& ha, const fulcrum::Transform& xa,
                                           const fulcrum::ConvexHull& hb, const fulcrum::Transform& xb) {
    using namespace exact_detail;
    const std::vector<D3> va = worldVertices(ha, xa), vb = worldVertices(hb, xb);
    ExactSeparation best;
    const auto tryAxis = [&](D3 n) {
        const double len = std::sqrt(dot(n, n));
        if (!(len > 1e-12)) return;
        n = {n.x / len, n.y / len, n.z / len};
        double maxA = -1e300, minA = 1e300, maxB = -1e300, minB = 1e300;
        for (const D3& p : va) maxA = std::max(maxA, dot(p, n)), minA = std::min(minA, dot(p, n));
        for (const D3& p : vb) maxB = std::max(maxB, dot(p, n)), minB = std::min(minB, dot(p, n));
        // Either orientation of the axis: B beyond A along n, or along -n.
        const double along = minB - maxA, against = minA - maxB;
        if (along > best.separation) best = {along, {n.x, n.y, n.z}};
        if (against > best.separation) best = {against, {-n.x, -n.y, -n.z}};
    };
    const auto faceNormals = [&](const fulcrum::ConvexHull& h, const std::vector<D3>& v) {
        for (const fulcrum::HullFace& f : h.faces) {
            // The face's plane from three of its vertices, in world coordinates.
            const std::uint32_t* i = h.faceVertices.data() + f.firstIndex;
            tryAxis(cross(sub(v[i[1]], v[i[0]]), sub(v[i[2]], v[i[0]])));
        }
    };
    faceNormals(ha, va);
    faceNormals(hb, vb);
    for (const auto& ea : ha.edges) {
        const D3 da = sub(va[ea[1]], va[ea[0]]);
        for (const auto& eb : hb.edges) tryAxis(cross(da, sub(vb[eb[1]], vb[eb[0]])));
    }
    return best;
}

}  // namespace bench
