// Vehicles: World.create_vehicle and the Vehicle handle (docs/vehicles.md).
#include "common.hpp"

#include <fulcrum/vehicle.hpp>

namespace fulcrum::python {

namespace {

// Vehicles are reached through free functions (fulcrum/vehicle.hpp), so the
// handle checks them itself.
struct VehicleHandle {
    std::weak_ptr<WorldState> owner;
    VehicleId id;
    struct Access {
        WorldPtr keep;
        World& world;
    };
    Access access() const {
        WorldPtr keep = lockWorld(owner, "Vehicle");
        World& world = keep->world;
        if (!isValid(world, id)) fail("stale Vehicle handle (index " + std::to_string(id.index) + "): it was destroyed");
        return {std::move(keep), world};
    }
};

Real number(const py::dict& d, const char* key, Real fallback) {
    return d.contains(key) ? d[key].cast<Real>() : fallback;
}
bool flag(const py::dict& d, const char* key, bool fallback) { return d.contains(key) ? d[key].cast<bool>() : fallback; }

WheelDef toWheel(py::handle value, std::size_t index) {
    if (!py::isinstance<py::dict>(value)) {
        throw py::type_error("argument 'wheels': item " + std::to_string(index) + ": expected a dict");
    }
    const py::dict d = py::reinterpret_borrow<py::dict>(value);
    static const char* const kKeys[] = {"position", "radius", "width", "rest_length", "stiffness", "damping", "steering",
                                        "driven", "hand_brake", "friction", "inertia"};
    for (const auto& item : d) {
        const std::string key = py::str(item.first);
        if (std::find_if(std::begin(kKeys), std::end(kKeys), [&](const char* k) { return key == k; }) == std::end(kKeys)) {
            fail("wheels[" + std::to_string(index) + "]: unknown key '" + key + "'");
        }
    }
    if (!d.contains("position")) fail("wheels[" + std::to_string(index) + "]: 'position' is required");
    WheelDef w;
    w.position = toVec3(d["position"], "position");
    w.radius = number(d, "radius", w.radius);
    w.width = number(d, "width", w.width);
    w.suspension.restLength = number(d, "rest_length", w.suspension.restLength);
    w.suspension.stiffness = number(d, "stiffness", w.suspension.stiffness);
    w.suspension.damping = number(d, "damping", w.suspension.damping);
    w.steering = flag(d, "steering", w.steering);
    w.driven = flag(d, "driven", w.driven);
    w.handBrake = flag(d, "hand_brake", !w.steering);
    w.friction = number(d, "friction", w.friction);
    w.inertia = number(d, "inertia", w.inertia);
    return w;
}

}  // namespace

void bindVehicles(py::module_& m) {
    using V = VehicleHandle;
    py::class_<V>(m, "Vehicle", "A wheeled vehicle: a chassis body with raycast wheels (docs/vehicles.md).")
        .def_property_readonly("name", [](const V& v) { auto a = v.access(); return vehicleDef(a.world, v.id).name; })
        .def_property_readonly("position", [](const V& v) { auto a = v.access(); return fromVec3(vehicleState(a.world, v.id).position); })
        .def_property_readonly("speed", [](const V& v) { auto a = v.access(); return vehicleState(a.world, v.id).speed; },
                               "m/s along the chassis's forward axis (local +z).")
        .def_property_readonly("gear", [](const V& v) { auto a = v.access(); return vehicleState(a.world, v.id).gear; })
        .def_property_readonly("engine_rpm", [](const V& v) { auto a = v.access(); return vehicleState(a.world, v.id).engineRpm; })
        .def("wheels", [](const V& v) {
            auto a = v.access();
            py::list out;
            for (const WheelState& w : vehicleState(a.world, v.id).wheels) {
                out.append(py::dict(py::arg("in_contact") = w.inContact, py::arg("suspension_length") = w.suspensionLength,
                                    py::arg("suspension_force") = w.suspensionForce,
                                    py::arg("angular_velocity") = w.angularVelocity, py::arg("steer_angle") = w.steerAngle,
                                    py::arg("longitudinal_slip") = w.longitudinalSlip, py::arg("lateral_slip") = w.lateralSlip));
            }
            return out;
        }, "Per wheel: in_contact, suspension_length, suspension_force, angular_velocity, steer_angle and slips.")
        .def("set_input", [](const V& v, Real throttle, Real brake, Real steering, bool handBrake) {
            auto a = v.access();
            checkIdle(*a.keep);
            VehicleInput in;
            in.throttle = throttle;
            in.brake = brake;
            in.steering = steering;
            in.handBrake = handBrake;
            setVehicleInput(a.world, v.id, in);
        }, py::kw_only(), py::arg("throttle") = 0, py::arg("brake") = 0, py::arg("steering") = 0, py::arg("hand_brake") = false,
           "The held input: throttle -1..1 (negative: backwards, reverse gear once stopped), brake 0..1, steering -1..1 (+1 turns left).")
        .def("__repr__", [](const V& v) {
            const WorldPtr s = v.owner.lock();
            if (!s || !isValid(s->world, v.id)) return std::string("<fulcrum.Vehicle (gone)>");
            return "<fulcrum.Vehicle '" + vehicleDef(s->world, v.id).name + "'>";
        });

    auto cls = py::reinterpret_borrow<py::class_<PyWorld>>(m.attr("World"));
    const VehicleDef d;
    cls.def(
        "create_vehicle",
        [](PyWorld& w, py::object chassis, py::list wheels, Real maxTorque, Real maxBrakeTorque, Real maxHandBrakeTorque,
           Real maxSteeringAngle, const std::string& name) {
            World& world = w.world();
            VehicleDef def;
            def.name = name;
            def.chassis = bodyIdOf(chassis, w.state, "chassis");
            for (std::size_t i = 0; i < wheels.size(); ++i) def.wheels.push_back(toWheel(wheels[i], i));
            def.engine.maxTorque = maxTorque;
            def.maxBrakeTorque = maxBrakeTorque;
            def.maxHandBrakeTorque = maxHandBrakeTorque;
            def.maxSteeringAngle = maxSteeringAngle;
            const VehicleId id = createVehicle(world, def);
            w.state->scene.vehicles.push_back({def, def.chassis.isNull() ? std::string() : world.name(def.chassis), {}});
            w.state->handles.vehicles.push_back(id);
            return VehicleHandle{w.state, id};
        },
        py::kw_only(), py::arg("chassis"), py::arg("wheels"), py::arg("max_torque") = d.engine.maxTorque,
        py::arg("max_brake_torque") = d.maxBrakeTorque, py::arg("max_hand_brake_torque") = d.maxHandBrakeTorque,
        py::arg("max_steering_angle") = d.maxSteeringAngle, py::arg("name") = "",
        "A vehicle on a dynamic chassis Body. wheels: dicts with position (world, at creation) and optionally radius, "
        "width, rest_length, stiffness, damping, steering, driven, hand_brake, friction, inertia.");
    cls.def("vehicles", [](PyWorld& w) {
        py::list out;
        for (const VehicleId id : fulcrum::vehicles(w.world())) out.append(VehicleHandle{w.state, id});
        return out;
    }, "The vehicles in creation order.");
}

}  // namespace fulcrum::python
