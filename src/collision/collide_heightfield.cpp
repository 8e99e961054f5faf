// Convex shapes against heightfields: the triangles of the cells under the
// shape's bounds (found through the min/max mip-map, heightfield.hpp) go
// through the same per-triangle collision, internal-edge handling and
// grouping into manifolds as a mesh's (collide_mesh.cpp), boxes and hulls
// through the separating-axis test (collide_triangle.cpp).
#include "collision/collide_mesh.hpp"
#include "collision/collide_triangle.hpp"
#include "collision/heightfield.hpp"

namespace fulcrum::detail {

void collideHeightFieldConvex(const HeightField& hf, const Transform& xf, const ConvexShape& b, const AABB& bBounds,
                              Real margin, ManifoldBuffer& out) {
    std::vector<MeshContactCandidate>& scratch = out.meshScratch();
    scratch.clear();
    TrianglePolytope polytope;
    const TrianglePolytope* sat = polytope.prepare(b, out.polytopeEdgeScratch()) ? &polytope : nullptr;
    const AABB localBox = transformBounds(inverse(xf), bBounds.fattened(margin));
    forEachHeightFieldTriangle(hf, localBox, [&](std::uint32_t t) {
        Vec3 w[3];
        hf.triangle(t, w);
        for (Vec3& v : w) v = transformPoint(xf, v);
        collideTriangleWithConvex(w, hf.convexEdgeMask[t], t, b, margin, scratch, sat);
    });
    groupTriangleContacts(scratch, margin, out, sat != nullptr);
}

}  // namespace fulcrum::detail
