// Robots from URDF files (docs/robots.md): load_urdf(world, path, ...) and
// the Robot object, with bulk drives and read-outs as NumPy arrays over the
// robot's actuated joints (revolute, continuous, prismatic) in file order.
#include <filesystem>

#include <fulcrum/urdf.hpp>
#include <pybind11/stl/filesystem.h>

#include "common.hpp"

namespace fulcrum::python {

namespace {

struct PyRobot {
    std::weak_ptr<WorldState> owner;
    Robot robot;

    WorldPtr lock() const { return lockWorld(owner, "Robot"); }
};

std::vector<Real> reals(py::handle value, const char* argument) {
    const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(value);
    if (!a || a.ndim() != 1) {
        PyErr_Clear();
        throw py::type_error(std::string("argument '") + argument + "': expected a sequence of numbers (one per actuated joint or dof)");
    }
    std::vector<Real> out(static_cast<std::size_t>(a.shape(0)));
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = static_cast<Real>(a.data()[i]);
    return out;
}

py::array_t<double> array(const std::vector<Real>& v) {
    py::array_t<double> out(static_cast<py::ssize_t>(v.size()));
    for (std::size_t i = 0; i < v.size(); ++i) out.mutable_data()[i] = v[i];
    return out;
}

}  // namespace

void bindRobots(py::module_& m) {
    py::class_<PyRobot>(m, "Robot",
                        "A robot loaded from a URDF file (load_urdf): links and joints by name, drives and read-outs "
                        "over the actuated joints (joint_names) as arrays.")
        .def_property_readonly("name", [](const PyRobot& r) { return r.robot.name; })
        .def_property_readonly("link_names", [](const PyRobot& r) {
            std::vector<std::string> out;
            for (const RobotLink& l : r.robot.links) out.push_back(l.name);
            return out;
        })
        .def_property_readonly("joint_names", [](const PyRobot& r) { return r.robot.actuatedJointNames(); },
                               "The actuated joints (revolute, continuous, prismatic), in file order: the order of every array.")
        .def_property_readonly("all_joint_names", [](const PyRobot& r) {
            std::vector<std::string> out;
            for (const RobotJoint& j : r.robot.joints) out.push_back(j.name);
            return out;
        })
        .def_property_readonly("warnings", [](const PyRobot& r) { return r.robot.warnings; })
        .def("body", [](const PyRobot& r, const std::string& link) { return bodyObject(r.lock(), r.robot.body(link)); },
             py::arg("link"))
        .def("joint", [](const PyRobot& r, const std::string& name) {
            const WorldPtr s = r.lock();
            return JointHandle{s, r.robot.joint(name)};
        }, py::arg("name"))
        .def("joint_type", [](const PyRobot& r, const std::string& name) { return std::string(toString(r.robot.jointInfo(name).type)); },
             py::arg("name"), "The URDF type: revolute, continuous, prismatic, fixed, floating.")
        .def("joint_limits", [](const PyRobot& r, const std::string& name) {
            const RobotJoint& j = r.robot.jointInfo(name);
            return py::dict(py::arg("lower") = j.lower, py::arg("upper") = j.upper, py::arg("effort") = j.effortLimit,
                            py::arg("velocity") = j.velocityLimit, py::arg("damping") = j.damping, py::arg("friction") = j.friction);
        }, py::arg("name"))
        .def("set_drive",
             [](const PyRobot& r, const std::string& joint, Real position, Real stiffness, Real damping, py::object velocity,
                Real maxForce) {
                 const WorldPtr s = r.lock();
                 JointDrive d;
                 d.position = position;
                 d.stiffness = stiffness;
                 d.damping = damping;
                 if (!velocity.is_none()) {
                     d.velocityDrive = true;
                     d.velocity = velocity.cast<Real>();
                 }
                 d.maxForce = maxForce;
                 r.robot.setDrive(s->world, joint, d);
             },
             py::arg("joint"), py::arg("position") = 0, py::arg("stiffness") = 0, py::arg("damping") = 0,
             py::arg("velocity") = py::none(), py::arg("max_force") = std::numeric_limits<Real>::infinity(),
             "One joint's drive: an implicit PD towards position (stiffness, damping) and/or a velocity target, "
             "each with at most max_force (N m or N; default: the URDF effort limit).")
        .def("set_position_targets",
             [](const PyRobot& r, py::handle q) { const WorldPtr s = r.lock(); r.robot.setPositionTargets(s->world, reals(q, "positions")); },
             py::arg("positions"), "One target per actuated joint (rad or m); the drives keep their gains.")
        .def("set_drive_gains",
             [](const PyRobot& r, py::handle kp, py::handle kd) {
                 const WorldPtr s = r.lock();
                 r.robot.setDriveGains(s->world, reals(kp, "stiffness"), reals(kd, "damping"));
             },
             py::arg("stiffness"), py::arg("damping"))
        .def("set_velocity_targets",
             [](const PyRobot& r, py::handle v) { const WorldPtr s = r.lock(); r.robot.setVelocityTargets(s->world, reals(v, "velocities")); },
             py::arg("velocities"), "Velocity drives on (max force: each joint's effort limit, or unlimited).")
        .def("set_drive_max_forces",
             [](const PyRobot& r, py::handle f) { const WorldPtr s = r.lock(); r.robot.setDriveMaxForces(s->world, reals(f, "max forces")); },
             py::arg("max_forces"),
             "The position drives' force limits, one per actuated joint (N m or N; inf: none); the other calls keep "
             "them. Loading sets them to the URDF effort limits.")
        .def("disable_drives", [](const PyRobot& r) { const WorldPtr s = r.lock(); r.robot.disableDrives(s->world); })
        .def_property_readonly("dof_names", [](const PyRobot& r) { return r.robot.dofNames(); },
                               "Every degree of freedom: the actuated joints and the free axes of floating and planar "
                               "joints ('joint/x' ... 'joint/rz'), in file order: the order of every dof_ array.")
        .def("set_dof_position_targets",
             [](const PyRobot& r, py::handle q) { const WorldPtr s = r.lock(); r.robot.setDofPositionTargets(s->world, reals(q, "positions")); },
             py::arg("positions"), "One target per dof (dof_names; rad or m); the drives keep their gains.")
        .def("set_dof_drive_gains",
             [](const PyRobot& r, py::handle kp, py::handle kd) {
                 const WorldPtr s = r.lock();
                 r.robot.setDofDriveGains(s->world, reals(kp, "stiffness"), reals(kd, "damping"));
             },
             py::arg("stiffness"), py::arg("damping"))
        .def("set_dof_velocity_targets",
             [](const PyRobot& r, py::handle v) { const WorldPtr s = r.lock(); r.robot.setDofVelocityTargets(s->world, reals(v, "velocities")); },
             py::arg("velocities"), "Velocity drives on every dof (max force: the effort limit, or unlimited).")
        .def("set_dof_drive_max_forces",
             [](const PyRobot& r, py::handle f) { const WorldPtr s = r.lock(); r.robot.setDofDriveMaxForces(s->world, reals(f, "max forces")); },
             py::arg("max_forces"), "The position drives' force limits, one per dof (N m or N; inf: none).")
        .def("dof_positions", [](const PyRobot& r) { const WorldPtr s = r.lock(); return array(r.robot.dofPositions(s->world)); })
        .def("dof_velocities", [](const PyRobot& r) { const WorldPtr s = r.lock(); return array(r.robot.dofVelocities(s->world)); })
        .def("dof_efforts", [](const PyRobot& r) { const WorldPtr s = r.lock(); return array(r.robot.dofEfforts(s->world)); },
             "Each dof's effort along its axis in the last step (N m or N).")
        .def("joint_positions", [](const PyRobot& r) { const WorldPtr s = r.lock(); return array(r.robot.jointPositions(s->world)); })
        .def("joint_velocities", [](const PyRobot& r) { const WorldPtr s = r.lock(); return array(r.robot.jointVelocities(s->world)); })
        .def("joint_efforts", [](const PyRobot& r) { const WorldPtr s = r.lock(); return array(r.robot.jointEfforts(s->world)); },
             "Each actuated joint's effort along its axis in the last step (N m or N).")
        .def("inverse_dynamics",
             [](const PyRobot& r, py::handle q, py::handle qd, py::handle qdd, bool damping, bool friction) {
                 const WorldPtr s = r.lock();
                 const std::vector<Real> pos = q.is_none() ? r.robot.jointPositions(s->world) : reals(q, "positions");
                 const std::vector<Real> zero(pos.size(), 0);
                 const std::vector<Real> vel = qd.is_none() ? zero : reals(qd, "velocities");
                 const std::vector<Real> acc = qdd.is_none() ? zero : reals(qdd, "accelerations");
                 return array(r.robot.inverseDynamics(s->world, pos, vel, acc, {damping, friction}));
             },
             py::arg("positions") = py::none(), py::arg("velocities") = py::none(), py::arg("accelerations") = py::none(),
             py::kw_only(), py::arg("damping") = true, py::arg("friction") = true,
             "The effort at each actuated joint (joint_names order; N m or N) that moves a fixed-base robot through "
             "positions, velocities and accelerations under the world's gravity (recursive Newton-Euler), with the "
             "URDF damping (d qd) and Coulomb friction (f sgn(qd); at qd = 0, f sgn(qdd)) unless turned off. "
             "Defaults: the current positions, zero velocities and accelerations, i.e. gravity compensation.")
        .def("floating_base_inverse_dynamics",
             [](const PyRobot& r, py::handle q, py::handle qd, py::handle qdd, py::handle basePosition,
                py::handle baseOrientation, py::handle baseAngularVelocity, py::handle baseLinearAcceleration,
                py::handle baseAngularAcceleration, bool damping, bool friction) {
                 const WorldPtr s = r.lock();
                 const std::vector<Real> pos = q.is_none() ? r.robot.jointPositions(s->world) : reals(q, "positions");
                 const std::vector<Real> zero(pos.size(), 0);
                 const std::vector<Real> vel = qd.is_none() ? r.robot.jointVelocities(s->world) : reals(qd, "velocities");
                 const std::vector<Real> acc = qdd.is_none() ? zero : reals(qdd, "accelerations");
                 RobotBaseState base = r.robot.baseState(s->world);
                 if (!basePosition.is_none()) base.position = toVec3(basePosition, "base_position");
                 if (!baseOrientation.is_none()) base.orientation = toQuat(baseOrientation, "base_orientation");
                 if (!baseAngularVelocity.is_none()) base.angularVelocity = toVec3(baseAngularVelocity, "base_angular_velocity");
                 const InverseDynamicsOptions options{damping, friction};
                 const bool prescribed = !baseLinearAcceleration.is_none() || !baseAngularAcceleration.is_none();
                 const FloatingBaseDynamics d =
                     prescribed ? r.robot.prescribedBaseInverseDynamics(
                                      s->world, base,
                                      baseLinearAcceleration.is_none() ? Vec3{} : toVec3(baseLinearAcceleration, "base_linear_acceleration"),
                                      baseAngularAcceleration.is_none() ? Vec3{} : toVec3(baseAngularAcceleration, "base_angular_acceleration"),
                                      pos, vel, acc, options)
                                : r.robot.freeBaseInverseDynamics(s->world, base, pos, vel, acc, options);
                 return py::dict(py::arg("efforts") = array(d.efforts), py::arg("linear_acceleration") = fromVec3(d.linearAcceleration),
                                 py::arg("angular_acceleration") = fromVec3(d.angularAcceleration),
                                 py::arg("force") = fromVec3(d.force), py::arg("torque") = fromVec3(d.torque));
             },
             py::arg("positions") = py::none(), py::arg("velocities") = py::none(), py::arg("accelerations") = py::none(),
             py::kw_only(), py::arg("base_position") = py::none(), py::arg("base_orientation") = py::none(),
             py::arg("base_angular_velocity") = py::none(), py::arg("base_linear_acceleration") = py::none(),
             py::arg("base_angular_acceleration") = py::none(), py::arg("damping") = true, py::arg("friction") = true,
             "Inverse dynamics of a robot with a floating base (root link not static). Without base accelerations: the "
             "free tree (no wrench on the base but gravity); returns the base's linear_acceleration (its frame origin's) "
             "and angular_acceleration and the joint efforts. With base_linear_acceleration and/or "
             "base_angular_acceleration: the base wrench (force, torque about its frame origin, world) and efforts "
             "that make that motion. The base's pose and angular velocity default to its body's now; positions and "
             "velocities to the joints' now, accelerations to zero. Returns a dict of efforts, linear_acceleration, "
             "angular_acceleration, force, torque.")
        .def("contact_forces", [](const PyRobot& r) { const WorldPtr s = r.lock(); return fromVec3List(r.robot.contactForces(s->world)); },
             "The contact force on every link over the last step (N, world), file order, as an (n_links, 3) array.")
        .def("sample_imu",
             [](PyRobot& r) {
                 const WorldPtr s = r.lock();
                 const std::vector<ImuReading> readings = r.robot.sampleImu(s->world);
                 std::vector<Vec3> f, w;
                 for (const ImuReading& x : readings) {
                     f.push_back(x.specificForce);
                     w.push_back(x.angularVelocity);
                 }
                 return py::make_tuple(fromVec3List(f), fromVec3List(w));
             },
             "IMU readings of every link (link_names order) in each link's axes: (specific_force (n, 3) m/s^2, "
             "angular_velocity (n, 3) rad/s). Call once after each step: the acceleration is the velocity change "
             "since the previous call.")
        .def("__repr__", [](const PyRobot& r) {
            return "<fulcrum.Robot '" + r.robot.name + "': " + std::to_string(r.robot.links.size()) + " links, " +
                   std::to_string(r.robot.actuatedJoints().size()) + " actuated joints>";
        });

    m.def(
        "load_urdf",
        [](PyWorld& w, const std::filesystem::path& path, py::handle position, py::handle orientation, bool fixedBase,
           bool selfCollision, const std::vector<std::filesystem::path>& searchPath) {
            World& world = w.world();
            UrdfOptions options;
            if (!position.is_none()) options.position = toVec3(position, "position");
            if (!orientation.is_none()) options.orientation = normalize(toQuat(orientation, "orientation"));
            options.fixedBase = fixedBase;
            options.selfCollision = selfCollision;
            options.searchPath = searchPath;
            options.collisionGroup = -static_cast<std::int32_t>(std::min<std::size_t>(world.bodyCount() + 1, 1u << 30));
            options.warn = [](const std::string& message) {
                py::module_::import("warnings").attr("warn")(message, py::module_::import("builtins").attr("UserWarning"), 2);
            };
            const std::string source = path.string();
            const UrdfSceneParts parts = urdfSceneParts(readUrdfText(path), source, options);
            PyRobot robot{w.state, createUrdfParts(world, parts, source)};
            // The binding's scene description (save_scene) gains the links and joints.
            for (std::size_t i = 0; i < parts.bodies.size(); ++i) {
                SceneBody body = parts.bodies[i];
                body.def.shape = buildShape(body.shape);
                w.state->scene.bodies.push_back(std::move(body));
                w.state->handles.bodies.push_back(robot.robot.links[i].body);
                w.state->bodyCreated(robot.robot.links[i].body);
            }
            for (std::size_t k = 0; k < parts.joints.size(); ++k) {
                w.state->scene.joints.push_back(parts.joints[k]);
                w.state->handles.joints.push_back(robot.robot.joints[parts.jointIndex[k]].joint);
            }
            return robot;
        },
        py::arg("world"), py::arg("path"), py::arg("position") = py::none(), py::arg("orientation") = py::none(),
        py::arg("fixed_base") = false, py::arg("self_collision") = false,
        py::arg("search_path") = std::vector<std::filesystem::path>{},
        "Loads a URDF robot into the world: links become bodies and joints joints, named as in the file "
        "(docs/robots.md). position / orientation place the root link (URDF is z-up: give the world gravity "
        "(0, 0, -9.81)); fixed_base makes the root static. Missing meshes are warnings (UserWarning) with a fallback; "
        "a malformed file raises fulcrum.Error naming the file, line and element.");
}

}  // namespace fulcrum::python
