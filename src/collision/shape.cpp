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
    }
    auto list = std::make_shared<std::vector<CompoundChild>>(children.begin(), children.end());
    for (CompoundChild& c : *list) c.transform.q = normalize(c.transform.q);
    Shape s;
    s.type_ = ShapeType::Compound;
    s.radius_ = 0;
    s.children_ = std::move(list);
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
        case ShapeType::ConvexHull: return hull_->bounds;
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
        case ShapeType::Compound: {
            AABB b;
            for (const CompoundChild& c : *children_) b.grow(c.shape.bounds(c.transform));
            return b;
        }
    }
    return {};
}

AABB Shape::bounds(const Transform& xf) const {
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
        default: return transformBounds(xf, localBounds());
    }
}

}  // namespace fulcrum
