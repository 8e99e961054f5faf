// Internal helpers of the scene reader and writer: number formatting, typo
// suggestions, enum names, and building shapes from their descriptions.
#include "io/scene_detail.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>

namespace fulcrum::detail {

std::string formatNumber(double v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

std::string formatNumber(float v) {
    if (std::isnan(v)) return "nan";
    if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
}

namespace {

std::size_t editDistance(std::string_view a, std::string_view b) {
    std::vector<std::size_t> prev(b.size() + 1), cur(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j) prev[j] = j;
    for (std::size_t i = 1; i <= a.size(); ++i) {
        cur[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j) {
            const std::size_t subst = prev[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
            cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, subst});
        }
        std::swap(prev, cur);
    }
    return prev[b.size()];
}

}  // namespace

std::string_view closestMatch(std::string_view word, std::span<const std::string_view> candidates) {
    std::string_view best;
    std::size_t bestDistance = std::numeric_limits<std::size_t>::max();
    for (std::string_view c : candidates) {
        const std::size_t d = editDistance(word, c);
        if (d < bestDistance) {
            bestDistance = d;
            best = c;
        }
    }
    // A typo is a few edits, and fewer than half the word.
    const std::size_t limit = std::min<std::size_t>(3, std::max<std::size_t>(1, word.size() / 2));
    return bestDistance <= limit ? best : std::string_view{};
}

std::string joinList(std::initializer_list<std::string_view> items) {
    std::string out;
    for (std::string_view s : items) {
        if (!out.empty()) out += ", ";
        out += s;
    }
    return out;
}

std::string nlohmannReason(std::string_view what) {
    // "[json.exception.parse_error.101] parse error at line 3, column 4: syntax error ..."
    std::string_view s = what;
    if (const auto p = s.find("] "); p != std::string_view::npos && !s.empty() && s[0] == '[') s.remove_prefix(p + 2);
    if (s.starts_with("parse error")) {
        if (const auto p = s.find(": "); p != std::string_view::npos) s.remove_prefix(p + 2);
    }
    std::string out(s);
    std::replace(out.begin(), out.end(), '\n', ' ');
    std::replace(out.begin(), out.end(), '\r', ' ');
    return out;
}

std::optional<ShapeType> shapeTypeFromString(std::string_view name) {
    for (ShapeType t : {ShapeType::Sphere, ShapeType::Box, ShapeType::Capsule, ShapeType::Cylinder, ShapeType::ConvexHull,
                        ShapeType::Plane, ShapeType::Mesh, ShapeType::Compound, ShapeType::HeightField}) {
        if (name == toString(t)) return t;
    }
    return std::nullopt;
}

std::optional<BodyType> bodyTypeFromString(std::string_view name) {
    for (BodyType t : {BodyType::Dynamic, BodyType::Static, BodyType::Kinematic}) {
        if (name == toString(t)) return t;
    }
    return std::nullopt;
}

std::optional<JointType> jointTypeFromString(std::string_view name) {
    for (JointType t : {JointType::Ball, JointType::Hinge, JointType::Slider, JointType::Distance, JointType::Fixed,
                        JointType::ConeTwist, JointType::SixDof}) {
        if (name == toString(t)) return t;
    }
    return std::nullopt;
}

std::string shapeTypeList() { return "sphere, box, capsule, cylinder, convex_hull, plane, mesh, heightfield, compound"; }
std::string jointTypeList() { return "ball, hinge, slider, distance, fixed, cone_twist, six_dof"; }
std::string integratorList() { return "semi_implicit_euler, explicit_euler, verlet"; }

bool isStaticOnly(const ShapeDesc& shape) {
    if (shape.type == ShapeType::Mesh && shape.decompose) return false;  // a compound of hulls
    if (shape.type == ShapeType::Plane || shape.type == ShapeType::Mesh || shape.type == ShapeType::HeightField) return true;
    return std::any_of(shape.children.begin(), shape.children.end(), [](const ShapeDesc::Child& c) { return isStaticOnly(c.shape); });
}

bool containsHullOrMesh(const ShapeDesc& shape) {
    if (shape.type == ShapeType::ConvexHull || shape.type == ShapeType::Mesh || shape.type == ShapeType::HeightField) return true;
    return std::any_of(shape.children.begin(), shape.children.end(),
                       [](const ShapeDesc::Child& c) { return containsHullOrMesh(c.shape); });
}

Shape buildPrimitiveShape(const ShapeDesc& s) {
    if (s.scale != Vec3{1, 1, 1}) {  // scaled shapes: build the shape as given, then scale it
        ShapeDesc unscaled = s;
        unscaled.scale = {1, 1, 1};
        return Shape::scaled(buildPrimitiveShape(unscaled), s.scale);
    }
    switch (s.type) {
        case ShapeType::Sphere: return Shape::sphere(s.radius);
        case ShapeType::Box: return s.convexRadius > 0 ? Shape::roundedBox(s.halfExtents, s.convexRadius) : Shape::box(s.halfExtents);
        case ShapeType::Capsule: return Shape::capsule(s.radius, s.halfHeight);
        case ShapeType::Cylinder:
            return s.convexRadius > 0 ? Shape::roundedCylinder(s.radius, s.halfHeight, s.convexRadius)
                                      : Shape::cylinder(s.radius, s.halfHeight);
        case ShapeType::Plane: return Shape::plane(s.normal, s.offset);
        case ShapeType::Compound: {
            std::vector<CompoundChild> children;
            children.reserve(s.children.size());
            for (const ShapeDesc::Child& c : s.children) {
                children.push_back({buildPrimitiveShape(c.shape), Transform(c.position, c.orientation)});
            }
            return Shape::compound(children);
        }
        case ShapeType::ConvexHull:
        case ShapeType::Mesh:
        case ShapeType::HeightField: break;
    }
    throw Error(std::string("internal: buildPrimitiveShape called for a ") + toString(s.type));
}

}  // namespace fulcrum::detail
