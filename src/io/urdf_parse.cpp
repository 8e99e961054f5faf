// URDF text -> UrdfModel (urdf_model.hpp), with every check that needs only
// the file. XML through Debian's tinyxml2; numbers through std::from_chars,
// so a process locale with a decimal comma cannot change them.
#include <tinyxml2.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <string>

#include "dynamics/body_mass.hpp"
#include "dynamics/validation.hpp"
#include "io/urdf_model.hpp"

namespace fulcrum::detail {

namespace {

constexpr std::size_t kNone = static_cast<std::size_t>(-1);

class UrdfReader {
public:
    explicit UrdfReader(std::string source) : source_(std::move(source)) {}

    [[noreturn]] void fail(const tinyxml2::XMLElement* at, const std::string& what) const {
        std::string where = source_;
        if (at != nullptr) where += ": line " + std::to_string(at->GetLineNum()) + ": " + describe(at);
        throw Error(where + ": " + what);
    }

    // "<joint name='elbow'>" (the element and its name, if it has one).
    static std::string describe(const tinyxml2::XMLElement* e) {
        std::string s = "<";
        s += e->Name();
        if (const char* n = e->Attribute("name")) {
            s += " name='";
            s += n;
            s += "'";
        }
        s += ">";
        return s;
    }
    // The element and its link or joint: "<limit> of <joint name='elbow'>".
    static std::string describeIn(const tinyxml2::XMLElement* e, const tinyxml2::XMLElement* owner) {
        std::string s = "<";
        s += e->Name();
        s += "> of ";
        s += describe(owner);
        return s;
    }

    std::vector<double> numbers(const tinyxml2::XMLElement* e, const char* attr, std::size_t count,
                                const tinyxml2::XMLElement* owner) const {
        const char* text = e->Attribute(attr);
        if (text == nullptr) failAttr(e, owner, attr, "is missing");
        std::vector<double> out;
        const std::string_view s(text);
        std::size_t i = 0;
        while (i < s.size()) {
            while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\n' || s[i] == '\r')) ++i;
            if (i >= s.size()) break;
            std::size_t j = i;
            while (j < s.size() && !(s[j] == ' ' || s[j] == '\t' || s[j] == '\n' || s[j] == '\r')) ++j;
            std::string_view word = s.substr(i, j - i);
            if (!word.empty() && word.front() == '+') word.remove_prefix(1);
            double v = 0;
            const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
            if (ec != std::errc() || end != word.data() + word.size() || !std::isfinite(v)) {
                failAttr(e, owner, attr, "is not " + std::string(count == 1 ? "a finite number" : "a list of finite numbers") +
                                             ": '" + std::string(text) + "'");
            }
            if (std::fabs(v) > static_cast<double>(std::numeric_limits<Real>::max())) {
                failAttr(e, owner, attr, "holds a number beyond the engine's range: '" + std::string(text) + "'");
            }
            out.push_back(v);
            i = j;
        }
        if (out.size() != count) {
            failAttr(e, owner, attr, "needs " + std::to_string(count) + (count == 1 ? " number" : " numbers") + ", got '" +
                                         std::string(text) + "'");
        }
        return out;
    }
    [[noreturn]] void failAttr(const tinyxml2::XMLElement* e, const tinyxml2::XMLElement* owner, const char* attr,
                               const std::string& what) const {
        throw Error(source_ + ": line " + std::to_string(e->GetLineNum()) + ": " +
                    (owner != nullptr && owner != e ? describeIn(e, owner) : describe(e)) + ": attribute '" + attr + "' " + what);
    }
    double number(const tinyxml2::XMLElement* e, const char* attr, const tinyxml2::XMLElement* owner) const {
        return numbers(e, attr, 1, owner)[0];
    }
    double numberOr(const tinyxml2::XMLElement* e, const char* attr, double fallback, const tinyxml2::XMLElement* owner) const {
        return e->Attribute(attr) == nullptr ? fallback : number(e, attr, owner);
    }
    Vec3 vec(const tinyxml2::XMLElement* e, const char* attr, const tinyxml2::XMLElement* owner) const {
        const auto v = numbers(e, attr, 3, owner);
        return {static_cast<Real>(v[0]), static_cast<Real>(v[1]), static_cast<Real>(v[2])};
    }

    // <origin xyz rpy>: both optional. rpy is fixed-axis roll (x), pitch (y), yaw (z).
    UrdfPose origin(const tinyxml2::XMLElement* parent, const tinyxml2::XMLElement* owner) const {
        UrdfPose pose;
        const tinyxml2::XMLElement* o = parent->FirstChildElement("origin");
        if (o == nullptr) return pose;
        if (o->Attribute("xyz") != nullptr) pose.p = vec(o, "xyz", owner);
        if (o->Attribute("rpy") != nullptr) {
            const auto r = numbers(o, "rpy", 3, owner);
            const Quat qx = Quat::fromAxisAngle({1, 0, 0}, static_cast<Real>(r[0]));
            const Quat qy = Quat::fromAxisAngle({0, 1, 0}, static_cast<Real>(r[1]));
            const Quat qz = Quat::fromAxisAngle({0, 0, 1}, static_cast<Real>(r[2]));
            pose.q = normalize(qz * qy * qx);
        }
        return pose;
    }

    UrdfGeometryElement geometryElement(const tinyxml2::XMLElement* e, const tinyxml2::XMLElement* link) const {
        UrdfGeometryElement out;
        out.line = e->GetLineNum();
        out.origin = origin(e, link);
        const tinyxml2::XMLElement* g = e->FirstChildElement("geometry");
        if (g == nullptr) fail(e, "in " + describe(link) + ": no <geometry>");
        const tinyxml2::XMLElement* shape = g->FirstChildElement();
        if (shape == nullptr) fail(g, "in " + describe(link) + ": no shape (box, cylinder, sphere, capsule or mesh)");
        UrdfGeometry& geo = out.geometry;
        const std::string kind = shape->Name();
        const auto positive = [&](const char* attr) {
            const double v = number(shape, attr, link);
            if (!(v > 0)) failAttr(shape, link, attr, "must be positive, got " + formatReal(v));
            return static_cast<Real>(v);
        };
        if (kind == "box") {
            geo.kind = UrdfGeometry::Kind::Box;
            geo.size = vec(shape, "size", link);
            if (!(geo.size.x > 0 && geo.size.y > 0 && geo.size.z > 0)) {
                failAttr(shape, link, "size", "must be three positive lengths, got " + formatVec(geo.size));
            }
        } else if (kind == "cylinder" || kind == "capsule") {
            geo.kind = kind == "cylinder" ? UrdfGeometry::Kind::Cylinder : UrdfGeometry::Kind::Capsule;
            geo.radius = positive("radius");
            geo.length = positive("length");
        } else if (kind == "sphere") {
            geo.kind = UrdfGeometry::Kind::Sphere;
            geo.radius = positive("radius");
        } else if (kind == "mesh") {
            geo.kind = UrdfGeometry::Kind::Mesh;
            const char* file = shape->Attribute("filename");
            if (file == nullptr || *file == '\0') failAttr(shape, link, "filename", "is missing");
            geo.filename = file;
            if (shape->Attribute("scale") != nullptr) geo.scale = vec(shape, "scale", link);
        } else {
            fail(shape, "in " + describe(link) + ": unknown geometry (expected box, cylinder, sphere, capsule or mesh)");
        }
        return out;
    }

    // A <material>'s <color rgba>, each component clamped to [0, 1]; nullopt
    // without a <color> (a texture only, or a reference by name).
    std::optional<std::array<float, 4>> materialColor(const tinyxml2::XMLElement* material, const tinyxml2::XMLElement* owner) const {
        const tinyxml2::XMLElement* c = material->FirstChildElement("color");
        if (c == nullptr) return std::nullopt;
        const auto v = numbers(c, "rgba", 4, owner);
        std::array<float, 4> rgba{};
        for (std::size_t k = 0; k < 4; ++k) rgba[k] = static_cast<float>(std::clamp(v[k], 0.0, 1.0));
        return rgba;
    }

    UrdfLink link(const tinyxml2::XMLElement* e) const {
        UrdfLink l;
        l.line = e->GetLineNum();
        const char* name = e->Attribute("name");
        if (name == nullptr || *name == '\0') fail(e, "a link needs a name");
        l.name = name;
        if (const tinyxml2::XMLElement* in = e->FirstChildElement("inertial")) {
            l.hasInertial = true;
            l.inertialOrigin = origin(in, e);
            const tinyxml2::XMLElement* m = in->FirstChildElement("mass");
            if (m == nullptr) fail(in, "in " + describe(e) + ": no <mass>");
            const double mass = number(m, "value", e);
            if (!(mass > 0)) failAttr(m, e, "value", "must be a positive mass (kg), got " + formatReal(mass));
            l.mass = static_cast<Real>(mass);
            const tinyxml2::XMLElement* i = in->FirstChildElement("inertia");
            if (i == nullptr) fail(in, "in " + describe(e) + ": no <inertia>");
            const auto get = [&](const char* a) { return static_cast<Real>(numberOr(i, a, 0, e)); };
            const Real ixx = get("ixx"), ixy = get("ixy"), ixz = get("ixz"), iyy = get("iyy"), iyz = get("iyz"), izz = get("izz");
            l.inertia = Mat3::fromRows({ixx, ixy, ixz}, {ixy, iyy, iyz}, {ixz, iyz, izz});
            if (!isSymmetricPositiveDefinite(l.inertia)) {
                throw Error(source_ + ": line " + std::to_string(i->GetLineNum()) + ": " + describeIn(i, e) +
                            ": the inertia tensor must be positive definite (ixx " + formatReal(ixx) + ", iyy " +
                            formatReal(iyy) + ", izz " + formatReal(izz) + ", ixy " + formatReal(ixy) + ", ixz " +
                            formatReal(ixz) + ", iyz " + formatReal(iyz) + ")");
            }
        }
        for (const tinyxml2::XMLElement* c = e->FirstChildElement("collision"); c; c = c->NextSiblingElement("collision")) {
            l.collisions.push_back(geometryElement(c, e));
        }
        for (const tinyxml2::XMLElement* v = e->FirstChildElement("visual"); v; v = v->NextSiblingElement("visual")) {
            UrdfGeometryElement visual = geometryElement(v, e);
            if (const tinyxml2::XMLElement* mat = v->FirstChildElement("material")) {
                if (const char* n = mat->Attribute("name")) visual.material = n;
                if (const auto rgba = materialColor(mat, e)) {
                    visual.hasColor = true;
                    visual.rgba = *rgba;
                }
            }
            l.visuals.push_back(std::move(visual));
        }
        return l;
    }

    UrdfJoint joint(const tinyxml2::XMLElement* e) const {
        UrdfJoint j;
        j.line = e->GetLineNum();
        const char* name = e->Attribute("name");
        if (name == nullptr || *name == '\0') fail(e, "a joint needs a name");
        j.name = name;
        const char* type = e->Attribute("type");
        if (type == nullptr) fail(e, "attribute 'type' is missing");
        const std::string t = type;
        if (t == "revolute") j.type = UrdfJointType::Revolute;
        else if (t == "continuous") j.type = UrdfJointType::Continuous;
        else if (t == "prismatic") j.type = UrdfJointType::Prismatic;
        else if (t == "fixed") j.type = UrdfJointType::Fixed;
        else if (t == "floating") j.type = UrdfJointType::Floating;
        else if (t == "planar") j.type = UrdfJointType::Planar;
        else fail(e, "unknown joint type '" + t + "' (expected revolute, continuous, prismatic, fixed, floating or planar)");
        const auto linkOf = [&](const char* tag) {
            const tinyxml2::XMLElement* x = e->FirstChildElement(tag);
            if (x == nullptr) fail(e, std::string("no <") + tag + ">");
            const char* l = x->Attribute("link");
            if (l == nullptr || *l == '\0') failAttr(x, e, "link", "is missing");
            return std::string(l);
        };
        j.parent = linkOf("parent");
        j.child = linkOf("child");
        j.origin = origin(e, e);
        if (const tinyxml2::XMLElement* a = e->FirstChildElement("axis")) {
            const Vec3 axis = vec(a, "xyz", e);
            const Real len = length(axis);
            const bool needsAxis = j.type == UrdfJointType::Revolute || j.type == UrdfJointType::Continuous ||
                                   j.type == UrdfJointType::Prismatic || j.type == UrdfJointType::Planar;
            if (!(len > Real(1e-6))) {
                if (needsAxis) failAttr(a, e, "xyz", "must not be the zero vector");
            } else {
                j.axis = axis / len;
            }
        }
        if (const tinyxml2::XMLElement* l = e->FirstChildElement("limit")) {
            j.hasLimit = true;
            j.hasLower = l->Attribute("lower") != nullptr;
            j.hasUpper = l->Attribute("upper") != nullptr;
            j.lower = static_cast<Real>(numberOr(l, "lower", 0, e));
            j.upper = static_cast<Real>(numberOr(l, "upper", 0, e));
            j.effort = static_cast<Real>(numberOr(l, "effort", 0, e));
            j.velocity = static_cast<Real>(numberOr(l, "velocity", 0, e));
            if (j.effort < 0) failAttr(l, e, "effort", "must not be negative, got " + formatReal(j.effort));
            if (j.velocity < 0) failAttr(l, e, "velocity", "must not be negative, got " + formatReal(j.velocity));
            if ((j.hasLower || j.hasUpper) && j.lower > j.upper) {
                failAttr(l, e, "lower", "(" + formatReal(j.lower) + ") is above upper (" + formatReal(j.upper) + ")");
            }
        }
        if (const tinyxml2::XMLElement* d = e->FirstChildElement("dynamics")) {
            j.damping = static_cast<Real>(numberOr(d, "damping", 0, e));
            j.friction = static_cast<Real>(numberOr(d, "friction", 0, e));
            if (j.damping < 0) failAttr(d, e, "damping", "must not be negative, got " + formatReal(j.damping));
            if (j.friction < 0) failAttr(d, e, "friction", "must not be negative, got " + formatReal(j.friction));
        }
        return j;
    }

    UrdfModel read(std::string_view xml) const {
        tinyxml2::XMLDocument doc;
        if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS) {
            const char* detail = doc.ErrorStr();
            throw Error(source_ + ": line " + std::to_string(doc.ErrorLineNum()) + ": malformed XML (" +
                        std::string(detail != nullptr ? detail : doc.ErrorName()) + ")");
        }
        const tinyxml2::XMLElement* robot = doc.RootElement();
        if (robot == nullptr) throw Error(source_ + ": not a URDF file: no XML element (expected <robot>)");
        if (std::string_view(robot->Name()) != "robot") {
            fail(robot, "not a URDF file: the root element must be <robot>");
        }
        UrdfModel m;
        m.source = source_;
        if (const char* n = robot->Attribute("name")) m.name = n;
        std::map<std::string, std::size_t, std::less<>> linkIndex;
        for (const tinyxml2::XMLElement* e = robot->FirstChildElement("link"); e; e = e->NextSiblingElement("link")) {
            UrdfLink l = link(e);
            if (const auto [it, isNew] = linkIndex.try_emplace(l.name, m.links.size()); !isNew) {
                fail(e, "duplicate link name '" + l.name + "' (also on line " + std::to_string(m.links[it->second].line) + ")");
            }
            m.links.push_back(std::move(l));
        }
        if (m.links.empty()) fail(robot, "the robot has no <link>");
        // Materials by name: those defined at the robot level, then those
        // defined inside a visual (as urdfdom does, the first definition of a
        // name counts); a visual naming one without a colour of its own takes it.
        std::map<std::string, std::array<float, 4>, std::less<>> materials;
        for (const tinyxml2::XMLElement* e = robot->FirstChildElement("material"); e; e = e->NextSiblingElement("material")) {
            const char* n = e->Attribute("name");
            if (n == nullptr) continue;
            if (const auto rgba = materialColor(e, e)) materials.try_emplace(n, *rgba);
        }
        for (const UrdfLink& l : m.links) {
            for (const UrdfGeometryElement& v : l.visuals) {
                if (v.hasColor && !v.material.empty()) materials.try_emplace(v.material, v.rgba);
            }
        }
        for (UrdfLink& l : m.links) {
            for (UrdfGeometryElement& v : l.visuals) {
                if (v.hasColor || v.material.empty()) continue;
                if (const auto it = materials.find(v.material); it != materials.end()) {
                    v.hasColor = true;
                    v.rgba = it->second;
                }
            }
        }
        std::map<std::string, int, std::less<>> jointNames;
        m.parentJoint.assign(m.links.size(), kNone);
        for (const tinyxml2::XMLElement* e = robot->FirstChildElement("joint"); e; e = e->NextSiblingElement("joint")) {
            UrdfJoint j = joint(e);
            if (const auto [it, isNew] = jointNames.try_emplace(j.name, j.line); !isNew) {
                fail(e, "duplicate joint name '" + j.name + "' (also on line " + std::to_string(it->second) + ")");
            }
            const auto parent = linkIndex.find(j.parent), child = linkIndex.find(j.child);
            if (parent == linkIndex.end()) fail(e, "its parent link '" + j.parent + "' does not exist");
            if (child == linkIndex.end()) fail(e, "its child link '" + j.child + "' does not exist");
            if (parent->second == child->second) fail(e, "joins link '" + j.parent + "' to itself");
            if (m.parentJoint[child->second] != kNone) {
                fail(e, "link '" + j.child + "' already has a parent (joint '" + m.joints[m.parentJoint[child->second]].name +
                            "'): a URDF robot is a tree, a link has one parent");
            }
            m.parentJoint[child->second] = m.joints.size();
            m.joints.push_back(std::move(j));
        }
        // One root; every link reachable from it (else the rest forms a loop).
        std::vector<std::size_t> roots;
        for (std::size_t i = 0; i < m.links.size(); ++i) {
            if (m.parentJoint[i] == kNone) roots.push_back(i);
        }
        if (roots.empty()) fail(robot, "the joints form a loop: every link has a parent, so there is no root link");
        if (roots.size() > 1) {
            fail(robot, "the robot is not one tree: links '" + m.links[roots[0]].name + "' and '" + m.links[roots[1]].name +
                            "' both have no parent joint");
        }
        m.root = roots[0];
        std::vector<std::vector<std::size_t>> children(m.links.size());
        for (std::size_t ji = 0; ji < m.joints.size(); ++ji) children[linkIndex.find(m.joints[ji].parent)->second].push_back(ji);
        m.order.push_back(m.root);
        for (std::size_t k = 0; k < m.order.size(); ++k) {
            for (const std::size_t ji : children[m.order[k]]) m.order.push_back(linkIndex.find(m.joints[ji].child)->second);
        }
        if (m.order.size() != m.links.size()) {
            std::vector<bool> seen(m.links.size());
            for (const std::size_t i : m.order) seen[i] = true;
            std::size_t lost = 0;
            while (seen[lost]) ++lost;
            const UrdfJoint& j = m.joints[m.parentJoint[lost]];
            throw Error(source_ + ": line " + std::to_string(j.line) + ": <joint name='" + j.name +
                        "'>: the joints form a loop (link '" + m.links[lost].name + "' is not reachable from the root link '" +
                        m.links[m.root].name + "')");
        }
        return m;
    }

private:
    std::string source_;
};

}  // namespace

UrdfModel parseUrdf(std::string_view xml, const std::string& source) { return UrdfReader(source).read(xml); }

}  // namespace fulcrum::detail
