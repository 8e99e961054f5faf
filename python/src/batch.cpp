// fulcrum._Batch: the C++ Batch (include/fulcrum/batch.hpp) for the Python
// class fulcrum.Batch (python/fulcrum/__init__.py turns scenes and override
// dicts into the JSON text this takes). Arrays out are float64 (N, bodies, k);
// arrays in are anything NumPy converts, checked for shape.
#include <atomic>
#include <string>
#include <utility>

#include <fulcrum/batch.hpp>
#include <fulcrum/scene_batch.hpp>
#include <fulcrum/snapshot.hpp>

#include "common.hpp"

namespace fulcrum::python {

namespace {

struct PyBatch {
    Batch batch;
    // As for a World: step() releases the GIL, so another Python thread could
    // reach the batch meanwhile; it is refused instead of racing.
    std::unique_ptr<std::atomic<bool>> busy = std::make_unique<std::atomic<bool>>(false);

    Batch& idle() {
        if (busy->load(std::memory_order_acquire)) fail("this batch is being stepped on another thread: wait for step() to return");
        return batch;
    }
};

using Gather = void (Batch::*)(std::span<Real>) const;
using Scatter = void (Batch::*)(std::span<const Real>);

py::array_t<double> gather(PyBatch& b, Gather read, py::ssize_t k) {
    Batch& batch = b.idle();
    const auto n = static_cast<py::ssize_t>(batch.size()), bodies = static_cast<py::ssize_t>(batch.bodyCount());
    std::vector<Real> values(static_cast<std::size_t>(n * bodies * k));
    (batch.*read)(values);
    py::array_t<double> out({n, bodies, k});
    double* d = out.mutable_data();
    for (Real v : values) *d++ = v;
    return out;
}

std::string shapeText(const py::array& a) {
    std::string s = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
    return s + (a.ndim() == 1 ? ",)" : ")");
}

std::vector<Real> checked(py::handle value, const char* function, std::vector<py::ssize_t> shape) {
    auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
    if (!a || value.is_none() || py::isinstance<py::str>(value)) {
        PyErr_Clear();
        throw py::type_error(std::string("Batch.") + function + ": expected an array of numbers, got " +
                             std::string(py::str(py::type::of(value).attr("__name__"))));
    }
    bool ok = a.ndim() == static_cast<py::ssize_t>(shape.size());
    for (std::size_t i = 0; ok && i < shape.size(); ++i) ok = a.shape(static_cast<py::ssize_t>(i)) == shape[i];
    if (!ok) {
        std::string want = "(";
        for (std::size_t i = 0; i < shape.size(); ++i) want += (i ? ", " : "") + std::to_string(shape[i]);
        fail(std::string("Batch.") + function + ": expected an array of shape " + want + ") (worlds, " +
             (shape.size() == 3 ? "bodies, 3" : "joints") + "), got shape " + shapeText(a));
    }
    const double* d = a.data();
    std::vector<Real> out(static_cast<std::size_t>(a.size()));
    for (Real& v : out) v = static_cast<Real>(*d++);
    return out;
}

void scatter(PyBatch& b, py::handle value, const char* function, Scatter write) {
    Batch& batch = b.idle();
    const std::vector<Real> v =
        checked(value, function, {static_cast<py::ssize_t>(batch.size()), static_cast<py::ssize_t>(batch.bodyCount()), 3});
    (batch.*write)(v);
}

std::vector<SceneOverrides> toOverrides(const std::vector<std::vector<std::pair<std::string, std::string>>>& sets) {
    std::vector<SceneOverrides> out;
    out.reserve(sets.size());
    for (const auto& set : sets) {
        SceneOverrides& o = out.emplace_back();
        for (const auto& [path, value] : set) o.push_back({path, value});
    }
    return out;
}

}  // namespace

void bindBatch(py::module_& m) {
    m.def(
        "_scene_run_settings",
        [](const std::string& sceneJson, const std::string& sourceName,
           const std::vector<std::pair<std::string, std::string>>& overrides) {
            SceneOverrides o;
            for (const auto& [path, value] : overrides) o.push_back({path, value});
            const Scene scene = parseSceneWithOverrides(sceneJson, o, sourceName);
            return py::make_tuple(static_cast<double>(scene.dt), scene.steps);
        },
        py::arg("scene_json"), py::arg("source_name"), py::arg("overrides"),
        "Reads a scene with overrides (raising SceneError as Batch would) and returns its (dt, steps).");
    py::class_<PyBatch>(m, "_Batch", "The compiled part of fulcrum.Batch (use that).")
        .def(py::init([](const std::string& sceneJson, const std::string& sourceName, std::size_t count,
                         const std::vector<std::vector<std::pair<std::string, std::string>>>& overrides, int threads) {
                 const std::vector<SceneOverrides> sets = toOverrides(overrides);
                 return PyBatch{makeSceneBatch(sceneJson, count, sets, BatchDef{threads}, sourceName)};
             }),
             py::arg("scene_json"), py::arg("source_name"), py::arg("count"), py::arg("overrides"), py::arg("threads"))
        .def(py::init([](const std::vector<std::string>& scenes, const std::vector<std::string>& names, int threads) {
                 return PyBatch{makeSceneBatch(scenes, BatchDef{threads}, names)};
             }),
             py::arg("scenes_json"), py::arg("source_names"), py::arg("threads"))
        .def("__len__", [](PyBatch& b) { return b.idle().size(); })
        .def_property_readonly("threads", [](PyBatch& b) { return b.idle().threads(); })
        .def_property_readonly("body_count", [](PyBatch& b) { return b.idle().bodyCount(); })
        .def_property_readonly("joint_count", [](PyBatch& b) { return b.idle().jointCount(); })
        .def("body_names",
             [](PyBatch& b, std::size_t w) {
                 const World& world = b.idle().world(w);
                 std::vector<std::string> names;
                 for (BodyId id : world.bodies()) names.push_back(world.name(id));
                 return names;
             },
             py::arg("world"))
        .def("body_types",
             [](PyBatch& b, std::size_t w) {
                 const World& world = b.idle().world(w);
                 std::vector<std::string> types;
                 for (BodyId id : world.bodies()) types.emplace_back(toString(world.bodyType(id)));
                 return types;
             },
             py::arg("world"))
        .def("step",
             [](PyBatch& b, double dt, long long steps) {
                 Batch& batch = b.idle();
                 if (steps < 0) fail("Batch.step: steps must be >= 0, got " + std::to_string(steps));
                 if (steps > std::numeric_limits<int>::max()) fail("Batch.step: steps is too large");
                 b.busy->store(true, std::memory_order_release);
                 struct Clear {
                     std::atomic<bool>& flag;
                     ~Clear() { flag.store(false, std::memory_order_release); }
                 } clear{*b.busy};
                 py::gil_scoped_release release;
                 batch.step(static_cast<Real>(dt), static_cast<int>(steps));
             },
             py::arg("dt"), py::arg("steps") = 1)
        .def("positions", [](PyBatch& b) { return gather(b, &Batch::positions, 3); })
        .def("orientations", [](PyBatch& b) { return gather(b, &Batch::orientations, 4); })
        .def("linear_velocities", [](PyBatch& b) { return gather(b, &Batch::linearVelocities, 3); })
        .def("angular_velocities", [](PyBatch& b) { return gather(b, &Batch::angularVelocities, 3); })
        .def("set_linear_velocities",
             [](PyBatch& b, py::handle v) { scatter(b, v, "set_linear_velocities", &Batch::setLinearVelocities); })
        .def("set_angular_velocities",
             [](PyBatch& b, py::handle v) { scatter(b, v, "set_angular_velocities", &Batch::setAngularVelocities); })
        .def("apply_forces", [](PyBatch& b, py::handle v) { scatter(b, v, "apply_forces", &Batch::applyForces); })
        .def("set_joint_motor_speeds",
             [](PyBatch& b, py::handle v) {
                 Batch& batch = b.idle();
                 const std::vector<Real> speeds = checked(
                     v, "set_joint_motor_speeds", {static_cast<py::ssize_t>(batch.size()), static_cast<py::ssize_t>(batch.jointCount())});
                 batch.setJointMotorSpeeds(speeds);
             })
        .def("reset", [](PyBatch& b, std::size_t w) { b.idle().reset(w); })
        .def("reset",
             [](PyBatch& b, std::size_t w, const py::bytes& snapshot) {
                 const std::string bytes = snapshot;
                 b.idle().reset(w, std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
             })
        .def("snapshot", [](PyBatch& b, std::size_t w) {
            const std::vector<std::uint8_t> bytes = b.idle().snapshot(w);
            return py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size());
        });
}

}  // namespace fulcrum::python
