// A parsed URDF model (urdf_parse.cpp) as scene bodies and joints, into a
// world, and the Robot handle's drives and read-outs. docs/robots.md is the
// mapping table (URDF -> Fulcrum) and lists every fallback made here.
#include "fulcrum/urdf.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <locale>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>

#include "dynamics/validation.hpp"
#include "io/mesh_import.hpp"
#include "io/urdf_model.hpp"
#include "world/input_file.hpp"

namespace fulcrum {

using detail::formatReal;
using detail::UrdfGeometry;
using detail::UrdfJoint;
using detail::UrdfLink;
using detail::UrdfModel;
using detail::UrdfPose;

const char* toString(UrdfJointType type) {
    switch (type) {
        case UrdfJointType::Revolute: return "revolute";
        case UrdfJointType::Continuous: return "continuous";
        case UrdfJointType::Prismatic: return "prismatic";
        case UrdfJointType::Fixed: return "fixed";
        case UrdfJointType::Floating: return "floating";
        case UrdfJointType::Planar: return "planar";
    }
    return "?";
}

namespace {

constexpr Real kPi = std::numbers::pi_v<Real>;

// A six-DOF axis's name in drive names ("joint/x" ... "joint/rz"), by SixDofAxisIndex.
constexpr std::array<const char*, kSixDofAxes> kAxisNames{"x", "y", "z", "rx", "ry", "rz"};

int axisIndex(std::string_view name) {
    for (int k = 0; k < kSixDofAxes; ++k) {
        if (name == kAxisNames[static_cast<std::size_t>(k)]) return k;
    }
    return -1;
}

// The axes a URDF six-DOF joint leaves free (urdfSceneParts): all of a
// floating joint's; a planar joint's x, y (in the plane) and rz (about the normal).
bool urdfAxisFree(UrdfJointType type, int axis) {
    return type == UrdfJointType::Floating || axis == kAxisX || axis == kAxisY || axis == kAxisRotZ;
}

bool isSixDof(UrdfJointType type) { return type == UrdfJointType::Floating || type == UrdfJointType::Planar; }

UrdfPose compose(const UrdfPose& a, const UrdfPose& b) { return {a.p + rotate(a.q, b.p), normalize(a.q * b.q)}; }

// Where a mesh file named in the model is: `package://NAME/rest` under each
// search folder as NAME/rest (and as rest, for a folder that is the package
// itself); a relative path beside the URDF file, then under each search folder.
std::optional<std::filesystem::path> findMesh(const std::string& filename, const std::filesystem::path& urdfFolder,
                                              const std::vector<std::filesystem::path>& searchPath) {
    namespace fs = std::filesystem;
    std::error_code ec;
    const auto exists = [&](const fs::path& p) { return fs::is_regular_file(p, ec); };
    const std::string_view pkg = "package://", file = "file://";
    if (filename.rfind(pkg, 0) == 0) {
        const std::string rest = filename.substr(pkg.size());
        const std::size_t slash = rest.find('/');
        const std::string inPackage = slash == std::string::npos ? rest : rest.substr(slash + 1);
        for (const fs::path& dir : searchPath) {
            if (exists(dir / rest)) return dir / rest;
            if (exists(dir / inPackage)) return dir / inPackage;
        }
        return std::nullopt;
    }
    const fs::path p = filename.rfind(file, 0) == 0 ? fs::path(filename.substr(file.size())) : fs::path(filename);
    if (p.is_absolute()) return exists(p) ? std::optional(p) : std::nullopt;
    if (exists(urdfFolder / p)) return urdfFolder / p;
    for (const fs::path& dir : searchPath) {
        if (exists(dir / p)) return dir / p;
    }
    return std::nullopt;
}

// The vertices and triangles of an STL (binary or ASCII), OBJ or COLLADA
// file, scaled; nullopt with `why` set for another format or a file it cannot
// read. STL and OBJ are read here (small, exact readers of what robot files
// use); COLLADA, a scene format with units, up axes and node transforms, by
// assimp (mesh_import.cpp).
struct MeshData {
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::optional<std::array<float, 4>> color;  // COLLADA: its first material's diffuse colour
};

std::optional<MeshData> readMesh(const std::filesystem::path& file, const Vec3& scale, std::string& why) {
    std::string ext = file.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".dae") {
        auto imported = detail::importColladaMesh(file, why);
        if (!imported) return std::nullopt;
        if (imported->vertices.size() < 4) {
            why = "it has fewer than 4 vertices";
            return std::nullopt;
        }
        MeshData m{std::move(imported->vertices), std::move(imported->triangles), imported->color};
        for (Vec3& v : m.vertices) v = {v.x * scale.x, v.y * scale.y, v.z * scale.z};
        return m;
    }
    if (ext != ".stl" && ext != ".obj") {
        why = "only STL, OBJ and COLLADA (.dae) meshes are read";
        return std::nullopt;
    }
    std::ifstream in(file, std::ios::binary);
    std::ostringstream buffer;
    buffer << in.rdbuf();
    const std::string text = buffer.str();
    if (!in && !in.eof()) {
        why = "it cannot be read";
        return std::nullopt;
    }
    MeshData m;
    const auto add = [&](double x, double y, double z) {
        m.vertices.push_back({static_cast<Real>(x) * scale.x, static_cast<Real>(y) * scale.y, static_cast<Real>(z) * scale.z});
    };
    const auto finite = [](double v) { return std::isfinite(v) && std::fabs(v) < 1e30; };
    if (ext == ".stl" && text.size() >= 84 && text.rfind("solid", 0) != 0) {
        // Binary: an 80-byte header, a triangle count, 50 bytes per triangle
        // (normal, three vertices as little-endian float32, two attribute bytes).
        std::uint32_t count = 0;
        std::memcpy(&count, text.data() + 80, 4);
        if (text.size() < 84 + std::size_t{count} * 50) {
            why = "the binary STL is shorter than its triangle count says";
            return std::nullopt;
        }
        for (std::uint32_t t = 0; t < count; ++t) {
            const char* p = text.data() + 84 + std::size_t{t} * 50 + 12;
            for (int k = 0; k < 3; ++k) {
                float xyz[3];
                std::memcpy(xyz, p + 12 * k, 12);
                if (!finite(xyz[0]) || !finite(xyz[1]) || !finite(xyz[2])) {
                    why = "it holds a non-finite vertex";
                    return std::nullopt;
                }
                add(xyz[0], xyz[1], xyz[2]);
            }
            m.triangles.push_back({3 * t, 3 * t + 1, 3 * t + 2});
        }
    } else {
        std::istringstream lines(text);
        lines.imbue(std::locale::classic());
        std::string line;
        std::vector<std::uint32_t> stlCorners;
        while (std::getline(lines, line)) {
            std::istringstream words(line);
            words.imbue(std::locale::classic());
            std::string key;
            words >> key;
            if (key == "v" || key == "vertex") {
                double x = 0, y = 0, z = 0;
                if (!(words >> x >> y >> z) || !finite(x) || !finite(y) || !finite(z)) {
                    why = "a vertex line is not three finite numbers: '" + line + "'";
                    return std::nullopt;
                }
                add(x, y, z);
                if (key == "vertex") {
                    stlCorners.push_back(static_cast<std::uint32_t>(m.vertices.size() - 1));
                    if (stlCorners.size() == 3) {
                        m.triangles.push_back({stlCorners[0], stlCorners[1], stlCorners[2]});
                        stlCorners.clear();
                    }
                }
            } else if (key == "f") {
                // "f a b c ...", each "i", "i/t", "i//n" or "i/t/n"; negative: from the end. A fan.
                std::vector<std::uint32_t> face;
                std::string corner;
                while (words >> corner) {
                    long long i = 0;
                    const auto [end, ec] = std::from_chars(corner.data(), corner.data() + corner.size(), i);
                    (void)end;
                    const long long n = static_cast<long long>(m.vertices.size());
                    if (ec != std::errc() || i == 0 || i > n || i < -n) {
                        why = "a face names a vertex that does not exist: '" + line + "'";
                        return std::nullopt;
                    }
                    face.push_back(static_cast<std::uint32_t>(i > 0 ? i - 1 : n + i));
                }
                for (std::size_t k = 2; k < face.size(); ++k) m.triangles.push_back({face[0], face[k - 1], face[k]});
            }
        }
    }
    if (m.vertices.size() < 4) {
        why = "it has fewer than 4 vertices";
        return std::nullopt;
    }
    return m;
}

// A primitive URDF geometry as a shape in the link frame. URDF cylinders and
// capsules lie along z, Fulcrum's along y.
ShapeDesc::Child primitive(const detail::UrdfGeometryElement& g) {
    ShapeDesc::Child c;
    c.position = g.origin.p;
    c.orientation = g.origin.q;
    const Quat yToZ = Quat::fromAxisAngle({1, 0, 0}, kPi / 2);
    switch (g.geometry.kind) {
        case UrdfGeometry::Kind::Box:
            c.shape.type = ShapeType::Box;
            c.shape.halfExtents = g.geometry.size * Real(0.5);
            break;
        case UrdfGeometry::Kind::Sphere:
            c.shape.type = ShapeType::Sphere;
            c.shape.radius = g.geometry.radius;
            break;
        case UrdfGeometry::Kind::Cylinder:
        case UrdfGeometry::Kind::Capsule:
            c.shape.type = g.geometry.kind == UrdfGeometry::Kind::Cylinder ? ShapeType::Cylinder : ShapeType::Capsule;
            c.shape.radius = g.geometry.radius;
            c.shape.halfHeight = g.geometry.length * Real(0.5);
            c.orientation = normalize(g.origin.q * yToZ);
            break;
        case UrdfGeometry::Kind::Mesh: break;  // not a primitive (the caller handles meshes)
    }
    return c;
}

// The box with a link's mass and inertia (the missing-mesh fallback): for a
// solid box, I_xx = m (b^2 + c^2) / 3 with half extents a, b, c, so
// a^2 = 3 (I_yy + I_zz - I_xx) / (2 m). The diagonal of the inertial frame's
// tensor; each half extent at least 5 mm.
ShapeDesc::Child inertiaBox(const UrdfLink& l) {
    ShapeDesc::Child c;
    c.position = l.inertialOrigin.p;
    c.orientation = l.inertialOrigin.q;
    c.shape.type = ShapeType::Box;
    const Real ixx = l.inertia(0, 0), iyy = l.inertia(1, 1), izz = l.inertia(2, 2);
    const auto half = [&](Real a, Real b, Real own) {
        return std::max(Real(0.005), std::sqrt(std::max(Real(0), Real(3) * (a + b - own) / (2 * l.mass))));
    };
    c.shape.halfExtents = {half(iyy, izz, ixx), half(ixx, izz, iyy), half(ixx, iyy, izz)};
    return c;
}

std::string lineOf(const UrdfModel& m, int line) { return m.source + ": line " + std::to_string(line); }

// A drive given to the importer (position spring and/or velocity motor) on a
// joint axis whose URDF <dynamics damping> is `damping`: the spring carries
// both dampings; a drive without its own force limit takes `defaultMaxForce`
// (the joint's effort limit: infinite for none) for its position drive, and
// for its velocity drive that or a large finite one.
void applyDrive(const JointDrive& drive, Real damping, Real defaultMaxForce, JointSpring& spring, JointMotor& motor) {
    spring.target = drive.position;
    spring.stiffness = drive.stiffness;
    spring.damping = damping + drive.damping;
    spring.enabled = spring.stiffness > 0 || spring.damping > 0;
    spring.maxForce = std::isfinite(drive.maxForce) ? drive.maxForce : defaultMaxForce;
    if (drive.velocityDrive) {
        motor.enabled = true;
        motor.speed = drive.velocity;
        motor.maxForce = std::isfinite(drive.maxForce) ? drive.maxForce : defaultMaxForce;
        if (!std::isfinite(motor.maxForce)) motor.maxForce = Real(1e9);
    }
}

}  // namespace

std::string readUrdfText(const std::filesystem::path& file) {
    const std::string name = file.string();
    if (const auto reason = detail::notARegularFile(file)) throw Error(name + ": " + *reason + " (expected a URDF file)");
    std::ifstream in(file, std::ios::binary);
    if (!in) throw Error(name + ": cannot open the URDF file for reading");
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw Error(name + ": error while reading the URDF file");
    return text.str();
}

UrdfSceneParts urdfSceneParts(std::string_view xml, const std::string& sourceName, const UrdfOptions& options,
                              const std::vector<std::pair<std::string, JointDrive>>& drives) {
    const UrdfModel m = detail::parseUrdf(xml, sourceName);
    detail::requireFinite("urdf options", "position", options.position);
    if (!(std::fabs(length(options.orientation) - 1) < Real(1e-3))) {
        throw Error(sourceName + ": the robot's orientation must be a unit quaternion");
    }
    if (!(options.defaultMass > 0) || !(options.defaultRadius > 0)) {
        throw Error(sourceName + ": defaultMass and defaultRadius must be positive");
    }
    UrdfSceneParts out;
    Robot& robot = out.robot;
    robot.name = m.name;
    const auto warn = [&](const std::string& what) {
        robot.warnings.push_back(what);
        if (options.warn) {
            options.warn(what);
        } else {
            std::cerr << "fulcrum: warning: " << what << "\n";
        }
    };
    const std::filesystem::path folder = std::filesystem::path(sourceName).parent_path();

    // World poses of the link frames with every joint at 0.
    std::vector<UrdfPose> pose(m.links.size());
    std::map<std::string, std::size_t, std::less<>> linkIndex;
    for (std::size_t i = 0; i < m.links.size(); ++i) linkIndex.emplace(m.links[i].name, i);
    for (const std::size_t i : m.order) {
        if (i == m.root) {
            pose[i] = {options.position, normalize(options.orientation)};
        } else {
            const UrdfJoint& j = m.joints[m.parentJoint[i]];
            pose[i] = compose(pose[linkIndex.find(j.parent)->second], j.origin);
        }
    }

    // Visuals (docs/robots.md): each mesh file read once, unscaled, and shared
    // by every visual showing it; a file that cannot be used is left out with
    // a warning (the link is then drawn as its other visuals, or its colliders).
    std::map<std::string, std::shared_ptr<const VisualMesh>> visualMeshes;
    std::map<std::string, std::array<float, 4>> meshColors;
    const auto makeVisual = [&](const detail::UrdfGeometryElement& v, const std::string& link) -> std::optional<BodyVisual> {
        BodyVisual visual;
        visual.local = {v.origin.p, v.origin.q};
        visual.hasColor = v.hasColor;
        visual.color = v.rgba;
        const Quat yToZ = Quat::fromAxisAngle({1, 0, 0}, kPi / 2);
        switch (v.geometry.kind) {
            case UrdfGeometry::Kind::Box:
                visual.geometry = BodyVisual::Geometry::Box;
                visual.halfExtents = v.geometry.size * Real(0.5);
                break;
            case UrdfGeometry::Kind::Sphere:
                visual.geometry = BodyVisual::Geometry::Sphere;
                visual.radius = v.geometry.radius;
                break;
            case UrdfGeometry::Kind::Cylinder:
            case UrdfGeometry::Kind::Capsule:
                visual.geometry = v.geometry.kind == UrdfGeometry::Kind::Cylinder ? BodyVisual::Geometry::Cylinder
                                                                                 : BodyVisual::Geometry::Capsule;
                visual.radius = v.geometry.radius;
                visual.halfHeight = v.geometry.length * Real(0.5);
                visual.local.q = normalize(v.origin.q * yToZ);  // URDF's along z, Fulcrum's along y
                break;
            case UrdfGeometry::Kind::Mesh: {
                visual.geometry = BodyVisual::Geometry::Mesh;
                visual.scale = v.geometry.scale;
                const std::string what = lineOf(m, v.line) + ": link '" + link + "', visual: mesh '" + v.geometry.filename + "' ";
                const auto found = findMesh(v.geometry.filename, folder, options.searchPath);
                if (!found) {
                    warn(what + "not found; this visual is left out");
                    return std::nullopt;
                }
                const std::string key = found->lexically_normal().string();
                auto it = visualMeshes.find(key);
                if (it == visualMeshes.end()) {
                    std::string why;
                    auto data = readMesh(*found, {1, 1, 1}, why);
                    if (!data) {
                        warn(what + "found at " + found->string() + " but not used (" + why + "); this visual is left out");
                        return std::nullopt;
                    }
                    for (const auto& t : data->triangles) {
                        if (t[0] >= data->vertices.size() || t[1] >= data->vertices.size() || t[2] >= data->vertices.size()) {
                            warn(what + "found at " + found->string() + " but not used (a triangle names a missing vertex)" +
                                 "; this visual is left out");
                            return std::nullopt;
                        }
                    }
                    auto mesh = std::make_shared<VisualMesh>();
                    mesh->name = found->string();
                    mesh->vertices = std::move(data->vertices);
                    mesh->triangles = std::move(data->triangles);
                    if (data->color) meshColors[key] = *data->color;
                    it = visualMeshes.emplace(key, std::move(mesh)).first;
                }
                visual.mesh = it->second;
                // A COLLADA file's own colour where the URDF gives none.
                if (const auto c = meshColors.find(key); !visual.hasColor && c != meshColors.end()) {
                    visual.hasColor = true;
                    visual.color = c->second;
                }
                break;
            }
        }
        if (!v.hasColor && !v.material.empty() && !visual.hasColor) {
            warn(lineOf(m, v.line) + ": link '" + link + "', visual: material '" + v.material +
                 "' has no colour defined in the file; the link's display colour is used");
        }
        return visual;
    };

    CollisionFilter filter;
    if (!options.selfCollision) filter.group = options.collisionGroup != 0 ? options.collisionGroup : -1;

    // Static links: the root of a fixed base (or a root named "world" without
    // an inertial), and every link welded to a static link by fixed joints: a
    // soft weld to the ground would let the whole robot sag and tilt under its
    // weight (the KR5's base on its "world" link: 2 mm, its tool 3 cm).
    std::vector<bool> staticLink(m.links.size(), false);
    for (const std::size_t i : m.order) {
        if (i == m.root) {
            const UrdfLink& l = m.links[i];
            staticLink[i] = options.fixedBase || (l.name == "world" && !l.hasInertial);
        } else {
            const UrdfJoint& j = m.joints[m.parentJoint[i]];
            staticLink[i] = j.type == UrdfJointType::Fixed && staticLink[linkIndex.find(j.parent)->second];
        }
    }

    for (std::size_t i = 0; i < m.links.size(); ++i) {
        const UrdfLink& l = m.links[i];
        const bool isStatic = staticLink[i];
        SceneBody body;
        BodyDef& d = body.def;
        d.name = l.name;
        d.type = isStatic ? BodyType::Static : BodyType::Dynamic;
        d.position = pose[i].p;
        d.orientation = pose[i].q;
        d.filter = filter;
        // A robot held by its drives often stands still: it must not fall asleep
        // with a drive target about to change (a new target wakes it anyway).
        d.allowSleep = false;

        std::vector<ShapeDesc::Child> parts;
        bool boxFallbackUsed = false;
        for (const auto& c : l.collisions) {
            if (c.geometry.kind != UrdfGeometry::Kind::Mesh) {
                parts.push_back(primitive(c));
                continue;
            }
            const auto found = findMesh(c.geometry.filename, folder, options.searchPath);
            std::string what = lineOf(m, c.line) + ": link '" + l.name + "', collision: mesh '" + c.geometry.filename + "' ";
            if (found) {
                std::string why;
                if (const auto mesh = readMesh(*found, c.geometry.scale, why)) {
                    // Dynamic links collide as the mesh's convex hull, static ones as the triangles.
                    ShapeDesc::Child part;
                    part.position = c.origin.p;
                    part.orientation = c.origin.q;
                    if (isStatic) {
                        part.shape.type = ShapeType::Mesh;
                        part.shape.vertices = mesh->vertices;
                        part.shape.triangles = mesh->triangles;
                    } else {
                        part.shape.type = ShapeType::ConvexHull;
                        part.shape.points = mesh->vertices;
                    }
                    try {
                        (void)buildShape(part.shape);  // a flat or degenerate mesh fails here, not in the world
                        parts.push_back(std::move(part));
                        continue;
                    } catch (const Error& e) {
                        why = e.what();
                    }
                }
                what += "found at " + found->string() + " but not used (" + why + ")";
            } else {
                what += "not found";
            }
            if (l.hasInertial && !boxFallbackUsed && !isStatic) {
                parts.push_back(inertiaBox(l));
                boxFallbackUsed = true;
                warn(what + "; the link collides as the box of its inertia instead");
            } else {
                warn(what + "; this collision element is left out");
            }
        }
        for (const auto& v : l.visuals) {
            if (auto visual = makeVisual(v, l.name)) body.visuals.push_back(std::move(*visual));
        }
        RobotLink rl;
        rl.name = l.name;
        rl.visuals = body.visuals;
        rl.collides = !parts.empty();
        if (parts.empty()) {
            // No collider: a small sphere that collides with nothing carries the mass.
            body.shape.type = ShapeType::Sphere;
            body.shape.radius = options.defaultRadius;
            d.filter = CollisionFilter{0, 0, 0};
        } else if (parts.size() == 1 && parts[0].position == Vec3{} && parts[0].orientation == Quat{}) {
            body.shape = parts[0].shape;
        } else {
            body.shape.type = ShapeType::Compound;
            body.shape.children = std::move(parts);
        }
        if (!isStatic) {
            if (l.hasInertial) {
                d.mass = l.mass;
                const Mat3 R = toMat3(l.inertialOrigin.q);
                const Mat3 I = R * l.inertia * transpose(R);
                d.inertia = (I + transpose(I)) * Real(0.5);  // symmetric to the last bit (scene files check it)
                d.centerOfMass = l.inertialOrigin.p;
            } else {
                d.mass = options.defaultMass;
                d.inertia = Mat3::diagonal(Real(0.4) * options.defaultMass * options.defaultRadius * options.defaultRadius);
                d.centerOfMass = Vec3{};
                warn(lineOf(m, l.line) + ": link '" + l.name + "' has no <inertial>: given " + formatReal(options.defaultMass) +
                     " kg as a solid sphere of radius " + formatReal(options.defaultRadius) + " m at its origin");
            }
            rl.mass = d.mass;
        }
        robot.links.push_back(rl);
        out.bodies.push_back(std::move(body));
    }

    std::map<std::string, JointDrive, std::less<>> driveOf;
    std::map<std::pair<std::string, int>, JointDrive> axisDriveOf;  // six-DOF axes: "joint/x" ... "joint/rz"
    for (const auto& entry : drives) {
        const std::string& name = entry.first;  // not a structured binding: clang 14 can't capture those in a lambda
        const JointDrive& drive = entry.second;
        auto it = std::find_if(m.joints.begin(), m.joints.end(), [&](const UrdfJoint& j) { return j.name == name; });
        const std::size_t slash = name.rfind('/');
        if (it == m.joints.end() && slash != std::string::npos) {
            const std::string jointName = name.substr(0, slash);
            const int axis = axisIndex(std::string_view(name).substr(slash + 1));
            it = std::find_if(m.joints.begin(), m.joints.end(), [&](const UrdfJoint& j) { return j.name == jointName; });
            if (it != m.joints.end() && isSixDof(it->type) && axis >= 0 && urdfAxisFree(it->type, axis)) {
                axisDriveOf[{jointName, axis}] = drive;
                continue;
            }
            if (it != m.joints.end()) {
                throw Error(sourceName + ": a drive names '" + name + "', which is no free axis of a floating or planar joint " +
                            "(axes x, y, z, rx, ry, rz; a planar joint's x, y, rz)");
            }
        }
        if (it == m.joints.end()) throw Error(sourceName + ": a drive names joint '" + name + "', which the robot does not have");
        if (it->type != UrdfJointType::Revolute && it->type != UrdfJointType::Continuous && it->type != UrdfJointType::Prismatic) {
            throw Error(sourceName + ": a drive names joint '" + name + "', a " + toString(it->type) +
                        " joint (only revolute, continuous and prismatic joints, and the axes of floating and planar ones " +
                        "named 'joint/x' ... 'joint/rz', have drives)");
        }
        driveOf[name] = drive;
    }

    for (const UrdfJoint& j : m.joints) {
        const std::size_t child = linkIndex.find(j.child)->second;
        RobotJoint rj;
        rj.name = j.name;
        rj.type = j.type;
        rj.parent = j.parent;
        rj.child = j.child;
        rj.axis = j.axis;
        rj.damping = j.damping;
        rj.friction = j.friction;
        if (j.hasLimit && j.effort > 0) rj.effortLimit = j.effort;
        if (j.hasLimit && j.velocity > 0) rj.velocityLimit = j.velocity;
        const std::string where = lineOf(m, j.line) + ": joint '" + j.name + "'";
        if (staticLink[child]) {
            // No joint: the child is static itself (welded to a static link).
            robot.joints.push_back(rj);
            continue;
        }
        out.jointIndex.push_back(robot.joints.size());
        SceneJoint sj;
        JointDef& d = sj.def;
        d.name = j.name;
        sj.bodyA = j.parent;
        sj.bodyB = j.child;
        d.anchor = pose[child].p;
        d.axis = normalize(rotate(pose[child].q, j.axis));
        d.collideConnected = false;  // adjacent links never collide
        switch (j.type) {
            case UrdfJointType::Fixed: d.type = JointType::Fixed; break;
            case UrdfJointType::Prismatic: d.type = JointType::Slider; break;
            case UrdfJointType::Floating:
            case UrdfJointType::Planar: d.type = JointType::SixDof; break;
            default: d.type = JointType::Hinge; break;
        }
        if (d.type == JointType::SixDof) {
            // Floating: every axis free (the joint only keeps the two links from
            // colliding and reads out the child's pose). Planar: the axis is the
            // plane's normal, the frame's z; x and y slide in the plane and the
            // child turns about z; the rest is locked.
            // A floating joint has no axis in URDF: its frame is the joint
            // origin's (the child link's axes at load), so its linear axes are
            // that frame's x, y, z, as a user driving them expects.
            Vec3 x, y;
            if (j.type == UrdfJointType::Floating) {
                x = rotate(pose[child].q, Vec3{1, 0, 0});
                y = rotate(pose[child].q, Vec3{0, 1, 0});
            } else {
                orthonormalBasis(d.axis, x, y);  // right-handed: x cross y = the normal
            }
            d.axis = x;
            d.axisY = y;
            for (SixDofAxis& a : d.axes) a.mode = j.type == UrdfJointType::Floating ? AxisMode::Free : AxisMode::Locked;
            if (j.type == UrdfJointType::Planar) {
                d.axes[kAxisX].mode = AxisMode::Free;
                d.axes[kAxisY].mode = AxisMode::Free;
                d.axes[kAxisRotZ].mode = AxisMode::Free;
            }
            for (int k = 0; k < kSixDofAxes; ++k) {
                const auto it = axisDriveOf.find({j.name, k});
                if (it == axisDriveOf.end()) continue;
                SixDofAxis& a = d.axes[static_cast<std::size_t>(k)];
                applyDrive(it->second, j.damping, std::numeric_limits<Real>::infinity(), a.spring, a.motor);
            }
        }
        const bool rangeGiven = j.hasLower || j.hasUpper;
        if (j.type == UrdfJointType::Revolute) {
            if (!rangeGiven) {
                // <limit> without lower and upper reads as the range [0, 0] in the
                // URDF defaults, a welded joint no author means (minitaur's knees): free instead.
                warn(where + ": a revolute joint without lower and upper limits is left unlimited");
            } else if (j.upper - j.lower >= 2 * kPi) {
                // A range of a full turn or more limits nothing a hinge angle in (-pi, pi] can show.
            } else {
                d.hasLimits = true;
                d.lowerLimit = std::max(j.lower, -kPi);
                d.upperLimit = std::min(j.upper, kPi);
                if (d.lowerLimit != j.lower || d.upperLimit != j.upper) {
                    warn(where + ": limits [" + formatReal(j.lower) + ", " + formatReal(j.upper) + "] clamped to [-pi, pi]");
                }
                if (d.lowerLimit > d.upperLimit) {
                    throw Error(where + ": limits [" + formatReal(j.lower) + ", " + formatReal(j.upper) +
                                "] lie outside (-pi, pi], which a hinge angle cannot reach");
                }
            }
        } else if (j.type == UrdfJointType::Prismatic && rangeGiven) {
            d.hasLimits = true;
            d.lowerLimit = j.lower;
            d.upperLimit = j.upper;
        }
        if (d.hasLimits) {
            rj.lower = d.lowerLimit;
            rj.upper = d.upperLimit;
        } else if (rangeGiven && j.type == UrdfJointType::Revolute) {
            rj.lower = j.lower;  // as written, though a full turn limits nothing
            rj.upper = j.upper;
        }
        if (rj.actuated()) {
            d.spring.enabled = j.damping > 0;
            d.spring.damping = j.damping;
            // The effort limit caps the position drive (the spring row, which
            // also carries the URDF damping), as MuJoCo's actuator force range.
            d.spring.maxForce = rj.effortLimit;
            d.frictionTorque = j.friction;  // N m on a hinge, N along a slider
            if (const auto it = driveOf.find(j.name); it != driveOf.end()) {
                applyDrive(it->second, j.damping, rj.effortLimit, d.spring, d.motor);
            }
        }
        robot.joints.push_back(rj);
        out.joints.push_back(std::move(sj));
    }
    return out;
}

namespace {

std::int32_t freshGroup(const World& world) {
    // Below every group a robot loaded before took (each robot its own).
    return -static_cast<std::int32_t>(std::min<std::size_t>(world.bodyCount() + 1, 1u << 30));
}

Robot build(World& world, std::string_view xml, const std::string& sourceName, UrdfOptions options) {
    if (options.collisionGroup == 0) options.collisionGroup = freshGroup(world);
    return createUrdfParts(world, urdfSceneParts(xml, sourceName, options), sourceName);
}

}  // namespace

Robot createUrdfParts(World& world, const UrdfSceneParts& parts, const std::string& sourceName) {
    Robot robot = parts.robot;
    std::map<std::string, BodyId, std::less<>> ids;
    std::vector<BodyId> created;
    std::vector<JointId> joints;
    try {
        for (std::size_t i = 0; i < parts.bodies.size(); ++i) {
            BodyDef def = parts.bodies[i].def;
            def.shape = buildShape(parts.bodies[i].shape);
            const BodyId id = world.createBody(def);
            created.push_back(id);
            ids[def.name] = id;
            robot.links[i].body = id;
            const bool dynamic = def.type == BodyType::Dynamic;
            robot.model_.push_back({def.position, def.orientation, def.centerOfMass.value_or(Vec3{}),
                                    dynamic ? def.inertia.value_or(world.localInertia(id)) : Mat3{},
                                    dynamic ? world.mass(id) : Real(0)});
        }
        for (std::size_t k = 0; k < parts.joints.size(); ++k) {
            RobotJoint& rj = robot.joints[parts.jointIndex[k]];
            JointDef def = parts.joints[k].def;
            def.bodyA = ids.at(rj.parent);
            def.bodyB = ids.at(rj.child);
            rj.joint = world.createJoint(def);
            joints.push_back(rj.joint);
        }
    } catch (const Error& e) {
        // Nothing half-built stays in the world.
        for (const JointId j : joints) world.destroyJoint(j);
        for (const BodyId b : created) world.destroyBody(b);
        throw Error(sourceName + ": " + e.what());
    }
    return robot;
}

Robot loadUrdf(World& world, const std::filesystem::path& file, const UrdfOptions& options) {
    return build(world, readUrdfText(file), file.string(), options);
}

Robot loadUrdfFromString(World& world, std::string_view xml, const std::string& sourceName, const UrdfOptions& options) {
    return build(world, xml, sourceName, options);
}

// ---- Robot

BodyId Robot::body(std::string_view link) const {
    for (const RobotLink& l : links) {
        if (l.name == link) return l.body;
    }
    throw Error("robot '" + name + "': no link named '" + std::string(link) + "'");
}

const RobotJoint& Robot::jointInfo(std::string_view joint) const {
    for (const RobotJoint& j : joints) {
        if (j.name == joint) return j;
    }
    throw Error("robot '" + name + "': no joint named '" + std::string(joint) + "'");
}

JointId Robot::joint(std::string_view joint) const {
    const RobotJoint& j = jointInfo(joint);
    if (j.joint.isNull()) {
        throw Error("robot '" + name + "': joint '" + j.name + "' is " +
                    "fixed to a static link (both static)" +
                    ": no Fulcrum joint stands for it");
    }
    return j.joint;
}

std::vector<std::size_t> Robot::actuatedJoints() const {
    std::vector<std::size_t> out;
    for (std::size_t i = 0; i < joints.size(); ++i) {
        if (joints[i].actuated()) out.push_back(i);
    }
    return out;
}

std::vector<std::string> Robot::actuatedJointNames() const {
    std::vector<std::string> out;
    for (const std::size_t i : actuatedJoints()) out.push_back(joints[i].name);
    return out;
}

namespace {

JointSpring springOf(const World& world, JointId id, int axis) {
    return axis < 0 ? world.jointDef(id).spring : world.jointDef(id).axes[static_cast<std::size_t>(axis)].spring;
}

void setSpring(World& world, JointId id, int axis, const JointSpring& spring) {
    if (axis < 0) return world.setJointSpring(id, spring);
    SixDofAxis a = world.jointDef(id).axes[static_cast<std::size_t>(axis)];
    a.spring = spring;
    world.setSixDofAxis(id, axis, a);
}

void setMotor(World& world, JointId id, int axis, const JointMotor& motor) {
    if (axis < 0) return world.setJointMotor(id, motor);
    SixDofAxis a = world.jointDef(id).axes[static_cast<std::size_t>(axis)];
    a.motor = motor;
    world.setSixDofAxis(id, axis, a);
}

// A velocity drive's force limit: the URDF effort limit, else (practically) none.
Real motorLimit(const RobotJoint& j) { return std::isfinite(j.effortLimit) ? j.effortLimit : Real(1e9); }

void requireCount(const Robot& r, std::size_t given, std::size_t wanted, const char* what) {
    if (given != wanted) {
        throw Error("robot '" + r.name + "': " + std::to_string(given) + " " + what + " for " + std::to_string(wanted) +
                    " actuated joints (give one per revolute, continuous or prismatic joint, in file order)");
    }
}

void requireDofCount(const Robot& r, std::size_t given, std::size_t wanted, const char* what) {
    if (given != wanted) {
        throw Error("robot '" + r.name + "': " + std::to_string(given) + " " + what + " for " + std::to_string(wanted) +
                    " degrees of freedom (give one per entry of dofNames: actuated joints and free six-DOF axes, in file order)");
    }
}

// The bulk setters' targets: the joint* calls address the actuated joints
// (each its hinge or slider row, axis -1), the dof* calls every dof.
std::vector<RobotDof> actuatedDofs(const Robot& r) {
    std::vector<RobotDof> out;
    for (const std::size_t i : r.actuatedJoints()) out.push_back({i, -1});
    return out;
}

// Each target's drive spring, read, changed by change(spring, joint, k) and set.
template <class Change>
void changeSprings(World& world, const Robot& r, const std::vector<RobotDof>& targets, Change change) {
    for (std::size_t k = 0; k < targets.size(); ++k) {
        const RobotJoint& j = r.joints[targets[k].joint];
        JointSpring s = springOf(world, j.joint, targets[k].axis);
        change(s, j, k);
        setSpring(world, j.joint, targets[k].axis, s);
    }
}

void applyPositionTargets(World& world, const Robot& r, const std::vector<RobotDof>& targets,
                          std::span<const Real> positions) {
    changeSprings(world, r, targets, [&](JointSpring& s, const RobotJoint&, std::size_t k) {
        s.target = positions[k];
        s.enabled = s.stiffness > 0 || s.damping > 0;
    });
}

void applyDriveGains(World& world, const Robot& r, const std::vector<RobotDof>& targets,
                     std::span<const Real> stiffness, std::span<const Real> damping) {
    changeSprings(world, r, targets, [&](JointSpring& s, const RobotJoint& j, std::size_t k) {
        s.stiffness = stiffness[k];
        s.damping = j.damping + damping[k];  // the URDF joint's own damping rides on the spring row
        s.enabled = s.stiffness > 0 || s.damping > 0;
    });
}

void applyDriveMaxForces(World& world, const Robot& r, const std::vector<RobotDof>& targets,
                         std::span<const Real> maxForces) {
    changeSprings(world, r, targets, [&](JointSpring& s, const RobotJoint&, std::size_t k) { s.maxForce = maxForces[k]; });
}

void applyVelocityTargets(World& world, const Robot& r, const std::vector<RobotDof>& targets,
                          std::span<const Real> velocities) {
    for (std::size_t k = 0; k < targets.size(); ++k) {
        const RobotJoint& j = r.joints[targets[k].joint];
        JointMotor m;
        m.enabled = true;
        m.speed = velocities[k];
        m.maxForce = motorLimit(j);
        setMotor(world, j.joint, targets[k].axis, m);
    }
}

}  // namespace

void Robot::setDrive(World& world, std::string_view jointName, const JointDrive& drive) const {
    const RobotJoint* found = nullptr;
    int axis = -1;
    for (const RobotJoint& j : joints) {
        if (j.name == jointName) found = &j;
    }
    const std::size_t slash = jointName.rfind('/');
    if (found == nullptr && slash != std::string_view::npos) {
        // "joint/x" ... "joint/rz": one axis of a six-DOF joint.
        const RobotJoint& j = jointInfo(jointName.substr(0, slash));
        axis = axisIndex(jointName.substr(slash + 1));
        if (!isSixDof(j.type) || axis < 0 || !urdfAxisFree(j.type, axis) || j.joint.isNull()) {
            throw Error("robot '" + name + "': '" + std::string(jointName) + "' names no free axis of a floating or planar joint " +
                        "(axes x, y, z, rx, ry, rz; a planar joint's x, y, rz)");
        }
        found = &j;
    }
    const RobotJoint& j = found != nullptr ? *found : jointInfo(jointName);
    if (!j.actuated() && axis < 0) {
        throw Error("robot '" + name + "': joint '" + j.name + "' is " + toString(j.type) +
                    ": only revolute, continuous and prismatic joints, and the axes of floating and planar ones "
                    "(named 'joint/x' ... 'joint/rz'), have drives");
    }
    JointSpring spring;
    spring.target = drive.position;
    spring.stiffness = drive.stiffness;
    spring.damping = j.damping + drive.damping;
    spring.enabled = spring.stiffness > 0 || spring.damping > 0;
    spring.maxForce = std::isfinite(drive.maxForce) ? drive.maxForce : j.effortLimit;
    setSpring(world, j.joint, axis, spring);
    JointMotor motor;
    if (drive.velocityDrive) {
        motor.enabled = true;
        motor.speed = drive.velocity;
        motor.maxForce = std::isfinite(drive.maxForce) ? drive.maxForce : motorLimit(j);
    }
    setMotor(world, j.joint, axis, motor);
}

void Robot::setPositionTargets(World& world, std::span<const Real> positions) const {
    const auto targets = actuatedDofs(*this);
    requireCount(*this, positions.size(), targets.size(), "position targets");
    applyPositionTargets(world, *this, targets, positions);
}

void Robot::setDriveGains(World& world, std::span<const Real> stiffness, std::span<const Real> damping) const {
    const auto targets = actuatedDofs(*this);
    requireCount(*this, stiffness.size(), targets.size(), "stiffnesses");
    requireCount(*this, damping.size(), targets.size(), "dampings");
    applyDriveGains(world, *this, targets, stiffness, damping);
}

void Robot::setDriveMaxForces(World& world, std::span<const Real> maxForces) const {
    const auto targets = actuatedDofs(*this);
    requireCount(*this, maxForces.size(), targets.size(), "force limits");
    applyDriveMaxForces(world, *this, targets, maxForces);
}

void Robot::setVelocityTargets(World& world, std::span<const Real> velocities) const {
    const auto targets = actuatedDofs(*this);
    requireCount(*this, velocities.size(), targets.size(), "velocity targets");
    applyVelocityTargets(world, *this, targets, velocities);
}

void Robot::disableDrives(World& world) const {
    for (const RobotDof& d : dofs()) {
        const RobotJoint& j = joints[d.joint];
        JointSpring s;
        s.damping = j.damping;
        s.enabled = j.damping > 0;
        s.maxForce = springOf(world, j.joint, d.axis).maxForce;  // kept for the drive's next gains
        setSpring(world, j.joint, d.axis, s);
        setMotor(world, j.joint, d.axis, JointMotor{});
    }
}

std::vector<RobotDof> Robot::dofs() const {
    std::vector<RobotDof> out;
    for (std::size_t i = 0; i < joints.size(); ++i) {
        const RobotJoint& j = joints[i];
        if (j.actuated()) {
            out.push_back({i, -1});
        } else if (isSixDof(j.type) && !j.joint.isNull()) {
            for (int k = 0; k < kSixDofAxes; ++k) {
                if (urdfAxisFree(j.type, k)) out.push_back({i, k});
            }
        }
    }
    return out;
}

std::vector<std::string> Robot::dofNames() const {
    std::vector<std::string> out;
    for (const RobotDof& d : dofs()) {
        out.push_back(d.axis < 0 ? joints[d.joint].name : joints[d.joint].name + "/" + kAxisNames[static_cast<std::size_t>(d.axis)]);
    }
    return out;
}

void Robot::setDofPositionTargets(World& world, std::span<const Real> positions) const {
    const auto targets = dofs();
    requireDofCount(*this, positions.size(), targets.size(), "position targets");
    applyPositionTargets(world, *this, targets, positions);
}

void Robot::setDofDriveGains(World& world, std::span<const Real> stiffness, std::span<const Real> damping) const {
    const auto targets = dofs();
    requireDofCount(*this, stiffness.size(), targets.size(), "stiffnesses");
    requireDofCount(*this, damping.size(), targets.size(), "dampings");
    applyDriveGains(world, *this, targets, stiffness, damping);
}

void Robot::setDofDriveMaxForces(World& world, std::span<const Real> maxForces) const {
    const auto targets = dofs();
    requireDofCount(*this, maxForces.size(), targets.size(), "force limits");
    applyDriveMaxForces(world, *this, targets, maxForces);
}

void Robot::setDofVelocityTargets(World& world, std::span<const Real> velocities) const {
    const auto targets = dofs();
    requireDofCount(*this, velocities.size(), targets.size(), "velocity targets");
    applyVelocityTargets(world, *this, targets, velocities);
}

namespace {

// One reading per dof: `single` for an actuated joint, `axes` picks from a
// six-DOF joint's reading (read once per joint).
template <class Single, class Axes>
std::vector<Real> readDofs(const Robot& r, const World& world, Single single, Axes axes) {
    std::vector<Real> out;
    std::size_t readJoint = r.joints.size();
    SixDofReading reading;
    for (const RobotDof& d : r.dofs()) {
        const JointId id = r.joints[d.joint].joint;
        if (d.axis < 0) {
            out.push_back(single(id));
            continue;
        }
        if (readJoint != d.joint) {
            reading = world.sixDofReading(id);
            readJoint = d.joint;
        }
        out.push_back(axes(reading)[static_cast<std::size_t>(d.axis)]);
    }
    return out;
}

}  // namespace

std::vector<Real> Robot::dofPositions(const World& world) const {
    return readDofs(*this, world, [&](JointId id) { return world.jointPosition(id); },
                    [](const SixDofReading& s) { return s.position; });
}

std::vector<Real> Robot::dofVelocities(const World& world) const {
    return readDofs(*this, world, [&](JointId id) { return world.jointVelocity(id); },
                    [](const SixDofReading& s) { return s.velocity; });
}

std::vector<Real> Robot::dofEfforts(const World& world) const {
    return readDofs(*this, world, [&](JointId id) { return world.jointEffort(id); },
                    [](const SixDofReading& s) { return s.effort; });
}

std::vector<Real> Robot::jointPositions(const World& world) const {
    std::vector<Real> out;
    for (const std::size_t i : actuatedJoints()) out.push_back(world.jointPosition(joints[i].joint));
    return out;
}

std::vector<Real> Robot::jointVelocities(const World& world) const {
    std::vector<Real> out;
    for (const std::size_t i : actuatedJoints()) out.push_back(world.jointVelocity(joints[i].joint));
    return out;
}

std::vector<Vec3> Robot::contactForces(const World& world) const {
    std::vector<BodyId> bodies;
    std::vector<std::size_t> at;
    for (std::size_t i = 0; i < links.size(); ++i) {
        if (links[i].body.isNull()) continue;
        bodies.push_back(links[i].body);
        at.push_back(i);
    }
    const std::vector<Vec3> forces = world.contactForces(bodies);
    std::vector<Vec3> out(links.size());
    for (std::size_t k = 0; k < at.size(); ++k) out[at[k]] = forces[k];
    return out;
}

std::vector<Real> Robot::jointEfforts(const World& world) const {
    std::vector<Real> out;
    for (const std::size_t i : actuatedJoints()) out.push_back(world.jointEffort(joints[i].joint));
    return out;
}

namespace {

// One body's reading; `elapsed` the time since `lastVelocity` was read (0:
// none yet, the acceleration reads zero). Keeps the velocity for the next.
ImuReading imuReading(const World& world, BodyId body, Vec3& lastVelocity, Real elapsed) {
    const Vec3 v = world.linearVelocity(body);
    const Vec3 a = elapsed > 0 ? (v - lastVelocity) / elapsed : Vec3{};
    lastVelocity = v;
    const Quat q = world.orientation(body);
    // An accelerometer reads everything but gravity.
    return {inverseRotate(q, a - world.settings().gravity), inverseRotate(q, world.angularVelocity(body))};
}

}  // namespace

ImuReading Imu::update(const World& world) {
    const Real t = world.time();
    const ImuReading r = imuReading(world, body_, lastVelocity_, sampled_ ? t - lastTime_ : Real(0));
    lastTime_ = t;
    sampled_ = true;
    return r;
}

std::vector<ImuReading> Robot::sampleImu(const World& world) {
    const Real t = world.time();
    const Real elapsed = sampled_ ? t - lastTime_ : Real(0);
    lastVelocity_.resize(links.size());
    std::vector<ImuReading> out;
    out.reserve(links.size());
    for (std::size_t i = 0; i < links.size(); ++i) out.push_back(imuReading(world, links[i].body, lastVelocity_[i], elapsed));
    lastTime_ = t;
    sampled_ = true;
    return out;
}

}  // namespace fulcrum
