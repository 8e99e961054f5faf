// Writing a Scene as JSON. Keys that hold their default value are left out,
// so a saved file reads like a hand-written one; parseScene fills the same
// defaults back in, which is what makes load -> save -> load exact.
#include <cmath>
#include <cstdlib>
#include <fstream>

#include <nlohmann/json.hpp>

#include "fulcrum/scene.hpp"
#include "io/scene_detail.hpp"

namespace fulcrum {

namespace {

using ojson = nlohmann::ordered_json;

// A float as the double with the same shortest decimal text ("0.1", not
// 0.10000000149011612), so files stay readable and read back to the same float.
double num(Real v) { return std::strtod(detail::formatNumber(v).c_str(), nullptr); }

ojson vec(const Vec3& v) { return ojson::array({num(v.x), num(v.y), num(v.z)}); }
ojson quat(const Quat& q) { return ojson::array({num(q.w), num(q.x), num(q.y), num(q.z)}); }
ojson bodyRef(const std::string& name) { return name.empty() ? ojson(nullptr) : ojson(name); }

ojson shapeJson(const ShapeDesc& s) {
    ojson j;
    j["type"] = toString(s.type);
    switch (s.type) {
        case ShapeType::Sphere: j["radius"] = num(s.radius); break;
        case ShapeType::Box: j["half_extents"] = vec(s.halfExtents); break;
        case ShapeType::Capsule:
        case ShapeType::Cylinder:
            j["radius"] = num(s.radius);
            j["half_height"] = num(s.halfHeight);
            break;
        case ShapeType::ConvexHull: {
            ojson pts = ojson::array();
            for (const Vec3& p : s.points) pts.push_back(vec(p));
            j["points"] = std::move(pts);
            break;
        }
        case ShapeType::Plane:
            j["normal"] = vec(s.normal);
            j["offset"] = num(s.offset);
            break;
        case ShapeType::Mesh: {
            ojson verts = ojson::array(), tris = ojson::array();
            for (const Vec3& p : s.vertices) verts.push_back(vec(p));
            for (const auto& t : s.triangles) tris.push_back(ojson::array({t[0], t[1], t[2]}));
            j["vertices"] = std::move(verts);
            j["triangles"] = std::move(tris);
            break;
        }
        case ShapeType::HeightField: {
            j["rows"] = s.rows;
            j["columns"] = s.columns;
            j["spacing"] = ojson::array({num(s.spacingX), num(s.spacingZ)});
            ojson heights = ojson::array();
            for (const Real h : s.heights) heights.push_back(num(h));
            j["heights"] = std::move(heights);
            if (!s.holes.empty()) j["holes"] = s.holes;
            break;
        }
        case ShapeType::Compound: {
            ojson kids = ojson::array();
            for (const ShapeDesc::Child& c : s.children) {
                ojson k;
                k["shape"] = shapeJson(c.shape);
                if (c.position != Vec3{}) k["position"] = vec(c.position);
                if (c.orientation != Quat{}) k["orientation"] = quat(c.orientation);
                kids.push_back(std::move(k));
            }
            j["children"] = std::move(kids);
            break;
        }
    }
    if (s.decompose) j["decompose"] = true;
    // Scaled shapes: a uniform scale as one number, as it is usually written.
    if (s.scale != Vec3{1, 1, 1}) {
        j["scale"] = s.scale.x == s.scale.y && s.scale.y == s.scale.z ? ojson(num(s.scale.x)) : vec(s.scale);
    }
    if (s.convexRadius > 0) j["convex_radius"] = num(s.convexRadius);  // rounded shapes
    return j;
}

ojson bodyJson(const SceneBody& body) {
    const BodyDef& d = body.def;
    const BodyDef defaults;
    ojson j;
    if (!d.name.empty()) j["name"] = d.name;
    j["type"] = toString(d.type);
    j["shape"] = shapeJson(body.shape);
    if (d.mass > 0) {
        j["mass"] = num(d.mass);
    } else if (d.type == BodyType::Dynamic || d.density != defaults.density) {
        j["density"] = num(d.density);
    }
    if (d.inertia) {
        const Mat3& m = *d.inertia;
        if (m(0, 1) == 0 && m(0, 2) == 0 && m(1, 2) == 0 && m(1, 0) == 0 && m(2, 0) == 0 && m(2, 1) == 0) {
            j["inertia"] = vec({m(0, 0), m(1, 1), m(2, 2)});
        } else {
            j["inertia"] = ojson::array({vec(m.row(0)), vec(m.row(1)), vec(m.row(2))});
        }
    }
    if (d.centerOfMass) j["center_of_mass"] = vec(*d.centerOfMass);
    j["position"] = vec(d.position);
    if (d.orientation != defaults.orientation) j["orientation"] = quat(d.orientation);
    if (d.linearVelocity != defaults.linearVelocity) j["linear_velocity"] = vec(d.linearVelocity);
    if (d.angularVelocity != defaults.angularVelocity) j["angular_velocity"] = vec(d.angularVelocity);
    const auto scalar = [&](const char* key, Real v, Real def) {
        if (v != def) j[key] = num(v);
    };
    scalar("friction", d.friction, defaults.friction);
    scalar("restitution", d.restitution, defaults.restitution);
    scalar("linear_damping", d.linearDamping, defaults.linearDamping);
    scalar("angular_damping", d.angularDamping, defaults.angularDamping);
    scalar("gravity_scale", d.gravityScale, defaults.gravityScale);
    scalar("rolling_resistance", d.rollingResistance, defaults.rollingResistance);
    scalar("linear_drag", d.linearDrag, defaults.linearDrag);
    scalar("quadratic_drag", d.quadraticDrag, defaults.quadraticDrag);
    if (d.filter.category != defaults.filter.category || d.filter.mask != defaults.filter.mask ||
        d.filter.group != defaults.filter.group) {
        j["filter"] = ojson{{"category", d.filter.category}, {"mask", d.filter.mask}, {"group", d.filter.group}};
    }
    if (d.isSensor) j["is_sensor"] = true;
    if (d.isBullet) j["is_bullet"] = true;
    if (!d.allowSleep) j["allow_sleep"] = false;
    if (!d.awake) j["awake"] = false;
    return j;
}

ojson jointJson(const SceneJoint& joint) {
    const JointDef& d = joint.def;
    const JointDef defaults;
    ojson j;
    if (!d.name.empty()) j["name"] = d.name;
    j["type"] = toString(d.type);
    j["body_a"] = bodyRef(joint.bodyA);
    j["body_b"] = joint.bodyB;
    j["anchor"] = vec(d.anchor);
    switch (d.type) {
        case JointType::Hinge:
        case JointType::Slider:
            j["axis"] = vec(d.axis);
            if (d.hasLimits) j["limits"] = ojson::array({num(d.lowerLimit), num(d.upperLimit)});
            if (d.motor.enabled) j["motor"] = ojson{{"speed", num(d.motor.speed)}, {"max_force", num(d.motor.maxForce)}};
            if (d.spring.enabled) {
                j["spring"] = ojson{{"target", num(d.spring.target)},
                                    {"stiffness", num(d.spring.stiffness)},
                                    {"damping", num(d.spring.damping)}};
                if (std::isfinite(d.spring.maxForce)) j["spring"]["max_force"] = num(d.spring.maxForce);
            }
            break;
        case JointType::Distance:
            j["anchor_b"] = vec(d.anchorB);
            if (d.minLength >= 0) j["min_length"] = num(d.minLength);
            if (d.maxLength >= 0) j["max_length"] = num(d.maxLength);
            if (d.stiffness != 0) j["stiffness"] = num(d.stiffness);
            if (d.damping != 0) j["damping"] = num(d.damping);
            break;
        case JointType::ConeTwist:
            j["axis"] = vec(d.axis);
            if (d.swingLimit != defaults.swingLimit) j["swing_limit"] = num(d.swingLimit);
            if (d.twistLower != defaults.twistLower || d.twistUpper != defaults.twistUpper) {
                j["twist_limits"] = ojson::array({num(d.twistLower), num(d.twistUpper)});
            }
            if (d.coneDrive.enabled) {
                const ConeTwistDrive& c = d.coneDrive;
                ojson drive{{"target", ojson::array({num(c.target.w), num(c.target.x), num(c.target.y), num(c.target.z)})},
                            {"damping", num(c.damping)}};
                if (std::isfinite(c.stiffness)) drive["stiffness"] = num(c.stiffness);
                if (std::isfinite(c.maxTorque)) drive["max_torque"] = num(c.maxTorque);
                j["drive"] = drive;
            }
            break;
        case JointType::SixDof: {
            j["axis"] = vec(d.axis);
            if (!(d.axisY == Vec3{})) j["axis_y"] = vec(d.axisY);  // zero: absent (world y or z), which the reader refuses as a value
            static constexpr const char* kNames[kSixDofAxes] = {"x", "y", "z", "rx", "ry", "rz"};
            ojson axes = ojson::object();
            for (int k = 0; k < kSixDofAxes; ++k) {
                const SixDofAxis& s = d.axes[static_cast<std::size_t>(k)];
                if (s.mode == AxisMode::Locked) continue;  // the default
                ojson a = ojson::object();
                a["mode"] = toString(s.mode);
                if (s.mode == AxisMode::Limited) a["limits"] = ojson::array({num(s.lower), num(s.upper)});
                if (s.motor.enabled) a["motor"] = ojson{{"speed", num(s.motor.speed)}, {"max_force", num(s.motor.maxForce)}};
                if (s.spring.enabled) {
                    a["spring"] = ojson{{"target", num(s.spring.target)},
                                        {"stiffness", num(s.spring.stiffness)},
                                        {"damping", num(s.spring.damping)}};
                    if (std::isfinite(s.spring.maxForce)) a["spring"]["max_force"] = num(s.spring.maxForce);
                }
                axes[kNames[k]] = a;
            }
            if (!axes.empty()) j["axes"] = axes;
            break;
        }
        case JointType::Ball:
        case JointType::Fixed: break;
    }
    if (d.breakForce != defaults.breakForce) j["break_force"] = num(d.breakForce);
    if (d.breakTorque != defaults.breakTorque) j["break_torque"] = num(d.breakTorque);
    if (d.collideConnected) j["collide_connected"] = true;
    if (d.frictionTorque != defaults.frictionTorque) j["friction_torque"] = num(d.frictionTorque);
    return j;
}

ojson springJson(const SceneSpring& spring) {
    const SpringDef& d = spring.def;
    ojson j;
    j["body_a"] = bodyRef(spring.bodyA);
    j["body_b"] = spring.bodyB;
    j["anchor_a"] = vec(d.anchorA);
    j["anchor_b"] = vec(d.anchorB);
    j["rest_length"] = num(d.restLength);
    j["stiffness"] = num(d.stiffness);
    if (d.damping != 0) j["damping"] = num(d.damping);
    return j;
}

ojson ropeJson(const SceneRope& rope) {
    const RopeDef& d = rope.def;
    ojson j;
    if (!d.name.empty()) j["name"] = d.name;
    j["start"] = vec(d.start);
    j["end"] = vec(d.end);
    j["segments"] = d.segments;
    j["particle_mass"] = num(d.particleMass);
    j["radius"] = num(d.radius);
    j["pin_start"] = d.pinStart;
    j["pin_end"] = d.pinEnd;
    if (!rope.attachStart.empty()) j["attach_start"] = rope.attachStart;
    if (!rope.attachEnd.empty()) j["attach_end"] = rope.attachEnd;
    j["stretch_compliance"] = num(d.stretchCompliance);
    j["bend_compliance"] = num(d.bendCompliance);
    return j;
}

ojson characterJson(const SceneCharacter& character) {
    const CharacterDef& d = character.def;
    ojson j;
    if (!d.name.empty()) j["name"] = d.name;
    j["position"] = vec(d.position);
    j["radius"] = num(d.radius);
    j["height"] = num(d.height);
    j["mass"] = num(d.mass);
    j["max_slope"] = num(d.maxSlope);
    j["step_height"] = num(d.stepHeight);
    j["jump_speed"] = num(d.jumpSpeed);
    j["max_push_force"] = num(d.maxPushForce);
    j["stick_distance"] = num(d.stickDistance);
    if (!d.inputs.empty()) {
        ojson inputs = ojson::array();
        for (const CharacterInput& in : d.inputs) {
            ojson e;
            e["time"] = num(in.time);
            e["velocity"] = vec(in.velocity);
            e["jump"] = in.jump;
            inputs.push_back(std::move(e));
        }
        j["inputs"] = std::move(inputs);
    }
    return j;
}

ojson vehicleJson(const SceneVehicle& vehicle) {
    const VehicleDef& d = vehicle.def;
    ojson j;
    if (!d.name.empty()) j["name"] = d.name;
    j["chassis"] = vehicle.chassis;
    ojson wheels = ojson::array();
    for (const WheelDef& w : d.wheels) {
        ojson e;
        e["position"] = vec(w.position);
        e["radius"] = num(w.radius);
        e["width"] = num(w.width);
        e["suspension"] = ojson{{"rest_length", num(w.suspension.restLength)},
                                {"stiffness", num(w.suspension.stiffness)},
                                {"damping", num(w.suspension.damping)}};
        e["steering"] = w.steering;
        e["driven"] = w.driven;
        e["hand_brake"] = w.handBrake;
        e["friction"] = num(w.friction);
        e["inertia"] = num(w.inertia);
        wheels.push_back(std::move(e));
    }
    j["wheels"] = std::move(wheels);
    ojson curve = ojson::array();
    for (const auto& p : d.engine.torqueCurve) curve.push_back(ojson::array({num(p[0]), num(p[1])}));
    j["engine"] = ojson{{"max_torque", num(d.engine.maxTorque)},
                        {"max_rpm", num(d.engine.maxRpm)},
                        {"min_rpm", num(d.engine.minRpm)},
                        {"torque_curve", std::move(curve)}};
    ojson ratios = ojson::array();
    for (const Real r : d.gearbox.ratios) ratios.push_back(num(r));
    j["gearbox"] = ojson{{"ratios", std::move(ratios)},
                         {"differential_ratio", num(d.gearbox.differentialRatio)},
                         {"shift_up_rpm", num(d.gearbox.shiftUpRpm)},
                         {"shift_down_rpm", num(d.gearbox.shiftDownRpm)}};
    j["max_brake_torque"] = num(d.maxBrakeTorque);
    j["max_hand_brake_torque"] = num(d.maxHandBrakeTorque);
    j["max_steering_angle"] = num(d.maxSteeringAngle);
    if (!d.antiRollBars.empty()) {
        ojson bars = ojson::array();
        for (const AntiRollBar& b : d.antiRollBars) bars.push_back(ojson{{"left", b.left}, {"right", b.right}, {"stiffness", num(b.stiffness)}});
        j["anti_roll_bars"] = std::move(bars);
    }
    if (!d.inputs.empty()) {
        ojson inputs = ojson::array();
        for (const VehicleInput& in : d.inputs) {
            inputs.push_back(ojson{{"time", num(in.time)},
                                   {"throttle", num(in.throttle)},
                                   {"brake", num(in.brake)},
                                   {"steering", num(in.steering)},
                                   {"hand_brake", in.handBrake}});
        }
        j["inputs"] = std::move(inputs);
    }
    return j;
}

ojson clothJson(const SceneCloth& cloth) {
    const ClothDef& d = cloth.def;
    ojson j;
    if (!d.name.empty()) j["name"] = d.name;
    j["origin"] = vec(d.origin);
    j["u_axis"] = vec(d.uAxis);
    j["v_axis"] = vec(d.vAxis);
    j["size"] = ojson::array({d.size[0], d.size[1]});
    j["spacing"] = num(d.spacing);
    j["particle_mass"] = num(d.particleMass);
    j["radius"] = num(d.radius);
    ojson pinned = ojson::array();
    for (const auto& p : d.pinned) pinned.push_back(ojson::array({p[0], p[1]}));
    j["pinned"] = std::move(pinned);
    j["stretch_compliance"] = num(d.stretchCompliance);
    j["bend_compliance"] = num(d.bendCompliance);
    return j;
}

}  // namespace

std::string sceneToJson(const Scene& scene) {
    const WorldDef defaults;
    ojson doc;
    doc["version"] = detail::kSceneFormatVersion;
    if (!scene.description.empty()) doc["description"] = scene.description;
    ojson world;
    world["gravity"] = vec(scene.world.gravity);
    world["dt"] = num(scene.dt);
    world["steps"] = scene.steps;
    world["substeps"] = scene.world.substeps;
    world["integrator"] = toString(scene.world.integrator);
    world["sleeping"] = scene.world.sleeping;
    if (scene.world.solverIterations != defaults.solverIterations) world["solver_iterations"] = scene.world.solverIterations;
    if (scene.world.threads != defaults.threads) world["threads"] = scene.world.threads;
    if (scene.world.jointHertz != defaults.jointHertz) world["joint_hertz"] = num(scene.world.jointHertz);
    if (scene.world.jointDampingRatio != defaults.jointDampingRatio) world["joint_damping_ratio"] = num(scene.world.jointDampingRatio);
    if (scene.world.jointProjectionSlop != defaults.jointProjectionSlop) {
        // JSON has no infinity: "off" (no position projection) stands for it.
        world["joint_projection_slop"] = std::isinf(scene.world.jointProjectionSlop) ? ojson("off") : ojson(num(scene.world.jointProjectionSlop));
    }
    if (scene.world.jointDirectSolve != defaults.jointDirectSolve) world["joint_direct_solve"] = scene.world.jointDirectSolve;
    if (scene.world.maxContactPairs != defaults.maxContactPairs) world["max_contact_pairs"] = scene.world.maxContactPairs;
    if (scene.world.hitEventThreshold != defaults.hitEventThreshold) world["hit_event_threshold"] = num(scene.world.hitEventThreshold);
    if (scene.world.pushOutGrownOverlaps != defaults.pushOutGrownOverlaps) world["push_out_grown_overlaps"] = scene.world.pushOutGrownOverlaps;
    if (scene.world.maxRotationPerSubstep != defaults.maxRotationPerSubstep) {
        world["max_rotation_per_substep"] =
            std::isinf(scene.world.maxRotationPerSubstep) ? ojson("off") : ojson(num(scene.world.maxRotationPerSubstep));
    }
    doc["world"] = std::move(world);
    ojson bodies = ojson::array();
    for (const SceneBody& b : scene.bodies) bodies.push_back(bodyJson(b));
    doc["bodies"] = std::move(bodies);
    if (!scene.joints.empty()) {
        ojson joints = ojson::array();
        for (const SceneJoint& j : scene.joints) joints.push_back(jointJson(j));
        doc["joints"] = std::move(joints);
    }
    if (!scene.springs.empty()) {
        ojson springs = ojson::array();
        for (const SceneSpring& s : scene.springs) springs.push_back(springJson(s));
        doc["springs"] = std::move(springs);
    }
    if (!scene.ropes.empty()) {
        ojson ropes = ojson::array();
        for (const SceneRope& r : scene.ropes) ropes.push_back(ropeJson(r));
        doc["ropes"] = std::move(ropes);
    }
    if (!scene.cloths.empty()) {
        ojson cloths = ojson::array();
        for (const SceneCloth& c : scene.cloths) cloths.push_back(clothJson(c));
        doc["cloths"] = std::move(cloths);
    }
    if (!scene.characters.empty()) {
        ojson characters = ojson::array();
        for (const SceneCharacter& c : scene.characters) characters.push_back(characterJson(c));
        doc["characters"] = std::move(characters);
    }
    if (!scene.vehicles.empty()) {
        ojson vehicles = ojson::array();
        for (const SceneVehicle& v : scene.vehicles) vehicles.push_back(vehicleJson(v));
        doc["vehicles"] = std::move(vehicles);
    }
    // Names need not be UTF-8 (the C++ API and snapshots take any bytes):
    // such bytes are written as U+FFFD rather than failing the write.
    return doc.dump(2, ' ', false, ojson::error_handler_t::replace) + "\n";
}

void saveScene(const Scene& scene, const std::filesystem::path& file) {
    const std::string text = sceneToJson(scene);
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    if (!out) throw SceneError(file.string(), "", 0, 0, "cannot open file for writing");
    out << text;
    out.flush();
    if (!out) throw SceneError(file.string(), "", 0, 0, "error while writing the file");
}

}  // namespace fulcrum
