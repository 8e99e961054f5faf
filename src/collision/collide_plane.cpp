// Every convex shape against a plane (the plane is shape A, so the normal is
// the plane's). Spheres and capsules are exact; boxes and hulls test every
// vertex; cylinders use their supporting feature (the cap's rim points when
// standing, the side line when lying, else the single deepest point). Several points are
// reduced to four (deepest first, then maximum area).
#include "collision/collide_pairs.hpp"

namespace fulcrum::detail {

bool collidePlaneConvex(const Vec3& n, Real offset, const ConvexShape& b, Real margin, Manifold& m) {
    m.normal = n;
    m.pointCount = 0;
    ContactCandidate cand[kMaxFacePoints + 1];
    std::uint32_t count = 0;
    auto add = [&](const Vec3& p, std::uint32_t id) {
        const Real depth = offset - dot(n, p);
        if (depth < -margin || count == kMaxFacePoints + 1) return;
        cand[count++] = {p + n * (Real(0.5) * depth), depth, id};
    };
    auto flush = [&] {
        if (count > 0) reduceContacts({cand, count}, margin, m);
        return m.pointCount > 0;
    };
    switch (b.kind) {
        case ConvexKind::Point: add(b.xf.p - n * b.radius, 0); return flush();
        case ConvexKind::Segment: {
            const Vec3 axis = rotate(b.xf.q, Vec3{0, b.halfHeight, 0});
            add(b.xf.p - axis - n * b.radius, 0);
            add(b.xf.p + axis - n * b.radius, 1);
            return flush();
        }
        case ConvexKind::Box: {
            // A quick reject on the box's support point before the 8 corners.
            if (offset - dot(n, b.coreSupport(-n)) < -margin) return false;
            for (std::uint32_t i = 0; i < 8; ++i) {
                const Vec3 local{(i & 1) ? b.halfExtents.x : -b.halfExtents.x, (i & 2) ? b.halfExtents.y : -b.halfExtents.y,
                                 (i & 4) ? b.halfExtents.z : -b.halfExtents.z};
                add(transformPoint(b.xf, local), i);
            }
            return flush();
        }
        case ConvexKind::Hull: {
            const Vec3 ln = inverseRotate(b.xf.q, n);
            const Real localOffset = offset - dot(n, b.xf.p);
            // Depth in local space, so only vertices within the margin are transformed.
            const std::vector<Vec3>& v = b.hull->vertices;
            for (std::size_t i = 0; i < v.size(); ++i) {
                const Real depth = localOffset - dot(ln, v[i]);
                if (depth < -margin) continue;
                if (count == kMaxFacePoints + 1) {
                    // Full: make room by reducing what we have to 4 and carrying on.
                    count = compactCandidates(cand, count, n, margin);
                }
                add(transformPoint(b.xf, v[i]), static_cast<std::uint32_t>(i));
            }
            return flush();
        }
        case ConvexKind::Cylinder: {
            SupportFace face;
            supportingFace(b, -n, face);
            for (std::uint32_t i = 0; i < face.count; ++i) add(face.points[i], face.id << 8 | i);
            // A tilted cap's square lies up to 0.29 r sin(tilt) above the
            // rim's lowest point, so with the rim inside the margin every
            // corner can still be beyond it: the rim's deepest point keeps
            // the speculative contact the margin promises (no contact would
            // let a fast cylinder reach the plane unseen).
            if (count == 0) add(b.support(-n), face.id << 8 | kCylinderCapPoints);
            return flush();
        }
        case ConvexKind::Triangle: return false;
    }
    return false;
}

}  // namespace fulcrum::detail
