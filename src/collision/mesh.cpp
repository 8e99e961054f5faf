// Shape::mesh: validation, triangle adjacency, convex-edge flags and the BVH.
//
// Internal edges. A box sliding over a flat mesh must not catch on the edges
// between coplanar triangles ("ghost collisions"). For every triangle edge we
// record whether the mesh is convex there (or open: a boundary); the narrow
// phase lets only such edges produce edge contacts, and pushes contacts on
// flat or concave edges back to the face normal. Two triangles are adjacent
// when they share an edge with opposite windings; an edge used by more than
// two triangles (non-manifold), or by two with the same winding, is treated as
// a boundary, which is the safe side (it may collide).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "collision/mesh_bvh.hpp"
#include "fulcrum/math/deterministic_math.hpp"
#include "fulcrum/shape.hpp"

namespace fulcrum {

namespace {

constexpr std::uint32_t kBoundary = std::numeric_limits<std::uint32_t>::max();

// Dihedral tolerance: edges bent by less than this (radians) either way count
// as flat, hence internal. 1e-3 rad (0.06 degrees) is far above float noise on
// coplanar triangles (~1e-6 rad) and below any bend a user would model.
constexpr Real kFlatAngle = Real(1e-3);

// A triangle is degenerate when its height is below this fraction of its
// longest edge: its normal would be dominated by float rounding.
constexpr double kMinAspect = 1e-6;

}  // namespace

// The dihedral angle phi of the neighbour, measured in the plane perpendicular
// to the edge: phi = atan2(y, x) with x the neighbour's far vertex's distance
// away from this triangle in its plane and y its height above the plane.
// phi = 0 is flat, phi < 0 bends away (convex), phi > 0 folds up (concave),
// |phi| near pi is a knife edge (two sheets back to back), which collides
// like a convex one. Shape building only, never in a step.
bool isConvexEdge(const Vec3& faceNormal, const Vec3& edgeStart, const Vec3& edgeEnd, const Vec3& farVertex) {
    const Vec3 e = normalize(edgeEnd - edgeStart);
    const Vec3 c = farVertex - edgeStart;
    const Real x = -dot(c, cross(faceNormal, e));  // cross(n, e) points into this triangle
    const Real y = dot(c, faceNormal);
    const Real phi = dmath::atan2(y, x);
    return phi < -kFlatAngle || std::fabs(phi) > std::numbers::pi_v<Real> - kFlatAngle;
}

Shape Shape::mesh(std::span<const Vec3> vertices, std::span<const std::array<std::uint32_t, 3>> triangles) {
    if (vertices.empty()) throw Error("mesh: vertices must not be empty");
    if (triangles.empty()) throw Error("mesh: triangles must not be empty");
    if (triangles.size() >= std::size_t(1) << 31 || vertices.size() >= std::size_t(1) << 31) {
        throw Error("mesh: too many vertices or triangles (limit 2^31)");
    }
    for (std::size_t i = 0; i < vertices.size(); ++i) {
        if (!isFinite(vertices[i])) throw Error("mesh: vertices[" + std::to_string(i) + "] is not finite (NaN or infinity)");
        if (maxComponent(abs(vertices[i])) > kMaxShapeCoordinate) {
            throw Error("mesh: vertices[" + std::to_string(i) + "] has a coordinate beyond the limit of 1e12 m (kMaxShapeCoordinate)");
        }
    }
    for (std::size_t t = 0; t < triangles.size(); ++t) {
        const auto& tri = triangles[t];
        for (std::size_t k = 0; k < 3; ++k) {
            if (tri[k] >= vertices.size()) {
                throw Error("mesh: triangles[" + std::to_string(t) + "][" + std::to_string(k) + "] = " + std::to_string(tri[k]) +
                            " is out of range (" + std::to_string(vertices.size()) + " vertices)");
            }
        }
        // Area in double from the float inputs, so a collinear triangle is not
        // rescued by rounding.
        const Vec3 &a = vertices[tri[0]], &b = vertices[tri[1]], &c = vertices[tri[2]];
        const double e1[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
        const double e2[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
        const double e3[3] = {double(c.x) - b.x, double(c.y) - b.y, double(c.z) - b.z};
        const double cx = e1[1] * e2[2] - e1[2] * e2[1], cy = e1[2] * e2[0] - e1[0] * e2[2], cz = e1[0] * e2[1] - e1[1] * e2[0];
        const double twiceArea = std::sqrt(cx * cx + cy * cy + cz * cz);
        auto len2 = [](const double* e) { return e[0] * e[0] + e[1] * e[1] + e[2] * e[2]; };
        const double longest2 = std::max({len2(e1), len2(e2), len2(e3)});
        if (tri[0] == tri[1] || tri[1] == tri[2] || tri[2] == tri[0] || !(twiceArea > kMinAspect * longest2)) {
            throw Error("mesh: triangles[" + std::to_string(t) + "] is degenerate (zero area)");
        }
    }

    auto mesh = std::make_shared<TriangleMesh>();
    mesh->vertices.assign(vertices.begin(), vertices.end());
    mesh->triangles.assign(triangles.begin(), triangles.end());
    for (const Vec3& v : mesh->vertices) mesh->bounds.grow(v);
    const std::size_t nt = triangles.size();

    // Adjacency: the edges sorted by their undirected key. A counting sort by
    // the lower vertex, then a sort of each vertex's few edges: the order of
    // one sort of the whole list at a fraction of its cost (a third of the
    // mesh's build on Box3D's 60,000-triangle trees mesh went to that sort).
    struct EdgeRef {
        std::uint32_t lo, hi, triangle, edge;
        bool operator<(const EdgeRef& o) const { return std::tie(lo, hi, triangle, edge) < std::tie(o.lo, o.hi, o.triangle, o.edge); }
    };
    const auto edgeRef = [&triangles](std::uint32_t t, std::uint32_t k) {
        const std::uint32_t a = triangles[t][k], b = triangles[t][(k + 1) % 3];
        return EdgeRef{std::min(a, b), std::max(a, b), t, k};
    };
    std::vector<std::uint32_t> firstEdge(vertices.size() + 1, 0);  // where each lower vertex's edges start
    for (std::uint32_t t = 0; t < nt; ++t) {
        for (std::uint32_t k = 0; k < 3; ++k) ++firstEdge[edgeRef(t, k).lo + 1];
    }
    for (std::size_t v = 1; v < firstEdge.size(); ++v) firstEdge[v] += firstEdge[v - 1];
    std::vector<EdgeRef> edges(3 * nt);
    {
        std::vector<std::uint32_t> next(firstEdge.begin(), firstEdge.end() - 1);
        for (std::uint32_t t = 0; t < nt; ++t) {
            for (std::uint32_t k = 0; k < 3; ++k) {
                const EdgeRef e = edgeRef(t, k);
                edges[next[e.lo]++] = e;
            }
        }
    }
    for (std::size_t v = 0; v + 1 < firstEdge.size(); ++v) {
        std::sort(edges.begin() + firstEdge[v], edges.begin() + firstEdge[v + 1]);
    }
    mesh->adjacency.assign(nt, {kBoundary, kBoundary, kBoundary});
    for (std::size_t i = 0; i < edges.size();) {
        std::size_t j = i + 1;
        while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
        if (j - i == 2) {
            const EdgeRef &e0 = edges[i], &e1 = edges[i + 1];
            const bool forward0 = triangles[e0.triangle][e0.edge] == e0.lo;
            const bool forward1 = triangles[e1.triangle][e1.edge] == e1.lo;
            if (forward0 != forward1) {
                mesh->adjacency[e0.triangle][e0.edge] = e1.triangle;
                mesh->adjacency[e1.triangle][e1.edge] = e0.triangle;
            }
        }
        i = j;
    }

    // Convex-edge flags (isConvexEdge).
    mesh->convexEdgeMask.assign(nt, 0);
    for (std::uint32_t t = 0; t < nt; ++t) {
        const auto& tri = triangles[t];
        const Vec3 n = normalize(cross(vertices[tri[1]] - vertices[tri[0]], vertices[tri[2]] - vertices[tri[0]]));
        std::uint8_t mask = 0;
        for (std::uint32_t k = 0; k < 3; ++k) {
            const std::uint32_t other = mesh->adjacency[t][k];
            if (other == kBoundary) { mask = static_cast<std::uint8_t>(mask | (1u << k)); continue; }
            const auto& nb = triangles[other];
            std::uint32_t far = nb[0];
            for (std::uint32_t v : nb) {
                if (v != tri[k] && v != tri[(k + 1) % 3]) far = v;
            }
            if (isConvexEdge(n, vertices[tri[k]], vertices[tri[(k + 1) % 3]], vertices[far])) {
                mask = static_cast<std::uint8_t>(mask | (1u << k));
            }
        }
        mesh->convexEdgeMask[t] = mask;
    }

    mesh->bvh = std::make_shared<const MeshBvh>(buildMeshBvh(*mesh));

    Shape s;
    s.type_ = ShapeType::Mesh;
    s.radius_ = 0;
    s.mesh_ = std::move(mesh);
    return s;
}

}  // namespace fulcrum
