// Shape factories, validation, mass properties and bounds of the primitives
// and compounds. Convex hulls are built in hull.cpp, meshes in mesh.cpp.
#include "fulcrum/shape.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

namespace fulcrum {

namespace {

constexpr Real kPi = std::numbers::pi_v<Real>;
// Planes are infinite; their bounds use a large finite extent so AABB
// arithmetic (surface areas in the broad phase) never overflows a float.
constexpr Real kHuge = Real(1e15);

std::string fmt(Real v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

void requirePositive(Real v, const char* what, const char* shape) {
    if (!std::isfinite(v) || v <= 0) {
        throw Error(std::string(shape) + ": " + what + " must be a positive finite number, got " + fmt(v));
    }
    if (v > kMaxShapeCoordinate) {
        throw Error(std::string(shape) + ": " + what + " must be at most " + fmt(kMaxShapeCoordinate) + " m, got " + fmt(v));
    }
}

// Inertia of `mp` after rotating it by `q` and expressing it about `point`
// (parallel-axis theorem: I + m (|d|^2 E - d d^T)).
Mat3 inertiaAbout(const MassProperties& mp, const Quat& q, const Vec3& com, const Vec3& point) {
    const Mat3 r = toMat3(q);
    const Mat3 rotated = r * mp.inertia * transpose(r);
    const Vec3 d = com - point;
    return rotated + (Mat3::diagonal(dot(d, d)) - Mat3::outer(d, d)) * mp.mass;
}

}  // namespace

Shape::Shape() = default;

Shape Shape::sphere(Real radius) {
    requirePositive(radius, "radius", "sphere");
    Shape s;
    s.type_ = ShapeType::Sphere;
    s.radius_ = radius;
    return s;
}

Shape Shape::box(const Vec3& halfExtents) {
    requirePositive(halfExtents.x, "half_extents.x", "box");
    requirePositive(halfExtents.y, "half_extents.y", "box");
    requirePositive(halfExtents.z, "half_extents.z", "box");
    Shape s;
    s.type_ = ShapeType::Box;
    s.radius_ = 0;
    s.halfExtents_ = halfExtents;
    return s;
}

Shape Shape::capsule(Real radius, Real halfHeight) {
    requirePositive(radius, "radius", "capsule");
    requirePositive(halfHeight, "half_height", "capsule");
    Shape s;
    s.type_ = ShapeType::Capsule;
    s.radius_ = radius;
    s.halfHeight_ = halfHeight;
    return s;
}

Shape Shape::cylinder(Real radius, Real halfHeight) {
    requirePositive(radius, "radius", "cylinder");
    requirePositive(halfHeight, "half_height", "cylinder");
    Shape s;
    s.type_ = ShapeType::Cylinder;
    s.radius_ = radius;
    s.halfHeight_ = halfHeight;
    return s;
}

Shape Shape::plane(const Vec3& normal, Real offset) {
    if (!isFinite(normal) || !std::isfinite(offset)) throw Error("plane: normal and offset must be finite");
    const Real len = length(normal);
    if (len < Real(1e-6)) throw Error("plane: normal must not be zero");
    if (std::fabs(offset / len) > kMaxShapeCoordinate) {
        throw Error("plane: offset must be at most " + fmt(kMaxShapeCoordinate) + " m from the origin, got " + fmt(offset / len));
    }
    Shape s;
    s.type_ = ShapeType::Plane;
    s.halfExtents_ = normal / len;
    s.radius_ = offset / len;  // keep n . p = offset for the normalised n
    return s;
}

namespace {
// Recursion bounded by kMaxCompoundLevels: every compound was checked when it was made.
int compoundLevels(const Shape& s) {
    if (s.type() != ShapeType::Compound) return 0;
    int deepest = 0;
    for (const CompoundChild& c : s.children()) deepest = std::max(deepest, compoundLevels(c.shape));
    return deepest + 1;
}
}  // namespace

Shape Shape::compound(std::span<const CompoundChild> children) {
    if (children.empty()) throw Error("compound: needs at least one child shape");
    for (std::size_t i = 0; i < children.size(); ++i) {
        if (compoundLevels(children[i].shape) >= kMaxCompoundLevels) {
            throw Error("compound: children[" + std::to_string(i) + "] makes compounds nested deeper than " +
                        std::to_string(kMaxCompoundLevels) + " levels");
        }
        const Transform& t = children[i].transform;
        if (!isFinite(t.p) || !isFinite(t.q)) {
            throw Error("compound: children[" + std::to_string(i) + "] has a non-finite position or orientation");
        }
        if (length(t.q) < Real(1e-6)) {
            throw Error("compound: children[" + std::to_string(i) + "] has a zero-length orientation quaternion");
        }
        if (maxComponent(abs(t.p)) > kMaxShapeCoordinate) {
            throw Error("compound: children[" + std::to_string(i) + "] position is farther than " + fmt(kMaxShapeCoordinate) +
                        " m from the compound's origin");
        }
    }
    auto list = std::make_shared<std::vector<CompoundChild>>(children.begin(), children.end());
    for (CompoundChild& c : *list) c.transform.q = normalize(c.transform.q);
    Shape s;
    s.type_ = ShapeType::Compound;
    s.radius_ = 0;
    s.setChildren(std::move(list));
    return s;
}

const ConvexHull& Shape::hull() const {
    if (type_ != ShapeType::ConvexHull || !hull_) throw Error(std::string("shape is a ") + toString(type_) + ", not a convex_hull");
    return *hull_;
}

const HeightField& Shape::heightField() const {
    if (type_ != ShapeType::HeightField || !heightField_) {
        throw Error(std::string("shape is a ") + toString(type_) + ", not a heightfield");
    }
    return *heightField_;
}

const TriangleMesh& Shape::mesh() const {
    if (type_ != ShapeType::Mesh || !mesh_) throw Error(std::string("shape is a ") + toString(type_) + ", not a mesh");
    return *mesh_;
}

std::span<const CompoundChild> Shape::children() const {
    if (type_ != ShapeType::Compound || !children_) return {};
    return {children_->data(), children_->size()};
}

bool Shape::staticOnly() const {
    if (type_ == ShapeType::Plane || type_ == ShapeType::Mesh || type_ == ShapeType::HeightField) return true;
    if (type_ == ShapeType::Compound) {
        for (const CompoundChild& c : *children_) {
            if (c.shape.staticOnly()) return true;
        }
    }
    return false;
}

Real Shape::volume() const {
    if (convexRadius_ > 0) return roundedVolume();
    switch (type_) {
        case ShapeType::Sphere: return Real(4) / 3 * kPi * radius_ * radius_ * radius_;
        case ShapeType::Box: return 8 * halfExtents_.x * halfExtents_.y * halfExtents_.z;
        case ShapeType::Capsule:
            return kPi * radius_ * radius_ * (2 * halfHeight_) + Real(4) / 3 * kPi * radius_ * radius_ * radius_;
        case ShapeType::Cylinder: return kPi * radius_ * radius_ * 2 * halfHeight_;
        case ShapeType::ConvexHull: return hull_->volume;
        case ShapeType::Plane:
        case ShapeType::Mesh:
        case ShapeType::HeightField: return 0;
        case ShapeType::Compound: {
            Real v = 0;
            for (const CompoundChild& c : *children_) v += c.shape.volume();
            return v;
        }
    }
    return 0;
}

MassProperties Shape::massProperties(Real density) const {
    if (!std::isfinite(density) || density <= 0) {
        throw Error("density must be a positive finite number, got " + fmt(density));
    }
    if (convexRadius_ > 0) return roundedMassProperties(density);
    MassProperties mp;
    const Real r = radius_, r2 = radius_ * radius_, h = halfHeight_;
    switch (type_) {
        case ShapeType::Sphere:
            mp.mass = density * volume();
            mp.inertia = Mat3::diagonal(Real(0.4) * mp.mass * r2);
            break;
        case ShapeType::Box: {
            mp.mass = density * volume();
            const Vec3 e = halfExtents_;
            const Real k = mp.mass / 3;
            mp.inertia = Mat3::diagonal({k * (e.y * e.y + e.z * e.z), k * (e.x * e.x + e.z * e.z), k * (e.x * e.x + e.y * e.y)});
            break;
        }
        case ShapeType::Capsule: {
            // Cylinder of length 2h plus two hemispheres whose centroids sit 3r/8
            // beyond the cylinder's ends (parallel-axis shift from the flat face).
            const Real mc = density * kPi * r2 * 2 * h;
            const Real ms = density * Real(4) / 3 * kPi * r2 * r;
            mp.mass = mc + ms;
            const Real iy = mc * r2 / 2 + ms * Real(0.4) * r2;
            const Real ix = mc * (r2 / 4 + h * h / 3) + ms * (Real(0.4) * r2 + h * h + Real(0.75) * h * r);
            mp.inertia = Mat3::diagonal({ix, iy, ix});
            break;
        }
        case ShapeType::Cylinder: {
            mp.mass = density * volume();
            const Real ix = mp.mass * (r2 / 4 + h * h / 3);
            mp.inertia = Mat3::diagonal({ix, mp.mass * r2 / 2, ix});
            break;
        }
        case ShapeType::ConvexHull:
            mp.mass = density * hull_->volume;
            mp.centerOfMass = hull_->centroid;
            mp.inertia = hull_->unitDensityInertia * density;
            break;
        case ShapeType::Plane:
        case ShapeType::Mesh:
        case ShapeType::HeightField:
            throw Error(std::string(toString(type_)) + " shapes have no volume, so no mass: use them on static bodies");
        case ShapeType::Compound: {
            std::vector<MassProperties> parts;
            parts.reserve(children_->size());
            for (const CompoundChild& c : *children_) {
                MassProperties p = c.shape.massProperties(density);
                p.centerOfMass = transformPoint(c.transform, p.centerOfMass);
                mp.mass += p.mass;
                mp.centerOfMass += p.centerOfMass * p.mass;
                parts.push_back(p);
            }
            mp.centerOfMass /= mp.mass;
            Mat3 inertia = Mat3::zero();
            for (std::size_t i = 0; i < parts.size(); ++i) {
                inertia += inertiaAbout(parts[i], (*children_)[i].transform.q, parts[i].centerOfMass, mp.centerOfMass);
            }
            mp.inertia = inertia;
            break;
        }
    }
    return mp;
}

AABB Shape::localBounds() const {
    switch (type_) {
        case ShapeType::Sphere: return AABB::fromCenterHalf(Vec3::zero(), Vec3::splat(radius_));
        case ShapeType::Box: return AABB::fromCenterHalf(Vec3::zero(), halfExtents_);
        case ShapeType::Capsule: return AABB::fromCenterHalf(Vec3::zero(), {radius_, halfHeight_ + radius_, radius_});
        case ShapeType::Cylinder: return AABB::fromCenterHalf(Vec3::zero(), {radius_, halfHeight_, radius_});
        case ShapeType::ConvexHull: return convexRadius_ > 0 ? hull_->bounds.fattened(convexRadius_) : hull_->bounds;
        case ShapeType::Mesh: return mesh_->bounds;
        case ShapeType::HeightField: return heightField_->bounds;
        case ShapeType::Plane: {
            // Solid below n . p = offset: an axis-aligned normal bounds one side.
            AABB b{Vec3::splat(-kHuge), Vec3::splat(kHuge)};
            const Vec3 n = halfExtents_;
            for (std::size_t i = 0; i < 3; ++i) {
                if (n[i] > Real(0.999999)) b.max[i] = radius_;
                if (n[i] < Real(-0.999999)) b.min[i] = -radius_;
            }
            return b;
        }
        case ShapeType::Compound: return childBounds_;
    }
    return {};
}

void Shape::setChildren(std::shared_ptr<const std::vector<CompoundChild>> children) {
    children_ = std::move(children);
    childBounds_ = AABB();
    for (const CompoundChild& c : *children_) childBounds_.grow(c.shape.bounds(c.transform));
}

AABB Shape::bounds(const Transform& xf) const {
    if (type_ == ShapeType::Box && convexRadius_ == 0) {
        // transformBounds(xf, localBounds()) bit for bit, in fewer steps: the
        // local box's centre is exactly zero and its half extents exactly
        // halfExtents_ ((h + h) / 2, far from overflow under
        // kMaxShapeCoordinate), and an unrotated body's |R| is exactly the
        // identity (h + 0 + 0 = h) and its rotation of the zero centre is +0
        // (+0 plus signed zeros), so the centre is p + 0. A million static
        // boxes: 242 to 109 instructions a body (docs/benchmarks.md, `lw8`).
        const Vec3& h = halfExtents_;
        if (xf.q.w == 1 && xf.q.x == 0 && xf.q.y == 0 && xf.q.z == 0) {
            const Vec3 c = xf.p + Vec3::zero();
            return {c - h, c + h};
        }
        // The rotated zero centre is a signed zero per axis, so
        // transformPoint(xf, 0) is xf.p but for the sign of a zero
        // coordinate, which c - e and c + e do not keep (every e > 0: each
        // row of |R| has a non-zero entry, every half extent is > 0): xf.p
        // itself, the same box without the rotation (~35 instructions a
        // body and step).
        const Vec3& c = xf.p;
        const Mat3 r = toMat3(xf.q);
        const Vec3 e = abs(r.c0) * h.x + abs(r.c1) * h.y + abs(r.c2) * h.z;
        return {c - e, c + e};
    }
    switch (type_) {
        case ShapeType::Sphere: return AABB::fromCenterHalf(xf.p, Vec3::splat(radius_));
        case ShapeType::Capsule: {
            const Vec3 a = rotate(xf.q, {0, halfHeight_, 0});
            AABB b{min(xf.p + a, xf.p - a), max(xf.p + a, xf.p - a)};
            return b.fattened(radius_);
        }
        case ShapeType::Plane: {
            const Vec3 n = rotate(xf.q, halfExtents_);
            const Real offset = radius_ + dot(n, xf.p);
            return Shape::plane(n, offset).localBounds();
        }
        case ShapeType::Compound: {
            AABB b;
            for (const CompoundChild& c : *children_) b.grow(c.shape.bounds(xf * c.transform));
            return b;
        }
        default: return convexRadius_ > 0 ? roundedBounds(xf) : transformBounds(xf, localBounds());
    }
}

}  // namespace fulcrum

// ---------------------------------------------------------------- rounded shapes
// docs/shapes.md, "Rounded shapes". A rounded shape is its core (box,
// cylinder or hull) swept by a ball of radius r: the Minkowski sum core + B(r).
namespace fulcrum {

namespace {

std::string roundingFieldError(const char* shape, Real r, const std::string& limitName, Real limit) {
    return std::string(shape) + ": convex_radius must be a finite number in [0, " + limitName + " = " + fmt(limit) +
           "], got " + fmt(r);
}

void requireRounding(Real r, const char* shape, const std::string& limitName, Real limit) {
    if (!std::isfinite(r) || r < 0 || r > limit) throw Error(roundingFieldError(shape, r, limitName, limit));
}

// Second moment integral of x^2 over the rounded box with core half extents
// a (along x), b, c and radius r, split into the Minkowski-sum pieces: the core,
// six slabs (one per face), twelve quarter cylinders (edges), eight ball
// octants (corners). Each piece's integral of (offset + u)^2 uses the quarter
// disc's moments (area pi r^2/4, first r^3/3, second pi r^4/16) and the ball
// octant's (volume pi r^3/6, first pi r^4/16, second pi r^5/30).
Real roundedBoxSecondMoment(Real a, Real b, Real c, Real r) {
    const Real a3 = a * a * a, r2 = r * r, r3 = r2 * r;
    const Real core = 8 * a3 * b * c / 3;
    const Real slabsX = 8 * b * c * ((a + r) * (a + r) * (a + r) - a3) / 3;
    const Real slabsYZ = 8 * a3 * r * (b + c) / 3;
    const Real edgesX = 2 * a3 * kPi * r2 / 3;
    const Real quarterDiscs = kPi * r2 * a * a + 8 * a * r3 / 3 + kPi * r2 * r2 / 4;  // four of them, about x
    const Real edgesYZ = 2 * (b + c) * quarterDiscs;
    const Real corners = 4 * kPi * a * a * r3 / 3 + kPi * a * r2 * r2 + 4 * kPi * r3 * r2 / 15;
    return core + slabsX + slabsYZ + edgesX + edgesYZ + corners;
}

// The rounded cylinder with core radius p, core half height h and radius r:
// the cylinder of the outer radius over the core's height, two cap discs of
// the core radius and thickness r, and two rims (a quarter disc of radius r
// revolved about the axis at distance p). Returns the volume and the integrals
// of s^2 (s: distance from the axis) and y^2.
struct CylinderMoments {
    Real volume, radial2, axial2;
};
CylinderMoments roundedCylinderMoments(Real p, Real h, Real r) {
    const Real R = p + r, r2 = r * r, r3 = r2 * r, r4 = r2 * r2, r5 = r4 * r;
    // Moments of the quarter disc u, v >= 0, u^2 + v^2 <= r^2.
    const Real m00 = kPi * r2 / 4, m10 = r3 / 3, m20 = kPi * r4 / 16, m11 = r4 / 8, m30 = 2 * r5 / 15, m12 = r5 / 15;
    const Real rimVolume = 2 * (2 * kPi) * (p * m00 + m10);
    const Real rimRadial = 2 * (2 * kPi) * (p * p * p * m00 + 3 * p * p * m10 + 3 * p * m20 + m30);
    const Real rimAxial = 2 * (2 * kPi) * (p * h * h * m00 + 2 * p * h * m10 + p * m20 + h * h * m10 + 2 * h * m11 + m12);
    CylinderMoments m;
    m.volume = kPi * R * R * 2 * h + 2 * kPi * p * p * r + rimVolume;
    m.radial2 = kPi * R * R * R * R * h + kPi * p * p * p * p * r + rimRadial;
    m.axial2 = kPi * R * R * 2 * h * h * h / 3 + 2 * kPi * p * p * ((h + r) * (h + r) * (h + r) - h * h * h) / 3 + rimAxial;
    return m;
}

// Unit directions spread over the sphere (a Fibonacci lattice): the polytope
// a rounded hull's ball is replaced by.
std::vector<Vec3> sphereDirections(std::size_t n) {
    std::vector<Vec3> d;
    d.reserve(n);
    const double golden = 3.14159265358979323846 * (3 - std::sqrt(5.0));
    for (std::size_t i = 0; i < n; ++i) {
        const double y = 1 - 2 * (static_cast<double>(i) + 0.5) / static_cast<double>(n);
        const double s = std::sqrt(std::max(0.0, 1 - y * y));
        const double phi = golden * static_cast<double>(i);
        d.push_back(Vec3{static_cast<Real>(s * std::cos(phi)), static_cast<Real>(y), static_cast<Real>(s * std::sin(phi))});
    }
    return d;
}

// The rounded hull's polyhedral stand-in: the hull of every core vertex
// plus every direction of a Fibonacci polytope scaled to the ball's volume
// (so a ball alone keeps its exact volume). That hull is the exact Minkowski
// sum of the core and the polytope; it differs from core + ball only in the
// curved pieces (the edges' cylinder wedges, the vertices' ball sectors).
// Measured against the exact rounded box (tests/shapes/rounded_shape_test.cpp):
// mass and inertia within 0.3 %.
ConvexHull roundedHullApproximation(const ConvexHull& core, Real r) {
    // At most ~4000 points (the quickhull's vertex limit is 4096), at least 32 directions.
    const std::size_t directions = std::clamp<std::size_t>(4000 / std::max<std::size_t>(core.vertices.size(), 1), 32, 256);
    const std::vector<Vec3> dirs = sphereDirections(directions);
    const Real polytopeVolume = Shape::convexHull(dirs).volume();
    const Real scale = r * static_cast<Real>(std::cbrt(4.0 / 3.0 * 3.14159265358979323846 / static_cast<double>(polytopeVolume)));
    std::vector<Vec3> points;
    points.reserve(core.vertices.size() * dirs.size());
    for (const Vec3& v : core.vertices) {
        for (const Vec3& d : dirs) points.push_back(v + d * scale);
    }
    return Shape::convexHull(points).hull();
}

}  // namespace

const ConvexHull* roundedHullOf(const Shape& s) { return s.roundedHull_.get(); }

std::shared_ptr<const ConvexHull> Shape::roundedHullFor(const ConvexHull& core, Real convexRadius) {
    try {
        return std::make_shared<const ConvexHull>(roundedHullApproximation(core, convexRadius));
    } catch (const Error& e) {
        throw Error(std::string("convex_hull: convex_radius ") + fmt(convexRadius) +
                    ": the rounded hull's polyhedral stand-in (docs/shapes.md) could not be built: " + e.what());
    }
}

Shape Shape::roundedBox(const Vec3& halfExtents, Real convexRadius) {
    Shape s = box(halfExtents);
    requireRounding(convexRadius, "box", "the smallest half extent", minComponent(halfExtents));
    s.convexRadius_ = convexRadius;
    return s;
}

Shape Shape::roundedCylinder(Real radius, Real halfHeight, Real convexRadius) {
    Shape s = cylinder(radius, halfHeight);
    requireRounding(convexRadius, "cylinder", "min(radius, half_height)", std::min(radius, halfHeight));
    s.convexRadius_ = convexRadius;
    return s;
}

Shape Shape::roundedConvexHull(std::span<const Vec3> points, Real convexRadius) {
    if (!std::isfinite(convexRadius) || convexRadius < 0) {
        throw Error("convex_hull: convex_radius must be a finite number >= 0, got " + fmt(convexRadius));
    }
    Shape s = convexHull(points);
    if (convexRadius > 0) {
        s.convexRadius_ = convexRadius;
        s.roundedHull_ = roundedHullFor(*s.hull_, convexRadius);
    }
    return s;
}

Real Shape::roundedVolume() const {
    const Real r = convexRadius_;
    switch (type_) {
        case ShapeType::Box: {
            const Vec3 c = halfExtents_ - Vec3::splat(r);
            return 8 * c.x * c.y * c.z + 8 * r * (c.x * c.y + c.y * c.z + c.z * c.x) + 2 * kPi * r * r * (c.x + c.y + c.z) +
                   Real(4) / 3 * kPi * r * r * r;
        }
        case ShapeType::Cylinder: return roundedCylinderMoments(radius_ - r, halfHeight_ - r, r).volume;
        case ShapeType::ConvexHull: return roundedHull_->volume;
        default: return 0;
    }
}

MassProperties Shape::roundedMassProperties(Real density) const {
    const Real r = convexRadius_;
    MassProperties mp;
    switch (type_) {
        case ShapeType::Box: {
            const Vec3 c = halfExtents_ - Vec3::splat(r);
            const Real sx = roundedBoxSecondMoment(c.x, c.y, c.z, r);
            const Real sy = roundedBoxSecondMoment(c.y, c.z, c.x, r);
            const Real sz = roundedBoxSecondMoment(c.z, c.x, c.y, r);
            mp.mass = density * roundedVolume();
            mp.inertia = Mat3::diagonal(Vec3{sy + sz, sx + sz, sx + sy} * density);
            break;
        }
        case ShapeType::Cylinder: {
            const CylinderMoments m = roundedCylinderMoments(radius_ - r, halfHeight_ - r, r);
            mp.mass = density * m.volume;
            const Real ix = density * (m.radial2 / 2 + m.axial2);
            mp.inertia = Mat3::diagonal({ix, density * m.radial2, ix});
            break;
        }
        case ShapeType::ConvexHull:
            mp.mass = density * roundedHull_->volume;
            mp.centerOfMass = roundedHull_->centroid;
            mp.inertia = roundedHull_->unitDensityInertia * density;
            break;
        default: break;
    }
    return mp;
}

// The core's bounds at xf grown by the radius: tighter than the outer box's
// rotated bounds (a rotated rounded box's corners are round).
AABB Shape::roundedBounds(const Transform& xf) const {
    const Real r = convexRadius_;
    switch (type_) {
        case ShapeType::Box:
            return transformBounds(xf, AABB::fromCenterHalf(Vec3::zero(), halfExtents_ - Vec3::splat(r))).fattened(r);
        case ShapeType::Cylinder:
            return transformBounds(xf, AABB::fromCenterHalf(Vec3::zero(), {radius_ - r, halfHeight_ - r, radius_ - r})).fattened(r);
        case ShapeType::ConvexHull: return transformBounds(xf, hull_->bounds).fattened(r);
        default: return transformBounds(xf, localBounds());
    }
}

}  // namespace fulcrum
