// SceneError and the value comparisons of the Scene description.
#include "fulcrum/scene.hpp"

namespace fulcrum {

namespace {

// A document path short enough for a one-line message: a path of a deeply
// nested value (hundreds of characters) keeps its first and last components,
// whole, around "...": "bodies[0].shape.children[0]...children[0].shape.radius".
// SceneError::path() keeps the whole path.
std::string shortenedPath(const std::string& path) {
    constexpr std::size_t kLimit = 100, kEachEnd = 40;
    if (path.size() <= kLimit) return path;
    // Cut only at the dots between components, so each kept one is whole.
    const std::size_t head = path.find('.', kEachEnd);
    const std::size_t tail = path.rfind('.', path.size() - kEachEnd);
    if (head == std::string::npos || tail == std::string::npos || tail <= head) return path;
    return path.substr(0, head) + "..." + path.substr(tail + 1);
}

std::string sceneErrorText(const std::string& file, const std::string& path, int line, int column, const std::string& reason) {
    // file:line: path: reason  (line:column only for problems of the text itself)
    std::string s = file.empty() ? "<scene>" : file;
    if (line > 0) {
        s += ':' + std::to_string(line);
        if (path.empty() && column > 0) s += ':' + std::to_string(column);
    }
    s += ": ";
    if (!path.empty()) s += shortenedPath(path) + ": ";
    s += reason;
    return s;
}

bool sameInertia(const std::optional<Mat3>& a, const std::optional<Mat3>& b) {
    if (a.has_value() != b.has_value()) return false;
    return !a || *a == *b;
}

}  // namespace

SceneError::SceneError(std::string file, std::string path, int line, int column, std::string reason)
    : Error(sceneErrorText(file, path, line, column, reason)),
      file_(std::move(file)),
      path_(std::move(path)),
      line_(line),
      column_(column),
      reason_(std::move(reason)) {}

bool ShapeDesc::operator==(const ShapeDesc& o) const {
    if (type != o.type || convexRadius != o.convexRadius) return false;
    if (scale != o.scale || decompose != o.decompose) return false;
    switch (type) {
        case ShapeType::Sphere: return radius == o.radius;
        case ShapeType::Box: return halfExtents == o.halfExtents;
        case ShapeType::Capsule:
        case ShapeType::Cylinder: return radius == o.radius && halfHeight == o.halfHeight;
        case ShapeType::ConvexHull: return points == o.points;
        case ShapeType::Plane: return normal == o.normal && offset == o.offset;
        case ShapeType::Mesh: return vertices == o.vertices && triangles == o.triangles;
        case ShapeType::Compound: return children == o.children;
        case ShapeType::HeightField:
            return rows == o.rows && columns == o.columns && spacingX == o.spacingX && spacingZ == o.spacingZ &&
                   heights == o.heights && holes == o.holes;
    }
    return false;
}

bool SceneBody::operator==(const SceneBody& o) const {
    const BodyDef &a = def, &b = o.def;
    return shape == o.shape && a.name == b.name && a.type == b.type && a.mass == b.mass && a.density == b.density &&
           sameInertia(a.inertia, b.inertia) && a.centerOfMass == b.centerOfMass && a.position == b.position && a.orientation == b.orientation &&
           a.linearVelocity == b.linearVelocity && a.angularVelocity == b.angularVelocity && a.friction == b.friction &&
           a.restitution == b.restitution && a.rollingResistance == b.rollingResistance &&
           a.linearDamping == b.linearDamping && a.angularDamping == b.angularDamping && a.linearDrag == b.linearDrag &&
           a.quadraticDrag == b.quadraticDrag && a.gravityScale == b.gravityScale &&
           a.filter.category == b.filter.category && a.filter.mask == b.filter.mask && a.filter.group == b.filter.group &&
           a.isSensor == b.isSensor && a.isBullet == b.isBullet && a.allowSleep == b.allowSleep && a.awake == b.awake;
}

bool SceneJoint::operator==(const SceneJoint& o) const {
    const JointDef &a = def, &b = o.def;
    return bodyA == o.bodyA && bodyB == o.bodyB && a.name == b.name && a.type == b.type && a.anchor == b.anchor &&
           a.anchorB == b.anchorB && a.axis == b.axis && a.hasLimits == b.hasLimits && a.lowerLimit == b.lowerLimit &&
           a.upperLimit == b.upperLimit && a.motor.enabled == b.motor.enabled && a.motor.speed == b.motor.speed &&
           a.motor.maxForce == b.motor.maxForce && a.spring.enabled == b.spring.enabled &&
           a.spring.target == b.spring.target && a.spring.stiffness == b.spring.stiffness &&
           a.spring.damping == b.spring.damping && a.spring.maxForce == b.spring.maxForce && a.minLength == b.minLength && a.maxLength == b.maxLength &&
           a.stiffness == b.stiffness && a.damping == b.damping && a.swingLimit == b.swingLimit &&
           a.twistLower == b.twistLower && a.twistUpper == b.twistUpper && a.breakForce == b.breakForce &&
           a.breakTorque == b.breakTorque && a.collideConnected == b.collideConnected && a.frictionTorque == b.frictionTorque;
}

bool SceneSpring::operator==(const SceneSpring& o) const {
    const SpringDef &a = def, &b = o.def;
    return bodyA == o.bodyA && bodyB == o.bodyB && a.anchorA == b.anchorA && a.anchorB == b.anchorB &&
           a.restLength == b.restLength && a.stiffness == b.stiffness && a.damping == b.damping;
}

bool SceneRope::operator==(const SceneRope& o) const {
    const RopeDef &a = def, &b = o.def;
    return attachStart == o.attachStart && attachEnd == o.attachEnd && a.name == b.name && a.start == b.start &&
           a.end == b.end && a.segments == b.segments && a.particleMass == b.particleMass && a.radius == b.radius &&
           a.pinStart == b.pinStart && a.pinEnd == b.pinEnd && a.stretchCompliance == b.stretchCompliance &&
           a.bendCompliance == b.bendCompliance;
}

bool SceneCharacter::operator==(const SceneCharacter& o) const {
    const CharacterDef &a = def, &b = o.def;
    if (a.inputs.size() != b.inputs.size()) return false;
    for (std::size_t i = 0; i < a.inputs.size(); ++i) {
        const CharacterInput &x = a.inputs[i], &y = b.inputs[i];
        if (x.time != y.time || x.velocity != y.velocity || x.jump != y.jump) return false;
    }
    return a.name == b.name && a.position == b.position && a.radius == b.radius && a.height == b.height &&
           a.mass == b.mass && a.maxSlope == b.maxSlope && a.stepHeight == b.stepHeight && a.jumpSpeed == b.jumpSpeed &&
           a.maxPushForce == b.maxPushForce && a.stickDistance == b.stickDistance;
}

bool SceneVehicle::operator==(const SceneVehicle& o) const {
    const VehicleDef &a = def, &b = o.def;
    if (chassis != o.chassis || a.name != b.name || a.wheels.size() != b.wheels.size() || a.inputs.size() != b.inputs.size() ||
        a.antiRollBars.size() != b.antiRollBars.size()) {
        return false;
    }
    for (std::size_t i = 0; i < a.wheels.size(); ++i) {
        const WheelDef &x = a.wheels[i], &y = b.wheels[i];
        if (x.position != y.position || x.radius != y.radius || x.width != y.width ||
            x.suspension.restLength != y.suspension.restLength || x.suspension.stiffness != y.suspension.stiffness ||
            x.suspension.damping != y.suspension.damping || x.steering != y.steering || x.driven != y.driven ||
            x.handBrake != y.handBrake || x.friction != y.friction || x.inertia != y.inertia) {
            return false;
        }
    }
    for (std::size_t i = 0; i < a.inputs.size(); ++i) {
        const VehicleInput &x = a.inputs[i], &y = b.inputs[i];
        if (x.time != y.time || x.throttle != y.throttle || x.brake != y.brake || x.steering != y.steering ||
            x.handBrake != y.handBrake) {
            return false;
        }
    }
    for (std::size_t i = 0; i < a.antiRollBars.size(); ++i) {
        const AntiRollBar &x = a.antiRollBars[i], &y = b.antiRollBars[i];
        if (x.left != y.left || x.right != y.right || x.stiffness != y.stiffness) return false;
    }
    return a.engine.maxTorque == b.engine.maxTorque && a.engine.maxRpm == b.engine.maxRpm &&
           a.engine.minRpm == b.engine.minRpm && a.engine.torqueCurve == b.engine.torqueCurve &&
           a.gearbox.ratios == b.gearbox.ratios && a.gearbox.differentialRatio == b.gearbox.differentialRatio &&
           a.gearbox.shiftUpRpm == b.gearbox.shiftUpRpm && a.gearbox.shiftDownRpm == b.gearbox.shiftDownRpm &&
           a.maxBrakeTorque == b.maxBrakeTorque && a.maxHandBrakeTorque == b.maxHandBrakeTorque &&
           a.maxSteeringAngle == b.maxSteeringAngle;
}

bool SceneCloth::operator==(const SceneCloth& o) const {
    const ClothDef &a = def, &b = o.def;
    return a.name == b.name && a.origin == b.origin && a.uAxis == b.uAxis && a.vAxis == b.vAxis && a.size == b.size &&
           a.spacing == b.spacing && a.particleMass == b.particleMass && a.radius == b.radius && a.pinned == b.pinned &&
           a.stretchCompliance == b.stretchCompliance && a.bendCompliance == b.bendCompliance;
}

bool Scene::operator==(const Scene& o) const {
    const WorldDef &a = world, &b = o.world;
    return description == o.description && a.gravity == b.gravity && a.integrator == b.integrator &&
           a.substeps == b.substeps && a.solverIterations == b.solverIterations && a.sleeping == b.sleeping &&
           a.threads == b.threads && a.jointHertz == b.jointHertz && a.jointDampingRatio == b.jointDampingRatio &&
           a.jointProjectionSlop == b.jointProjectionSlop && a.maxRotationPerSubstep == b.maxRotationPerSubstep && a.jointDirectSolve == b.jointDirectSolve &&
           a.maxContactPairs == b.maxContactPairs && a.hitEventThreshold == b.hitEventThreshold &&
           a.pushOutGrownOverlaps == b.pushOutGrownOverlaps && dt == o.dt && steps == o.steps && bodies == o.bodies && joints == o.joints &&
           springs == o.springs && ropes == o.ropes && cloths == o.cloths &&
           characters == o.characters && vehicles == o.vehicles;
}

std::string sceneBodyName(const Scene& scene, std::size_t index) {
    if (index < scene.bodies.size() && !scene.bodies[index].def.name.empty()) return scene.bodies[index].def.name;
    return "body" + std::to_string(index);
}

}  // namespace fulcrum
