// Render meshes for collision shapes (see tessellate.hpp).
#include "io/tessellate.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace fulcrum::io {

namespace {

// One point of a profile revolved about the y axis: radius, height and the
// profile normal (radial and vertical parts).
struct ProfilePoint {
    Real r, y, nr, ny;
};

// Revolves a profile (bottom to top) about y. Consecutive profile points form
// a band of quads; a point with r = 0 is a pole, where each quad collapses to
// one triangle. Quad (a, b, c, d) = (k,s), (k,s+1), (k+1,s+1), (k+1,s) is
// wound (a, d, c) + (a, c, b): counter-clockwise seen from outside.
void lathe(const std::vector<ProfilePoint>& profile, int segments, RenderMesh& out) {
    const auto base = static_cast<std::uint32_t>(out.positions.size());
    const auto segs = static_cast<std::uint32_t>(segments);
    for (const ProfilePoint& p : profile) {
        for (std::uint32_t s = 0; s < segs; ++s) {
            const Real theta = Real(2) * std::numbers::pi_v<Real> * static_cast<Real>(s) / static_cast<Real>(segs);
            const Real c = std::cos(theta), sn = std::sin(theta);
            out.positions.push_back({p.r * c, p.y, p.r * sn});
            out.normals.push_back(normalize(Vec3{p.nr * c, p.ny, p.nr * sn}));
        }
    }
    for (std::uint32_t k = 0; k + 1 < profile.size(); ++k) {
        const bool bottomPole = profile[k].r == 0;
        const bool topPole = profile[k + 1].r == 0;
        for (std::uint32_t s = 0; s < segs; ++s) {
            const std::uint32_t s1 = (s + 1) % segs;
            const std::uint32_t a = base + k * segs + s, b = base + k * segs + s1;
            const std::uint32_t c = base + (k + 1) * segs + s1, d = base + (k + 1) * segs + s;
            if (!topPole) out.indices.insert(out.indices.end(), {a, d, c});
            if (!bottomPole) out.indices.insert(out.indices.end(), {a, c, b});
        }
    }
}

// A hemisphere's profile points from its pole to its equator (or reverse).
void hemisphere(std::vector<ProfilePoint>& profile, Real radius, Real centerY, int rings, bool upper) {
    for (int i = 0; i <= rings; ++i) {
        // phi from -pi/2 (south pole) to 0 (equator) for the lower half, 0 to pi/2 for the upper.
        const Real t = static_cast<Real>(i) / static_cast<Real>(rings);
        const Real phi = (upper ? t : t - 1) * std::numbers::pi_v<Real> / 2;
        const Real cr = std::cos(phi), sy = std::sin(phi);
        const bool pole = (upper && i == rings) || (!upper && i == 0);
        profile.push_back({pole ? Real(0) : radius * cr, centerY + radius * sy, pole ? Real(0) : cr, sy});
    }
}

void appendQuad(RenderMesh& out, const Vec3 corners[4], const Vec3& normal) {
    const auto base = static_cast<std::uint32_t>(out.positions.size());
    for (int i = 0; i < 4; ++i) {
        out.positions.push_back(corners[i]);
        out.normals.push_back(normal);
    }
    out.indices.insert(out.indices.end(), {base, base + 1, base + 2, base, base + 2, base + 3});
}

int atLeast(int v, int lo) { return v < lo ? lo : v; }

// A rounded box, cylinder or hull as the polyhedron its mass comes from (a
// hull's stand-in, docs/shapes.md): the box's core corners or a ring of 24
// points on each of the cylinder core's rims, swept by the radius. A flat
// core (a radius at its limit) is drawn 0.1 mm thick, as a hull needs volume.
RenderMesh tessellateRounded(const Shape& shape) {
    const Real r = shape.convexRadius();
    if (shape.type() == ShapeType::ConvexHull) return tessellateHull(*roundedHullOf(shape));
    std::vector<Vec3> core;
    if (shape.type() == ShapeType::Box) {
        const Vec3 c = max(shape.halfExtents() - Vec3::splat(r), Vec3::splat(Real(1e-4)));
        for (int i = 0; i < 8; ++i) core.push_back({(i & 1) ? c.x : -c.x, (i & 2) ? c.y : -c.y, (i & 4) ? c.z : -c.z});
    } else {
        const Real p = std::max(shape.radius() - r, Real(1e-4)), h = std::max(shape.halfHeight() - r, Real(1e-4));
        for (int i = 0; i < 24; ++i) {
            const Real a = Real(2) * std::numbers::pi_v<Real> * static_cast<Real>(i) / 24;
            core.push_back({p * std::cos(a), h, p * std::sin(a)});
            core.push_back({p * std::cos(a), -h, p * std::sin(a)});
        }
    }
    return tessellateHull(*roundedHullOf(Shape::roundedConvexHull(core, r)));
}

void flatten(const Shape& shape, const Transform& frame, const TessellationOptions& options,
             std::vector<RenderPart>& parts) {
    if (shape.type() == ShapeType::Compound) {
        for (const CompoundChild& child : shape.children()) flatten(child.shape, frame * child.transform, options, parts);
        return;
    }
    TessellationOptions local = options;
    // The plane's quad is centred near the requested point, expressed in this part's frame.
    local.planeCenter = inverseTransformPoint(frame, options.planeCenter);
    RenderPart part;
    part.local = frame;
    if (shape.convexRadius() > 0) {  // rounded shapes: drawn as their polyhedral stand-in
        part.mesh = tessellateRounded(shape);
        parts.push_back(std::move(part));
        return;
    }
    switch (shape.type()) {
        case ShapeType::Sphere: part.mesh = tessellateSphere(shape.radius(), local); break;
        case ShapeType::Box: part.mesh = tessellateBox(shape.halfExtents()); break;
        case ShapeType::Capsule: part.mesh = tessellateCapsule(shape.radius(), shape.halfHeight(), local); break;
        case ShapeType::Cylinder: part.mesh = tessellateCylinder(shape.radius(), shape.halfHeight(), local); break;
        case ShapeType::ConvexHull: part.mesh = tessellateHull(shape.hull()); break;
        case ShapeType::Mesh: part.mesh = tessellateTriangleMesh(shape.mesh()); break;
        case ShapeType::HeightField: part.mesh = tessellateHeightField(shape.heightField()); break;
        case ShapeType::Plane: part.mesh = tessellatePlane(shape.planeNormal(), shape.planeOffset(), local); break;
        case ShapeType::Compound: break;  // handled above
    }
    parts.push_back(std::move(part));
}

}  // namespace

RenderMesh tessellateSphere(Real radius, const TessellationOptions& options) {
    const int rings = atLeast(options.rings, 2);
    std::vector<ProfilePoint> profile;
    for (int i = 0; i <= rings; ++i) {
        const Real phi = (static_cast<Real>(i) / static_cast<Real>(rings) - Real(0.5)) * std::numbers::pi_v<Real>;
        const bool pole = i == 0 || i == rings;
        profile.push_back({pole ? Real(0) : radius * std::cos(phi), radius * std::sin(phi),
                           pole ? Real(0) : std::cos(phi), std::sin(phi)});
    }
    RenderMesh mesh;
    lathe(profile, atLeast(options.segments, 3), mesh);
    return mesh;
}

RenderMesh tessellateCapsule(Real radius, Real halfHeight, const TessellationOptions& options) {
    const int half = atLeast(options.rings / 2, 1);
    std::vector<ProfilePoint> profile;
    hemisphere(profile, radius, -halfHeight, half, false);  // ends at the lower equator
    hemisphere(profile, radius, halfHeight, half, true);    // starts at the upper equator: the band between is the side
    RenderMesh mesh;
    lathe(profile, atLeast(options.segments, 3), mesh);
    return mesh;
}

RenderMesh tessellateCylinder(Real radius, Real halfHeight, const TessellationOptions& options) {
    const int segments = atLeast(options.segments, 3);
    RenderMesh mesh;
    lathe({{radius, -halfHeight, 1, 0}, {radius, halfHeight, 1, 0}}, segments, mesh);
    // Caps: fans around a centre vertex, with the cap's own flat normal.
    for (int side = 0; side < 2; ++side) {
        const Real y = side == 0 ? -halfHeight : halfHeight;
        const Vec3 n{0, side == 0 ? Real(-1) : Real(1), 0};
        const auto center = static_cast<std::uint32_t>(mesh.positions.size());
        mesh.positions.push_back({0, y, 0});
        mesh.normals.push_back(n);
        const auto segs = static_cast<std::uint32_t>(segments);
        for (std::uint32_t s = 0; s < segs; ++s) {
            const Real theta = Real(2) * std::numbers::pi_v<Real> * static_cast<Real>(s) / static_cast<Real>(segs);
            mesh.positions.push_back({radius * std::cos(theta), y, radius * std::sin(theta)});
            mesh.normals.push_back(n);
        }
        for (std::uint32_t s = 0; s < segs; ++s) {
            const std::uint32_t p0 = center + 1 + s, p1 = center + 1 + (s + 1) % segs;
            if (side == 0) {
                mesh.indices.insert(mesh.indices.end(), {center, p0, p1});
            } else {
                mesh.indices.insert(mesh.indices.end(), {center, p1, p0});
            }
        }
    }
    return mesh;
}

RenderMesh tessellateBox(const Vec3& h) {
    // Each face: normal n and tangents u, v with u x v = n; corners (-,-), (+,-), (+,+), (-,+) run counter-clockwise.
    struct Face { Vec3 n, u, v; };
    static const Face faces[6] = {
        {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}},  {{-1, 0, 0}, {0, 0, 1}, {0, 1, 0}},
        {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}},  {{0, -1, 0}, {1, 0, 0}, {0, 0, 1}},
        {{0, 0, 1}, {1, 0, 0}, {0, 1, 0}},  {{0, 0, -1}, {0, 1, 0}, {1, 0, 0}},
    };
    RenderMesh mesh;
    for (const Face& f : faces) {
        const Vec3 corners[4] = {mul(h, f.n - f.u - f.v), mul(h, f.n + f.u - f.v), mul(h, f.n + f.u + f.v),
                                 mul(h, f.n - f.u + f.v)};
        appendQuad(mesh, corners, f.n);
    }
    return mesh;
}

RenderMesh tessellateHull(const ConvexHull& hull) {
    RenderMesh mesh;
    for (const HullFace& face : hull.faces) {
        const auto base = static_cast<std::uint32_t>(mesh.positions.size());
        for (std::uint32_t i = 0; i < face.indexCount; ++i) {
            mesh.positions.push_back(hull.vertices[hull.faceVertices[face.firstIndex + i]]);
            mesh.normals.push_back(face.normal);
        }
        for (std::uint32_t i = 1; i + 1 < face.indexCount; ++i) {
            mesh.indices.insert(mesh.indices.end(), {base, base + i, base + i + 1});  // fan: the face is convex
        }
    }
    return mesh;
}

RenderMesh tessellateHeightField(const HeightField& field, std::uint32_t maxCells) {
    // Every stride-th sample along each axis (and the last), so at most
    // maxCells cells per axis are drawn.
    const std::uint32_t longest = std::max(field.cellRows(), field.cellColumns());
    const std::uint32_t stride = std::max<std::uint32_t>(1, (longest + maxCells - 1) / std::max<std::uint32_t>(1, maxCells));
    std::vector<std::uint32_t> rows, columns;
    for (std::uint32_t r = 0; r < field.rows; r += stride) rows.push_back(r);
    if (rows.back() != field.rows - 1) rows.push_back(field.rows - 1);
    for (std::uint32_t c = 0; c < field.columns; c += stride) columns.push_back(c);
    if (columns.back() != field.columns - 1) columns.push_back(field.columns - 1);
    RenderMesh mesh;
    mesh.positions.reserve(rows.size() * columns.size());
    mesh.normals.reserve(rows.size() * columns.size());
    for (const std::uint32_t r : rows) {
        for (const std::uint32_t c : columns) {
            // Smooth shading: the normal of the central-difference slopes.
            const std::uint32_t r0 = r > 0 ? r - 1 : r, r1 = r + 1 < field.rows ? r + 1 : r;
            const std::uint32_t c0 = c > 0 ? c - 1 : c, c1 = c + 1 < field.columns ? c + 1 : c;
            const Real dhdx = (field.height(r, c1) - field.height(r, c0)) / (static_cast<Real>(c1 - c0) * field.spacingX);
            const Real dhdz = (field.height(r1, c) - field.height(r0, c)) / (static_cast<Real>(r1 - r0) * field.spacingZ);
            mesh.positions.push_back(field.sample(r, c));
            mesh.normals.push_back(normalize(Vec3{-dhdx, 1, -dhdz}));
        }
    }
    const auto vertex = [&](std::size_t i, std::size_t j) { return static_cast<std::uint32_t>(i * columns.size() + j); };
    for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
        for (std::size_t j = 0; j + 1 < columns.size(); ++j) {
            // A drawn cell covering any hole is left out, so holes stay visible.
            bool hole = false;
            for (std::uint32_t r = rows[i]; r < rows[i + 1] && !hole; ++r) {
                for (std::uint32_t c = columns[j]; c < columns[j + 1] && !hole; ++c) hole = field.isHole(r * field.cellColumns() + c);
            }
            if (hole) continue;
            // The field's diagonal, (r, c) to (r + 1, c + 1); counter-clockwise from above.
            mesh.indices.insert(mesh.indices.end(), {vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1)});
            mesh.indices.insert(mesh.indices.end(), {vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1)});
        }
    }
    return mesh;
}

RenderMesh tessellateTriangleMesh(const TriangleMesh& source) {
    RenderMesh mesh;
    mesh.positions.reserve(source.triangles.size() * 3);
    mesh.normals.reserve(source.triangles.size() * 3);
    mesh.indices.reserve(source.triangles.size() * 3);
    for (const auto& tri : source.triangles) {
        const Vec3 &a = source.vertices[tri[0]], &b = source.vertices[tri[1]], &c = source.vertices[tri[2]];
        const Vec3 n = normalize(cross(b - a, c - a));
        for (const Vec3* p : {&a, &b, &c}) {
            mesh.indices.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
            mesh.positions.push_back(*p);
            mesh.normals.push_back(n);
        }
    }
    // Meshes are often open (terrain): show their back faces rather than holes.
    mesh.doubleSided = true;
    return mesh;
}

RenderMesh tessellatePlane(const Vec3& normal, Real offset, const TessellationOptions& options) {
    const Vec3 n = normalize(normal);
    const Vec3 center = options.planeCenter - n * (dot(n, options.planeCenter) - offset);
    Vec3 t1, t2;
    orthonormalBasis(n, t1, t2);  // right-handed: t1 x t2 = n
    const Real s = options.planeHalfSize;
    const Vec3 corners[4] = {center - t1 * s - t2 * s, center + t1 * s - t2 * s, center + t1 * s + t2 * s,
                             center - t1 * s + t2 * s};
    RenderMesh mesh;
    appendQuad(mesh, corners, n);
    mesh.doubleSided = true;
    return mesh;
}

std::vector<RenderPart> tessellate(const Shape& shape, const TessellationOptions& options) {
    std::vector<RenderPart> parts;
    flatten(shape, Transform::identity(), options, parts);
    return parts;
}

double enclosedVolume(const RenderMesh& mesh) {
    double volume = 0;
    for (std::size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
        const Vec3 &a = mesh.positions[mesh.indices[i]], &b = mesh.positions[mesh.indices[i + 1]],
                   &c = mesh.positions[mesh.indices[i + 2]];
        const Vec3 bc = cross(b, c);
        volume += (static_cast<double>(a.x) * bc.x + static_cast<double>(a.y) * bc.y + static_cast<double>(a.z) * bc.z) / 6.0;
    }
    return volume;
}

}  // namespace fulcrum::io
