// Joints and springs. Each joint type has its own creation function with only
// the keywords that type uses (create_hinge_joint(a, b, anchor=, axis=,
// limits=, motor_speed=, ...)), rather than the C++ JointDef that holds every
// type's fields; the Joint handle reads the solver's results and changes
// motors, limits and springs later.
#include <cmath>
#include <limits>

#include "common.hpp"

namespace fulcrum::python {

namespace {

constexpr Real kInf = std::numeric_limits<Real>::infinity();

// A scene's name for a joint's or spring's body: its name, "" for the world,
// and a marker save_scene reports for unnamed bodies (the format joins by name).
const char* const kUnnamed = "\x01unnamed";
std::string sceneName(const World& w, BodyId id) {
    if (id.isNull()) return "";
    const std::string& name = w.name(id);
    return name.empty() ? kUnnamed : name;
}

std::pair<Real, Real> pairOf(py::handle value, const char* argument) {
    const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
    if (!a || a.ndim() != 1 || a.shape(0) != 2) {
        PyErr_Clear();
        throw py::type_error(std::string("argument '") + argument + "': expected (lower, upper)");
    }
    return {Real(a.data()[0]), Real(a.data()[1])};
}

struct Common {
    py::object bodyA, bodyB;
    std::string name;
    bool collideConnected = false;
    Real breakForce = kInf, breakTorque = kInf;
};

JointHandle create(PyWorld& w, JointDef def, const Common& c) {
    World& world = w.world();
    def.bodyA = bodyIdOf(c.bodyA, w.state, "body_a");
    def.bodyB = bodyIdOf(c.bodyB, w.state, "body_b");
    if (def.bodyB.isNull()) fail("joint: body_b must be a Body (body_a may be None: the static world)");
    def.name = c.name;
    def.collideConnected = c.collideConnected;
    def.breakForce = c.breakForce;
    def.breakTorque = c.breakTorque;
    const JointId id = world.createJoint(def);
    w.state->scene.joints.push_back({def, sceneName(world, def.bodyA), sceneName(world, def.bodyB), {}});
    w.state->handles.joints.push_back(id);
    return JointHandle{w.state, id};
}

void setMotor(JointDef& def, const py::object& speed, Real maxForce) {
    if (speed.is_none()) return;
    def.motor = {true, speed.cast<Real>(), maxForce};
}
void setLimits(JointDef& def, const py::object& limits) {
    if (limits.is_none()) return;
    const auto [lo, hi] = pairOf(limits, "limits");
    def.hasLimits = true, def.lowerLimit = lo, def.upperLimit = hi;
}
void setSpring(JointDef& def, Real target, Real stiffness, Real damping, Real maxForce) {
    if (stiffness == 0 && damping == 0) return;
    def.spring = {true, target, stiffness, damping, maxForce};
}

// Six-DOF axes by name or index, and one axis's settings from a dict in the
// scene format's shape: "free" / "locked", or {"mode", "limits": (lo, hi),
// "motor": {"speed", "max_force"}, "spring": {"target", "stiffness", "damping", "max_force"}}.
constexpr const char* kAxisNames[kSixDofAxes] = {"x", "y", "z", "rx", "ry", "rz"};
int axisIndex(py::handle key) {
    if (py::isinstance<py::str>(key)) {
        const std::string name = key.cast<std::string>();
        for (int k = 0; k < kSixDofAxes; ++k) {
            if (name == kAxisNames[k]) return k;
        }
        fail("six-DOF axis '" + name + "' is not one of x, y, z, rx, ry, rz");
    }
    const int k = key.cast<int>();
    if (k < 0 || k >= kSixDofAxes) fail("six-DOF axis " + std::to_string(k) + " is not in 0..5");
    return k;
}
AxisMode axisMode(const std::string& name) {
    if (name == "free") return AxisMode::Free;
    if (name == "limited") return AxisMode::Limited;
    if (name == "locked") return AxisMode::Locked;
    fail("six-DOF axis mode '" + name + "' is not one of free, limited, locked");
}
SixDofAxis axisSettings(py::handle value) {
    SixDofAxis s;
    if (py::isinstance<py::str>(value)) {
        s.mode = axisMode(value.cast<std::string>());
        return s;
    }
    const py::dict d = py::reinterpret_borrow<py::dict>(value);
    for (const auto& item : d) {
        const std::string key = item.first.cast<std::string>();
        if (key != "mode" && key != "limits" && key != "motor" && key != "spring") {
            fail("six-DOF axis setting '" + key + "' is not one of mode, limits, motor, spring");
        }
    }
    s.mode = AxisMode::Free;
    if (d.contains("limits") && !d["limits"].is_none()) {
        const auto [lo, hi] = pairOf(d["limits"], "limits");
        s.mode = AxisMode::Limited, s.lower = lo, s.upper = hi;
    }
    if (d.contains("mode")) s.mode = axisMode(d["mode"].cast<std::string>());
    if (d.contains("motor") && !d["motor"].is_none()) {
        const py::dict m = d["motor"].cast<py::dict>();
        s.motor = {true, m["speed"].cast<Real>(), m.contains("max_force") ? m["max_force"].cast<Real>() : Real(0)};
    }
    if (d.contains("spring") && !d["spring"].is_none()) {
        const py::dict m = d["spring"].cast<py::dict>();
        s.spring = {true, m.contains("target") ? m["target"].cast<Real>() : Real(0), m["stiffness"].cast<Real>(),
                    m.contains("damping") ? m["damping"].cast<Real>() : Real(0),
                    m.contains("max_force") ? m["max_force"].cast<Real>() : kInf};
    }
    return s;
}

// The keywords every joint type takes, after its own.
#define FULCRUM_JOINT_COMMON_ARGS                                                                                  \
    py::arg("name") = "", py::arg("collide_connected") = false, py::arg("break_force") = kInf,                     \
        py::arg("break_torque") = kInf

}  // namespace

void bindJoints(py::module_& m) {
    using J = JointHandle;
    py::class_<J>(m, "Joint",
                  "A handle to a joint. After a step: reaction_force / reaction_torque (on body_b), position (hinge "
                  "angle, slider translation, distance length), error (m). Breaks above break_force / break_torque.")
        .def_property_readonly("type", [](const J& j) { auto a = j.access("Joint"); return std::string(toString(a.world.jointDef(j.id).type)); })
        .def_property_readonly("name", [](const J& j) { auto a = j.access("Joint"); return a.world.name(j.id); })
        .def_property_readonly("body_a", [](const J& j) { auto a = j.access("Joint"); return bodyObject(a.keep, a.world.jointDef(j.id).bodyA); },
                               "A Body, or None for the static world.")
        .def_property_readonly("body_b", [](const J& j) { auto a = j.access("Joint"); return bodyObject(a.keep, a.world.jointDef(j.id).bodyB); })
        .def_property_readonly("error", [](const J& j) { auto a = j.access("Joint"); return a.world.jointError(j.id); },
                               "Position error, m.")
        .def_property_readonly("reaction_force", [](const J& j) { auto a = j.access("Joint"); return fromVec3(a.world.jointReactionForce(j.id)); },
                               "N on body_b, last step.")
        .def_property_readonly("reaction_torque", [](const J& j) { auto a = j.access("Joint"); return fromVec3(a.world.jointReactionTorque(j.id)); },
                               "N m on body_b, last step.")
        .def_property_readonly("position", [](const J& j) { auto a = j.access("Joint"); return a.world.jointPosition(j.id); },
                               "Hinge / cone-twist twist angle (rad), slider translation (m), distance length (m); 0 for ball and fixed.")
        .def_property_readonly("velocity", [](const J& j) { auto a = j.access("Joint"); return a.world.jointVelocity(j.id); },
                               "Hinge: rad/s about the axis; slider: m/s along it; 0 for the other types.")
        .def_property_readonly("effort", [](const J& j) { auto a = j.access("Joint"); return a.world.jointEffort(j.id); },
                               "Hinge / slider: torque (N m) or force (N) of its spring, motor, friction and limits on "
                               "body_b along the axis, last step (a robot's actuator effort).")
        .def_property(
            "enabled", [](const J& j) { auto a = j.access("Joint"); return a.world.isJointEnabled(j.id); },
            [](const J& j, bool on) { auto a = j.access("Joint"); a.world.setJointEnabled(j.id, on); },
            "A disabled joint is not solved; enabling a broken joint mends it.")
        .def_property_readonly("broken", [](const J& j) { auto a = j.access("Joint"); return a.world.isJointBroken(j.id); })
        .def_property_readonly("valid", [](const J& j) { const WorldPtr s = j.owner.lock(); return s && s->world.isValid(j.id); })
        .def("set_motor",
             [](const J& j, py::object speed, Real maxForce) {
                 auto a = j.access("Joint");
                 JointMotor motor;
                 if (!speed.is_none()) motor = {true, speed.cast<Real>(), maxForce};
                 a.world.setJointMotor(j.id, motor);
             },
             py::arg("speed"), py::arg("max_force") = 0,
             "Hinge (rad/s, N m) and slider (m/s, N) motors; speed None switches it off.")
        .def("set_limits",
             [](const J& j, py::object limits) {
                 auto a = j.access("Joint");
                 if (limits.is_none()) {
                     a.world.setJointLimits(j.id, false, 0, 0);
                     return;
                 }
                 const auto [lo, hi] = pairOf(limits, "limits");
                 a.world.setJointLimits(j.id, true, lo, hi);
             },
             py::arg("limits"), "(lower, upper): rad for hinges, m for sliders; None removes them.")
        .def("set_spring",
             [](const J& j, Real target, Real stiffness, Real damping, Real maxForce) {
                 auto a = j.access("Joint");
                 a.world.setJointSpring(j.id, {stiffness != 0 || damping != 0, target, stiffness, damping, maxForce});
             },
             py::arg("target") = 0, py::arg("stiffness") = 0, py::arg("damping") = 0, py::arg("max_force") = kInf,
             "A spring (position drive) towards a hinge angle or slider position, its torque or force at most "
             "max_force (N m or N; default unlimited); stiffness = damping = 0 removes it.")
        .def("set_axis",
             [](const J& j, py::object axis, py::object settings) {
                 auto a = j.access("Joint");
                 a.world.setSixDofAxis(j.id, axisIndex(axis), axisSettings(settings));
             },
             py::arg("axis"), py::arg("settings"),
             "Six-DOF: one axis ('x', 'y', 'z', 'rx', 'ry', 'rz' or 0..5) as a dict {'limits': (lo, hi), 'motor': "
             "{'speed', 'max_force'}, 'spring': {'target', 'stiffness', 'damping', 'max_force'}}; its mode stays as created.")
        .def_property_readonly("axes",
             [](const J& j) {
                 auto a = j.access("Joint");
                 const SixDofReading r = a.world.sixDofReading(j.id);
                 const auto arr = [](const std::array<Real, kSixDofAxes>& v) {
                     py::array_t<double> out(kSixDofAxes);
                     for (int k = 0; k < kSixDofAxes; ++k) out.mutable_at(k) = double(v[static_cast<std::size_t>(k)]);
                     return out;
                 };
                 return py::dict(py::arg("position") = arr(r.position), py::arg("velocity") = arr(r.velocity),
                                 py::arg("effort") = arr(r.effort));
             },
             "Six-DOF: {'position', 'velocity', 'effort'}, arrays over x, y, z (m, m/s, N), rx, ry, rz (rad, rad/s, N m); "
             "zeros for other types.")
        .def("set_drive",
             [](const J& j, py::object target, Real stiffness, Real damping, Real maxTorque) {
                 auto a = j.access("Joint");
                 ConeTwistDrive drive;
                 if (!target.is_none()) drive = {true, toQuat(target, "target"), stiffness, damping, maxTorque};
                 a.world.setConeTwistDrive(j.id, drive);
             },
             py::arg("target"), py::kw_only(), py::arg("stiffness") = kInf, py::arg("damping") = 0,
             py::arg("max_torque") = kInf,
             "Cone-twist: drive body_b to the orientation `target` (w, x, y, z) relative to its rest pose, as a "
             "spring (stiffness N m/rad, damping N m s/rad; infinite stiffness: rigid) with up to max_torque; None: off.")
        .def("__eq__", [](const J& a, const J& b) { return a.sameAs(b); })
        .def("__hash__", [](const J& j) { return py::hash(py::make_tuple(reinterpret_cast<std::uintptr_t>(j.owner.lock().get()), j.id.index, j.id.generation)); })
        .def("__repr__", [](const J& j) {
            const WorldPtr s = j.owner.lock();
            if (!s) return std::string("<fulcrum.Joint (world deleted)>");
            if (!s->world.isValid(j.id)) return std::string("<fulcrum.Joint (destroyed)>");
            const std::string& name = s->world.name(j.id);
            return "<fulcrum.Joint " + std::string(toString(s->world.jointDef(j.id).type)) +
                   (name.empty() ? "" : " '" + name + "'") + (s->world.isJointBroken(j.id) ? " (broken)" : "") + ">";
        });

    using S = SpringHandle;
    py::class_<S>(m, "Spring", "A damped spring F = -k (L - L0) n - c (v_rel . n) n between two anchors.")
        .def_property_readonly("length", [](const S& s) { auto a = s.access("Spring"); return a.world.springLength(s.id); }, "m")
        .def_property_readonly("valid", [](const S& s) { const WorldPtr w = s.owner.lock(); return w && w->world.isValid(s.id); })
        .def("__eq__", [](const S& a, const S& b) { return a.sameAs(b); })
        .def("__repr__", [](const S& s) {
            const WorldPtr w = s.owner.lock();
            if (!w || !w->world.isValid(s.id)) return std::string("<fulcrum.Spring (gone)>");
            return "<fulcrum.Spring length " + std::to_string(w->world.springLength(s.id)) + " m>";
        });

    auto cls = py::reinterpret_borrow<py::class_<PyWorld>>(m.attr("World"));
    const JointDef d;
    cls.def(
        "create_ball_joint",
        [](PyWorld& w, py::object a, py::object b, py::object anchor, Real frictionTorque, const std::string& name,
           bool cc, Real bf, Real bt) {
            JointDef def;
            def.type = JointType::Ball;
            def.anchor = toVec3(anchor, "anchor");
            def.frictionTorque = frictionTorque;
            return create(w, def, {a, b, name, cc, bf, bt});
        },
        py::arg("body_a"), py::arg("body_b"), py::kw_only(), py::arg("anchor"), py::arg("friction_torque") = d.frictionTorque,
        FULCRUM_JOINT_COMMON_ARGS,
        "A ball-and-socket joint at a world anchor. body_a None: the static world. Returns a Joint.");
    cls.def(
        "create_hinge_joint",
        [](PyWorld& w, py::object a, py::object b, py::object anchor, py::object axis, py::object limits,
           py::object motorSpeed, Real maxMotorForce, Real springTarget, Real springStiffness, Real springDamping,
           Real springMaxForce, Real frictionTorque, const std::string& name, bool cc, Real bf, Real bt) {
            JointDef def;
            def.type = JointType::Hinge;
            def.anchor = toVec3(anchor, "anchor");
            def.axis = toVec3(axis, "axis");
            setLimits(def, limits);
            setMotor(def, motorSpeed, maxMotorForce);
            setSpring(def, springTarget, springStiffness, springDamping, springMaxForce);
            def.frictionTorque = frictionTorque;
            return create(w, def, {a, b, name, cc, bf, bt});
        },
        py::arg("body_a"), py::arg("body_b"), py::kw_only(), py::arg("anchor"), py::arg("axis") = py::make_tuple(0, 1, 0),
        py::arg("limits") = py::none(), py::arg("motor_speed") = py::none(), py::arg("max_motor_force") = 0,
        py::arg("spring_target") = 0, py::arg("spring_stiffness") = 0, py::arg("spring_damping") = 0,
        py::arg("spring_max_force") = kInf, py::arg("friction_torque") = d.frictionTorque, FULCRUM_JOINT_COMMON_ARGS,
        "A hinge about a world axis through a world anchor. limits: (lower, upper) angle in rad from the pose at "
        "creation; motor_speed (rad/s) with max_motor_force (N m) turns the motor on; spring_stiffness (N m/rad) / "
        "spring_damping pull towards spring_target with at most spring_max_force (N m; default unlimited).");
    cls.def(
        "create_slider_joint",
        [](PyWorld& w, py::object a, py::object b, py::object anchor, py::object axis, py::object limits,
           py::object motorSpeed, Real maxMotorForce, Real springTarget, Real springStiffness, Real springDamping,
           Real springMaxForce, Real frictionForce, const std::string& name, bool cc, Real bf, Real bt) {
            JointDef def;
            def.type = JointType::Slider;
            def.anchor = toVec3(anchor, "anchor");
            def.axis = toVec3(axis, "axis");
            setLimits(def, limits);
            setMotor(def, motorSpeed, maxMotorForce);
            setSpring(def, springTarget, springStiffness, springDamping, springMaxForce);
            def.frictionTorque = frictionForce;  // JointDef's friction field: a force along a slider's axis
            return create(w, def, {a, b, name, cc, bf, bt});
        },
        py::arg("body_a"), py::arg("body_b"), py::kw_only(), py::arg("anchor"), py::arg("axis") = py::make_tuple(1, 0, 0),
        py::arg("limits") = py::none(), py::arg("motor_speed") = py::none(), py::arg("max_motor_force") = 0,
        py::arg("spring_target") = 0, py::arg("spring_stiffness") = 0, py::arg("spring_damping") = 0,
        py::arg("spring_max_force") = kInf, py::arg("friction_force") = 0, FULCRUM_JOINT_COMMON_ARGS,
        "A prismatic joint along a world axis: limits in m, motor in m/s and N, spring in N/m (at most "
        "spring_max_force N), dry friction friction_force in N (while the motor is off).");
    cls.def(
        "create_distance_joint",
        [](PyWorld& w, py::object a, py::object b, py::object anchorA, py::object anchorB, Real minLength,
           Real maxLength, Real stiffness, Real damping, const std::string& name, bool cc, Real bf, Real bt) {
            JointDef def;
            def.type = JointType::Distance;
            def.anchor = toVec3(anchorA, "anchor_a");
            def.anchorB = toVec3(anchorB, "anchor_b");
            def.minLength = minLength;
            def.maxLength = maxLength;
            def.stiffness = stiffness;
            def.damping = damping;
            return create(w, def, {a, b, name, cc, bf, bt});
        },
        py::arg("body_a"), py::arg("body_b"), py::kw_only(), py::arg("anchor_a"), py::arg("anchor_b"),
        py::arg("min_length") = d.minLength, py::arg("max_length") = d.maxLength, py::arg("stiffness") = d.stiffness,
        py::arg("damping") = d.damping, FULCRUM_JOINT_COMMON_ARGS,
        "Keeps the anchors' distance in [min_length, max_length] (negative: the distance at creation): a rod when "
        "equal, a rope when min_length = 0. stiffness > 0 (N/m) makes it a soft spring.");
    cls.def(
        "create_fixed_joint",
        [](PyWorld& w, py::object a, py::object b, py::object anchor, const std::string& name, bool cc, Real bf, Real bt) {
            JointDef def;
            def.type = JointType::Fixed;
            def.anchor = toVec3(anchor, "anchor");
            return create(w, def, {a, b, name, cc, bf, bt});
        },
        py::arg("body_a"), py::arg("body_b"), py::kw_only(), py::arg("anchor") = py::make_tuple(0, 0, 0),
        FULCRUM_JOINT_COMMON_ARGS, "Welds two bodies in their pose at creation.");
    cls.def(
        "create_cone_twist_joint",
        [](PyWorld& w, py::object a, py::object b, py::object anchor, py::object axis, Real swingLimit,
           py::object twistLimits, Real frictionTorque, const std::string& name, bool cc, Real bf, Real bt) {
            JointDef def;
            def.type = JointType::ConeTwist;
            def.anchor = toVec3(anchor, "anchor");
            def.axis = toVec3(axis, "axis");
            def.swingLimit = swingLimit;
            const auto [lo, hi] = pairOf(twistLimits, "twist_limits");
            def.twistLower = lo, def.twistUpper = hi;
            def.frictionTorque = frictionTorque;
            return create(w, def, {a, b, name, cc, bf, bt});
        },
        py::arg("body_a"), py::arg("body_b"), py::kw_only(), py::arg("anchor"), py::arg("axis") = py::make_tuple(0, 1, 0),
        py::arg("swing_limit") = d.swingLimit, py::arg("twist_limits") = py::make_tuple(d.twistLower, d.twistUpper),
        py::arg("friction_torque") = d.frictionTorque, FULCRUM_JOINT_COMMON_ARGS,
        "A ball joint whose swing of the twist axis stays in a cone of half-angle swing_limit (rad) and whose twist "
        "about it stays in twist_limits (rad): shoulders and hips.");
    cls.def(
        "create_six_dof_joint",
        [](PyWorld& w, py::object a, py::object b, py::object anchor, py::object axis, py::object axisY, py::object axes,
           const std::string& name, bool cc, Real bf, Real bt) {
            JointDef def;
            def.type = JointType::SixDof;
            def.anchor = toVec3(anchor, "anchor");
            def.axis = toVec3(axis, "axis");
            def.axisY = toVec3(axisY, "axis_y");
            if (!axes.is_none()) {
                for (const auto& item : axes.cast<py::dict>()) {
                    def.axes[static_cast<std::size_t>(axisIndex(item.first))] = axisSettings(item.second);
                }
            }
            return create(w, def, {a, b, name, cc, bf, bt});
        },
        py::arg("body_a"), py::arg("body_b"), py::kw_only(), py::arg("anchor"), py::arg("axis") = py::make_tuple(1, 0, 0),
        py::arg("axis_y") = py::make_tuple(0, 0, 0), py::arg("axes") = py::none(), FULCRUM_JOINT_COMMON_ARGS,
        "Six degrees of freedom in a joint frame at `anchor` (x = axis, y = axis_y made perpendicular; (0, 0, 0): world y, or world z when axis is near y): axes maps "
        "'x', 'y', 'z', 'rx', 'ry', 'rz' to 'free', 'locked' or {'limits': (lo, hi), 'motor': {'speed', 'max_force'}, "
        "'spring': {'target', 'stiffness', 'damping'}}; unnamed axes are locked. Angles: x-y-z Euler angles of body_b's "
        "frame against body_a's (docs/joints.md).");
    cls
        .def("destroy_joint",
             [](PyWorld& w, const JointHandle& j) {
                 destroyOwned(w, j, "destroy_joint", [](World& world, JointId id) { world.destroyJoint(id); });
             },
             py::arg("joint"))
        .def("joints",
             [](const PyWorld& w) { return handleList(w.state, w.world().joints()); },
             "Every live joint, in creation order.")
        .def("joint_break_events",
             [](const PyWorld& w) {
                 py::list out;
                 for (const JointBreakEvent& e : w.world().jointBreakEvents())
                     out.append(py::dict(py::arg("joint") = JointHandle{w.state, e.joint},
                                         py::arg("body_a") = bodyObject(w.state, e.bodyA),
                                         py::arg("body_b") = bodyObject(w.state, e.bodyB),
                                         py::arg("force") = fromVec3(e.force), py::arg("torque") = fromVec3(e.torque)));
                 return out;
             },
             "Joints that broke in the last step: [{'joint', 'body_a', 'body_b', 'force', 'torque'}, ...].");

    cls
        .def("create_spring",
             [](PyWorld& w, py::object a, py::object b, py::object anchorA, py::object anchorB, Real restLength,
                Real stiffness, Real damping) {
                 World& world = w.world();
                 SpringDef def;
                 def.bodyA = bodyIdOf(a, w.state, "body_a");
                 def.bodyB = bodyIdOf(b, w.state, "body_b");
                 def.anchorA = toVec3(anchorA, "anchor_a");
                 def.anchorB = toVec3(anchorB, "anchor_b");
                 def.restLength = restLength;
                 def.stiffness = stiffness;
                 def.damping = damping;
                 const SpringId id = world.createSpring(def);
                 w.state->scene.springs.push_back({def, sceneName(world, def.bodyA), sceneName(world, def.bodyB), {}});
                 w.state->handles.springs.push_back(id);
                 return SpringHandle{w.state, id};
             },
             py::arg("body_a"), py::arg("body_b"), py::kw_only(), py::arg("anchor_a"), py::arg("anchor_b"),
             py::arg("rest_length") = 0, py::arg("stiffness") = 0, py::arg("damping") = 0,
             "A damped spring between world anchors (fixed in the bodies at creation); body_a None: the static "
             "world. A force element, integrated by the world's integrator.")
        .def("destroy_spring",
             [](PyWorld& w, const SpringHandle& s) {
                 destroyOwned(w, s, "destroy_spring", [](World& world, SpringId id) { world.destroySpring(id); });
             },
             py::arg("spring"))
        .def_property_readonly("spring_count", [](const PyWorld& w) { return w.world().springCount(); });
}

bool isUnnamedMarker(const std::string& name) { return name == kUnnamed; }

}  // namespace fulcrum::python
