// Scene files (load_scene, World.save_scene), recordings (Recorder: .glb and
// .html) and the scene description a world carries through pickle/snapshots.
#include <cmath>
#include <limits>
#include <sstream>

#include <pybind11/stl/filesystem.h>

#include "common.hpp"
#include <fulcrum/recording.hpp>

namespace fulcrum::python {

bool isUnnamedMarker(const std::string& name);  // joints.cpp

namespace {

PyWorld worldFromScene(Scene scene) {
    SceneHandles handles;
    World world = buildWorld(scene, &handles);
    auto state = std::make_shared<WorldState>(std::move(world));
    state->scene = std::move(scene);
    state->handles = std::move(handles);
    return PyWorld{std::move(state)};
}

// The scene and handles of what still exists in the world: objects destroyed
// since drop out (destroying a body also destroys its joints and springs).
std::pair<Scene, SceneHandles> liveScene(const WorldState& s, bool forSaving = true) {
    if (forSaving && !s.sceneKnown) fail("save_scene: this world was loaded from a snapshot that holds no scene description");
    const World& w = s.world;
    std::pair<Scene, SceneHandles> out;
    Scene& scene = out.first;
    SceneHandles& h = out.second;
    scene.sourceName = s.scene.sourceName;
    scene.description = s.scene.description;
    scene.world = s.scene.world;
    scene.dt = s.scene.dt;
    scene.steps = s.scene.steps;
    for (std::size_t i = 0; i < s.scene.bodies.size(); ++i)
        if (w.isValid(s.handles.bodies[i])) scene.bodies.push_back(s.scene.bodies[i]), h.bodies.push_back(s.handles.bodies[i]);
    const auto named = [&](const std::string& body, const char* what, std::size_t i) {
        if (forSaving && isUnnamedMarker(body))
            fail(std::string("save_scene: ") + what + " #" + std::to_string(i) +
                 " is attached to an unnamed body; scene files join them by name: give the body a name");
    };
    for (std::size_t i = 0; i < s.scene.joints.size(); ++i)
        if (w.isValid(s.handles.joints[i])) {
            named(s.scene.joints[i].bodyA, "joint", i), named(s.scene.joints[i].bodyB, "joint", i);
            scene.joints.push_back(s.scene.joints[i]), h.joints.push_back(s.handles.joints[i]);
        }
    for (std::size_t i = 0; i < s.scene.springs.size(); ++i)
        if (w.isValid(s.handles.springs[i])) {
            named(s.scene.springs[i].bodyA, "spring", i), named(s.scene.springs[i].bodyB, "spring", i);
            scene.springs.push_back(s.scene.springs[i]), h.springs.push_back(s.handles.springs[i]);
        }
    for (std::size_t i = 0; i < s.scene.ropes.size(); ++i)
        if (w.isValid(s.handles.ropes[i])) scene.ropes.push_back(s.scene.ropes[i]), h.ropes.push_back(s.handles.ropes[i]);
    for (std::size_t i = 0; i < s.scene.cloths.size(); ++i)
        if (w.isValid(s.handles.cloths[i])) scene.cloths.push_back(s.scene.cloths[i]), h.cloths.push_back(s.handles.cloths[i]);
    return out;
}

template <class Id>
void packIds(std::ostringstream& out, const std::vector<Id>& ids) {
    out << ids.size();
    for (const Id& id : ids) out << ' ' << id.index << ' ' << id.generation;
    out << '\n';
}
template <class Id>
void unpackIds(std::istringstream& in, std::vector<Id>& ids) {
    std::size_t n = 0;
    in >> n;
    ids.resize(n);
    for (Id& id : ids) in >> id.index >> id.generation;
}

constexpr const char* kPackMagic = "fulcrum-python-scene 1\n";

struct PyRecorder {
    std::weak_ptr<WorldState> owner;
    io::Recorder recorder;
};

}  // namespace

void compactScene(WorldState& s) {
    const World& w = s.world;
    const std::size_t recorded = s.handles.bodies.size() + s.handles.joints.size() + s.handles.springs.size() +
                                 s.handles.ropes.size() + s.handles.cloths.size();
    const std::size_t live = w.bodyCount() + w.joints().size() + w.springCount() + w.particleSystems().size();
    if (recorded < 2 * live + 64) return;
    auto [scene, handles] = liveScene(s, false);
    s.scene = std::move(scene);
    s.handles = std::move(handles);
}

std::string packScene(const WorldState& s) {
    std::pair<Scene, SceneHandles> live;
    try {
        live = liveScene(s);
    } catch (const Error&) {
        return {};  // not describable (unnamed joint bodies): the copy can step, not save_scene
    }
    std::ostringstream out;
    out << kPackMagic;
    packIds(out, live.second.bodies), packIds(out, live.second.joints), packIds(out, live.second.springs);
    packIds(out, live.second.ropes), packIds(out, live.second.cloths);
    out << sceneToJson(live.first);
    return out.str();
}

void unpackScene(WorldState& s, const std::string& user) {
    s.sceneKnown = false;
    if (user.rfind(kPackMagic, 0) != 0) return;
    std::istringstream in(user.substr(std::string(kPackMagic).size()));
    SceneHandles h;
    unpackIds(in, h.bodies), unpackIds(in, h.joints), unpackIds(in, h.springs), unpackIds(in, h.ropes), unpackIds(in, h.cloths);
    std::string json((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    s.scene = parseScene(json, "snapshot scene");
    s.handles = std::move(h);
    s.sceneKnown = true;
}

void bindIo(py::module_& m) {
    m.def("_load_scene_file", [](const std::filesystem::path& path) { return worldFromScene(loadScene(path)); }, py::arg("path"));
    m.def("_load_scene_text",
          [](const std::string& text, const std::string& sourceName) { return worldFromScene(parseScene(text, sourceName)); },
          py::arg("text"), py::arg("source_name") = "<scene>");

    auto cls = py::reinterpret_borrow<py::class_<PyWorld>>(m.attr("World"));
    cls
        .def("scene_json",
             [](const PyWorld& w) {
                 const auto live = liveScene(*w.state);
                 return sceneToJson(captureScene(w.world(), live.first, live.second));
             },
             "The world's current state as scene-file JSON text (docs/scene-format.md).")
        .def("save_scene",
             [](const PyWorld& w, const std::filesystem::path& path) {
                 const auto live = liveScene(*w.state);
                 saveScene(captureScene(w.world(), live.first, live.second), path);
             },
             py::arg("path"),
             "Writes the world's current state as a scene file; load_scene(path) continues from it (solver warm "
             "starts restart). Joints and springs need named bodies.")
        .def_property(
            "scene_dt", [](const PyWorld& w) { return w.state->scene.dt; },
            [](PyWorld& w, Real dt) {
                w.world();
                // Checked here, not at run(): save_scene would write it too.
                if (!std::isfinite(dt) || !(dt >= std::numeric_limits<Real>::min())) {
                    std::ostringstream text;
                    text << "World.scene_dt: must be a positive finite time step in seconds, got " << dt;
                    throw Error(text.str());
                }
                w.state->scene.dt = dt;
            },
            "The scene file's dt (s), default 1/60: what run() and save_scene use.")
        .def_property(
            "scene_steps", [](const PyWorld& w) { return w.state->scene.steps; },
            [](PyWorld& w, int steps) {
                w.world();
                if (steps < 0) throw Error("World.scene_steps: must not be negative, got " + std::to_string(steps));
                w.state->scene.steps = steps;
            },
            "The scene file's step count, default 600.");

    py::class_<PyRecorder>(m, "Recorder",
                           "Records a run for replay outside the engine (docs/recording.md): capture() after each step, "
                           "then write('run.glb') (animated glTF) or write('run.html') (a self-contained replay page).")
        .def(py::init([](const PyWorld& w, double interval, bool contacts, bool bounds, const std::string& title) {
                 PyRecorder r{w.state, io::Recorder(w.world(), io::RecordOptions{interval, contacts, bounds, title})};
                 // Robot links (load_urdf, a scene's "urdf") are drawn as their URDF visuals (docs/robots.md).
                 const Scene& scene = w.state->scene;
                 const std::vector<BodyId>& ids = w.state->handles.bodies;
                 for (std::size_t i = 0; i < scene.bodies.size() && i < ids.size(); ++i) {
                     if (!scene.bodies[i].visuals.empty() && w.world().isValid(ids[i])) {
                         r.recorder.setVisuals(ids[i], scene.bodies[i].visuals);
                     }
                 }
                 return r;
             }),
             py::arg("world"), py::kw_only(), py::arg("capture_interval") = 0.0, py::arg("contacts") = true,
             py::arg("bounds") = true, py::arg("title") = "Fulcrum recording",
             "Starts recording the bodies, joints, ropes and cloths the world has now; robot links are drawn as their "
             "URDF visuals. capture_interval: seconds of simulated time between frames (0: every capture()).")
        .def("capture",
             [](PyRecorder& r) {
                 const WorldPtr s = lockWorld(r.owner, "Recorder");
                 r.recorder.capture(s->world);
             },
             "Appends a frame (the world's current state), if capture_interval has passed.")
        .def_property_readonly("frame_count", [](const PyRecorder& r) { return r.recorder.frameCount(); })
        .def("write", [](const PyRecorder& r, const std::filesystem::path& path) { r.recorder.write(path); }, py::arg("path"),
             "Writes .glb or .html (by extension).");
}

}  // namespace fulcrum::python
