// From a Scene description to a World (buildWorld), and back (captureScene).
#include <optional>
#include <stdexcept>
#include <string_view>
#include <unordered_map>

#include "fulcrum/scene.hpp"
#include "fulcrum/world.hpp"
#include "io/scene_detail.hpp"

namespace fulcrum {

namespace {

[[noreturn]] void rethrow(const Scene& scene, const SceneLocation& where, const std::string& suffix, const Error& e) {
    std::string path = where.path;
    if (!suffix.empty()) path += (path.empty() ? "" : ".") + suffix;
    throw SceneError(scene.sourceName, path, where.line, where.column, e.what());
}

// A point or direction given in world space when the scene was created, moved
// along with the body it belongs to from its creation pose to its pose now.
Vec3 carryPoint(const Transform& creation, const Transform& now, const Vec3& p) {
    return transformPoint(now, inverseTransformPoint(creation, p));
}
Vec3 carryVector(const Transform& creation, const Transform& now, const Vec3& v) {
    return transformVector(now, inverseTransformVector(creation, v));
}

}  // namespace

Shape buildShape(const ShapeDesc& s) {
    if (s.scale != Vec3{1, 1, 1}) {  // scaled shapes: build the shape as given, then scale it
        ShapeDesc unscaled = s;
        unscaled.scale = {1, 1, 1};
        return Shape::scaled(buildShape(unscaled), s.scale);
    }
    switch (s.type) {
        case ShapeType::ConvexHull:
            return s.convexRadius > 0 ? Shape::roundedConvexHull(s.points, s.convexRadius) : Shape::convexHull(s.points);
        case ShapeType::Mesh:
            if (s.decompose) return Shape::convexDecomposition(s.vertices, s.triangles);
            return Shape::mesh(s.vertices, s.triangles);
        case ShapeType::HeightField: return Shape::heightField(s.rows, s.columns, s.spacingX, s.spacingZ, s.heights, s.holes);
        case ShapeType::Compound: {
            if (!detail::containsHullOrMesh(s)) return detail::buildPrimitiveShape(s);
            std::vector<CompoundChild> children;
            children.reserve(s.children.size());
            for (const ShapeDesc::Child& c : s.children) children.push_back({buildShape(c.shape), Transform(c.position, c.orientation)});
            return Shape::compound(children);
        }
        default: return detail::buildPrimitiveShape(s);
    }
}

World buildWorld(const Scene& scene, SceneHandles* handles) {
    World world(scene.world);
    SceneHandles local;
    SceneHandles& h = handles ? *handles : local;
    h = {};
    // The bodies that springs, joints and ropes name, found as the bodies are
    // created (the first of a name, as World::findBody): only those names are
    // indexed, usually a few of many (a map of every name, a cache miss per
    // body, was a tenth of the time to load a million-body scene).
    std::unordered_map<std::string_view, BodyId> byName;
    for (const SceneSpring& s : scene.springs) byName.insert({{s.bodyA, {}}, {s.bodyB, {}}});
    for (const SceneJoint& j : scene.joints) byName.insert({{j.bodyA, {}}, {j.bodyB, {}}});
    for (const SceneRope& r : scene.ropes) byName.insert({{r.attachStart, {}}, {r.attachEnd, {}}});
    for (const SceneVehicle& v : scene.vehicles) byName.insert({v.chassis, {}});
    byName.erase("");
    const auto findNamed = [&](const std::string& name) -> std::optional<BodyId> {
        if (name.empty()) return kWorldBody;
        const auto it = byName.find(name);
        if (it == byName.end() || it->second.isNull()) return std::nullopt;
        return it->second;
    };
    const auto resolve = [&](const std::string& name) {
        if (const auto id = findNamed(name)) return *id;
        throw std::out_of_range("unknown body");
    };

    h.bodies.reserve(scene.bodies.size());
    for (const SceneBody& body : scene.bodies) {
        BodyDef def = body.def;
        try {
            def.shape = buildShape(body.shape);
        } catch (const Error& e) {
            rethrow(scene, body.where, "shape", e);
        }
        def.orientation = normalize(def.orientation);
        BodyId id;
        try {
            id = world.createBody(def);
        } catch (const Error& e) {
            rethrow(scene, body.where, "", e);
        }
        h.bodies.push_back(id);
        if (!byName.empty() && !def.name.empty()) {
            if (const auto it = byName.find(def.name); it != byName.end() && it->second.isNull()) it->second = id;
        }
    }
    for (const SceneSpring& spring : scene.springs) {
        SpringDef def = spring.def;
        try {
            def.bodyA = resolve(spring.bodyA);
            def.bodyB = resolve(spring.bodyB);
            h.springs.push_back(world.createSpring(def));
        } catch (const std::out_of_range&) {
            throw SceneError(scene.sourceName, spring.where.path, spring.where.line, spring.where.column, "refers to an unknown body");
        } catch (const Error& e) {
            rethrow(scene, spring.where, "", e);
        }
    }
    for (const SceneJoint& joint : scene.joints) {
        JointDef def = joint.def;
        try {
            def.bodyA = resolve(joint.bodyA);
            def.bodyB = resolve(joint.bodyB);
            h.joints.push_back(world.createJoint(def));
        } catch (const std::out_of_range&) {
            throw SceneError(scene.sourceName, joint.where.path, joint.where.line, joint.where.column, "refers to an unknown body");
        } catch (const Error& e) {
            rethrow(scene, joint.where, "", e);
        }
    }
    // Ropes and cloths last: attachments name bodies.
    const auto systemPath = [](const SceneLocation& where, const char* section, std::size_t i) {
        return where.path.empty() ? std::string(section) + "[" + std::to_string(i) + "]" : where.path;
    };
    for (std::size_t i = 0; i < scene.ropes.size(); ++i) {
        const SceneRope& rope = scene.ropes[i];
        const std::string path = systemPath(rope.where, "ropes", i);
        RopeDef def = rope.def;
        const auto attach = [&](const std::string& name, const char* key) {
            const auto id = findNamed(name);
            if (!id) throw SceneError(scene.sourceName, path + "." + key, rope.where.line, rope.where.column, "unknown body '" + name + "'");
            return *id;
        };
        def.attachStart = attach(rope.attachStart, "attach_start");
        def.attachEnd = attach(rope.attachEnd, "attach_end");
        try {
            h.ropes.push_back(world.createRope(def));
        } catch (const Error& e) {
            throw SceneError(scene.sourceName, path, rope.where.line, rope.where.column, e.what());
        }
    }
    for (std::size_t i = 0; i < scene.cloths.size(); ++i) {
        const SceneCloth& cloth = scene.cloths[i];
        try {
            h.cloths.push_back(world.createCloth(cloth.def));
        } catch (const Error& e) {
            throw SceneError(scene.sourceName, systemPath(cloth.where, "cloths", i), cloth.where.line, cloth.where.column, e.what());
        }
    }
    for (std::size_t i = 0; i < scene.characters.size(); ++i) {
        const SceneCharacter& c = scene.characters[i];
        try {
            h.characters.push_back(world.createCharacter(c.def));
        } catch (const Error& e) {
            throw SceneError(scene.sourceName, systemPath(c.where, "characters", i), c.where.line, c.where.column, e.what());
        }
    }
    for (std::size_t i = 0; i < scene.vehicles.size(); ++i) {
        const SceneVehicle& v = scene.vehicles[i];
        const std::string path = systemPath(v.where, "vehicles", i);
        VehicleDef def = v.def;
        const auto chassis = findNamed(v.chassis);
        if (!chassis || chassis->isNull()) {
            throw SceneError(scene.sourceName, path + ".chassis", v.where.line, v.where.column, "unknown body '" + v.chassis + "'");
        }
        def.chassis = *chassis;
        try {
            h.vehicles.push_back(createVehicle(world, def));
        } catch (const Error& e) {
            throw SceneError(scene.sourceName, path, v.where.line, v.where.column, e.what());
        }
    }
    return world;
}

Scene captureScene(const World& world, const Scene& base, const SceneHandles& handles) {
    if (handles.bodies.size() != base.bodies.size()) {
        throw Error("captureScene: handles hold " + std::to_string(handles.bodies.size()) + " bodies but the base scene has " +
                    std::to_string(base.bodies.size()));
    }
    Scene scene = base;
    const WorldDef& settings = world.settings();
    scene.world = settings;

    // Creation and current poses of named bodies, to carry world-space anchors.
    struct Poses {
        Transform creation, now;
    };
    std::unordered_map<std::string, Poses> poses;
    for (std::size_t i = 0; i < base.bodies.size(); ++i) {
        const BodyId id = handles.bodies[i];
        if (!world.isValid(id)) throw Error("captureScene: body " + sceneBodyName(base, i) + " no longer exists in the world");
        BodyDef& def = scene.bodies[i].def;
        const Transform creation(def.position, normalize(def.orientation));
        def.position = world.position(id);
        def.orientation = world.orientation(id);
        def.linearVelocity = world.linearVelocity(id);
        def.angularVelocity = world.angularVelocity(id);
        def.awake = world.isAwake(id);
        if (!def.name.empty()) poses[def.name] = {creation, Transform(def.position, def.orientation)};
    }
    const auto carry = [&](const std::string& body, Vec3& point, Vec3* direction) {
        if (body.empty()) return;  // fixed in the world
        const Poses& p = poses.at(body);
        point = carryPoint(p.creation, p.now, point);
        if (direction) *direction = carryVector(p.creation, p.now, *direction);
    };
    for (SceneJoint& joint : scene.joints) {
        carry(joint.bodyA, joint.def.anchor, &joint.def.axis);  // the anchor and axis belong to body A (or the world)
        if (joint.def.type == JointType::Distance) carry(joint.bodyB, joint.def.anchorB, nullptr);
    }
    for (SceneSpring& spring : scene.springs) {
        carry(spring.bodyA, spring.def.anchorA, nullptr);
        carry(spring.bodyB, spring.def.anchorB, nullptr);
    }
    // Characters: where they are now (their velocity, ground and script
    // progress are not in the format; the script's times are world times).
    for (std::size_t i = 0; i < scene.characters.size() && i < handles.characters.size(); ++i) {
        if (world.isValid(handles.characters[i])) scene.characters[i].def.position = world.characterState(handles.characters[i]).position;
    }
    return scene;
}

}  // namespace fulcrum
