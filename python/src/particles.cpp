// Ropes and cloths: World.create_rope / create_cloth and the ParticleSystem
// handle, whose particle positions come out as one (n, 3) array.
#include "common.hpp"

namespace fulcrum::python {

namespace {

std::vector<std::array<int, 2>> toPins(py::handle value) {
    std::vector<std::array<int, 2>> out;
    if (value.is_none()) return out;
    auto a = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(value);
    if (!a || !((a.ndim() == 2 && a.shape(1) == 2) || (a.ndim() == 1 && a.shape(0) == 0))) {
        PyErr_Clear();
        throw py::type_error("argument 'pinned': expected a list of (i, j) particle indices");
    }
    const long long* d = a.data();
    for (py::ssize_t i = 0; a.ndim() == 2 && i < a.shape(0); ++i)
        out.push_back({static_cast<int>(d[2 * i]), static_cast<int>(d[2 * i + 1])});
    return out;
}

}  // namespace

void bindParticles(py::module_& m) {
    using P = ParticleHandle;
    py::class_<P>(m, "ParticleSystem", "A rope or a cloth of Verlet particles (docs/particles.md).")
        .def_property_readonly("type", [](const P& p) {
            auto a = p.access("ParticleSystem");
            return std::string(a.world.particleSystemType(p.id) == ParticleSystemType::Rope ? "rope" : "cloth");
        }, "'rope' or 'cloth'")
        .def_property_readonly("name", [](const P& p) { auto a = p.access("ParticleSystem"); return a.world.name(p.id); })
        .def_property_readonly("particle_count", [](const P& p) { auto a = p.access("ParticleSystem"); return a.world.particleCount(p.id); })
        .def_property_readonly("size", [](const P& p) {
            auto a = p.access("ParticleSystem");
            const auto s = a.world.clothSize(p.id);
            return py::make_tuple(s[0], s[1]);
        }, "Cloth: (columns, rows), particle (i, j) is row j * columns + i of positions(); rope: (n, 1).")
        .def_property_readonly("radius", [](const P& p) { auto a = p.access("ParticleSystem"); return a.world.particleRadius(p.id); })
        .def("positions", [](const P& p) { auto a = p.access("ParticleSystem"); return fromVec3List(a.world.particlePositions(p.id)); },
             "(n, 3) float64 particle positions.")
        .def("velocities", [](const P& p) {
            auto a = p.access("ParticleSystem");
            const std::size_t n = a.world.particleCount(p.id);
            std::vector<Vec3> v(n);
            for (std::size_t i = 0; i < n; ++i) v[i] = a.world.particleVelocity(p.id, i);
            return fromVec3List(v);
        }, "(n, 3) velocities over the last particle sub-step.")
        .def("report", [](const P& p) {
            auto a = p.access("ParticleSystem");
            const ParticleReport r = a.world.particleReport(p.id);
            return py::dict(py::arg("name") = r.name, py::arg("particles") = r.particles,
                            py::arg("centroid") = fromVec3(r.centroid), py::arg("max_stretch") = r.maxStretch,
                            py::arg("mean_stretch") = r.meanStretch, py::arg("max_penetration") = r.maxPenetration);
        }, "The figures of --json's particle_systems entry.")
        .def_property_readonly("valid", [](const P& p) { const WorldPtr s = p.owner.lock(); return s && s->world.isValid(p.id); })
        .def("__eq__", [](const P& a, const P& b) { return a.sameAs(b); })
        .def("__repr__", [](const P& p) {
            const WorldPtr s = p.owner.lock();
            if (!s || !s->world.isValid(p.id)) return std::string("<fulcrum.ParticleSystem (gone)>");
            const bool rope = s->world.particleSystemType(p.id) == ParticleSystemType::Rope;
            return std::string("<fulcrum.ParticleSystem ") + (rope ? "rope" : "cloth") + " '" + s->world.name(p.id) + "', " +
                   std::to_string(s->world.particleCount(p.id)) + " particles>";
        });

    auto cls = py::reinterpret_borrow<py::class_<PyWorld>>(m.attr("World"));
    const RopeDef r;
    const ClothDef c;
    cls.def(
        "create_rope",
        [](PyWorld& w, py::object start, py::object end, int segments, Real particleMass, Real radius, bool pinStart,
           bool pinEnd, py::object attachStart, py::object attachEnd, Real stretch, Real bend, Real damping,
           Real friction, Real attachCompliance, bool tethers, const std::string& name) {
            World& world = w.world();
            RopeDef def;
            def.name = name;
            def.start = toVec3(start, "start");
            def.end = toVec3(end, "end");
            def.segments = segments;
            def.particleMass = particleMass;
            def.radius = radius;
            def.pinStart = pinStart;
            def.pinEnd = pinEnd;
            def.attachStart = bodyIdOf(attachStart, w.state, "attach_start");
            def.attachEnd = bodyIdOf(attachEnd, w.state, "attach_end");
            def.stretchCompliance = stretch;
            def.bendCompliance = bend;
            def.damping = damping;
            def.friction = friction;
            def.attachCompliance = attachCompliance;
            def.tethers = tethers;
            const ParticleSystemId id = world.createRope(def);
            const auto named = [&](BodyId b) { return b.isNull() ? std::string() : world.name(b); };
            w.state->scene.ropes.push_back({def, named(def.attachStart), named(def.attachEnd), {}});
            w.state->handles.ropes.push_back(id);
            return ParticleHandle{w.state, id};
        },
        py::kw_only(), py::arg("start"), py::arg("end"), py::arg("segments") = r.segments,
        py::arg("particle_mass") = r.particleMass, py::arg("radius") = r.radius, py::arg("pin_start") = r.pinStart,
        py::arg("pin_end") = r.pinEnd, py::arg("attach_start") = py::none(), py::arg("attach_end") = py::none(),
        py::arg("stretch_compliance") = r.stretchCompliance, py::arg("bend_compliance") = r.bendCompliance,
        py::arg("damping") = r.damping, py::arg("friction") = r.friction,
        py::arg("attach_compliance") = r.attachCompliance, py::arg("tethers") = r.tethers, py::arg("name") = "",
        "A rope of segments + 1 particles from start to end (the C++ RopeDef's fields). attach_start / attach_end: "
        "a Body to tie that end to.");
    cls.def(
        "create_cloth",
        [](PyWorld& w, py::object origin, py::object uAxis, py::object vAxis, std::array<int, 2> size, Real spacing,
           Real particleMass, Real radius, py::object pinned, Real stretch, Real bend, std::optional<Real> shear,
           Real damping, Real friction, bool selfCollision, bool tethers, Real drag, Real lift, const std::string& name) {
            World& world = w.world();
            ClothDef def;
            def.name = name;
            def.origin = toVec3(origin, "origin");
            def.uAxis = toVec3(uAxis, "u_axis");
            def.vAxis = toVec3(vAxis, "v_axis");
            def.size = size;
            def.spacing = spacing;
            def.particleMass = particleMass;
            def.radius = radius;
            def.pinned = toPins(pinned);
            def.stretchCompliance = stretch;
            def.bendCompliance = bend;
            def.shearCompliance = shear;
            def.damping = damping;
            def.friction = friction;
            def.selfCollision = selfCollision;
            def.tethers = tethers;
            def.dragCoefficient = drag;
            def.liftCoefficient = lift;
            const ParticleSystemId id = world.createCloth(def);
            w.state->scene.cloths.push_back({def, {}});
            w.state->handles.cloths.push_back(id);
            return ParticleHandle{w.state, id};
        },
        py::kw_only(), py::arg("origin") = py::make_tuple(0, 0, 0), py::arg("u_axis") = py::make_tuple(1, 0, 0),
        py::arg("v_axis") = py::make_tuple(0, 0, 1), py::arg("size") = c.size, py::arg("spacing") = c.spacing,
        py::arg("particle_mass") = c.particleMass, py::arg("radius") = c.radius, py::arg("pinned") = py::none(),
        py::arg("stretch_compliance") = c.stretchCompliance, py::arg("bend_compliance") = c.bendCompliance,
        py::arg("shear_compliance") = py::none(), py::arg("damping") = c.damping, py::arg("friction") = c.friction,
        py::arg("self_collision") = c.selfCollision, py::arg("tethers") = c.tethers,
        py::arg("drag_coefficient") = c.dragCoefficient, py::arg("lift_coefficient") = c.liftCoefficient,
        py::arg("name") = "",
        "A cloth of size = (columns, rows) particles; particle (i, j) starts at origin + spacing * (i u_axis + j "
        "v_axis). pinned: [(i, j), ...] particles held in place (the C++ ClothDef's fields).");
    cls
        .def("destroy_particle_system",
             [](PyWorld& w, const ParticleHandle& p) {
                 destroyOwned(w, p, "destroy_particle_system",
                              [](World& world, ParticleSystemId id) { world.destroyParticleSystem(id); });
             },
             py::arg("system"))
        .def("particle_systems",
             [](const PyWorld& w) { return handleList(w.state, w.world().particleSystems()); },
             "Every live rope and cloth, in creation order.")
        .def("find_particle_system",
             [](const PyWorld& w, const std::string& name) -> py::object {
                 const World& world = w.world();
                 for (const ParticleSystemId id : world.particleSystems())
                     if (world.name(id) == name) return py::cast(ParticleHandle{w.state, id});
                 return py::none();
             },
             py::arg("name"), "The first rope or cloth with this name, or None.");
}

}  // namespace fulcrum::python
