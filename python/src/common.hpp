#pragma once
// Shared pieces of the Python binding (docs/python.md): the world the Python
// objects share, the handle classes, and conversions between Python values and
// the engine's math types.
//
// Lifetime: a Python `World` owns its engine World through a shared_ptr; every
// handle (Body, Joint, Spring, Rope, Cloth) keeps only a weak_ptr, so a handle
// that outlives its world raises fulcrum.Error instead of touching freed memory,
// and handles never keep a world alive behind the user's back.
//
// Threads: World.step releases the GIL. A world is not safe to use from two
// threads at once (as in C++), so `busy` marks a world being stepped and every
// other call on it from another Python thread raises instead of racing.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <fulcrum/fulcrum.hpp>
#include <fulcrum/scene.hpp>

namespace fulcrum::python {

namespace py = pybind11;

// The engine world and what the binding keeps beside it.
struct WorldState {
    World world;
    std::atomic<bool> busy{false};
    // The scene description this world was built from (load_scene) or that the
    // binding keeps up to date as objects are created from Python: save_scene
    // writes captureScene(world, scene, handles).
    Scene scene;
    SceneHandles handles;
    bool sceneKnown = true;  // false for a snapshot without the binding's scene description
    // A Python exception raised inside a force callback during step(): kept
    // here (with the GIL held) and raised when step() returns.
    std::optional<py::error_already_set> callbackError;
    std::atomic<bool> callbackFailed{false};

    explicit WorldState(World w) : world(std::move(w)) {}

    // The live bodies in creation order (World::bodies() sorts them at every
    // call: 1.2 ms for 10,000 bodies). Kept here; creating a body appends to
    // it, destroying one marks it stale. All changes go through the binding.
    const std::vector<BodyId>& creationOrder() {
        if (orderStale || order.size() != world.bodyCount()) {
            order = world.bodies();
            orderStale = false;
        }
        return order;
    }
    void bodyCreated(BodyId id) {
        if (!orderStale && order.size() + 1 == world.bodyCount()) order.push_back(id);
        else orderStale = true;
    }
    void bodyDestroyed() { orderStale = true; }

private:
    std::vector<BodyId> order;
    bool orderStale = true;
};
using WorldPtr = std::shared_ptr<WorldState>;

// Raises fulcrum.Error (a C++ fulcrum::Error translated by the module).
[[noreturn]] void fail(const std::string& message);

// The world of a handle, or fulcrum.Error when it is gone; also refuses a
// world being stepped on another thread.
WorldPtr lockWorld(const std::weak_ptr<WorldState>& weak, const char* what);
void checkIdle(const WorldState& state);

// RAII: marks a world busy for the duration of a step.
class BusyGuard {
public:
    explicit BusyGuard(WorldState& state);
    ~BusyGuard();
    BusyGuard(const BusyGuard&) = delete;
    BusyGuard& operator=(const BusyGuard&) = delete;

private:
    WorldState& state_;
};

// The Python `World` object.
struct PyWorld {
    WorldPtr state;
    World& world() const {
        checkIdle(*state);
        return state->world;
    }
};

// A handle to an object of a world: Body, Joint, Spring, ParticleSystem.
template <class Id>
struct Handle {
    std::weak_ptr<WorldState> owner;
    Id id;
    // The engine world, after checking that the world lives and the handle is
    // valid; throws fulcrum.Error otherwise.
    struct Access {
        WorldPtr keep;
        World& world;
    };
    Access access(const char* what) const {
        WorldPtr keep = lockWorld(owner, what);
        World& world = keep->world;
        if (!world.isValid(id))
            fail(std::string("stale ") + what + " handle (index " + std::to_string(id.index) +
                 "): it was destroyed");
        return {std::move(keep), world};
    }
    bool sameAs(const Handle& o) const { return !owner.owner_before(o.owner) && !o.owner.owner_before(owner) && id == o.id; }
};
using BodyHandle = Handle<BodyId>;
using JointHandle = Handle<JointId>;
using SpringHandle = Handle<SpringId>;
using ParticleHandle = Handle<ParticleSystemId>;

void compactScene(WorldState& state);

// World.destroy_*: refuses another world's handle, destroys, and drops the
// description of what is gone.
template <class Id, class Destroy>
void destroyOwned(PyWorld& w, const Handle<Id>& h, const char* what, Destroy destroy) {
    World& world = w.world();
    if (h.owner.lock() != w.state) fail(std::string(what) + ": it belongs to another world");
    destroy(world, h.id);
    compactScene(*w.state);
}

// Handles of a world's objects as a Python list.
template <class Id>
py::list handleList(const WorldPtr& state, const std::vector<Id>& ids) {
    py::list out;
    for (const Id id : ids) out.append(Handle<Id>{state, id});
    return out;
}

// ---- conversions. Arrays the binding returns are float64 (the engine's
// float32 values widened exactly); inputs are any sequence or array of numbers.
Vec3 toVec3(py::handle value, const char* argument);
Quat toQuat(py::handle value, const char* argument);   // (w, x, y, z)
std::vector<Vec3> toVec3List(py::handle value, const char* argument);  // (n, 3)
py::array_t<double> fromVec3(const Vec3& v);
py::array_t<double> fromQuat(const Quat& q);
py::array_t<double> fromVec3List(std::span<const Vec3> values);
Mat3 toMat3(py::handle value, const char* argument);    // (3, 3), or a diagonal (3,)
py::array_t<double> fromMat3(const Mat3& m);
BodyId bodyIdOf(py::handle value, const WorldPtr& state, const char* argument);  // a Body of this world, or None: the static world

std::string reprVec3(const Vec3& v);

// ---- the modules' parts, one per area
void bindShapes(py::module_& m);
void bindWorld(py::module_& m);
void bindBodies(py::module_& m);
void bindJoints(py::module_& m);
void bindParticles(py::module_& m);
void bindCharacters(py::module_& m);
void bindVehicles(py::module_& m);
void bindQueries(py::module_& m);
void bindIo(py::module_& m);
void bindBatch(py::module_& m);
void bindRobots(py::module_& m);

// Shapes to scene-file descriptions (save_scene of a Python-built world), and
// to the Python class of their kind.
ShapeDesc describeShape(const Shape& shape);
py::object shapeToPython(const Shape& shape);

// The scene kept beside a world (WorldState::scene and handles) as the
// snapshot's user data, so a pickled or snapshotted world can still save_scene.
std::string packScene(const WorldState& state);
void unpackScene(WorldState& state, const std::string& userData);
// compactScene (above) drops the description of destroyed objects once they
// outnumber the live ones, so create/destroy cycles don't grow memory
// (amortised O(1) per destroy).

// Handle objects of a world (bodies.cpp, joints.cpp, particles.cpp); None for a null id.
py::object bodyObject(const WorldPtr& state, BodyId id);

}  // namespace fulcrum::python
