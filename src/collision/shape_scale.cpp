// Scaled shapes: Shape::scaled bakes a scale (and, inside compounds, the
// linear map a scale makes of a rotated child) into a new immutable shape of
// the same kind where the image is still that kind, so the narrow phase,
// queries and mass properties need nothing new at run time and stay exact.
// docs/shapes.md, "Scaled shapes", states the rules.
#include <cmath>
#include <sstream>
#include <string>
#include <vector>

#include "fulcrum/shape.hpp"

namespace fulcrum {

namespace {

// Two scale factors count as equal (a sphere's uniform scale, a cylinder's
// x == z) within this relative tolerance, and a linear map's columns as
// orthogonal within it: the matrix of a rotated child is only orthogonal to
// float rounding, so exact tests would turn every rotated box into a hull.
constexpr Real kScaleTolerance = Real(1e-5);

std::string num(Real v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

std::string text(const Vec3& v) { return "(" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ")"; }

bool nearlyEqual(Real a, Real b) { return std::fabs(a - b) <= kScaleTolerance * std::max(std::fabs(a), std::fabs(b)); }

Shape scaleDiagonal(const Shape& s, const Vec3& d);

std::string roundedNeedsUniform(const Shape& s) {
    return std::string("a rounded ") + toString(s.type()) + " (convex_radius " + num(s.convexRadius()) +
           ") only takes a uniform scale (|x| == |y| == |z|): an unevenly scaled ball is an ellipsoid";
}

// A shape whose geometry is `linear` applied to the points of another, in
// the same frame up to `rotation`: rotate(rotation, shape) == linear(original).
struct Placed {
    Shape shape;
    Quat rotation;
};
Placed placeLinear(const Shape& s, const Mat3& linear);

Shape hullThrough(std::span<const Vec3> points, const Mat3& linear) {
    std::vector<Vec3> moved;
    moved.reserve(points.size());
    for (const Vec3& p : points) moved.push_back(linear * p);
    return Shape::convexHull(moved);
}

// A mirror (negative determinant) turns counter-clockwise triangles
// clockwise: swapping two corners keeps the front faces in front.
Shape meshThrough(const TriangleMesh& mesh, const Mat3& linear) {
    std::vector<Vec3> vertices;
    vertices.reserve(mesh.vertices.size());
    for (const Vec3& v : mesh.vertices) vertices.push_back(linear * v);
    std::vector<std::array<std::uint32_t, 3>> triangles = mesh.triangles;
    if (determinant(linear) < 0) {
        for (auto& t : triangles) std::swap(t[1], t[2]);
    }
    return Shape::mesh(vertices, triangles);
}

// n . p = d maps to (L^-T n) . p' = d for p' = L p; Shape::plane normalises.
Shape planeThrough(const Shape& s, const Mat3& linear) {
    return Shape::plane(transpose(inverse(linear)) * s.planeNormal(), s.planeOffset());
}

Shape compoundThrough(const Shape& s, const Mat3& linear) {
    std::vector<CompoundChild> children;
    children.reserve(s.children().size());
    std::size_t i = 0;
    for (const CompoundChild& c : s.children()) {
        try {
            Placed placed = placeLinear(c.shape, linear * toMat3(c.transform.q));
            children.push_back({std::move(placed.shape), Transform(linear * c.transform.p, placed.rotation)});
        } catch (const Error& e) {
            throw Error("compound: children[" + std::to_string(i) + "]: " + e.what());
        }
        ++i;
    }
    return Shape::compound(children);
}

Placed placeLinear(const Shape& s, const Mat3& linear) {
    const Vec3 norms{length(linear.c0), length(linear.c1), length(linear.c2)};
    const bool orthogonal = std::fabs(dot(linear.c0, linear.c1)) <= kScaleTolerance * norms.x * norms.y &&
                            std::fabs(dot(linear.c0, linear.c2)) <= kScaleTolerance * norms.x * norms.z &&
                            std::fabs(dot(linear.c1, linear.c2)) <= kScaleTolerance * norms.y * norms.z;
    if (orthogonal) {
        // linear = Q diag(d) with Q a rotation: a scale along the shape's own
        // axes, then a rotation; a mirror goes into d so Q stays proper.
        Vec3 d = norms;
        Mat3 q{linear.c0 / norms.x, linear.c1 / norms.y, linear.c2 / norms.z};
        if (determinant(q) < 0) {
            d.x = -d.x;
            q.c0 = -q.c0;
        }
        return {scaleDiagonal(s, d), normalize(Quat::fromMatrix(q))};
    }
    // A shear: only shapes given by points (or planes) survive it; a rounded
    // shape's ball would become an ellipsoid.
    if (s.convexRadius() > 0) throw Error(roundedNeedsUniform(s));
    switch (s.type()) {
        case ShapeType::Box: {
            const Vec3 h = s.halfExtents();
            std::vector<Vec3> corners;
            for (int k = 0; k < 8; ++k) corners.push_back({(k & 1) ? h.x : -h.x, (k & 2) ? h.y : -h.y, (k & 4) ? h.z : -h.z});
            return {hullThrough(corners, linear), Quat()};
        }
        case ShapeType::ConvexHull: return {hullThrough(s.hull().vertices, linear), Quat()};
        case ShapeType::Mesh: return {meshThrough(s.mesh(), linear), Quat()};
        case ShapeType::Plane: return {planeThrough(s, linear), Quat()};
        case ShapeType::Compound: return {compoundThrough(s, linear), Quat()};
        case ShapeType::Sphere:
        case ShapeType::Capsule:
        case ShapeType::Cylinder:
        case ShapeType::HeightField: break;
    }
    throw Error(std::string("a ") + toString(s.type()) +
                " rotated relative to a non-uniform scale would be sheared, which leaves no " + toString(s.type()) +
                ": align its axes with the scale axes, scale uniformly, or use a convex hull of points on it");
}

Shape scaleDiagonal(const Shape& s, const Vec3& d) {
    const Vec3 a = abs(d);
    if (s.convexRadius() > 0) {
        // Rounded shapes (core + ball): a uniform scale scales the core and
        // the radius alike; any other scale turns the ball into an ellipsoid.
        if (!nearlyEqual(a.x, a.y) || !nearlyEqual(a.y, a.z)) throw Error(roundedNeedsUniform(s) + ", got " + text(d));
        const Real u = (a.x + a.y + a.z) / 3;
        const Real r = s.convexRadius() * u;
        switch (s.type()) {
            case ShapeType::Box: return Shape::roundedBox(s.halfExtents() * u, r);
            case ShapeType::Cylinder: return Shape::roundedCylinder(s.radius() * u, s.halfHeight() * u, r);
            case ShapeType::ConvexHull: {
                std::vector<Vec3> core;
                for (const Vec3& v : s.hull().vertices) core.push_back(mul(v, d));
                return Shape::roundedConvexHull(core, r);
            }
            default: break;
        }
    }
    switch (s.type()) {
        case ShapeType::Sphere:
        case ShapeType::Capsule:
            if (!nearlyEqual(a.x, a.y) || !nearlyEqual(a.y, a.z)) {
                throw Error(std::string("a ") + toString(s.type()) + " only takes a uniform scale (|x| == |y| == |z|), got " +
                            text(d) + ": an unevenly scaled " + toString(s.type()) +
                            " is no longer one; scale its dimensions instead, or use a convex hull of points on it");
            }
            if (s.type() == ShapeType::Sphere) return Shape::sphere(s.radius() * (a.x + a.y + a.z) / 3);
            return Shape::capsule(s.radius() * (a.x + a.y + a.z) / 3, s.halfHeight() * (a.x + a.y + a.z) / 3);
        case ShapeType::Cylinder:
            if (!nearlyEqual(a.x, a.z)) {
                throw Error("a cylinder only takes a scale with |x| == |z| (x and z scale the radius, y the half height), got " +
                            text(d) + ": an elliptic cylinder is no cylinder; use a convex hull of points on it");
            }
            return Shape::cylinder(s.radius() * (a.x + a.z) / 2, s.halfHeight() * a.y);
        case ShapeType::Box: return Shape::box(mul(s.halfExtents(), a));  // symmetric: a mirror is the same box
        case ShapeType::ConvexHull: return hullThrough(s.hull().vertices, Mat3::diagonal(d));
        case ShapeType::Mesh: return meshThrough(s.mesh(), Mat3::diagonal(d));
        case ShapeType::Plane: return planeThrough(s, Mat3::diagonal(d));
        case ShapeType::Compound: return compoundThrough(s, Mat3::diagonal(d));
        case ShapeType::HeightField: {
            if (d.x < 0 || d.y < 0 || d.z < 0) {
                throw Error("a heightfield cannot be mirrored (its samples run along +x and +z, heights along +y), got scale " + text(d));
            }
            const HeightField& h = s.heightField();
            std::vector<Real> heights = h.heights;
            for (Real& y : heights) y *= d.y;
            return Shape::heightField(h.rows, h.columns, h.spacingX * d.x, h.spacingZ * d.z, heights, h.holes);
        }
    }
    throw Error("internal: unknown shape type in Shape::scaled");
}

}  // namespace

Shape Shape::scaled(const Shape& shape, const Vec3& scale) {
    static const char* const kAxis[] = {"x", "y", "z"};
    for (std::size_t i = 0; i < 3; ++i) {
        if (!std::isfinite(scale[i]) || scale[i] == 0) {
            throw Error(std::string("scale: scale.") + kAxis[i] + " must be a finite nonzero number (negative mirrors), got " +
                        num(scale[i]));
        }
    }
    try {
        return scaleDiagonal(shape, scale);
    } catch (const Error& e) {
        throw Error(std::string("scale ") + text(scale) + " of a " + toString(shape.type()) + ": " + e.what());
    }
}

}  // namespace fulcrum
