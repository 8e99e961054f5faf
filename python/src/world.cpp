// fulcrum.World: settings, stepping (the GIL released), state of all bodies as
// NumPy arrays, bulk setters, diagnostics, events, snapshots and pickle.
#include <cmath>
#include <cstring>

#include <fulcrum/snapshot.hpp>

#include "world/world_access.hpp"

#include "common.hpp"

namespace fulcrum::python {

namespace {

Integrator integratorNamed(const std::string& name) {
    const auto i = integratorFromString(name);
    if (!i) fail("world: unknown integrator '" + name + "' (use 'explicit_euler', 'semi_implicit_euler' or 'verlet')");
    return *i;
}

// Rows of the body list selected by `indices` (None: every body, in creation order).
std::vector<BodyId> selectBodies(WorldState& state, const py::object& indices) {
    const std::vector<BodyId>& all = state.creationOrder();
    if (indices.is_none()) return all;
    auto a = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(indices);
    if (!a || a.ndim() != 1) {
        PyErr_Clear();
        throw py::type_error("argument 'indices': expected a 1-d array of body indices (creation order)");
    }
    std::vector<BodyId> out(static_cast<std::size_t>(a.shape(0)));
    const long long* d = a.data();
    for (std::size_t i = 0; i < out.size(); ++i) {
        const long long k = d[i] < 0 ? d[i] + static_cast<long long>(all.size()) : d[i];
        if (k < 0 || k >= static_cast<long long>(all.size()))
            throw py::index_error("indices[" + std::to_string(i) + "] = " + std::to_string(d[i]) + " is out of range for " +
                                  std::to_string(all.size()) + " bodies");
        out[i] = all[static_cast<std::size_t>(k)];
    }
    return out;
}

// An (n, 3) float64 view of `values`, checked against the selection's size.
py::array_t<double, py::array::c_style | py::array::forcecast> rows3(const py::object& values, std::size_t n,
                                                                    const char* argument) {
    auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(values);
    if (!a || values.is_none() || a.ndim() != 2 || a.shape(1) != 3) {
        PyErr_Clear();
        throw py::type_error(std::string("argument '") + argument + "': expected an (n, 3) array of numbers");
    }
    if (static_cast<std::size_t>(a.shape(0)) != n)
        fail(std::string(argument) + ": " + std::to_string(a.shape(0)) + " rows for " + std::to_string(n) + " bodies");
    return a;
}

// One row per body in creation order, read straight from the dense arrays
// (the same expressions as World::position & co., without re-validating each
// handle of a list that is valid by construction).
template <int Columns, class Get>
py::array_t<double> gather(const PyWorld& w, Get get) {
    w.world();
    const std::vector<BodyId>& ids = w.state->creationOrder();
    const WorldImpl& impl = detail::implOf(w.state->world);
    py::array_t<double> out({static_cast<py::ssize_t>(ids.size()), py::ssize_t(Columns)});
    double* d = out.mutable_data();
    for (const BodyId id : ids) {
        get(impl, impl.bodySlots[id.index].dense, d);
        d += Columns;
    }
    return out;
}
inline void put(double* d, const Vec3& v) { d[0] = v.x, d[1] = v.y, d[2] = v.z; }

// WorldImpl::origin, the same bits, a third of the time for the usual body
// whose centre of mass is its origin: rotate(q, (+0, +0, +0)) is (+0, +0, +0)
// for every finite q (v + t w + u x t with v = +0 adds to +0 first), and
// com - (+0) is com, so only a local centre of mass with a non-zero bit needs
// the rotation.
inline Vec3 origin(const WorldImpl& impl, std::uint32_t dense) {
    const Vec3& c = impl.params[dense].localCom;
    const auto positiveZero = [](Real r) { return r == 0 && !std::signbit(r); };
    if (positiveZero(c.x) && positiveZero(c.y) && positiveZero(c.z))
        return impl.motion[dense].com;
    return impl.origin(dense);
}

template <class Set>
void scatter3(PyWorld& w, const py::object& values, const py::object& indices, const char* argument, Set set) {
    w.world();
    const std::vector<BodyId> ids = selectBodies(*w.state, indices);
    const auto a = rows3(values, ids.size(), argument);
    const double* d = a.data();
    // Check every row first, so a bad row changes nothing.
    for (std::size_t i = 0; i < 3 * ids.size(); ++i)
        if (!std::isfinite(static_cast<Real>(d[i])))
            fail(std::string(argument) + "[" + std::to_string(i / 3) + "]: must be finite, got " + std::to_string(d[i]));
    for (std::size_t i = 0; i < ids.size(); ++i)
        set(ids[i], Vec3{Real(d[3 * i]), Real(d[3 * i + 1]), Real(d[3 * i + 2])});
}

}  // namespace


static py::list eventList(const WorldPtr& state, std::span<const ContactEvent> events) {
    py::list out;
    for (const ContactEvent& e : events) out.append(py::make_tuple(bodyObject(state, e.bodyA), bodyObject(state, e.bodyB)));
    return out;
}

void bindWorld(py::module_& m) {
    const WorldDef d;
    py::class_<PyWorld> world(m, "World",
                              "A simulated world: bodies, joints, springs, ropes and cloths, advanced by step(dt).\n\n"
                              "Every keyword is a field of the C++ WorldDef (include/fulcrum/world.hpp) with its default.");
    world.def(py::init([](py::object gravity, const std::string& integrator, int substeps, int solverIterations,
                          bool sleeping, int threads, std::uint32_t parallelMinBodies, Real contactHertz,
                          Real contactDampingRatio, Real contactPushMaxVelocity, Real speculativeMargin,
                          Real restitutionThreshold, Real jointHertz, Real jointDampingRatio, Real maxRotationPerSubstep,
                          Real jointProjectionSlop, bool jointDirectSolve, Real linearSleepVelocity,
                          Real angularSleepVelocity, Real timeToSleep, bool continuousCollision,
                          std::int64_t maxContactPairs, Real hitEventThreshold, bool pushOutGrownOverlaps) {
                  WorldDef def;
                  def.gravity = toVec3(gravity, "gravity");
                  def.integrator = integratorNamed(integrator);
                  def.substeps = substeps;
                  def.solverIterations = solverIterations;
                  def.sleeping = sleeping;
                  def.threads = threads;
                  def.parallelMinBodies = parallelMinBodies;
                  def.contactHertz = contactHertz;
                  def.contactDampingRatio = contactDampingRatio;
                  def.contactPushMaxVelocity = contactPushMaxVelocity;
                  def.speculativeMargin = speculativeMargin;
                  def.restitutionThreshold = restitutionThreshold;
                  def.jointHertz = jointHertz;
                  def.jointDampingRatio = jointDampingRatio;
                  def.maxRotationPerSubstep = maxRotationPerSubstep;
                  def.jointProjectionSlop = jointProjectionSlop;
                  def.jointDirectSolve = jointDirectSolve;
                  def.linearSleepVelocity = linearSleepVelocity;
                  def.angularSleepVelocity = angularSleepVelocity;
                  def.timeToSleep = timeToSleep;
                  def.continuousCollision = continuousCollision;
                  def.maxContactPairs = maxContactPairs;
                  def.hitEventThreshold = hitEventThreshold;
                  def.pushOutGrownOverlaps = pushOutGrownOverlaps;
                  auto state = std::make_shared<WorldState>(World(def));
                  state->scene.world = def;
                  return PyWorld{std::move(state)};
              }),
              py::kw_only(), py::arg("gravity") = py::make_tuple(d.gravity.x, d.gravity.y, d.gravity.z),
              py::arg("integrator") = std::string(toString(d.integrator)), py::arg("substeps") = d.substeps,
              py::arg("solver_iterations") = d.solverIterations, py::arg("sleeping") = d.sleeping,
              py::arg("threads") = d.threads, py::arg("parallel_min_bodies") = d.parallelMinBodies,
              py::arg("contact_hertz") = d.contactHertz, py::arg("contact_damping_ratio") = d.contactDampingRatio,
              py::arg("contact_push_max_velocity") = d.contactPushMaxVelocity,
              py::arg("speculative_margin") = d.speculativeMargin,
              py::arg("restitution_threshold") = d.restitutionThreshold, py::arg("joint_hertz") = d.jointHertz,
              py::arg("joint_damping_ratio") = d.jointDampingRatio,
              py::arg("max_rotation_per_substep") = d.maxRotationPerSubstep,
              py::arg("joint_projection_slop") = d.jointProjectionSlop,
              py::arg("joint_direct_solve") = d.jointDirectSolve,
              py::arg("linear_sleep_velocity") = d.linearSleepVelocity,
              py::arg("angular_sleep_velocity") = d.angularSleepVelocity, py::arg("time_to_sleep") = d.timeToSleep,
              py::arg("continuous_collision") = d.continuousCollision,
              py::arg("max_contact_pairs") = d.maxContactPairs, py::arg("hit_event_threshold") = d.hitEventThreshold,
              py::arg("push_out_grown_overlaps") = d.pushOutGrownOverlaps);

    // ---- settings
    world
        .def_property(
            "gravity", [](const PyWorld& w) { return fromVec3(w.world().settings().gravity); },
            [](PyWorld& w, py::object g) { w.world().setGravity(toVec3(g, "gravity")); }, "m/s^2, (3,)")
        .def_property(
            "integrator", [](const PyWorld& w) { return std::string(toString(w.world().settings().integrator)); },
            [](PyWorld& w, const std::string& name) { w.world().setIntegrator(integratorNamed(name)); },
            "'explicit_euler', 'semi_implicit_euler' or 'verlet'")
        .def_property(
            "substeps", [](const PyWorld& w) { return w.world().settings().substeps; },
            [](PyWorld& w, int n) { w.world().setSubsteps(n); })
        .def_property(
            "solver_iterations", [](const PyWorld& w) { return w.world().settings().solverIterations; },
            [](PyWorld& w, int n) { w.world().setSolverIterations(n); })
        .def_property(
            "sleeping", [](const PyWorld& w) { return w.world().settings().sleeping; },
            [](PyWorld& w, bool on) { w.world().setSleepingEnabled(on); })
        .def_property(
            "threads", [](const PyWorld& w) { return w.world().settings().threads; },
            [](PyWorld& w, int n) { w.world().setThreadCount(n); }, "Worker threads of step(); results are identical for every count.")
        .def_property(
            "parallel_min_bodies", [](const PyWorld& w) { return w.world().settings().parallelMinBodies; },
            [](PyWorld& w, std::uint32_t n) { w.world().setParallelMinBodies(n); })
        .def_property(
            "hit_event_threshold", [](const PyWorld& w) { return w.world().settings().hitEventThreshold; },
            [](PyWorld& w, Real v) { w.world().setHitEventThreshold(v); },
            "m/s: slower impacts make no contact_hit_events().")
        .def_property(
            "max_contact_pairs", [](const PyWorld& w) { return w.world().settings().maxContactPairs; },
            [](PyWorld& w, std::int64_t n) { w.world().setMaxContactPairs(n); },
            "The contact pair limit; 0 is automatic (docs/solver.md, 'Contact pair limit').")
        .def_property(
            "push_out_grown_overlaps", [](const PyWorld& w) { return w.world().settings().pushOutGrownOverlaps; },
            [](PyWorld& w, bool on) {
                w.world().setPushOutGrownOverlaps(on);
                w.state->scene.world.pushOutGrownOverlaps = on;  // save_scene writes it
            },
            "Pairs that got deeper within a step are pushed apart by position after the sub-steps "
            "(WorldDef::pushOutGrownOverlaps, docs/solver.md 'Grown overlaps'); off by default; from the next step on.")
        .def("settings",
             [](const PyWorld& w) {
                 const WorldDef& s = w.world().settings();
                 py::dict out;
                 out["gravity"] = fromVec3(s.gravity);
                 out["integrator"] = toString(s.integrator);
                 out["substeps"] = s.substeps;
                 out["solver_iterations"] = s.solverIterations;
                 out["sleeping"] = s.sleeping;
                 out["threads"] = s.threads;
                 out["parallel_min_bodies"] = s.parallelMinBodies;
                 out["contact_hertz"] = s.contactHertz;
                 out["contact_damping_ratio"] = s.contactDampingRatio;
                 out["contact_push_max_velocity"] = s.contactPushMaxVelocity;
                 out["speculative_margin"] = s.speculativeMargin;
                 out["restitution_threshold"] = s.restitutionThreshold;
                 out["hit_event_threshold"] = s.hitEventThreshold;
                 out["joint_hertz"] = s.jointHertz;
                 out["joint_damping_ratio"] = s.jointDampingRatio;
                 out["max_rotation_per_substep"] = s.maxRotationPerSubstep;
                 out["joint_projection_slop"] = s.jointProjectionSlop;
                 out["joint_direct_solve"] = s.jointDirectSolve;
                 out["linear_sleep_velocity"] = s.linearSleepVelocity;
                 out["angular_sleep_velocity"] = s.angularSleepVelocity;
                 out["time_to_sleep"] = s.timeToSleep;
                 out["continuous_collision"] = s.continuousCollision;
                 out["max_contact_pairs"] = s.maxContactPairs;
                 out["push_out_grown_overlaps"] = s.pushOutGrownOverlaps;
                 return out;
             },
             "Every WorldDef field as a dict (the World() keywords).");

    // ---- stepping
    world.def(
        "step",
        [](PyWorld& w, py::handle dtValue, py::handle stepsValue) {
            // Converted here rather than by pybind11, to name the argument in
            // a TypeError at no cost (the same conversion: double, then Real).
            const double seconds = PyFloat_AsDouble(dtValue.ptr());
            if (seconds == -1.0 && PyErr_Occurred()) {
                PyErr_Clear();
                throw py::type_error("step(): argument 'dt': expected float, got " +
                                     std::string(py::str(py::type::of(dtValue).attr("__name__"))));
            }
            const Real dt = static_cast<Real>(seconds);
            const auto index = py::reinterpret_steal<py::object>(PyNumber_Index(stepsValue.ptr()));
            if (!index) {
                PyErr_Clear();
                throw py::type_error("step(): argument 'steps': expected int, got " +
                                     std::string(py::str(py::type::of(stepsValue).attr("__name__"))));
            }
            const long long steps = PyLong_AsLongLong(index.ptr());
            if (steps == -1 && PyErr_Occurred()) {
                PyErr_Clear();
                fail("step: steps is too large");
            }
            if (steps < 0) fail("step: steps must be >= 0, got " + std::to_string(steps));
            WorldState& state = *w.state;
            {
                BusyGuard busy(state);
                py::gil_scoped_release release;
                for (long long i = 0; i < steps && !state.callbackFailed.load(std::memory_order_relaxed); ++i)
                    state.world.step(dt);
            }
            if (state.callbackFailed.exchange(false)) {
                py::error_already_set e = std::move(*state.callbackError);
                state.callbackError.reset();
                throw e;
            }
        },
        py::arg("dt"), py::arg("steps") = 1,
        "Advances the world by `steps` steps of dt seconds, all in C++ with the GIL released (other Python threads "
        "run meanwhile; this world must not be used by them until it returns). Raises fulcrum.NumericalError if the "
        "state becomes NaN/inf, and re-raises an exception of a force callback after the step it happened in.");
    world.def_property_readonly("time", [](const PyWorld& w) { return w.world().time(); }, "Simulated seconds.")
        .def_property_readonly("step_count", [](const PyWorld& w) { return w.world().stepCount(); });

    // ---- all bodies as arrays (creation order)
    world
        .def("positions", [](const PyWorld& w) { return gather<3>(w, [](const WorldImpl& i, std::uint32_t k, double* o) { put(o, origin(i, k)); }); },
             "Body origins, (N, 3) float64, creation order.")
        .def("centers_of_mass", [](const PyWorld& w) { return gather<3>(w, [](const WorldImpl& i, std::uint32_t k, double* o) { put(o, i.motion[k].com); }); },
             "(N, 3) float64, creation order.")
        .def("linear_velocities", [](const PyWorld& w) { return gather<3>(w, [](const WorldImpl& i, std::uint32_t k, double* o) { put(o, i.motion[k].v); }); },
             "Velocities of the centres of mass, (N, 3) float64, creation order.")
        .def("angular_velocities", [](const PyWorld& w) { return gather<3>(w, [](const WorldImpl& i, std::uint32_t k, double* o) { put(o, i.motion[k].w); }); },
             "rad/s in world axes, (N, 3) float64, creation order.")
        .def("orientations",
             [](const PyWorld& w) {
                 return gather<4>(w, [](const WorldImpl& i, std::uint32_t k, double* o) {
                     const Quat& q = i.motion[k].q;
                     o[0] = q.w, o[1] = q.x, o[2] = q.y, o[3] = q.z;
                 });
             },
             "Unit quaternions (w, x, y, z), (N, 4) float64, creation order.")
        .def("awake",
             [](const PyWorld& w) {
                 const World& x = w.world();
                 const std::vector<BodyId>& ids = w.state->creationOrder();
                 py::array_t<bool> out(static_cast<py::ssize_t>(ids.size()));
                 bool* p = out.mutable_data();
                 for (const BodyId id : ids) *p++ = x.isAwake(id);
                 return out;
             },
             "Awake flags, (N,) bool, creation order.")
        .def("set_positions",
             [](PyWorld& w, py::object values, py::object indices) {
                 World& x = w.state->world;
                 scatter3(w, values, indices, "positions", [&](BodyId id, const Vec3& p) { x.setTransform(id, p, x.orientation(id)); });
             },
             py::arg("positions"), py::arg("indices") = py::none(),
             "Teleports bodies (all, or those at `indices` in creation order) to (n, 3) positions, keeping orientations.")
        ;
    // The bulk forms of the per-body setters: one call for all bodies (or
    // those at `indices`), every row checked before any is applied.
    using Setter = void (World::*)(BodyId, const Vec3&);
    const auto bulk = [&](const char* name, const char* argument, Setter set, const char* doc) {
        world.def(
            name,
            [argument, set](PyWorld& w, py::object values, py::object indices) {
                World& x = w.state->world;
                scatter3(w, values, indices, argument, [&](BodyId id, const Vec3& v) { (x.*set)(id, v); });
            },
            py::arg(argument), py::arg("indices") = py::none(), doc);
    };
    bulk("set_linear_velocities", "velocities", &World::setLinearVelocity,
         "Sets the linear velocities of all bodies (or those at `indices`, creation order) from an (n, 3) array.");
    bulk("set_angular_velocities", "velocities", &World::setAngularVelocity,
         "Sets the angular velocities (rad/s, world axes) of all bodies (or those at `indices`) from an (n, 3) array.");
    bulk("apply_forces", "forces", &World::applyForceAtCenter,
         "Adds (n, 3) forces (N) at the centres of mass for the next step, to all bodies or those at `indices`.");
    bulk("apply_torques", "torques", &World::applyTorque, "Adds (n, 3) torques (N m) for the next step.");
    bulk("apply_impulses", "impulses", &World::applyLinearImpulseAtCenter,
         "Linear impulses (N s) at the centres of mass, applied at once.");

    // ---- diagnostics
    world
        .def("energy",
             [](const PyWorld& w) {
                 const EnergyReport e = w.world().energy();
                 return py::dict(py::arg("kinetic") = e.kinetic, py::arg("potential") = e.potential, py::arg("total") = e.total);
             },
             "{'kinetic', 'potential', 'total'} in joules (double precision).")
        .def("linear_momentum", [](const PyWorld& w) { return fromVec3(w.world().linearMomentum()); })
        .def("angular_momentum", [](const PyWorld& w) { return fromVec3(w.world().angularMomentum()); },
             "About the world origin.")
        .def("last_step_profile",
             [](const PyWorld& w) {
                 const StepProfile p = w.world().lastStepProfile();
                 py::dict out;
                 out["total"] = p.total, out["collide"] = p.collide, out["prepare"] = p.prepare, out["solve"] = p.solve;
                 out["store"] = p.store, out["continuous"] = p.continuous, out["particles"] = p.particles;
                 out["sleep"] = p.sleep, out["finish"] = p.finish, out["awake_bodies"] = p.awakeBodies;
                 out["contact_constraints"] = p.contactConstraints, out["joint_constraints"] = p.jointConstraints;
                 out["workers"] = p.workers;
                 out["contact_pairs"] = p.contactPairs, out["contact_pair_limit"] = p.contactPairLimit;
                 out["pairs_left_out"] = p.pairsLeftOut, out["bodies_over_pair_limit"] = p.bodiesOverPairLimit;
                 return out;
             },
             "Wall-clock milliseconds per phase of the last step, and what it worked on (docs/api.md, 'Profiling').")
        .def("warnings",
             [](const PyWorld& w) {
                 py::list out;
                 for (const WorldWarning& warning : w.world().warnings()) {
                     out.append(py::dict(py::arg("step") = warning.step, py::arg("message") = warning.message));
                 }
                 return out;
             },
             "[{'step', 'message'}, ...]: what the world noticed (e.g. the contact pair limit held pairs back), oldest first.")
        .def("deep_overlaps",
             [](const PyWorld& w, Real fraction) {
                 py::list out;
                 for (const DeepOverlap& o : w.world().deepOverlaps(fraction)) {
                     out.append(py::dict(py::arg("body_a") = bodyObject(w.state, o.bodyA),
                                         py::arg("body_b") = bodyObject(w.state, o.bodyB), py::arg("depth") = o.depth,
                                         py::arg("size") = o.size));
                 }
                 return out;
             },
             py::arg("fraction") = Real(0.1),
             "[{'body_a', 'body_b', 'depth', 'size'}, ...]: pairs left overlapping deeper than fraction x the smaller "
             "body's smallest extent, deepest first (World::deepOverlaps, docs/api.md).");

    // ---- events of the last step
    world
        .def("contact_begin_events", [](const PyWorld& w) { w.world(); return eventList(w.state, w.state->world.contactBeginEvents()); },
             "[(body_a, body_b), ...]: pairs that started touching in the last step.")
        .def("contact_end_events", [](const PyWorld& w) { w.world(); return eventList(w.state, w.state->world.contactEndEvents()); },
             "Pairs that stopped touching in the last step (a destroyed body's pairs name it as None).")
        .def("sensor_begin_events", [](const PyWorld& w) { w.world(); return eventList(w.state, w.state->world.sensorBeginEvents()); },
             "[(sensor, visitor), ...]")
        .def("sensor_end_events", [](const PyWorld& w) { w.world(); return eventList(w.state, w.state->world.sensorEndEvents()); });

    // ---- snapshots and pickle
    world
        .def("save_snapshot",
             [](const PyWorld& w, py::object path) -> py::object {
                 const std::vector<std::uint8_t> bytes = saveSnapshotToMemory(w.world(), packScene(*w.state));
                 if (path.is_none()) return py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size());
                 saveSnapshot(w.world(), std::string(py::str(path)), packScene(*w.state));
                 return py::none();
             },
             py::arg("path") = py::none(),
             "The whole state as bytes (or written to `path`): load_snapshot continues it bit for bit. Force callbacks are "
             "code, not data: set them again after loading.")
        .def(py::pickle(
            [](const PyWorld& w) {
                const std::vector<std::uint8_t> bytes = saveSnapshotToMemory(w.world(), packScene(*w.state));
                return py::make_tuple(py::bytes(reinterpret_cast<const char*>(bytes.data()), bytes.size()));
            },
            [](py::tuple t) {
                if (t.size() != 1 || !py::isinstance<py::bytes>(t[0])) fail("World pickle: expected (snapshot bytes,)");
                const std::string bytes = t[0].cast<std::string>();
                std::string user;
                World loaded = loadSnapshotFromMemory(
                    std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()), &user, "pickle");
                auto state = std::make_shared<WorldState>(std::move(loaded));
                unpackScene(*state, user);
                return PyWorld{std::move(state)};
            }))
        .def("__repr__", [](const PyWorld& w) {
            const World& x = w.world();
            return "<fulcrum.World: " + std::to_string(x.bodyCount()) + " bodies, " + std::to_string(x.joints().size()) +
                   " joints, t = " + std::to_string(x.time()) + " s, " + toString(x.settings().integrator) + ">";
        });

    m.def(
        "load_snapshot",
        [](py::object source) {
            std::string user;
            World loaded = [&] {
                if (py::isinstance<py::bytes>(source)) {
                    const std::string bytes = source.cast<std::string>();
                    return loadSnapshotFromMemory(std::span(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()),
                                                  &user, "snapshot bytes");
                }
                return loadSnapshot(std::string(py::str(source)), &user);
            }();
            auto state = std::make_shared<WorldState>(std::move(loaded));
            unpackScene(*state, user);
            return PyWorld{std::move(state)};
        },
        py::arg("source"), "A World from snapshot bytes (World.save_snapshot()) or a snapshot file path.");
}

}  // namespace fulcrum::python
