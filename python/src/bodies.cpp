// Bodies: World.create_body / destroy_body / find_body / bodies, and the Body
// handle class with its properties, forces, impulses and force callbacks.
#include <cmath>
#include <cstdio>

#include "common.hpp"

namespace fulcrum::python {

namespace {

BodyType bodyTypeNamed(const std::string& name) {
    if (name == "dynamic") return BodyType::Dynamic;
    if (name == "static") return BodyType::Static;
    if (name == "kinematic") return BodyType::Kinematic;
    fail("body: unknown type '" + name + "' (use 'dynamic', 'static' or 'kinematic')");
}

// The state handed to a force callback, as read-only NumPy-valued attributes.
struct PyKinematics {
    BodyKinematics k;
};

// A Python callable as a ForceCallback. The callable is released with the GIL
// held whichever thread drops the last copy of the std::function.
ForceCallback makeCallback(WorldState& state, py::function fn) {
    auto owned = std::shared_ptr<py::object>(new py::object(std::move(fn)), [](py::object* p) {
        py::gil_scoped_acquire gil;
        delete p;
    });
    WorldState* s = &state;  // the callback lives inside the world it points to
    return [s, owned](const BodyKinematics& k) -> Wrench {
        py::gil_scoped_acquire gil;
        if (s->callbackFailed.load(std::memory_order_relaxed)) return {};
        try {
            const py::object result = (*owned)(PyKinematics{k});
            if (result.is_none()) return {};
            if (!py::isinstance<py::sequence>(result) || py::len(result) != 2)
                throw py::type_error("force callback: expected it to return (force, torque) or None");
            const py::sequence pair = py::reinterpret_borrow<py::sequence>(result);
            return {toVec3(pair[0], "force"), toVec3(pair[1], "torque")};
        } catch (py::error_already_set& e) {
            s->callbackError.emplace(std::move(e));
        } catch (py::builtin_exception& e) {
            e.set_error();
            s->callbackError.emplace();
        } catch (const std::exception& e) {
            PyErr_SetString(PyExc_RuntimeError, e.what());
            s->callbackError.emplace();
        }
        s->callbackFailed.store(true);
        return {};
    };
}

std::string bodyLabel(const World& w, BodyId id) {
    const std::string& name = w.name(id);
    return name.empty() ? "#" + std::to_string(id.index) : "'" + name + "'";
}

}  // namespace

py::object bodyObject(const WorldPtr& state, BodyId id) {
    if (id.isNull()) return py::none();
    return py::cast(BodyHandle{state, id});
}

void bindBodies(py::module_& m) {
    py::class_<PyKinematics>(m, "BodyKinematics", "The state a force callback sees: centre of mass, orientation, velocities, mass, time.")
        .def_property_readonly("position", [](const PyKinematics& k) { return fromVec3(k.k.position); }, "Centre of mass, world.")
        .def_property_readonly("orientation", [](const PyKinematics& k) { return fromQuat(k.k.orientation); })
        .def_property_readonly("linear_velocity", [](const PyKinematics& k) { return fromVec3(k.k.linearVelocity); })
        .def_property_readonly("angular_velocity", [](const PyKinematics& k) { return fromVec3(k.k.angularVelocity); })
        .def_property_readonly("mass", [](const PyKinematics& k) { return k.k.mass; })
        .def_property_readonly("time", [](const PyKinematics& k) { return k.k.time; });

    using B = BodyHandle;
    py::class_<B> body(m, "Body",
                       "A handle to a body of a World. Its properties read and write the world; after "
                       "World.destroy_body (or once the World is deleted) every use raises fulcrum.Error.");
    body.def_property_readonly("name", [](const B& b) { auto a = b.access("Body"); return a.world.name(b.id); })
        .def_property_readonly("type", [](const B& b) { auto a = b.access("Body"); return std::string(toString(a.world.bodyType(b.id))); },
                               "'dynamic', 'static' or 'kinematic'")
        .def_property_readonly("shape", [](const B& b) { auto a = b.access("Body"); return shapeToPython(a.world.shape(b.id)); })
        .def_property_readonly("mass", [](const B& b) { auto a = b.access("Body"); return a.world.mass(b.id); },
                               "kg (0 for static and kinematic bodies)")
        .def_property_readonly("inertia", [](const B& b) { auto a = b.access("Body"); return fromMat3(a.world.localInertia(b.id)); },
                               "About the centre of mass, body axes, (3, 3).")
        .def_property_readonly("local_center_of_mass", [](const B& b) { auto a = b.access("Body"); return fromVec3(a.world.localCenterOfMass(b.id)); })
        .def_property_readonly("center_of_mass", [](const B& b) { auto a = b.access("Body"); return fromVec3(a.world.centerOfMass(b.id)); },
                               "World space.")
        .def_property(
            "position", [](const B& b) { auto a = b.access("Body"); return fromVec3(a.world.position(b.id)); },
            [](const B& b, py::object p) {
                auto a = b.access("Body");
                a.world.setTransform(b.id, toVec3(p, "position"), a.world.orientation(b.id));
            },
            "The body origin (the shape's frame), (3,) float64. Setting it teleports the body (and wakes it).")
        .def_property(
            "orientation", [](const B& b) { auto a = b.access("Body"); return fromQuat(a.world.orientation(b.id)); },
            [](const B& b, py::object q) {
                auto a = b.access("Body");
                a.world.setTransform(b.id, a.world.position(b.id), toQuat(q, "orientation"));
            },
            "Unit quaternion (w, x, y, z), (4,) float64.")
        .def_property(
            "linear_velocity", [](const B& b) { auto a = b.access("Body"); return fromVec3(a.world.linearVelocity(b.id)); },
            [](const B& b, py::object v) { auto a = b.access("Body"); a.world.setLinearVelocity(b.id, toVec3(v, "linear_velocity")); },
            "Of the centre of mass, m/s, (3,).")
        .def_property(
            "angular_velocity", [](const B& b) { auto a = b.access("Body"); return fromVec3(a.world.angularVelocity(b.id)); },
            [](const B& b, py::object v) { auto a = b.access("Body"); a.world.setAngularVelocity(b.id, toVec3(v, "angular_velocity")); },
            "rad/s, world axes, (3,).")
        .def_property(
            "friction", [](const B& b) { auto a = b.access("Body"); return a.world.friction(b.id); },
            [](const B& b, Real f) { auto a = b.access("Body"); a.world.setFriction(b.id, f); })
        .def_property(
            "restitution", [](const B& b) { auto a = b.access("Body"); return a.world.restitution(b.id); },
            [](const B& b, Real r) { auto a = b.access("Body"); a.world.setRestitution(b.id, r); })
        .def_property(
            "awake", [](const B& b) { auto a = b.access("Body"); return a.world.isAwake(b.id); },
            [](const B& b, bool on) {
                auto a = b.access("Body");
                if (!on) fail("body " + bodyLabel(a.world, b.id) + ": bodies fall asleep by themselves; only awake = True is allowed");
                a.world.wake(b.id);
            },
            "False while asleep; set True to wake it.")
        .def_property_readonly("valid", [](const B& b) {
            const WorldPtr s = b.owner.lock();
            return s && s->world.isValid(b.id);
        }, "False once the body was destroyed or its world deleted (never raises).")
        .def_property_readonly("id", [](const B& b) { return py::make_tuple(b.id.index, b.id.generation); },
                               "(slot index, generation) of the engine's BodyId.")
        .def("set_transform",
             [](const B& b, py::object p, py::object q) {
                 auto a = b.access("Body");
                 a.world.setTransform(b.id, toVec3(p, "position"), toQuat(q, "orientation"));
             },
             py::arg("position"), py::arg("orientation"), "Teleports the body (also resets its previous transform).")
        .def("move_kinematic",
             [](const B& b, py::object p, py::object q, Real dt) {
                 auto a = b.access("Body");
                 a.world.moveKinematic(b.id, Transform(toVec3(p, "position"), toQuat(q, "orientation")), dt);
             },
             py::arg("position"), py::arg("orientation"), py::arg("dt"),
             "Kinematic bodies: sets the velocities that bring it to (position, orientation) after a step of dt.")
        .def("previous_transform", [](const B& b) {
            auto a = b.access("Body");
            const Transform t = a.world.previousTransform(b.id);
            return py::make_tuple(fromVec3(t.p), fromQuat(t.q));
        }, "(position, orientation) at the start of the last step.")
        .def("velocity_at_point", [](const B& b, py::object p) { auto a = b.access("Body"); return fromVec3(a.world.velocityAtPoint(b.id, toVec3(p, "point"))); },
             py::arg("point"), "Velocity of the body's material at a world point.")
        .def("set_gravity_scale", [](const B& b, Real s) { auto a = b.access("Body"); a.world.setGravityScale(b.id, s); }, py::arg("scale"))
        .def("set_damping", [](const B& b, Real lin, Real ang) { auto a = b.access("Body"); a.world.setDamping(b.id, lin, ang); },
             py::arg("linear"), py::arg("angular"), "1/s: v *= 1 / (1 + h c) each sub-step.")
        .def("set_drag", [](const B& b, Real lin, Real quad) { auto a = b.access("Body"); a.world.setDrag(b.id, lin, quad); },
             py::arg("linear"), py::arg("quadratic"), "F = -linear v - quadratic |v| v.")
        .def("wake", [](const B& b) { auto a = b.access("Body"); a.world.wake(b.id); })
        .def("apply_force",
             [](const B& b, py::object f, py::object point) {
                 auto a = b.access("Body");
                 if (point.is_none()) a.world.applyForceAtCenter(b.id, toVec3(f, "force"));
                 else a.world.applyForce(b.id, toVec3(f, "force"), toVec3(point, "point"));
             },
             py::arg("force"), py::arg("point") = py::none(),
             "Adds a force (N) for the next step, at a world point (default: the centre of mass).")
        .def("apply_torque", [](const B& b, py::object t) { auto a = b.access("Body"); a.world.applyTorque(b.id, toVec3(t, "torque")); },
             py::arg("torque"), "Adds a torque (N m) for the next step.")
        .def("apply_impulse",
             [](const B& b, py::object j, py::object point) {
                 auto a = b.access("Body");
                 if (point.is_none()) a.world.applyLinearImpulseAtCenter(b.id, toVec3(j, "impulse"));
                 else a.world.applyLinearImpulse(b.id, toVec3(j, "impulse"), toVec3(point, "point"));
             },
             py::arg("impulse"), py::arg("point") = py::none(), "Changes the velocity at once (N s), at a world point (default: the centre of mass).")
        .def("apply_angular_impulse", [](const B& b, py::object j) { auto a = b.access("Body"); a.world.applyAngularImpulse(b.id, toVec3(j, "impulse")); },
             py::arg("impulse"))
        .def("set_force_callback",
             [](const B& b, py::object fn) {
                 auto a = b.access("Body");
                 if (fn.is_none()) {
                     a.world.setForceCallback(b.id, {});
                     return;
                 }
                 if (!PyCallable_Check(fn.ptr())) throw py::type_error("argument 'callback': expected a callable or None");
                 a.world.setForceCallback(b.id, makeCallback(*a.keep, py::reinterpret_borrow<py::function>(fn)));
             },
             py::arg("callback"),
             "callback(k: BodyKinematics) -> (force, torque) or None, called at every force evaluation of the "
             "integrator (several per step, with the GIL taken for it). It must be deterministic and must not use the "
             "World. An exception in it stops step() and is raised from there. None removes it.")
        .def("__eq__", [](const B& a, const B& b) { return a.sameAs(b); })
        .def("__hash__", [](const B& b) { return py::hash(py::make_tuple(reinterpret_cast<std::uintptr_t>(b.owner.lock().get()), b.id.index, b.id.generation)); })
        .def("__repr__", [](const B& b) {
            const WorldPtr s = b.owner.lock();
            if (!s) return std::string("<fulcrum.Body (world deleted)>");
            if (!s->world.isValid(b.id)) return "<fulcrum.Body #" + std::to_string(b.id.index) + " (destroyed)>";
            const World& w = s->world;
            return "<fulcrum.Body " + bodyLabel(w, b.id) + " " + toString(w.bodyType(b.id)) + " " +
                   toString(w.shape(b.id).type()) + " at " + reprVec3(w.position(b.id)) + ">";
        });

    auto cls = py::reinterpret_borrow<py::class_<PyWorld>>(m.attr("World"));
    const BodyDef d;
    cls.def(
        "create_body",
        [](PyWorld& w, py::object shape, py::object position, py::object orientation, const std::string& type, Real mass,
           Real density, py::object inertia, py::object linearVelocity, py::object angularVelocity, Real friction,
           Real restitution, Real rollingResistance, Real linearDamping, Real angularDamping, Real linearDrag,
           Real quadraticDrag, Real gravityScale, std::uint32_t category, std::uint32_t mask, std::int32_t group,
           bool isSensor, bool isBullet, bool allowSleep, bool awake, const std::string& name) {
            World& world = w.world();
            BodyDef def;
            def.name = name;
            def.type = bodyTypeNamed(type);
            if (!shape.is_none()) {
                if (!py::isinstance<Shape>(shape)) throw py::type_error("argument 'shape': expected a fulcrum Shape (Sphere, Box, ...)");
                def.shape = shape.cast<Shape>();
            }
            def.mass = mass;
            def.density = density;
            if (!inertia.is_none()) def.inertia = toMat3(inertia, "inertia");
            def.position = toVec3(position, "position");
            def.orientation = toQuat(orientation, "orientation");
            def.linearVelocity = toVec3(linearVelocity, "linear_velocity");
            def.angularVelocity = toVec3(angularVelocity, "angular_velocity");
            def.friction = friction;
            def.restitution = restitution;
            def.rollingResistance = rollingResistance;
            def.linearDamping = linearDamping;
            def.angularDamping = angularDamping;
            def.linearDrag = linearDrag;
            def.quadraticDrag = quadraticDrag;
            def.gravityScale = gravityScale;
            def.filter = {category, mask, group};
            def.isSensor = isSensor;
            def.isBullet = isBullet;
            def.allowSleep = allowSleep;
            def.awake = awake;
            const BodyId id = world.createBody(def);
            w.state->bodyCreated(id);
            SceneBody entry{def, describeShape(def.shape), {}};
            entry.def.shape = Shape();
            w.state->scene.bodies.push_back(std::move(entry));
            w.state->handles.bodies.push_back(id);
            return BodyHandle{w.state, id};
        },
        py::kw_only(), py::arg("shape") = py::none(), py::arg("position") = py::make_tuple(0, 0, 0),
        py::arg("orientation") = py::make_tuple(1, 0, 0, 0), py::arg("type") = "dynamic", py::arg("mass") = d.mass,
        py::arg("density") = d.density, py::arg("inertia") = py::none(), py::arg("linear_velocity") = py::make_tuple(0, 0, 0),
        py::arg("angular_velocity") = py::make_tuple(0, 0, 0), py::arg("friction") = d.friction,
        py::arg("restitution") = d.restitution, py::arg("rolling_resistance") = d.rollingResistance,
        py::arg("linear_damping") = d.linearDamping, py::arg("angular_damping") = d.angularDamping,
        py::arg("linear_drag") = d.linearDrag, py::arg("quadratic_drag") = d.quadraticDrag,
        py::arg("gravity_scale") = d.gravityScale, py::arg("category") = d.filter.category,
        py::arg("mask") = d.filter.mask, py::arg("group") = d.filter.group, py::arg("is_sensor") = d.isSensor,
        py::arg("is_bullet") = d.isBullet, py::arg("allow_sleep") = d.allowSleep, py::arg("awake") = d.awake,
        py::arg("name") = "",
        "Creates a body; every keyword is a field of the C++ BodyDef (include/fulcrum/body.hpp) with its default. "
        "shape: default a unit sphere. mass > 0 sets the mass, else density * volume. inertia: (3, 3) or its "
        "diagonal, about the centre of mass in body axes. Bad values raise fulcrum.Error naming the field.");
    cls
        .def("destroy_body",
             [](PyWorld& w, const BodyHandle& b) {
                 destroyOwned(w, b, "destroy_body", [&](World& world, BodyId id) {
                     world.destroyBody(id);
                     w.state->bodyDestroyed();
                 });
             },
             py::arg("body"), "Destroys a body (and its springs and joints); its handles then raise.")
        .def("find_body",
             [](const PyWorld& w, const std::string& name) { return bodyObject(w.state, w.world().findBody(name)); },
             py::arg("name"), "The first body with this name, or None.")
        .def("body",
             [](const PyWorld& w, const std::string& name) {
                 const BodyId id = w.world().findBody(name);
                 if (id.isNull()) fail("no body named '" + name + "'");
                 return BodyHandle{w.state, id};
             },
             py::arg("name"), "The first body with this name; fulcrum.Error if there is none.")
        .def("bodies",
             [](const PyWorld& w) {
                 w.world();
                 return handleList(w.state, w.state->creationOrder());
             },
             "Every live body, in creation order (the rows of positions() and the other arrays).")
        .def_property_readonly("body_count", [](const PyWorld& w) { return w.world().bodyCount(); });
}

}  // namespace fulcrum::python
