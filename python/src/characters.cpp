// Characters: World.create_character and the Character handle (docs/characters.md).
#include "common.hpp"

namespace fulcrum::python {

using CharacterHandle = Handle<CharacterId>;

void bindCharacters(py::module_& m) {
    using C = CharacterHandle;
    py::class_<C>(m, "Character",
                  "A kinematic capsule character moved at the end of every step by its input (docs/characters.md).")
        .def_property_readonly("name", [](const C& c) { auto a = c.access("Character"); return a.world.name(c.id); })
        .def_property_readonly("position", [](const C& c) {
            auto a = c.access("Character");
            return fromVec3(a.world.characterState(c.id).position);
        }, "Capsule centre, (3,) float64.")
        .def_property_readonly("velocity", [](const C& c) {
            auto a = c.access("Character");
            return fromVec3(a.world.characterState(c.id).velocity);
        }, "m/s over the last step (its own motion plus the ground's).")
        .def_property_readonly("ground_state", [](const C& c) {
            auto a = c.access("Character");
            return std::string(toString(a.world.characterState(c.id).ground));
        }, "'on_ground', 'on_steep_ground' or 'in_air'.")
        .def_property_readonly("on_ground", [](const C& c) {
            auto a = c.access("Character");
            return a.world.characterState(c.id).ground == GroundState::OnGround;
        })
        .def_property_readonly("ground_normal", [](const C& c) {
            auto a = c.access("Character");
            return fromVec3(a.world.characterState(c.id).groundNormal);
        })
        .def_property_readonly("ground_velocity", [](const C& c) {
            auto a = c.access("Character");
            return fromVec3(a.world.characterState(c.id).groundVelocity);
        })
        .def_property_readonly("body", [](const C& c) {
            auto a = c.access("Character");
            return BodyHandle{a.keep, a.world.characterBody(c.id)};
        }, "The character's kinematic capsule body.")
        .def("set_input", [](const C& c, py::object velocity, bool jump) {
            auto a = c.access("Character");
            checkIdle(*a.keep);
            a.world.setCharacterInput(c.id, toVec3(velocity, "velocity"), jump);
        }, py::arg("velocity"), py::arg("jump") = false,
           "The held input: desired velocity (horizontal part, relative to the ground) and whether to jump.")
        .def("__eq__", [](const C& a, const C& b) { return a.sameAs(b); })
        .def("__repr__", [](const C& c) {
            const WorldPtr s = c.owner.lock();
            if (!s || !s->world.isValid(c.id)) return std::string("<fulcrum.Character (gone)>");
            return "<fulcrum.Character '" + s->world.name(c.id) + "'>";
        });

    auto cls = py::reinterpret_borrow<py::class_<PyWorld>>(m.attr("World"));
    const CharacterDef d;
    cls.def(
        "create_character",
        [](PyWorld& w, py::object position, Real radius, Real height, Real mass, Real maxSlope, Real stepHeight,
           Real jumpSpeed, Real maxPushForce, Real stickDistance, const std::string& name) {
            World& world = w.world();
            CharacterDef def;
            def.name = name;
            def.position = toVec3(position, "position");
            def.radius = radius;
            def.height = height;
            def.mass = mass;
            def.maxSlope = maxSlope;
            def.stepHeight = stepHeight;
            def.jumpSpeed = jumpSpeed;
            def.maxPushForce = maxPushForce;
            def.stickDistance = stickDistance;
            const CharacterId id = world.createCharacter(def);
            w.state->scene.characters.push_back({def, {}});
            w.state->handles.characters.push_back(id);
            return CharacterHandle{w.state, id};
        },
        py::kw_only(), py::arg("position"), py::arg("radius") = d.radius, py::arg("height") = d.height,
        py::arg("mass") = d.mass, py::arg("max_slope") = d.maxSlope, py::arg("step_height") = d.stepHeight,
        py::arg("jump_speed") = d.jumpSpeed, py::arg("max_push_force") = d.maxPushForce,
        py::arg("stick_distance") = d.stickDistance, py::arg("name") = "",
        "A character (the C++ CharacterDef's fields); set its input with Character.set_input.");
    cls.def("characters", [](PyWorld& w) { return handleList(w.state, w.world().characters()); },
            "The live characters in creation order.");
}

}  // namespace fulcrum::python
