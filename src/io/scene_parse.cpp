// Reading a scene file: JSON text -> validated Scene (every key is documented
// in docs/scene-format.md).
//
// Validation is strict on purpose: an unknown key, a wrong type or a value
// without physical sense is an error that names the path in the document and
// its line, because a silently ignored typo ("shap") costs a user far more
// time than a refused file. Where the engine already has a rule (shape
// factories), the parser calls it and re-throws its message with the path, so
// the rule lives in one place.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <sstream>
#include <unordered_map>

#include <nlohmann/json.hpp>

#include "fulcrum/scene.hpp"
#include "fulcrum/urdf.hpp"
#include "io/json_locator.hpp"
#include "io/scene_detail.hpp"
#include "math/real_bits.hpp"
#include "world/input_file.hpp"

namespace fulcrum {

namespace {

using nlohmann::json;
using detail::childPath;

constexpr Real kPi = std::numbers::pi_v<Real>;

class Parser {
public:
    Parser(std::string_view text, std::string_view source) : text_(text), source_(source) {}

    Scene parse();

private:
    // ---- errors
    [[noreturn]] void fail(const std::string& path, const std::string& reason) const {
        const auto loc = detail::locateJsonPath(text_, path);
        throw SceneError(source_, path, loc ? loc->line : 0, loc ? loc->column : 0, reason);
    }

    // Names already taken in a section of the document (views of the names
    // kept in the Scene, whose vectors are sized before they are filled), and
    // the index of the element that took each.
    using NameIndex = std::unordered_map<std::string_view, std::size_t>;

    // Registers the name (if any) of element `index` of `section`; an earlier
    // element with the same name is an error.
    void registerName(NameIndex& names, const std::string& name, std::size_t index, const std::string& path,
                      std::string_view what, std::string_view section) const {
        if (name.empty()) return;
        const auto [taken, isNew] = names.try_emplace(name, index);
        if (!isNew) {
            fail(childPath(path, "name"), "duplicate " + std::string(what) + " name '" + name + "' (also " +
                                              childPath(section, taken->second) + ")");
        }
    }

    static std::string typeName(const json& v) {
        if (v.is_number()) return "a number";
        if (v.is_string()) return "a string";
        if (v.is_boolean()) return "a boolean";
        if (v.is_null()) return "null";
        if (v.is_array()) return "an array";
        return "an object";
    }

    // Unknown keys are errors; the closest known key is suggested.
    void checkKeys(const json& obj, const std::string& path, std::initializer_list<std::string_view> allowed,
                   std::string_view what) const {
        for (auto it = obj.begin(); it != obj.end(); ++it) {
            const std::string& key = it.key();
            if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
            std::string reason = "unknown key";
            if (!what.empty()) reason += std::string(" for ") + std::string(what);
            const std::string_view close = detail::closestMatch(key, allowed);
            if (!close.empty()) {
                reason += " (did you mean '" + std::string(close) + "'?)";
            } else {
                reason += " (valid keys: " + detail::joinList(allowed) + ")";
            }
            fail(childPath(path, key), reason);
        }
    }

    const json& requireObject(const json& v, const std::string& path) const {
        if (!v.is_object()) fail(path, "expected an object, got " + typeName(v));
        return v;
    }
    const json& requireArray(const json& v, const std::string& path) const {
        if (!v.is_array()) fail(path, "expected an array, got " + typeName(v));
        return v;
    }
    static const json* member(const json& obj, std::string_view key) {
        const auto it = obj.find(key);
        return it == obj.end() ? nullptr : &*it;
    }
    const json& required(const json& obj, const std::string& path, std::string_view key) const {
        const json* v = member(obj, key);
        if (!v) fail(path, "missing key '" + std::string(key) + "'");
        return *v;
    }

    // ---- values
    Real number(const json& v, const std::string& path) const {
        if (!v.is_number()) fail(path, "expected a number, got " + typeName(v));
        const double d = v.get<double>();
        if (!std::isfinite(d)) fail(path, "must be a finite number, got " + detail::formatNumber(d));
        if (std::fabs(d) > static_cast<double>(std::numeric_limits<Real>::max())) {
            fail(path, "out of range for the engine's " + std::string(fulcrum::detail::kRealPrecision) + " numbers, got " + detail::formatNumber(d));
        }
        return static_cast<Real>(d);
    }
    // A number (> 0 if strictlyPositive, else >= 0) or "off", which stands for
    // infinity (JSON has none): world settings that can be switched off.
    Real numberOrOff(const json& v, const std::string& path, std::string_view field, bool strictlyPositive,
                     const char* unit) const {
        const std::string range = std::string(strictlyPositive ? "> 0" : ">= 0") + " (" + unit + ")";
        if (v.is_string()) {
            if (v.get<std::string>() != "off") {
                fail(path, std::string(field) + " must be a number " + range + " or \"off\", got \"" + v.get<std::string>() + "\"");
            }
            return std::numeric_limits<Real>::infinity();
        }
        if (!v.is_number()) fail(path, "expected a number " + range + " or \"off\", got " + typeName(v));
        return strictlyPositive ? positive(v, path, field) : nonNegative(v, path, field);
    }

    Real positive(const json& v, const std::string& path, std::string_view field) const {
        const Real r = number(v, path);
        const double written = v.get<double>();
        if (!(written > 0)) fail(path, std::string(field) + " must be positive, got " + detail::formatNumber(written));
        requireNormal(r, written, path, field);
        return r;
    }
    // A positive value that single precision holds only as a denormal (or
    // rounds to 0) loses its digits and breaks divisions by it: an error that
    // names the limit, not a later complaint about something derived from it.
    void requireNormal(Real r, double written, const std::string& path, std::string_view field) const {
        if (r >= std::numeric_limits<Real>::min()) return;
        fail(path, std::string(field) + " is too small for the engine's " + fulcrum::detail::kRealPrecision + " numbers (at least " +
                       detail::formatNumber(std::numeric_limits<Real>::min()) + "), got " + detail::formatNumber(written));
    }
    Real nonNegative(const json& v, const std::string& path, std::string_view field) const {
        const Real r = number(v, path);
        if (r < 0) fail(path, std::string(field) + " must not be negative, got " + detail::formatNumber(r));
        return r;
    }
    long long integer(const json& v, const std::string& path, long long lo, long long hi, std::string_view field) const {
        if (!v.is_number()) fail(path, "expected an integer, got " + typeName(v));
        const double d = v.get<double>();
        if (!std::isfinite(d) || d != std::floor(d)) fail(path, std::string(field) + " must be an integer, got " + detail::formatNumber(d));
        if (d < static_cast<double>(lo) || d > static_cast<double>(hi)) {
            // Always both ends: "at least 0" for 1e20 would not say what the limit is.
            fail(path, std::string(field) + " must be between " + std::to_string(lo) + " and " + std::to_string(hi) + ", got " +
                           detail::formatNumber(d));
        }
        if (v.is_number_unsigned()) return static_cast<long long>(v.get<std::uint64_t>());
        if (v.is_number_integer()) return v.get<std::int64_t>();
        return static_cast<long long>(d);
    }
    bool boolean(const json& v, const std::string& path) const {
        if (!v.is_boolean()) fail(path, "expected true or false, got " + typeName(v));
        return v.get<bool>();
    }
    std::string string(const json& v, const std::string& path) const {
        if (!v.is_string()) fail(path, "expected a string, got " + typeName(v));
        return v.get<std::string>();
    }
    Vec3 vec3(const json& v, const std::string& path) const {
        if (!v.is_array() || v.size() != 3) fail(path, "expected an array of 3 numbers [x, y, z], got " + describe(v));
        return {number(v[0], childPath(path, 0)), number(v[1], childPath(path, 1)), number(v[2], childPath(path, 2))};
    }
    // A shape's "scale": one number (uniform) or [sx, sy, sz]; each finite and
    // nonzero (negative mirrors); Shape::scaled judges the rest per shape.
    Vec3 shapeScale(const json& v, const std::string& path) const {
        const Vec3 s = v.is_number() ? Vec3::splat(number(v, path)) : vec3(v, path);
        for (std::size_t i = 0; i < 3; ++i) {
            if (s[i] == 0) fail(v.is_number() ? path : childPath(path, i), "scale must not be zero (negative mirrors)");
        }
        return s;
    }
    Vec3 nonZeroVec3(const json& v, const std::string& path, std::string_view field) const {
        const Vec3 r = vec3(v, path);
        if (!(length(r) > Real(1e-6))) fail(path, std::string(field) + " must not be the zero vector");
        return r;
    }
    Quat quat(const json& v, const std::string& path) const {
        if (!v.is_array() || v.size() != 4) fail(path, "expected a quaternion [w, x, y, z], got " + describe(v));
        const Quat q{number(v[0], childPath(path, 0)), number(v[1], childPath(path, 1)), number(v[2], childPath(path, 2)),
                     number(v[3], childPath(path, 3))};
        if (!(length(q) > Real(1e-6))) fail(path, "quaternion must not have zero length (identity is [1, 0, 0, 0])");
        return q;
    }
    std::array<Real, 2> range(const json& v, const std::string& path, std::string_view field) const {
        if (!v.is_array() || v.size() != 2) fail(path, "expected [lower, upper], got " + describe(v));
        const Real lo = number(v[0], childPath(path, 0)), hi = number(v[1], childPath(path, 1));
        if (lo > hi) {
            fail(path, std::string(field) + ": lower must not exceed upper, got [" + detail::formatNumber(lo) + ", " +
                           detail::formatNumber(hi) + "]");
        }
        return {lo, hi};
    }
    static std::string describe(const json& v) {
        if (v.is_array()) return "an array of " + std::to_string(v.size());
        return typeName(v);
    }

    // Reads optional key `key` of `obj` with `read(value, path)` into `out`.
    template <class Fn>
    bool opt(const json& obj, const std::string& path, std::string_view key, Fn&& read) const {
        const json* v = member(obj, key);
        if (!v) return false;
        read(*v, childPath(path, key));
        return true;
    }

    // ---- sections
    // Reads the root's optional array `key` into `out` with read(element,
    // path, out[i], i), one element at a time from its own text (the root
    // was parsed without them), noting where each sits (buildWorld's errors
    // name it).
    template <class T, class Read>
    void section(const json& root, std::string_view key, std::vector<T>& out, Read&& read) const {
        opt(root, "", key, [&](const json& v, const std::string& p) {
            requireArray(v, p);
            const std::span<const detail::JsonElement> elements = elements_->elements(key);
            out.resize(elements.size());
            for (std::size_t i = 0; i < elements.size(); ++i) {
                const std::string elementPath = childPath(p, i);
                out[i].where = {elementPath, elements[i].where.line, elements[i].where.column};
                read(json::parse(elements[i].text), elementPath, out[i], i);
            }
        });
    }
    void parseWorld(const json& j, const std::string& path, Scene& scene) const;
    ShapeDesc parseShape(const json& j, const std::string& path, int depth) const;
    void parseBody(const json& j, const std::string& path, SceneBody& body) const;
    void parseJoint(const json& j, const std::string& path, const Scene& scene, SceneJoint& joint) const;
    void parseSpring(const json& j, const std::string& path, const Scene& scene, SceneSpring& spring) const;
    void parseRope(const json& j, const std::string& path, const Scene& scene, SceneRope& rope) const;
    void parseCloth(const json& j, const std::string& path, SceneCloth& cloth) const;
    // A "urdf" entry: the robot's links and joints appended to the scene (docs/robots.md).
    struct UrdfEntry {
        SceneLocation where;
    };
    void parseUrdf(const json& j, const std::string& path, const SceneLocation& where, Scene& scene) const;
    void parseCharacter(const json& j, const std::string& path, SceneCharacter& character) const;
    void parseVehicle(const json& j, const std::string& path, const Scene& scene, SceneVehicle& vehicle) const;
    // A body reference: a name of the scene's bodies; null (or absent) when `allowNull`.
    std::string bodyRef(const json& v, const std::string& path, const Scene& scene, bool allowNull) const;

    std::string_view text_;
    std::string source_;
    std::optional<detail::JsonElementIndex> elements_;  // built once the text is known to be valid JSON
    NameIndex bodyIndex_;                               // the bodies' names, which joints and springs refer to
};

void Parser::parseWorld(const json& j, const std::string& path, Scene& scene) const {
    requireObject(j, path);
    checkKeys(j, path, {"gravity", "dt", "steps", "substeps", "integrator", "sleeping", "solver_iterations", "threads",
                        "joint_hertz", "joint_damping_ratio", "joint_projection_slop", "joint_direct_solve",
                        "max_rotation_per_substep", "max_contact_pairs", "hit_event_threshold", "push_out_grown_overlaps"},
              "");
    WorldDef& w = scene.world;
    opt(j, path, "gravity", [&](const json& v, const std::string& p) { w.gravity = vec3(v, p); });
    opt(j, path, "dt", [&](const json& v, const std::string& p) { scene.dt = positive(v, p, "dt"); });
    opt(j, path, "steps", [&](const json& v, const std::string& p) {
        scene.steps = static_cast<int>(integer(v, p, 0, std::numeric_limits<int>::max(), "steps"));
    });
    opt(j, path, "substeps", [&](const json& v, const std::string& p) {
        w.substeps = static_cast<int>(integer(v, p, 1, kSceneMaxSubsteps, "substeps"));
    });
    opt(j, path, "solver_iterations", [&](const json& v, const std::string& p) {
        w.solverIterations = static_cast<int>(integer(v, p, 1, kSceneMaxSolverIterations, "solver_iterations"));
    });
    opt(j, path, "threads", [&](const json& v, const std::string& p) {
        w.threads = static_cast<int>(integer(v, p, 1, kMaxThreads, "threads"));
    });
    opt(j, path, "integrator", [&](const json& v, const std::string& p) {
        const std::string name = string(v, p);
        const auto integrator = integratorFromString(name);
        if (!integrator) fail(p, "unknown integrator '" + name + "' (valid: " + detail::integratorList() + ")");
        w.integrator = *integrator;
    });
    opt(j, path, "sleeping", [&](const json& v, const std::string& p) { w.sleeping = boolean(v, p); });
    // Joint solver tuning (WorldDef, docs/joints.md).
    opt(j, path, "joint_hertz", [&](const json& v, const std::string& p) { w.jointHertz = positive(v, p, "joint_hertz"); });
    opt(j, path, "joint_damping_ratio", [&](const json& v, const std::string& p) {
        w.jointDampingRatio = positive(v, p, "joint_damping_ratio");
    });
    // JSON has no infinity: "off" stands for it (no position projection).
    opt(j, path, "joint_projection_slop", [&](const json& v, const std::string& p) {
        w.jointProjectionSlop = numberOrOff(v, p, "joint_projection_slop", false, "m");
    });
    opt(j, path, "joint_direct_solve", [&](const json& v, const std::string& p) { w.jointDirectSolve = boolean(v, p); });
    opt(j, path, "max_rotation_per_substep", [&](const json& v, const std::string& p) {
        w.maxRotationPerSubstep = numberOrOff(v, p, "max_rotation_per_substep", true, "rad");
    });
    opt(j, path, "hit_event_threshold", [&](const json& v, const std::string& p) {
        w.hitEventThreshold = nonNegative(v, p, "hit_event_threshold");
    });
    // WorldDef::pushOutGrownOverlaps (docs/solver.md, "Grown overlaps").
    opt(j, path, "push_out_grown_overlaps", [&](const json& v, const std::string& p) { w.pushOutGrownOverlaps = boolean(v, p); });
    // WorldDef::maxContactPairs: "auto" (or 0) for the automatic limit.
    opt(j, path, "max_contact_pairs", [&](const json& v, const std::string& p) {
        if (v.is_string() && v.get<std::string>() == "auto") {
            w.maxContactPairs = 0;
            return;
        }
        if (!v.is_number()) {
            fail(p, "expected a pair count (an integer) or \"auto\", got " +
                        (v.is_string() ? "\"" + v.get<std::string>() + "\"" : describe(v)));
        }
        // (integer() would say "at least 0" for a limit of INT_MAX.)
        const double d = v.get<double>();
        if (d < 0 || d > static_cast<double>(kMaxContactPairs)) {
            fail(p, "max_contact_pairs must be between 0 and " + std::to_string(kMaxContactPairs) +
                        " (0 or \"auto\": automatic), got " + detail::formatNumber(d));
        }
        w.maxContactPairs = integer(v, p, 0, kMaxContactPairs, "max_contact_pairs");
    });
}

ShapeDesc Parser::parseShape(const json& given, const std::string& path, int depth) const {
    requireObject(given, path);
    // Scaled shapes (docs/shapes.md): "scale" belongs to every type, so it is
    // read here and each type below checks only the keys of its own; so is a
    // mesh's "decompose" (convex decomposition).
    const json* scaleJson = member(given, "scale");
    const json* decomposeJson = member(given, "decompose");
    json unscaled;
    if (scaleJson || decomposeJson) {
        unscaled = given;
        unscaled.erase("scale");
        unscaled.erase("decompose");
    }
    const json& j = scaleJson || decomposeJson ? unscaled : given;
    const std::string typePath = childPath(path, "type");
    const std::string typeName = string(required(j, path, "type"), typePath);
    ShapeDesc s;
    const auto type = detail::shapeTypeFromString(typeName);
    if (!type) fail(typePath, "unknown shape type '" + typeName + "' (valid: " + detail::shapeTypeList() + ")");
    s.type = *type;
    const std::string what = "a " + typeName + " shape";
    const auto positiveField = [&](std::string_view key) {
        return positive(required(j, path, key), childPath(path, key), key);
    };
    switch (s.type) {
        case ShapeType::Sphere:
            checkKeys(j, path, {"type", "radius"}, what);
            s.radius = positiveField("radius");
            break;
        case ShapeType::Box: {
            checkKeys(j, path, {"type", "half_extents", "convex_radius"}, what);
            const std::string p = childPath(path, "half_extents");
            s.halfExtents = vec3(required(j, path, "half_extents"), p);
            for (std::size_t i = 0; i < 3; ++i) {
                if (!(s.halfExtents[i] > 0)) {
                    fail(childPath(p, i), "half extents must be positive, got " + detail::formatNumber(s.halfExtents[i]));
                }
            }
            break;
        }
        case ShapeType::Capsule:
        case ShapeType::Cylinder:
            if (s.type == ShapeType::Cylinder) {
                checkKeys(j, path, {"type", "radius", "half_height", "convex_radius"}, what);
            } else {
                checkKeys(j, path, {"type", "radius", "half_height"}, what);
            }
            s.radius = positiveField("radius");
            s.halfHeight = positiveField("half_height");
            break;
        case ShapeType::ConvexHull: {
            checkKeys(j, path, {"type", "points", "convex_radius"}, what);
            const std::string p = childPath(path, "points");
            const json& pts = requireArray(required(j, path, "points"), p);
            if (pts.size() < 4) fail(p, "a convex hull needs at least 4 points, got " + std::to_string(pts.size()));
            s.points.reserve(pts.size());
            for (std::size_t i = 0; i < pts.size(); ++i) s.points.push_back(vec3(pts[i], childPath(p, i)));
            break;
        }
        case ShapeType::Plane:
            checkKeys(j, path, {"type", "normal", "offset"}, what);
            s.normal = nonZeroVec3(required(j, path, "normal"), childPath(path, "normal"), "normal");
            s.offset = 0;
            opt(j, path, "offset", [&](const json& v, const std::string& p) { s.offset = number(v, p); });
            break;
        case ShapeType::Mesh: {
            checkKeys(j, path, {"type", "vertices", "triangles"}, what);
            const std::string vp = childPath(path, "vertices");
            const json& verts = requireArray(required(j, path, "vertices"), vp);
            if (verts.size() < 3) fail(vp, "a mesh needs at least 3 vertices, got " + std::to_string(verts.size()));
            s.vertices.reserve(verts.size());
            for (std::size_t i = 0; i < verts.size(); ++i) s.vertices.push_back(vec3(verts[i], childPath(vp, i)));
            const std::string tp = childPath(path, "triangles");
            const json& tris = requireArray(required(j, path, "triangles"), tp);
            if (tris.empty()) fail(tp, "a mesh needs at least one triangle");
            s.triangles.reserve(tris.size());
            const long long maxIndex = static_cast<long long>(verts.size()) - 1;
            for (std::size_t i = 0; i < tris.size(); ++i) {
                const std::string ti = childPath(tp, i);
                if (!tris[i].is_array() || tris[i].size() != 3) fail(ti, "expected 3 vertex indices [i, j, k], got " + describe(tris[i]));
                std::array<std::uint32_t, 3> t{};
                for (std::size_t k = 0; k < 3; ++k) {
                    t[k] = static_cast<std::uint32_t>(integer(tris[i][k], childPath(ti, k), 0, maxIndex, "vertex index"));
                }
                if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2]) fail(ti, "triangle repeats a vertex index (degenerate)");
                s.triangles.push_back(t);
            }
            break;
        }
        case ShapeType::HeightField: {
            checkKeys(j, path, {"type", "rows", "columns", "spacing", "heights", "holes"}, what);
            const long long maxSamples = kMaxHeightFieldSamples;
            s.rows = static_cast<std::uint32_t>(integer(required(j, path, "rows"), childPath(path, "rows"), 2, maxSamples, "rows"));
            s.columns = static_cast<std::uint32_t>(
                integer(required(j, path, "columns"), childPath(path, "columns"), 2, maxSamples, "columns"));
            const std::string sp = childPath(path, "spacing");
            const json& spacing = requireArray(required(j, path, "spacing"), sp);
            if (spacing.size() != 2) fail(sp, "expected [dx, dz], got " + describe(spacing));
            s.spacingX = positive(spacing[0], childPath(sp, 0), "spacing");
            s.spacingZ = positive(spacing[1], childPath(sp, 1), "spacing");
            const std::string hp = childPath(path, "heights");
            const json& heights = requireArray(required(j, path, "heights"), hp);
            const std::size_t samples = std::size_t(s.rows) * s.columns;
            if (heights.size() != samples) {
                fail(hp, "expected rows * columns = " + std::to_string(s.rows) + " * " + std::to_string(s.columns) + " = " +
                             std::to_string(samples) + " heights, got " + std::to_string(heights.size()));
            }
            s.heights.reserve(samples);
            for (std::size_t i = 0; i < samples; ++i) s.heights.push_back(number(heights[i], childPath(hp, i)));
            opt(j, path, "holes", [&](const json& v, const std::string& p) {
                const json& holes = requireArray(v, p);
                const long long lastCell = static_cast<long long>(s.rows - 1) * (s.columns - 1) - 1;
                for (std::size_t i = 0; i < holes.size(); ++i) {
                    s.holes.push_back(static_cast<std::uint32_t>(integer(holes[i], childPath(p, i), 0, lastCell, "cell index")));
                }
            });
            break;
        }
        case ShapeType::Compound: {
            checkKeys(j, path, {"type", "children"}, what);
            if (depth >= kMaxCompoundLevels) {  // depth counts from 0: this compound is level depth + 1
                fail(path, "compounds nested deeper than " + std::to_string(kMaxCompoundLevels) + " levels");
            }
            const std::string cp = childPath(path, "children");
            const json& kids = requireArray(required(j, path, "children"), cp);
            if (kids.empty()) fail(cp, "a compound needs at least one child");
            for (std::size_t i = 0; i < kids.size(); ++i) {
                const std::string kp = childPath(cp, i);
                requireObject(kids[i], kp);
                checkKeys(kids[i], kp, {"shape", "position", "orientation"}, "a compound child");
                ShapeDesc::Child child;
                child.shape = parseShape(required(kids[i], kp, "shape"), childPath(kp, "shape"), depth + 1);
                opt(kids[i], kp, "position", [&](const json& v, const std::string& p) { child.position = vec3(v, p); });
                opt(kids[i], kp, "orientation", [&](const json& v, const std::string& p) { child.orientation = quat(v, p); });
                s.children.push_back(std::move(child));
            }
            break;
        }
    }
    if (scaleJson) s.scale = shapeScale(*scaleJson, childPath(path, "scale"));
    if (decomposeJson) {
        const std::string p = childPath(path, "decompose");
        s.decompose = boolean(*decomposeJson, p);
        if (s.type != ShapeType::Mesh) fail(p, "only a mesh can be decomposed into convex hulls, this is a " + typeName);
    }
    // Rounded shapes: the optional convex radius of a box, cylinder or hull
    // (checkKeys above refuses it on any other shape).
    opt(j, path, "convex_radius", [&](const json& v, const std::string& p) {
        s.convexRadius = number(v, p);
        Real limit = std::numeric_limits<Real>::infinity();
        std::string limitName = "infinity";
        if (s.type == ShapeType::Box) limit = minComponent(s.halfExtents), limitName = "the smallest half extent";
        if (s.type == ShapeType::Cylinder) limit = std::min(s.radius, s.halfHeight), limitName = "min(radius, half_height)";
        if (!std::isfinite(s.convexRadius) || s.convexRadius < 0 || s.convexRadius > limit) {
            fail(p, "convex_radius must be in [0, " + limitName + " = " + detail::formatNumber(limit) + "], got " +
                        detail::formatNumber(s.convexRadius));
        }
    });
    // The engine's own rules, as the last word (hulls and meshes are built,
    // and checked geometrically, by buildWorld).
    if (s.type != ShapeType::ConvexHull && s.type != ShapeType::Mesh && !detail::containsHullOrMesh(s)) {
        try {
            (void)detail::buildPrimitiveShape(s);
        } catch (const SceneError&) {
            throw;
        } catch (const Error& e) {
            fail(path, e.what());
        }
    }
    return s;
}

void Parser::parseBody(const json& j, const std::string& path, SceneBody& body) const {
    requireObject(j, path);
    checkKeys(j, path,
              {"name", "type", "shape", "mass", "density", "inertia", "position", "orientation", "linear_velocity",
               "angular_velocity", "friction", "restitution", "linear_damping", "angular_damping", "gravity_scale",
               "rolling_resistance", "linear_drag", "quadratic_drag", "filter", "is_sensor", "is_bullet", "allow_sleep",
               "awake", "center_of_mass"},
              "a body");
    BodyDef& d = body.def;
    opt(j, path, "name", [&](const json& v, const std::string& p) { d.name = string(v, p); });
    opt(j, path, "type", [&](const json& v, const std::string& p) {
        const std::string name = string(v, p);
        const auto type = detail::bodyTypeFromString(name);
        if (!type) fail(p, "unknown body type '" + name + "' (valid: dynamic, static, kinematic)");
        d.type = *type;
    });
    const bool dynamic = d.type == BodyType::Dynamic;
    const std::string shapePath = childPath(path, "shape");
    body.shape = parseShape(required(j, path, "shape"), shapePath, 0);
    if (d.type != BodyType::Static && detail::isStaticOnly(body.shape)) {
        fail(childPath(shapePath, "type"), std::string("a ") + toString(body.shape.type) +
                                                " shape can only belong to a static body, but this body is " +
                                                toString(d.type) +
                                                (body.shape.type == ShapeType::Mesh
                                                     ? " (a closed mesh can be a dynamic body's shape as convex hulls: add "
                                                       "\"decompose\": true)"
                                                     : ""));
    }

    const json* mass = member(j, "mass");
    const json* density = member(j, "density");
    if (mass && density) fail(childPath(path, "density"), "give either mass or density, not both");
    if (mass) {
        const std::string p = childPath(path, "mass");
        d.mass = number(*mass, p);
        if (dynamic && !(mass->get<double>() > 0)) fail(p, "mass must be positive for a dynamic body, got " + detail::formatNumber(d.mass));
        if (d.mass < 0) fail(p, "mass must not be negative, got " + detail::formatNumber(d.mass));
        if (d.mass != 0 || mass->get<double>() != 0) requireNormal(d.mass, mass->get<double>(), p, "mass");
    }
    if (density) {
        const std::string p = childPath(path, "density");
        d.density = number(*density, p);
        if (dynamic && !(density->get<double>() > 0)) {
            fail(p, "density must be positive for a dynamic body, got " + detail::formatNumber(d.density));
        }
        if (d.density < 0) fail(p, "density must not be negative, got " + detail::formatNumber(d.density));
        if (d.density != 0 || density->get<double>() != 0) requireNormal(d.density, density->get<double>(), p, "density");
    }
    opt(j, path, "inertia", [&](const json& v, const std::string& p) {
        if (!dynamic) fail(p, "only dynamic bodies have an inertia tensor");
        Mat3 m = Mat3::zero();
        if (v.is_array() && v.size() == 3 && v[0].is_number()) {
            const Vec3 diag = vec3(v, p);
            m = Mat3::diagonal(diag);
        } else if (v.is_array() && v.size() == 3) {
            const Vec3 r0 = vec3(v[0], childPath(p, 0)), r1 = vec3(v[1], childPath(p, 1)), r2 = vec3(v[2], childPath(p, 2));
            m = Mat3::fromRows(r0, r1, r2);
        } else {
            fail(p, "expected [Ixx, Iyy, Izz] or a 3x3 matrix [[...], [...], [...]], got " + describe(v));
        }
        for (int a = 0; a < 3; ++a) {
            if (!(m(a, a) > 0)) fail(p, "the diagonal of the inertia tensor must be positive");
            for (int b = 0; b < 3; ++b) {
                if (std::fabs(m(a, b) - m(b, a)) > Real(1e-6) * (std::fabs(m(a, b)) + std::fabs(m(b, a)))) {
                    fail(p, "the inertia tensor must be symmetric");
                }
            }
        }
        // Principal moments of a real body satisfy the triangle inequality.
        const Real ixx = m(0, 0), iyy = m(1, 1), izz = m(2, 2);
        const Real slack = Real(1e-5) * (ixx + iyy + izz);
        if (ixx + iyy + slack < izz || iyy + izz + slack < ixx || izz + ixx + slack < iyy) {
            fail(p, "inertia violates the triangle inequality (each diagonal moment must not exceed the sum of the other two)");
        }
        d.inertia = m;
    });
    opt(j, path, "center_of_mass", [&](const json& v, const std::string& p) {
        if (!dynamic) fail(p, "only dynamic bodies have a centre of mass of their own");
        d.centerOfMass = vec3(v, p);
    });
    opt(j, path, "position", [&](const json& v, const std::string& p) { d.position = vec3(v, p); });
    opt(j, path, "orientation", [&](const json& v, const std::string& p) { d.orientation = quat(v, p); });
    opt(j, path, "linear_velocity", [&](const json& v, const std::string& p) { d.linearVelocity = vec3(v, p); });
    opt(j, path, "angular_velocity", [&](const json& v, const std::string& p) { d.angularVelocity = vec3(v, p); });
    opt(j, path, "friction", [&](const json& v, const std::string& p) { d.friction = nonNegative(v, p, "friction"); });
    opt(j, path, "restitution", [&](const json& v, const std::string& p) {
        d.restitution = nonNegative(v, p, "restitution");
        if (d.restitution > 1) fail(p, "restitution must be between 0 and 1, got " + detail::formatNumber(d.restitution));
    });
    opt(j, path, "linear_damping", [&](const json& v, const std::string& p) { d.linearDamping = nonNegative(v, p, "linear_damping"); });
    opt(j, path, "angular_damping", [&](const json& v, const std::string& p) { d.angularDamping = nonNegative(v, p, "angular_damping"); });
    opt(j, path, "gravity_scale", [&](const json& v, const std::string& p) { d.gravityScale = number(v, p); });
    opt(j, path, "rolling_resistance", [&](const json& v, const std::string& p) {
        d.rollingResistance = nonNegative(v, p, "rolling_resistance");
    });
    opt(j, path, "linear_drag", [&](const json& v, const std::string& p) { d.linearDrag = nonNegative(v, p, "linear_drag"); });
    opt(j, path, "quadratic_drag", [&](const json& v, const std::string& p) { d.quadraticDrag = nonNegative(v, p, "quadratic_drag"); });
    opt(j, path, "filter", [&](const json& v, const std::string& p) {
        requireObject(v, p);
        checkKeys(v, p, {"category", "mask", "group"}, "a collision filter");
        opt(v, p, "category", [&](const json& x, const std::string& q) {
            d.filter.category = static_cast<std::uint32_t>(integer(x, q, 0, 0xFFFFFFFFll, "category"));
        });
        opt(v, p, "mask", [&](const json& x, const std::string& q) {
            d.filter.mask = static_cast<std::uint32_t>(integer(x, q, 0, 0xFFFFFFFFll, "mask"));
        });
        opt(v, p, "group", [&](const json& x, const std::string& q) {
            d.filter.group = static_cast<std::int32_t>(integer(x, q, std::numeric_limits<std::int32_t>::min(),
                                                               std::numeric_limits<std::int32_t>::max(), "group"));
        });
    });
    opt(j, path, "is_sensor", [&](const json& v, const std::string& p) { d.isSensor = boolean(v, p); });
    opt(j, path, "is_bullet", [&](const json& v, const std::string& p) { d.isBullet = boolean(v, p); });
    opt(j, path, "allow_sleep", [&](const json& v, const std::string& p) { d.allowSleep = boolean(v, p); });
    opt(j, path, "awake", [&](const json& v, const std::string& p) { d.awake = boolean(v, p); });
}

std::string Parser::bodyRef(const json& v, const std::string& path, const Scene& scene, bool allowNull) const {
    if (v.is_null()) {
        if (allowNull) return {};
        fail(path, "must name a body (only body_a may be null, meaning the static world)");
    }
    const std::string name = string(v, path);
    if (name.empty()) fail(path, "body name must not be empty");
    if (bodyIndex_.contains(name)) return name;
    std::vector<std::string_view> names;
    for (const SceneBody& b : scene.bodies) {
        if (!b.def.name.empty()) names.push_back(b.def.name);
    }
    std::string reason = "unknown body '" + name + "'";
    const std::string_view close = detail::closestMatch(name, names);
    if (!close.empty()) reason += " (did you mean '" + std::string(close) + "'?)";
    fail(path, reason);
}

void Parser::parseJoint(const json& j, const std::string& path, const Scene& scene, SceneJoint& joint) const {
    requireObject(j, path);
    JointDef& d = joint.def;
    const std::string typePath = childPath(path, "type");
    const std::string typeName = string(required(j, path, "type"), typePath);
    const auto type = detail::jointTypeFromString(typeName);
    if (!type) fail(typePath, "unknown joint type '" + typeName + "' (valid: " + detail::jointTypeList() + ")");
    d.type = *type;
    const std::string what = "a " + typeName + " joint";
    // Joint friction exists for the rotational joints and the slider (a force
    // along its axis, N) only (the solver ignores it on the others), so
    // elsewhere the key is a mistake worth naming.
    const bool hasFriction = d.type == JointType::Ball || d.type == JointType::Hinge || d.type == JointType::ConeTwist ||
                             d.type == JointType::Slider;
    if (!hasFriction && member(j, "friction_torque") != nullptr) {
        fail(childPath(path, "friction_torque"),
             "friction_torque applies only to ball, hinge, slider and cone_twist joints, not to " + what);
    }
#define FULCRUM_JOINT_COMMON "name", "type", "body_a", "body_b", "anchor", "break_force", "break_torque", "collide_connected"
    switch (d.type) {
        case JointType::Ball: checkKeys(j, path, {FULCRUM_JOINT_COMMON, "friction_torque"}, what); break;
        case JointType::Fixed: checkKeys(j, path, {FULCRUM_JOINT_COMMON}, what); break;
        case JointType::Hinge:
            checkKeys(j, path, {FULCRUM_JOINT_COMMON, "axis", "limits", "motor", "spring", "friction_torque"}, what);
            break;
        case JointType::Slider: checkKeys(j, path, {FULCRUM_JOINT_COMMON, "axis", "limits", "motor", "spring", "friction_torque"}, what); break;
        case JointType::Distance:
            checkKeys(j, path, {FULCRUM_JOINT_COMMON, "anchor_b", "min_length", "max_length", "stiffness", "damping"}, what);
            break;
        case JointType::ConeTwist:
            checkKeys(j, path, {FULCRUM_JOINT_COMMON, "axis", "swing_limit", "twist_limits", "friction_torque", "drive"}, what);
            break;
        case JointType::SixDof: checkKeys(j, path, {FULCRUM_JOINT_COMMON, "axis", "axis_y", "axes"}, what); break;
    }
#undef FULCRUM_JOINT_COMMON
    opt(j, path, "name", [&](const json& v, const std::string& p) { d.name = string(v, p); });
    opt(j, path, "body_a", [&](const json& v, const std::string& p) { joint.bodyA = bodyRef(v, p, scene, true); });
    joint.bodyB = bodyRef(required(j, path, "body_b"), childPath(path, "body_b"), scene, false);
    if (joint.bodyA == joint.bodyB) fail(childPath(path, "body_b"), "a joint needs two different bodies, got '" + joint.bodyB + "' twice");
    d.anchor = vec3(required(j, path, "anchor"), childPath(path, "anchor"));
    opt(j, path, "anchor_b", [&](const json& v, const std::string& p) { d.anchorB = vec3(v, p); });
    if (d.type == JointType::Distance) d.anchorB = vec3(required(j, path, "anchor_b"), childPath(path, "anchor_b"));
    opt(j, path, "axis", [&](const json& v, const std::string& p) { d.axis = nonZeroVec3(v, p, "axis"); });
    opt(j, path, "limits", [&](const json& v, const std::string& p) {
        const auto r = range(v, p, "limits");
        d.hasLimits = true;
        d.lowerLimit = r[0];
        d.upperLimit = r[1];
    });
    const auto readMotor = [&](const json& v, const std::string& p, JointMotor& motor) {
        requireObject(v, p);
        checkKeys(v, p, {"speed", "max_force"}, "a motor");
        motor.enabled = true;
        motor.speed = number(required(v, p, "speed"), childPath(p, "speed"));
        motor.maxForce = nonNegative(required(v, p, "max_force"), childPath(p, "max_force"), "max_force");
    };
    const auto readSpring = [&](const json& v, const std::string& p, JointSpring& spring) {
        requireObject(v, p);
        checkKeys(v, p, {"target", "stiffness", "damping", "max_force"}, "a joint spring");
        spring.enabled = true;
        opt(v, p, "target", [&](const json& x, const std::string& q) { spring.target = number(x, q); });
        spring.stiffness = nonNegative(required(v, p, "stiffness"), childPath(p, "stiffness"), "stiffness");
        opt(v, p, "damping", [&](const json& x, const std::string& q) { spring.damping = nonNegative(x, q, "damping"); });
        // The position drive's force limit (absent: unlimited; JSON has no infinity).
        opt(v, p, "max_force", [&](const json& x, const std::string& q) { spring.maxForce = nonNegative(x, q, "max_force"); });
    };
    opt(j, path, "motor", [&](const json& v, const std::string& p) { readMotor(v, p, d.motor); });
    opt(j, path, "spring", [&](const json& v, const std::string& p) { readSpring(v, p, d.spring); });
    // Cone-twist: the orientation drive (absent stiffness: rigid; JSON has no infinity).
    opt(j, path, "drive", [&](const json& v, const std::string& p) {
        requireObject(v, p);
        checkKeys(v, p, {"target", "stiffness", "damping", "max_torque"}, "a cone-twist drive");
        ConeTwistDrive& drive = d.coneDrive;
        drive.enabled = true;
        drive.stiffness = std::numeric_limits<Real>::infinity();
        opt(v, p, "target", [&](const json& x, const std::string& q) { drive.target = normalize(quat(x, q)); });
        opt(v, p, "stiffness", [&](const json& x, const std::string& q) { drive.stiffness = nonNegative(x, q, "stiffness"); });
        opt(v, p, "damping", [&](const json& x, const std::string& q) { drive.damping = nonNegative(x, q, "damping"); });
        opt(v, p, "max_torque", [&](const json& x, const std::string& q) { drive.maxTorque = positive(x, q, "max_torque"); });
    });
    // Six-DOF: the frame's y axis, and its axes by name ("free", "locked", or
    // an object: mode, limits, motor, spring; unnamed axes stay locked).
    opt(j, path, "axis_y", [&](const json& v, const std::string& p) { d.axisY = nonZeroVec3(v, p, "axis_y"); });
    opt(j, path, "axes", [&](const json& v, const std::string& p) {
        requireObject(v, p);
        static constexpr const char* kNames[kSixDofAxes] = {"x", "y", "z", "rx", "ry", "rz"};
        checkKeys(v, p, {"x", "y", "z", "rx", "ry", "rz"}, "the six-DOF axes");
        for (int k = 0; k < kSixDofAxes; ++k) {
            SixDofAxis& axis = d.axes[static_cast<std::size_t>(k)];
            opt(v, p, kNames[k], [&](const json& x, const std::string& q) {
                const auto mode = [&](const json& m, const std::string& mp) {
                    const std::string name = string(m, mp);
                    if (name == "free") return AxisMode::Free;
                    if (name == "locked") return AxisMode::Locked;
                    if (name == "limited") return AxisMode::Limited;
                    fail(mp, "unknown axis mode '" + name + "' (valid: free, limited, locked)");
                };
                if (x.is_string()) {
                    axis.mode = mode(x, q);
                    if (axis.mode == AxisMode::Limited) fail(q, "a limited axis needs its limits: {\"limits\": [lower, upper]}");
                    return;
                }
                requireObject(x, q);
                checkKeys(x, q, {"mode", "limits", "motor", "spring"}, "a six-DOF axis");
                axis.mode = AxisMode::Free;
                opt(x, q, "limits", [&](const json& r, const std::string& rp) {
                    const auto lim = range(r, rp, "limits");
                    axis.mode = AxisMode::Limited;
                    axis.lower = lim[0];
                    axis.upper = lim[1];
                });
                opt(x, q, "mode", [&](const json& m, const std::string& mp) {
                    const AxisMode given = mode(m, mp);
                    if ((given == AxisMode::Limited) != (axis.mode == AxisMode::Limited)) {
                        fail(mp, given == AxisMode::Limited ? "a limited axis needs \"limits\"" : "\"limits\" make the axis limited");
                    }
                    axis.mode = given;
                });
                opt(x, q, "motor", [&](const json& m, const std::string& mp) { readMotor(m, mp, axis.motor); });
                opt(x, q, "spring", [&](const json& m, const std::string& mp) { readSpring(m, mp, axis.spring); });
            });
        }
    });
    opt(j, path, "min_length", [&](const json& v, const std::string& p) { d.minLength = nonNegative(v, p, "min_length"); });
    opt(j, path, "max_length", [&](const json& v, const std::string& p) { d.maxLength = nonNegative(v, p, "max_length"); });
    if (d.minLength >= 0 && d.maxLength >= 0 && d.minLength > d.maxLength) {
        fail(childPath(path, "max_length"), "max_length must not be less than min_length, got " + detail::formatNumber(d.maxLength) +
                                                " < " + detail::formatNumber(d.minLength));
    }
    opt(j, path, "stiffness", [&](const json& v, const std::string& p) { d.stiffness = nonNegative(v, p, "stiffness"); });
    opt(j, path, "damping", [&](const json& v, const std::string& p) { d.damping = nonNegative(v, p, "damping"); });
    opt(j, path, "swing_limit", [&](const json& v, const std::string& p) {
        d.swingLimit = positive(v, p, "swing_limit");
        if (d.swingLimit > kPi) fail(p, "swing_limit must be at most pi radians, got " + detail::formatNumber(d.swingLimit));
    });
    opt(j, path, "twist_limits", [&](const json& v, const std::string& p) {
        const auto r = range(v, p, "twist_limits");
        if (r[0] < -kPi || r[1] > kPi) fail(p, "twist limits must lie within [-pi, pi] radians");
        d.twistLower = r[0];
        d.twistUpper = r[1];
    });
    opt(j, path, "break_force", [&](const json& v, const std::string& p) { d.breakForce = positive(v, p, "break_force"); });
    opt(j, path, "break_torque", [&](const json& v, const std::string& p) { d.breakTorque = positive(v, p, "break_torque"); });
    opt(j, path, "collide_connected", [&](const json& v, const std::string& p) { d.collideConnected = boolean(v, p); });
    opt(j, path, "friction_torque", [&](const json& v, const std::string& p) { d.frictionTorque = nonNegative(v, p, "friction_torque"); });
}

void Parser::parseSpring(const json& j, const std::string& path, const Scene& scene, SceneSpring& spring) const {
    requireObject(j, path);
    checkKeys(j, path, {"body_a", "body_b", "anchor_a", "anchor_b", "rest_length", "stiffness", "damping"}, "a spring");
    SpringDef& d = spring.def;
    opt(j, path, "body_a", [&](const json& v, const std::string& p) { spring.bodyA = bodyRef(v, p, scene, true); });
    spring.bodyB = bodyRef(required(j, path, "body_b"), childPath(path, "body_b"), scene, false);
    if (spring.bodyA == spring.bodyB) fail(childPath(path, "body_b"), "a spring needs two different bodies, got '" + spring.bodyB + "' twice");
    d.anchorA = vec3(required(j, path, "anchor_a"), childPath(path, "anchor_a"));
    d.anchorB = vec3(required(j, path, "anchor_b"), childPath(path, "anchor_b"));
    d.restLength = distance(d.anchorA, d.anchorB);
    opt(j, path, "rest_length", [&](const json& v, const std::string& p) { d.restLength = nonNegative(v, p, "rest_length"); });
    d.stiffness = nonNegative(required(j, path, "stiffness"), childPath(path, "stiffness"), "stiffness");
    opt(j, path, "damping", [&](const json& v, const std::string& p) { d.damping = nonNegative(v, p, "damping"); });
}

void Parser::parseRope(const json& j, const std::string& path, const Scene& scene, SceneRope& rope) const {
    requireObject(j, path);
    checkKeys(j, path,
              {"name", "start", "end", "segments", "particle_mass", "radius", "pin_start", "pin_end", "attach_start",
               "attach_end", "stretch_compliance", "bend_compliance"},
              "a rope");
    RopeDef& d = rope.def;
    opt(j, path, "name", [&](const json& v, const std::string& p) { d.name = string(v, p); });
    d.start = vec3(required(j, path, "start"), childPath(path, "start"));
    d.end = vec3(required(j, path, "end"), childPath(path, "end"));
    if (!(distance(d.start, d.end) > Real(1e-6))) fail(childPath(path, "end"), "a rope's end must differ from its start");
    opt(j, path, "segments", [&](const json& v, const std::string& p) {
        d.segments = static_cast<int>(integer(v, p, 1, kSceneMaxRopeSegments, "segments"));
    });
    opt(j, path, "particle_mass", [&](const json& v, const std::string& p) { d.particleMass = positive(v, p, "particle_mass"); });
    opt(j, path, "radius", [&](const json& v, const std::string& p) { d.radius = positive(v, p, "radius"); });
    opt(j, path, "pin_start", [&](const json& v, const std::string& p) { d.pinStart = boolean(v, p); });
    opt(j, path, "pin_end", [&](const json& v, const std::string& p) { d.pinEnd = boolean(v, p); });
    opt(j, path, "attach_start", [&](const json& v, const std::string& p) { rope.attachStart = bodyRef(v, p, scene, true); });
    opt(j, path, "attach_end", [&](const json& v, const std::string& p) { rope.attachEnd = bodyRef(v, p, scene, true); });
    opt(j, path, "stretch_compliance", [&](const json& v, const std::string& p) {
        d.stretchCompliance = nonNegative(v, p, "stretch_compliance");
    });
    d.bendCompliance = kSceneDefaultBendCompliance;  // floppy unless given (scene.hpp)
    opt(j, path, "bend_compliance", [&](const json& v, const std::string& p) { d.bendCompliance = nonNegative(v, p, "bend_compliance"); });
}

void Parser::parseCloth(const json& j, const std::string& path, SceneCloth& cloth) const {
    requireObject(j, path);
    checkKeys(j, path,
              {"name", "origin", "u_axis", "v_axis", "size", "spacing", "particle_mass", "radius", "pinned",
               "stretch_compliance", "bend_compliance"},
              "a cloth");
    ClothDef& d = cloth.def;
    opt(j, path, "name", [&](const json& v, const std::string& p) { d.name = string(v, p); });
    d.origin = vec3(required(j, path, "origin"), childPath(path, "origin"));
    opt(j, path, "u_axis", [&](const json& v, const std::string& p) { d.uAxis = nonZeroVec3(v, p, "u_axis"); });
    opt(j, path, "v_axis", [&](const json& v, const std::string& p) { d.vAxis = nonZeroVec3(v, p, "v_axis"); });
    if (!(length(cross(normalize(d.uAxis), normalize(d.vAxis))) > Real(1e-3))) {
        fail(childPath(path, member(j, "v_axis") ? "v_axis" : "u_axis"), "u_axis and v_axis must not be parallel");
    }
    opt(j, path, "size", [&](const json& v, const std::string& p) {
        if (!v.is_array() || v.size() != 2) fail(p, "expected [nu, nv], got " + describe(v));
        d.size[0] = static_cast<int>(integer(v[0], childPath(p, 0), 2, kSceneMaxClothSide, "size"));
        d.size[1] = static_cast<int>(integer(v[1], childPath(p, 1), 2, kSceneMaxClothSide, "size"));
        const long long particles = static_cast<long long>(d.size[0]) * d.size[1];
        if (particles > kSceneMaxClothParticles) {
            fail(p, "a cloth has at most " + std::to_string(kSceneMaxClothParticles) + " particles (size[0] * size[1]), got " +
                        std::to_string(d.size[0]) + " * " + std::to_string(d.size[1]) + " = " + std::to_string(particles));
        }
    });
    opt(j, path, "spacing", [&](const json& v, const std::string& p) { d.spacing = positive(v, p, "spacing"); });
    opt(j, path, "particle_mass", [&](const json& v, const std::string& p) { d.particleMass = positive(v, p, "particle_mass"); });
    opt(j, path, "radius", [&](const json& v, const std::string& p) { d.radius = positive(v, p, "radius"); });
    opt(j, path, "pinned", [&](const json& v, const std::string& p) {
        requireArray(v, p);
        for (std::size_t i = 0; i < v.size(); ++i) {
            const std::string q = childPath(p, i);
            if (!v[i].is_array() || v[i].size() != 2) fail(q, "expected a particle index [i, j], got " + describe(v[i]));
            const int a = static_cast<int>(integer(v[i][0], childPath(q, 0), 0, d.size[0] - 1, "i"));
            const int b = static_cast<int>(integer(v[i][1], childPath(q, 1), 0, d.size[1] - 1, "j"));
            d.pinned.push_back({a, b});
        }
    });
    opt(j, path, "stretch_compliance", [&](const json& v, const std::string& p) {
        d.stretchCompliance = nonNegative(v, p, "stretch_compliance");
    });
    d.bendCompliance = kSceneDefaultBendCompliance;  // floppy unless given (scene.hpp)
    opt(j, path, "bend_compliance", [&](const json& v, const std::string& p) { d.bendCompliance = nonNegative(v, p, "bend_compliance"); });
}

void Parser::parseCharacter(const json& j, const std::string& path, SceneCharacter& character) const {
    requireObject(j, path);
    checkKeys(j, path,
              {"name", "position", "radius", "height", "mass", "max_slope", "step_height", "jump_speed", "max_push_force",
               "stick_distance", "inputs"},
              "a character");
    CharacterDef& d = character.def;
    opt(j, path, "name", [&](const json& v, const std::string& p) { d.name = string(v, p); });
    d.position = vec3(required(j, path, "position"), childPath(path, "position"));
    opt(j, path, "radius", [&](const json& v, const std::string& p) { d.radius = positive(v, p, "radius"); });
    opt(j, path, "height", [&](const json& v, const std::string& p) { d.height = positive(v, p, "height"); });
    if (d.height < 2 * d.radius) {
        fail(childPath(path, "height"), "height must be at least twice the radius (" + detail::formatNumber(2 * d.radius) +
                                            "), got " + detail::formatNumber(d.height));
    }
    opt(j, path, "mass", [&](const json& v, const std::string& p) { d.mass = positive(v, p, "mass"); });
    opt(j, path, "max_slope", [&](const json& v, const std::string& p) {
        d.maxSlope = positive(v, p, "max_slope");
        if (!(d.maxSlope < kPi / 2)) fail(p, "max_slope must be below pi/2 radians, got " + detail::formatNumber(d.maxSlope));
    });
    opt(j, path, "step_height", [&](const json& v, const std::string& p) { d.stepHeight = nonNegative(v, p, "step_height"); });
    opt(j, path, "jump_speed", [&](const json& v, const std::string& p) { d.jumpSpeed = nonNegative(v, p, "jump_speed"); });
    opt(j, path, "max_push_force", [&](const json& v, const std::string& p) { d.maxPushForce = nonNegative(v, p, "max_push_force"); });
    opt(j, path, "stick_distance", [&](const json& v, const std::string& p) { d.stickDistance = nonNegative(v, p, "stick_distance"); });
    opt(j, path, "inputs", [&](const json& v, const std::string& p) {
        requireArray(v, p);
        for (std::size_t i = 0; i < v.size(); ++i) {
            const std::string q = childPath(p, i);
            requireObject(v[i], q);
            checkKeys(v[i], q, {"time", "velocity", "jump"}, "a character input");
            CharacterInput in;
            in.time = nonNegative(required(v[i], q, "time"), childPath(q, "time"), "time");
            if (!d.inputs.empty() && in.time < d.inputs.back().time) {
                fail(childPath(q, "time"), "inputs must be in time order, got " + detail::formatNumber(in.time) + " after " +
                                               detail::formatNumber(d.inputs.back().time));
            }
            opt(v[i], q, "velocity", [&](const json& x, const std::string& r) { in.velocity = vec3(x, r); });
            opt(v[i], q, "jump", [&](const json& x, const std::string& r) { in.jump = boolean(x, r); });
            d.inputs.push_back(in);
        }
    });
}

void Parser::parseVehicle(const json& j, const std::string& path, const Scene& scene, SceneVehicle& vehicle) const {
    requireObject(j, path);
    checkKeys(j, path,
              {"name", "chassis", "wheels", "engine", "gearbox", "max_brake_torque", "max_hand_brake_torque",
               "max_steering_angle", "anti_roll_bars", "inputs"},
              "a vehicle");
    VehicleDef& d = vehicle.def;
    opt(j, path, "name", [&](const json& v, const std::string& p) { d.name = string(v, p); });
    vehicle.chassis = bodyRef(required(j, path, "chassis"), childPath(path, "chassis"), scene, false);
    const json& wheels = required(j, path, "wheels");
    const std::string wp = childPath(path, "wheels");
    requireArray(wheels, wp);
    if (wheels.empty()) fail(wp, "a vehicle needs at least one wheel");
    for (std::size_t i = 0; i < wheels.size(); ++i) {
        const std::string q = childPath(wp, i);
        const json& w = wheels[i];
        requireObject(w, q);
        checkKeys(w, q, {"position", "radius", "width", "suspension", "steering", "driven", "hand_brake", "friction", "inertia"},
                  "a wheel");
        WheelDef wd;
        wd.position = vec3(required(w, q, "position"), childPath(q, "position"));
        opt(w, q, "radius", [&](const json& v, const std::string& p) { wd.radius = positive(v, p, "radius"); });
        opt(w, q, "width", [&](const json& v, const std::string& p) { wd.width = positive(v, p, "width"); });
        opt(w, q, "suspension", [&](const json& v, const std::string& p) {
            requireObject(v, p);
            checkKeys(v, p, {"rest_length", "stiffness", "damping"}, "a suspension");
            opt(v, p, "rest_length", [&](const json& x, const std::string& r) { wd.suspension.restLength = positive(x, r, "rest_length"); });
            opt(v, p, "stiffness", [&](const json& x, const std::string& r) { wd.suspension.stiffness = positive(x, r, "stiffness"); });
            opt(v, p, "damping", [&](const json& x, const std::string& r) { wd.suspension.damping = nonNegative(x, r, "damping"); });
        });
        opt(w, q, "steering", [&](const json& v, const std::string& p) { wd.steering = boolean(v, p); });
        opt(w, q, "driven", [&](const json& v, const std::string& p) { wd.driven = boolean(v, p); });
        wd.handBrake = !wd.steering;  // the scene default: the unsteered wheels
        opt(w, q, "hand_brake", [&](const json& v, const std::string& p) { wd.handBrake = boolean(v, p); });
        opt(w, q, "friction", [&](const json& v, const std::string& p) { wd.friction = positive(v, p, "friction"); });
        opt(w, q, "inertia", [&](const json& v, const std::string& p) { wd.inertia = positive(v, p, "inertia"); });
        d.wheels.push_back(wd);
    }
    opt(j, path, "engine", [&](const json& v, const std::string& p) {
        requireObject(v, p);
        checkKeys(v, p, {"max_torque", "max_rpm", "min_rpm", "torque_curve"}, "an engine");
        opt(v, p, "max_torque", [&](const json& x, const std::string& r) { d.engine.maxTorque = nonNegative(x, r, "max_torque"); });
        opt(v, p, "max_rpm", [&](const json& x, const std::string& r) { d.engine.maxRpm = positive(x, r, "max_rpm"); });
        opt(v, p, "min_rpm", [&](const json& x, const std::string& r) { d.engine.minRpm = positive(x, r, "min_rpm"); });
        opt(v, p, "torque_curve", [&](const json& x, const std::string& r) {
            requireArray(x, r);
            d.engine.torqueCurve.clear();
            for (std::size_t i = 0; i < x.size(); ++i) {
                const std::string q = childPath(r, i);
                if (!x[i].is_array() || x[i].size() != 2) fail(q, "expected [rpm / max_rpm, torque / max_torque], got " + describe(x[i]));
                d.engine.torqueCurve.push_back({nonNegative(x[i][0], childPath(q, 0), "rpm fraction"),
                                                nonNegative(x[i][1], childPath(q, 1), "torque fraction")});
            }
        });
    });
    opt(j, path, "gearbox", [&](const json& v, const std::string& p) {
        requireObject(v, p);
        checkKeys(v, p, {"ratios", "differential_ratio", "shift_up_rpm", "shift_down_rpm"}, "a gearbox");
        opt(v, p, "ratios", [&](const json& x, const std::string& r) {
            requireArray(x, r);
            d.gearbox.ratios.clear();
            for (std::size_t i = 0; i < x.size(); ++i) d.gearbox.ratios.push_back(positive(x[i], childPath(r, i), "ratio"));
        });
        opt(v, p, "differential_ratio", [&](const json& x, const std::string& r) { d.gearbox.differentialRatio = positive(x, r, "differential_ratio"); });
        opt(v, p, "shift_up_rpm", [&](const json& x, const std::string& r) { d.gearbox.shiftUpRpm = positive(x, r, "shift_up_rpm"); });
        opt(v, p, "shift_down_rpm", [&](const json& x, const std::string& r) { d.gearbox.shiftDownRpm = nonNegative(x, r, "shift_down_rpm"); });
    });
    opt(j, path, "max_brake_torque", [&](const json& v, const std::string& p) { d.maxBrakeTorque = nonNegative(v, p, "max_brake_torque"); });
    opt(j, path, "max_hand_brake_torque", [&](const json& v, const std::string& p) {
        d.maxHandBrakeTorque = nonNegative(v, p, "max_hand_brake_torque");
    });
    opt(j, path, "max_steering_angle", [&](const json& v, const std::string& p) {
        d.maxSteeringAngle = nonNegative(v, p, "max_steering_angle");
    });
    opt(j, path, "anti_roll_bars", [&](const json& v, const std::string& p) {
        requireArray(v, p);
        for (std::size_t i = 0; i < v.size(); ++i) {
            const std::string q = childPath(p, i);
            requireObject(v[i], q);
            checkKeys(v[i], q, {"left", "right", "stiffness"}, "an anti-roll bar");
            AntiRollBar bar;
            const long long last = static_cast<long long>(d.wheels.size()) - 1;
            bar.left = static_cast<std::uint32_t>(integer(required(v[i], q, "left"), childPath(q, "left"), 0, last, "left"));
            bar.right = static_cast<std::uint32_t>(integer(required(v[i], q, "right"), childPath(q, "right"), 0, last, "right"));
            opt(v[i], q, "stiffness", [&](const json& x, const std::string& r) { bar.stiffness = nonNegative(x, r, "stiffness"); });
            d.antiRollBars.push_back(bar);
        }
    });
    opt(j, path, "inputs", [&](const json& v, const std::string& p) {
        requireArray(v, p);
        for (std::size_t i = 0; i < v.size(); ++i) {
            const std::string q = childPath(p, i);
            requireObject(v[i], q);
            checkKeys(v[i], q, {"time", "throttle", "brake", "steering", "hand_brake"}, "a vehicle input");
            VehicleInput in;
            in.time = nonNegative(required(v[i], q, "time"), childPath(q, "time"), "time");
            if (!d.inputs.empty() && in.time < d.inputs.back().time) {
                fail(childPath(q, "time"), "inputs must be in time order, got " + detail::formatNumber(in.time) + " after " +
                                               detail::formatNumber(d.inputs.back().time));
            }
            const auto unit = [&](const char* key, Real lo, Real& out) {
                opt(v[i], q, key, [&](const json& x, const std::string& r) {
                    out = number(x, r);
                    if (!(out >= lo && out <= 1)) fail(r, std::string(key) + " must be in [" + detail::formatNumber(lo) + ", 1], got " + detail::formatNumber(out));
                });
            };
            unit("throttle", -1, in.throttle);  // negative: backwards (reverse)
            unit("brake", 0, in.brake);
            unit("steering", -1, in.steering);
            opt(v[i], q, "hand_brake", [&](const json& x, const std::string& r) { in.handBrake = boolean(x, r); });
            d.inputs.push_back(in);
        }
    });
}

Scene Parser::parse() {
    // JSON text has no raw NUL (not even in strings); a file with one is binary
    // or damaged, and what follows it must not be silently dropped.
    if (const std::size_t nul = text_.find('\0'); nul != std::string_view::npos) {
        const auto loc = detail::locationOfOffset(text_, nul);
        throw SceneError(source_, "", loc.line, loc.column,
                         "a NUL byte at byte offset " + std::to_string(nul) + " (of " + std::to_string(text_.size()) +
                             "): a scene file is JSON text");
    }
    // The document without the elements of the root's arrays (bodies,
    // joints...): those are parsed one at a time by section(), so a large
    // scene never has its whole document tree in memory (a gigabyte for a
    // million bodies, and the time to allocate and free it). The parse still
    // reads, and checks, all of the text.
    bool inRootArray = false;
    const auto skipRootArrayElements = [&inRootArray](int depth, json::parse_event_t event, json&) {
        using E = json::parse_event_t;
        if (depth == 1 && (event == E::array_start || event == E::object_start)) inRootArray = event == E::array_start;
        return !(depth == 2 && inRootArray && (event == E::object_start || event == E::array_start || event == E::value));
    };
    json doc;
    try {
        doc = json::parse(text_, skipRootArrayElements);
    } catch (const json::parse_error& e) {
        const auto loc = detail::locationOfOffset(text_, e.byte > 0 ? e.byte - 1 : 0);
        throw SceneError(source_, "", loc.line, loc.column, "malformed JSON: " + detail::nlohmannReason(e.what()));
    } catch (const json::exception& e) {
        // e.g. out_of_range.406 for 1e999, which nlohmann reports without a position.
        if (const auto problem = detail::findJsonProblem(text_)) {
            throw SceneError(source_, problem->path, problem->where.line, problem->where.column, problem->reason);
        }
        throw SceneError(source_, "", 0, 0, "malformed JSON: " + detail::nlohmannReason(e.what()));
    }
    if (const auto problem = detail::findJsonProblem(text_)) {
        throw SceneError(source_, problem->path, problem->where.line, problem->where.column, problem->reason);
    }

    Scene scene;
    scene.sourceName = source_;
    const std::string root;
    if (!doc.is_object()) fail(root, "a scene file must be a JSON object, got " + typeName(doc));
    // "version": the scene format's version (docs/scene-format.md), optional; 1
    // is the only one so far. Read before the keys are checked, so a newer file
    // is refused for its version rather than for the keys it added.
    if (const auto it = doc.find("version"); it != doc.end()) {
        const long long version = integer(*it, childPath(root, "version"), 1, std::numeric_limits<int>::max(), "version");
        if (version != detail::kSceneFormatVersion) {
            fail(childPath(root, "version"), "unsupported scene format version " + std::to_string(version) +
                                                 " (this build reads version " + std::to_string(detail::kSceneFormatVersion) + ")");
        }
    }
    checkKeys(doc, root, {"version", "description", "world", "bodies", "joints", "springs", "ropes", "cloths", "characters", "vehicles",
                          "urdf"},
              "a scene");
    opt(doc, root, "description", [&](const json& v, const std::string& p) { scene.description = string(v, p); });
    opt(doc, root, "world", [&](const json& v, const std::string& p) { parseWorld(v, p, scene); });
    elements_.emplace(text_);
    section(doc, "bodies", scene.bodies, [&](const json& v, const std::string& p, SceneBody& body, std::size_t i) {
        parseBody(v, p, body);
        registerName(bodyIndex_, body.def.name, i, p, "body", "bodies");
    });
    section(doc, "springs", scene.springs, [&](const json& v, const std::string& p, SceneSpring& spring, std::size_t) {
        parseSpring(v, p, scene, spring);
    });
    NameIndex jointNames;
    section(doc, "joints", scene.joints, [&](const json& v, const std::string& p, SceneJoint& joint, std::size_t i) {
        parseJoint(v, p, scene, joint);
        registerName(jointNames, joint.def.name, i, p, "joint", "joints");
    });
    section(doc, "ropes", scene.ropes, [&](const json& v, const std::string& p, SceneRope& rope, std::size_t) {
        parseRope(v, p, scene, rope);
    });
    section(doc, "cloths", scene.cloths, [&](const json& v, const std::string& p, SceneCloth& cloth, std::size_t) {
        parseCloth(v, p, cloth);
    });
    NameIndex characterNames;
    section(doc, "characters", scene.characters, [&](const json& v, const std::string& p, SceneCharacter& c, std::size_t i) {
        parseCharacter(v, p, c);
        registerName(characterNames, c.def.name, i, p, "character", "characters");
    });
    NameIndex vehicleNames;
    section(doc, "vehicles", scene.vehicles, [&](const json& v, const std::string& p, SceneVehicle& vehicle, std::size_t i) {
        parseVehicle(v, p, scene, vehicle);
        registerName(vehicleNames, vehicle.def.name, i, p, "vehicle", "vehicles");
    });
    // Robots last: their links and joints are appended to the bodies and
    // joints (which therefore cannot refer to them).
    std::vector<UrdfEntry> robots;
    section(doc, "urdf", robots, [&](const json& v, const std::string& p, UrdfEntry& entry, std::size_t) {
        parseUrdf(v, p, entry.where, scene);
    });
    return scene;
}

void Parser::parseUrdf(const json& j, const std::string& path, const SceneLocation& where, Scene& scene) const {
    requireObject(j, path);
    checkKeys(j, path, {"file", "position", "orientation", "fixed_base", "self_collision", "search_path", "drives"}, "a urdf entry");
    const json* file = member(j, "file");
    if (file == nullptr) fail(path, "a urdf entry needs \"file\" (the URDF file, relative to the scene file)");
    const std::filesystem::path folder = std::filesystem::path(source_).parent_path();
    const std::filesystem::path urdfPath = folder / string(*file, childPath(path, "file"));
    UrdfOptions options;
    opt(j, path, "position", [&](const json& v, const std::string& p) { options.position = vec3(v, p); });
    opt(j, path, "orientation", [&](const json& v, const std::string& p) { options.orientation = normalize(quat(v, p)); });
    opt(j, path, "fixed_base", [&](const json& v, const std::string& p) { options.fixedBase = boolean(v, p); });
    opt(j, path, "self_collision", [&](const json& v, const std::string& p) { options.selfCollision = boolean(v, p); });
    opt(j, path, "search_path", [&](const json& v, const std::string& p) {
        requireArray(v, p);
        for (std::size_t i = 0; i < v.size(); ++i) options.searchPath.push_back(folder / string(v[i], childPath(p, i)));
    });
    std::vector<std::pair<std::string, JointDrive>> drives;
    opt(j, path, "drives", [&](const json& v, const std::string& p) {
        requireObject(v, p);
        for (const auto& [name, d] : v.items()) {
            const std::string q = childPath(p, name);
            requireObject(d, q);
            checkKeys(d, q, {"position", "stiffness", "damping", "velocity", "max_force"}, "a joint drive");
            JointDrive drive;
            opt(d, q, "position", [&](const json& x, const std::string& r) { drive.position = number(x, r); });
            opt(d, q, "stiffness", [&](const json& x, const std::string& r) { drive.stiffness = nonNegative(x, r, "stiffness"); });
            opt(d, q, "damping", [&](const json& x, const std::string& r) { drive.damping = nonNegative(x, r, "damping"); });
            opt(d, q, "velocity", [&](const json& x, const std::string& r) {
                drive.velocityDrive = true;
                drive.velocity = number(x, r);
            });
            opt(d, q, "max_force", [&](const json& x, const std::string& r) { drive.maxForce = positive(x, r, "max_force"); });
            drives.emplace_back(name, drive);
        }
    });
    // Each robot its own negative collision group, below every group in the scene.
    std::int32_t group = -static_cast<std::int32_t>(std::min<std::size_t>(scene.bodies.size() + 1, 1u << 30));
    for (const SceneBody& b : scene.bodies) group = std::min(group, b.def.filter.group - 1);
    options.collisionGroup = group;
    UrdfSceneParts parts;
    try {
        parts = urdfSceneParts(readUrdfText(urdfPath), urdfPath.string(), options, drives);
    } catch (const Error& e) {
        fail(childPath(path, "file"), e.what());
    }
    std::unordered_map<std::string, std::size_t> taken;
    for (std::size_t i = 0; i < scene.bodies.size(); ++i) taken.emplace(scene.bodies[i].def.name, i);
    for (SceneBody& b : parts.bodies) {
        if (const auto it = taken.find(b.def.name); it != taken.end()) {
            fail(childPath(path, "file"), "the robot's link '" + b.def.name + "' has the name of " + childPath("bodies", it->second) +
                                              " (link names become body names and must be unique in the scene)");
        }
        b.where = where;
    }
    std::unordered_map<std::string, std::size_t> jointTaken;
    for (std::size_t i = 0; i < scene.joints.size(); ++i) jointTaken.emplace(scene.joints[i].def.name, i);
    for (SceneJoint& sj : parts.joints) {
        if (const auto it = jointTaken.find(sj.def.name); it != jointTaken.end() && !sj.def.name.empty()) {
            fail(childPath(path, "file"), "the robot's joint '" + sj.def.name + "' has the name of " + childPath("joints", it->second) +
                                              " (joint names must be unique in the scene)");
        }
        sj.where = where;
    }
    for (SceneBody& b : parts.bodies) scene.bodies.push_back(std::move(b));
    for (SceneJoint& sj : parts.joints) scene.joints.push_back(std::move(sj));
}

}  // namespace

Scene parseScene(std::string_view json, std::string_view sourceName) {
    return Parser(json, sourceName).parse();
}

std::string readSceneText(const std::filesystem::path& file) {
    const std::string name = file.string();
    // A directory, device or FIFO is refused before reading: /dev/zero would never end.
    if (const auto reason = detail::notARegularFile(file)) throw SceneError(name, "", 0, 0, *reason + " (expected a scene file)");
    std::ifstream in(file, std::ios::binary);
    if (!in) throw SceneError(name, "", 0, 0, "cannot open file for reading");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw SceneError(name, "", 0, 0, "error while reading the file");
    return text.str();
}

Scene loadScene(const std::filesystem::path& file) { return parseScene(readSceneText(file), file.string()); }

}  // namespace fulcrum
