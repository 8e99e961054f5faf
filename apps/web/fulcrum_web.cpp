// The C API of Fulcrum's JavaScript module (docs/browser.md). Emscripten
// exports these functions from build-wasm/fulcrum_web.js; web/fulcrum.js
// wraps them (cwrap) in a small object API. A plain C API rather than
// embind: Debian's Emscripten 3.1.6 handles it without extra runtime, the
// JavaScript side reads state straight out of the module's memory as typed
// arrays, and the same file builds natively (fulcrum_web_hash) so the
// browser test can compare a page's state hash with the native build's.
//
// Worlds are small integer handles; bodies and joints are indices in
// creation order (the order of a scene file's "bodies"). Failures return a
// negative value (or 0 for a world) and leave the message in
// fw_last_error(): the engine's fulcrum::Error text, naming the field.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "determinism/state_hash.hpp"
#include "fulcrum/scene.hpp"
#include "fulcrum/world.hpp"
#include "io/recording_display.hpp"
#include "io/tessellate.hpp"

#ifdef __EMSCRIPTEN__
#include <emscripten/emscripten.h>
#define FW_EXPORT extern "C" EMSCRIPTEN_KEEPALIVE
#else
#define FW_EXPORT extern "C"
#endif

namespace {

using namespace fulcrum;
using nlohmann::json;

// A grabbed body pulled towards a target point by a damped spring at the
// picked point: the force is applied before every step, scaled by the
// body's mass so light and heavy bodies follow alike (about 4 Hz, damped
// near critically; stable for steps up to 1/30 s).
struct Grab {
    int body = -1;
    Vec3 localPoint;
    Vec3 target;
};

struct WebWorld {
    World world;
    Real dt = Real(1) / 60;
    std::vector<BodyId> bodies;
    std::vector<JointId> joints;
    json jointShapes = json::array();  // per joint: type, bodies, anchors in the bodies' frames
    std::vector<float> state;   // per body: position xyz, orientation xyzw, awake
    std::vector<float> particles;
    std::vector<float> contacts;  // per point: position xyz, normal xyz
    Grab grab;
    std::string text;           // the last string handed to JavaScript

    explicit WebWorld(World w) : world(std::move(w)) {}
};

std::vector<std::unique_ptr<WebWorld>> worlds(1);  // handle 0: none
std::string lastError;

WebWorld* get(int handle) {
    if (handle <= 0 || handle >= int(worlds.size()) || !worlds[std::size_t(handle)]) {
        lastError = "no world " + std::to_string(handle);
        return nullptr;
    }
    return worlds[std::size_t(handle)].get();
}

int keep(std::unique_ptr<WebWorld> w) {
    for (std::size_t i = 1; i < worlds.size(); ++i) {
        if (!worlds[i]) {
            worlds[i] = std::move(w);
            return int(i);
        }
    }
    worlds.push_back(std::move(w));
    return int(worlds.size() - 1);
}

bool validBody(WebWorld* w, int body) {
    if (body < 0 || body >= int(w->bodies.size()) || !w->world.isValid(w->bodies[std::size_t(body)])) {
        lastError = "no body " + std::to_string(body);
        return false;
    }
    return true;
}

template <class F>
auto guarded(F&& f, decltype(f()) failure) -> decltype(f()) {
    try {
        return f();
    } catch (const std::exception& e) {
        lastError = e.what();
        return failure;
    }
}

json vec(const Vec3& v) { return json::array({v.x, v.y, v.z}); }

// A new joint's bodies (indices, -1 the world) and anchors in their frames,
// taken at creation, while the definition's world anchors are current.
void describeJoint(WebWorld* w, JointId id) {
    const JointDef& def = w->world.jointDef(id);
    auto side = [&](BodyId body, const Vec3& anchor) -> std::pair<int, Vec3> {
        for (std::size_t b = 0; b < w->bodies.size(); ++b) {
            if (w->bodies[b] == body) {
                return {int(b), inverseRotate(w->world.orientation(body), anchor - w->world.position(body))};
            }
        }
        return {-1, anchor};
    };
    const auto [a, localA] = side(def.bodyA, def.anchor);
    const auto [b, localB] = side(def.bodyB, def.type == JointType::Distance ? def.anchorB : def.anchor);
    w->jointShapes.push_back({{"type", toString(def.type)}, {"bodyA", a}, {"bodyB", b}, {"anchorA", vec(localA)},
                              {"anchorB", vec(localB)}});
}

// What the page draws for one body: the replay page's description of a body
// (docs/recording.md), with plain arrays in place of packed ones.
json describeBody(const World& world, BodyId id, std::size_t index) {
    json parts = json::array();
    io::TessellationOptions options;
    options.planeHalfSize = 50;
    for (const io::RenderPart& part : io::tessellate(world.shape(id), options)) {
        std::vector<float> positions, normals;
        for (const Vec3& p : part.mesh.positions) positions.insert(positions.end(), {float(p.x), float(p.y), float(p.z)});
        for (const Vec3& n : part.mesh.normals) normals.insert(normals.end(), {float(n.x), float(n.y), float(n.z)});
        const Quat& q = part.local.q;
        parts.push_back({{"position", vec(part.local.p)},
                         {"rotation", json::array({q.x, q.y, q.z, q.w})},
                         {"positions", positions},
                         {"normals", normals},
                         {"indices", part.mesh.indices},
                         {"doubleSided", part.mesh.doubleSided}});
    }
    const BodyType type = world.bodyType(id);
    const io::Rgb c = io::bodyColor(type, index, false), s = io::bodyColor(type, index, true);
    return {{"name", world.name(id)},
            {"type", toString(type)},
            {"shape", toString(world.shape(id).type())},
            {"mass", type == BodyType::Dynamic ? json(world.mass(id)) : json(0)},
            {"color", json::array({c.r, c.g, c.b})},
            {"sleepColor", json::array({s.r, s.g, s.b})},
            {"parts", std::move(parts)}};
}

}  // namespace

FW_EXPORT const char* fw_last_error() { return lastError.c_str(); }

// A world from the text of a scene file (docs/scene-format.md); its dt is the scene's.
FW_EXPORT int fw_world_from_scene(const char* sceneJson) {
    return guarded([&] {
        const Scene scene = parseScene(sceneJson, "<scene>");
        SceneHandles handles;
        auto w = std::make_unique<WebWorld>(buildWorld(scene, &handles));
        w->dt = scene.dt;
        w->bodies = handles.bodies;
        w->joints = handles.joints;
        for (const JointId id : w->joints) describeJoint(w.get(), id);
        return keep(std::move(w));
    }, 0);
}

// An empty world: gravity, time step and sub-steps.
FW_EXPORT int fw_world_create(double gx, double gy, double gz, double dt, int substeps) {
    return guarded([&] {
        if (!(dt > 0) || !std::isfinite(dt)) throw Error("world: dt must be positive, got " + std::to_string(dt));
        WorldDef def;
        def.gravity = Vec3(Real(gx), Real(gy), Real(gz));
        if (substeps > 0) def.substeps = substeps;
        auto w = std::make_unique<WebWorld>(World(def));
        w->dt = Real(dt);
        return keep(std::move(w));
    }, 0);
}

FW_EXPORT void fw_world_destroy(int handle) {
    if (get(handle)) worlds[std::size_t(handle)].reset();
}

FW_EXPORT double fw_world_dt(int handle) {
    WebWorld* w = get(handle);
    return w ? double(w->dt) : 0;
}

// A body: type 0 static, 1 kinematic, 2 dynamic; shape 0 sphere (a = radius),
// 1 box (a, b, c = half extents), 2 capsule (a = radius, b = half height, along
// y), 3 cylinder (as the capsule), 4 plane (normal (a, b, c) through the
// position). mass <= 0: density 1000. Returns the body's index.
FW_EXPORT int fw_body_create(int handle, const char* name, int type, int shape, double a, double b, double c,
                             double px, double py, double pz, double qx, double qy, double qz, double qw,
                             double mass, double friction, double restitution) {
    WebWorld* w = get(handle);
    if (!w) return -1;
    return guarded([&] {
        BodyDef def;
        def.name = name ? name : "";
        if (type < 0 || type > 2) throw Error("body '" + def.name + "': type must be 0 static, 1 kinematic or 2 dynamic");
        def.type = type == 0 ? BodyType::Static : type == 1 ? BodyType::Kinematic : BodyType::Dynamic;
        def.position = Vec3(Real(px), Real(py), Real(pz));
        def.orientation = normalize(Quat(Real(qw), Real(qx), Real(qy), Real(qz)));
        switch (shape) {
            case 0: def.shape = Shape::sphere(Real(a)); break;
            case 1: def.shape = Shape::box(Vec3(Real(a), Real(b), Real(c))); break;
            case 2: def.shape = Shape::capsule(Real(a), Real(b)); break;
            case 3: def.shape = Shape::cylinder(Real(a), Real(b)); break;
            case 4: {
                const Vec3 n = normalize(Vec3(Real(a), Real(b), Real(c)));
                def.shape = Shape::plane(n, dot(n, def.position));
                def.position = Vec3();
                def.orientation = Quat();
                break;
            }
            default: throw Error("body '" + def.name + "': shape must be 0 sphere, 1 box, 2 capsule, 3 cylinder or 4 plane");
        }
        if (mass > 0) def.mass = Real(mass);
        def.friction = Real(friction);
        def.restitution = Real(restitution);
        w->bodies.push_back(w->world.createBody(def));
        return int(w->bodies.size() - 1);
    }, -1);
}

// A joint between bodies a and b (-1: the static world) at a world anchor:
// type 0 ball, 1 hinge (about axis), 2 slider (along axis), 3 fixed,
// 4 distance (a rod from the anchor to the second point (bx, by, bz)).
FW_EXPORT int fw_joint_create(int handle, int type, int bodyA, int bodyB, double ax, double ay, double az,
                              double axisX, double axisY, double axisZ, double bx, double by, double bz) {
    WebWorld* w = get(handle);
    if (!w) return -1;
    if ((bodyA != -1 && !validBody(w, bodyA)) || !validBody(w, bodyB)) return -1;
    return guarded([&] {
        static constexpr JointType types[] = {JointType::Ball, JointType::Hinge, JointType::Slider, JointType::Fixed,
                                              JointType::Distance};
        if (type < 0 || type > 4) throw Error("joint: type must be 0 ball, 1 hinge, 2 slider, 3 fixed or 4 distance");
        JointDef def;
        def.type = types[type];
        def.bodyA = bodyA < 0 ? kWorldBody : w->bodies[std::size_t(bodyA)];
        def.bodyB = w->bodies[std::size_t(bodyB)];
        def.anchor = Vec3(Real(ax), Real(ay), Real(az));
        def.axis = Vec3(Real(axisX), Real(axisY), Real(axisZ));
        def.anchorB = Vec3(Real(bx), Real(by), Real(bz));
        w->joints.push_back(w->world.createJoint(def));
        describeJoint(w, w->joints.back());
        return int(w->joints.size() - 1);
    }, -1);
}

// Steps `count` times by the world's dt, applying the grab spring before each
// step. Returns 0, or -1 when the engine refused (fw_last_error()).
FW_EXPORT int fw_step(int handle, int count) {
    WebWorld* w = get(handle);
    if (!w) return -1;
    return guarded([&] {
        for (int i = 0; i < count; ++i) {
            if (w->grab.body >= 0 && w->world.isValid(w->bodies[std::size_t(w->grab.body)])) {
                const BodyId id = w->bodies[std::size_t(w->grab.body)];
                const Real omega = Real(2 * 3.14159265358979 * 4), m = w->world.mass(id);
                const Vec3 point = w->world.position(id) + rotate(w->world.orientation(id), w->grab.localPoint);
                const Vec3 force = (w->grab.target - point) * (m * omega * omega) -
                                   w->world.velocityAtPoint(id, point) * (2 * Real(0.9) * m * omega);
                w->world.applyForce(id, force, point);
                // Some spin damping so a body held at one corner settles.
                w->world.applyTorque(id, w->world.angularVelocity(id) * (-m * Real(0.5)));
            }
            w->world.step(w->dt);
        }
        return 0;
    }, -1);
}

FW_EXPORT int fw_body_count(int handle) {
    WebWorld* w = get(handle);
    return w ? int(w->bodies.size()) : -1;
}

// Fills the state array (8 floats per body: position xyz, orientation xyzw,
// awake 1/0; a destroyed body's slots are 0) and returns its address in the
// module's memory; valid until the next call that creates bodies.
FW_EXPORT float* fw_read_state(int handle) {
    WebWorld* w = get(handle);
    if (!w) return nullptr;
    w->state.assign(w->bodies.size() * 8, 0.0f);
    for (std::size_t b = 0; b < w->bodies.size(); ++b) {
        const BodyId id = w->bodies[b];
        if (!w->world.isValid(id)) continue;
        const Vec3 p = w->world.position(id);
        const Quat q = w->world.orientation(id);
        float* s = &w->state[8 * b];
        s[0] = float(p.x), s[1] = float(p.y), s[2] = float(p.z);
        s[3] = float(q.x), s[4] = float(q.y), s[5] = float(q.z), s[6] = float(q.w);
        s[7] = w->world.isAwake(id) ? 1.0f : 0.0f;
    }
    return w->state.data();
}

// The contact points of the last step (6 floats each: point xyz, normal xyz);
// the address of the array; fw_contact_count() says how many.
FW_EXPORT float* fw_read_contacts(int handle) {
    WebWorld* w = get(handle);
    if (!w) return nullptr;
    w->contacts.clear();
    for (const ContactReport& c : w->world.contacts()) {
        for (const Vec3& p : c.points) {
            w->contacts.insert(w->contacts.end(), {float(p.x), float(p.y), float(p.z), float(c.normal.x), float(c.normal.y),
                                                   float(c.normal.z)});
        }
    }
    return w->contacts.data();
}

FW_EXPORT int fw_contact_count(int handle) {
    WebWorld* w = get(handle);
    return w ? int(w->contacts.size() / 6) : -1;
}

// Every rope's and cloth's particle positions, system after system (3 floats each).
FW_EXPORT float* fw_read_particles(int handle) {
    WebWorld* w = get(handle);
    if (!w) return nullptr;
    w->particles.clear();
    for (const ParticleSystemId id : w->world.particleSystems()) {
        for (const Vec3& x : w->world.particlePositions(id)) w->particles.insert(w->particles.end(), {float(x.x), float(x.y), float(x.z)});
    }
    return w->particles.data();
}

FW_EXPORT int fw_apply_impulse(int handle, int body, double ix, double iy, double iz, double px, double py, double pz) {
    WebWorld* w = get(handle);
    if (!w || !validBody(w, body)) return -1;
    return guarded([&] {
        const BodyId id = w->bodies[std::size_t(body)];
        w->world.wake(id);
        w->world.applyLinearImpulse(id, Vec3(Real(ix), Real(iy), Real(iz)), Vec3(Real(px), Real(py), Real(pz)));
        return 0;
    }, -1);
}

FW_EXPORT int fw_set_velocity(int handle, int body, double vx, double vy, double vz, double wx, double wy, double wz) {
    WebWorld* w = get(handle);
    if (!w || !validBody(w, body)) return -1;
    return guarded([&] {
        const BodyId id = w->bodies[std::size_t(body)];
        w->world.wake(id);
        w->world.setLinearVelocity(id, Vec3(Real(vx), Real(vy), Real(vz)));
        w->world.setAngularVelocity(id, Vec3(Real(wx), Real(wy), Real(wz)));
        return 0;
    }, -1);
}

// Grabs a dynamic body at a world point: from the next step a spring pulls
// that point of the body towards the target (fw_grab_move). One grab per world.
FW_EXPORT int fw_grab(int handle, int body, double px, double py, double pz) {
    WebWorld* w = get(handle);
    if (!w || !validBody(w, body)) return -1;
    const BodyId id = w->bodies[std::size_t(body)];
    if (w->world.bodyType(id) != BodyType::Dynamic) {
        lastError = "body " + std::to_string(body) + " is not dynamic: it cannot be grabbed";
        return -1;
    }
    const Vec3 point{Real(px), Real(py), Real(pz)};
    w->grab = {body, rotate(conjugate(w->world.orientation(id)), point - w->world.position(id)), point};
    w->world.wake(id);
    return 0;
}

FW_EXPORT void fw_grab_move(int handle, double x, double y, double z) {
    if (WebWorld* w = get(handle)) {
        w->grab.target = Vec3(Real(x), Real(y), Real(z));
        if (w->grab.body >= 0 && w->world.isValid(w->bodies[std::size_t(w->grab.body)])) w->world.wake(w->bodies[std::size_t(w->grab.body)]);
    }
}

FW_EXPORT void fw_release(int handle) {
    if (WebWorld* w = get(handle)) w->grab.body = -1;
}

// The hash of the whole state (tests/determinism/state_hash.hpp: every
// body's pose, velocities and awake flag, every particle), 16 hex digits.
FW_EXPORT const char* fw_state_hash(int handle) {
    WebWorld* w = get(handle);
    if (!w) return "";
    char hex[17];
    std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(test::stateHash(w->world)));
    w->text = hex;
    return w->text.c_str();
}

// The bodies from index `first` on, as JSON: name, type, shape, mass,
// colours and render meshes (the replay page's body description).
FW_EXPORT const char* fw_bodies_json(int handle, int first) {
    WebWorld* w = get(handle);
    if (!w) return "";
    return guarded([&] {
        json out = json::array();
        for (std::size_t b = std::size_t(std::max(first, 0)); b < w->bodies.size(); ++b) {
            if (w->world.isValid(w->bodies[b])) out.push_back(describeBody(w->world, w->bodies[b], b));
            else out.push_back(nullptr);
        }
        w->text = out.dump();
        return w->text.c_str();
    }, "");
}

// Joints (type, body indices, anchors in the bodies' frames) and ropes and
// cloths (kind, particle count, radius, segment or triangle indices), as JSON.
FW_EXPORT const char* fw_structure_json(int handle) {
    WebWorld* w = get(handle);
    if (!w) return "";
    return guarded([&] {
        json particles = json::array();
        for (const ParticleSystemId id : w->world.particleSystems()) {
            const bool cloth = w->world.particleSystemType(id) == ParticleSystemType::Cloth;
            const auto n = std::uint32_t(w->world.particleCount(id));
            std::vector<std::uint32_t> indices;
            if (cloth) {
                const auto size = w->world.clothSize(id);
                const auto index = [&](int i, int j) { return std::uint32_t(j * size[0] + i); };
                for (int j = 0; j + 1 < size[1]; ++j) {
                    for (int i = 0; i + 1 < size[0]; ++i) {
                        indices.insert(indices.end(), {index(i, j), index(i, j + 1), index(i + 1, j)});
                        indices.insert(indices.end(), {index(i + 1, j), index(i, j + 1), index(i + 1, j + 1)});
                    }
                }
            } else {
                for (std::uint32_t i = 0; i + 1 < n; ++i) indices.insert(indices.end(), {i, i + 1});
            }
            particles.push_back({{"name", w->world.name(id)}, {"kind", cloth ? "cloth" : "rope"}, {"count", n},
                                 {"radius", w->world.particleRadius(id)}, {"indices", indices}});
        }
        w->text = json{{"joints", w->jointShapes}, {"particles", particles}}.dump();
        return w->text.c_str();
    }, "");
}

FW_EXPORT double fw_time(int handle) {
    WebWorld* w = get(handle);
    return w ? double(w->world.time()) : 0;
}
