// The extension module fulcrum._fulcrum: errors, conversions and the parts of
// the API (one file per area). The pure-Python package fulcrum/__init__.py
// re-exports it (docs/python.md).
#include <cmath>
#include <cstdio>
#include <span>

#include "common.hpp"

namespace fulcrum::python {

void fail(const std::string& message) { throw Error(message); }

void checkIdle(const WorldState& state) {
    if (state.busy.load(std::memory_order_acquire))
        fail("this world is being stepped on another thread: wait for step() to return");
}

WorldPtr lockWorld(const std::weak_ptr<WorldState>& weak, const char* what) {
    WorldPtr state = weak.lock();
    if (!state) fail(std::string("this ") + what + "'s world no longer exists (the World object was deleted)");
    checkIdle(*state);
    return state;
}

BusyGuard::BusyGuard(WorldState& state) : state_(state) {
    bool expected = false;
    if (!state_.busy.compare_exchange_strong(expected, true, std::memory_order_acq_rel))
        fail("this world is being stepped on another thread: wait for step() to return");
}
BusyGuard::~BusyGuard() { state_.busy.store(false, std::memory_order_release); }

namespace {

[[noreturn]] void typeError(const char* argument, const std::string& expected, py::handle got) {
    throw py::type_error(std::string("argument '") + argument + "': expected " + expected + ", got " +
                         std::string(py::str(py::type::of(got).attr("__name__"))));
}

py::array_t<double, py::array::c_style | py::array::forcecast> shaped(py::handle value, const char* argument,
                                                                     const std::string& expected, py::ssize_t columns,
                                                                     bool list) {
    auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
    if (!a || value.is_none() || py::isinstance<py::str>(value)) {
        PyErr_Clear();
        typeError(argument, expected, value);
    }
    const bool ok = list ? (a.ndim() == 2 && a.shape(1) == columns) || (a.ndim() == 1 && a.shape(0) == 0)
                         : (a.ndim() == 1 && a.shape(0) == columns);
    if (!ok) {
        std::string shape = "(";
        for (py::ssize_t i = 0; i < a.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(a.shape(i));
        shape += a.ndim() == 1 ? ",)" : ")";
        throw py::type_error(std::string("argument '") + argument + "': expected " + expected + ", got shape " + shape);
    }
    return a;
}

}  // namespace

Vec3 toVec3(py::handle value, const char* argument) {
    const auto a = shaped(value, argument, "3 numbers (x, y, z)", 3, false);
    const double* d = a.data();
    return {Real(d[0]), Real(d[1]), Real(d[2])};
}

Quat toQuat(py::handle value, const char* argument) {
    const auto a = shaped(value, argument, "4 numbers (w, x, y, z)", 4, false);
    const double* d = a.data();
    return {Real(d[0]), Real(d[1]), Real(d[2]), Real(d[3])};
}

std::vector<Vec3> toVec3List(py::handle value, const char* argument) {
    const auto a = shaped(value, argument, "an (n, 3) array of numbers", 3, true);
    std::vector<Vec3> out(a.ndim() == 2 ? static_cast<std::size_t>(a.shape(0)) : 0);
    const double* d = a.data();
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = {Real(d[3 * i]), Real(d[3 * i + 1]), Real(d[3 * i + 2])};
    return out;
}

Mat3 toMat3(py::handle value, const char* argument) {
    auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
    if (!a || value.is_none()) {
        PyErr_Clear();
        typeError(argument, "a 3x3 matrix or 3 diagonal numbers", value);
    }
    const double* d = a.data();
    if (a.ndim() == 1 && a.shape(0) == 3) return Mat3::diagonal(Vec3{Real(d[0]), Real(d[1]), Real(d[2])});
    if (a.ndim() == 2 && a.shape(0) == 3 && a.shape(1) == 3)
        return Mat3::fromRows({Real(d[0]), Real(d[1]), Real(d[2])}, {Real(d[3]), Real(d[4]), Real(d[5])},
                              {Real(d[6]), Real(d[7]), Real(d[8])});
    throw py::type_error(std::string("argument '") + argument + "': expected a 3x3 matrix or 3 diagonal numbers");
}

py::array_t<double> fromVec3(const Vec3& v) {
    py::array_t<double> a(3);
    double* d = a.mutable_data();
    d[0] = v.x, d[1] = v.y, d[2] = v.z;
    return a;
}

py::array_t<double> fromQuat(const Quat& q) {
    py::array_t<double> a(4);
    double* d = a.mutable_data();
    d[0] = q.w, d[1] = q.x, d[2] = q.y, d[3] = q.z;
    return a;
}

py::array_t<double> fromVec3List(std::span<const Vec3> values) {
    py::array_t<double> a({static_cast<py::ssize_t>(values.size()), py::ssize_t(3)});
    double* d = a.mutable_data();
    for (const Vec3& v : values) *d++ = v.x, *d++ = v.y, *d++ = v.z;
    return a;
}

py::array_t<double> fromMat3(const Mat3& m) {
    py::array_t<double> a({py::ssize_t(3), py::ssize_t(3)});
    double* d = a.mutable_data();
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) *d++ = m(r, c);
    return a;
}

BodyId bodyIdOf(py::handle value, const WorldPtr& state, const char* argument) {
    if (value.is_none()) return kWorldBody;
    if (!py::isinstance<BodyHandle>(value)) typeError(argument, "a Body or None (the static world)", value);
    const auto& body = value.cast<const BodyHandle&>();
    const WorldPtr owner = body.owner.lock();
    if (owner != state) fail(std::string(argument) + ": the body belongs to another world (or its world is gone)");
    if (!state->world.isValid(body.id)) fail(std::string(argument) + ": stale Body handle: that body was destroyed");
    return body.id;
}

std::string reprVec3(const Vec3& v) {
    char text[96];
    std::snprintf(text, sizeof text, "(%.6g, %.6g, %.6g)", double(v.x), double(v.y), double(v.z));
    return text;
}

}  // namespace fulcrum::python

PYBIND11_MODULE(_fulcrum, m) {
    namespace fp = fulcrum::python;
    m.doc() = "Fulcrum, a 3D rigid-body physics engine: the compiled core of the `fulcrum` package (docs/python.md).";
    // Translators: the most derived first (pybind11 tries the last registered first).
    auto& error = pybind11::register_exception<fulcrum::Error>(m, "Error", PyExc_ValueError);
    error.doc() = "Every bad input and engine error: the C++ fulcrum::Error, with its message. A ValueError.";
    auto& sceneError = pybind11::register_exception<fulcrum::SceneError>(m, "SceneError", error.ptr());
    sceneError.doc() = "A problem in a scene file: the message names the file, the path in the document and the line.";
    auto& numericalError = pybind11::register_exception<fulcrum::NumericalError>(m, "NumericalError", error.ptr());
    numericalError.doc() = "The simulation state became NaN or infinite during step(); the message names the body.";
    m.attr("real_bytes") = sizeof(fulcrum::Real);

    fp::bindShapes(m);
    fp::bindWorld(m);
    fp::bindBodies(m);
    fp::bindJoints(m);
    fp::bindParticles(m);
    fp::bindCharacters(m);
    fp::bindVehicles(m);
    fp::bindQueries(m);
    fp::bindIo(m);
    fp::bindBatch(m);
    fp::bindRobots(m);
}
