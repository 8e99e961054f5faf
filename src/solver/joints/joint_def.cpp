#include "solver/joints/joint_def.hpp"

#include <cmath>
#include <numbers>

#include "fulcrum/world.hpp"

namespace fulcrum::detail {

namespace {

constexpr Real kPi = std::numbers::pi_v<Real>;

EndPose endPose(const World& world, BodyId id, const char* where, const char* field) {
    if (id.isNull()) return {};
    if (!world.isValid(id)) {
        throw Error(std::string(where) + ": " + field + " refers to a body that does not exist or was destroyed (index " +
                    std::to_string(id.index) + ", generation " + std::to_string(id.generation) + ")");
    }
    return {world.centerOfMass(id), world.orientation(id), false};
}

}  // namespace

JointEnds jointEnds(const World& world, BodyId a, BodyId b, const char* where) {
    if (b.isNull()) throw Error(std::string(where) + ": bodyB must be a body (only bodyA may be the static world)");
    return {endPose(world, a, where, "bodyA"), endPose(world, b, where, "bodyB")};
}

Vec3 worldAxisArgument(const Vec3& axis, const char* where) {
    const Real len = length(axis);
    if (!isFinite(axis) || !(len > Real(1e-6))) {
        throw Error(std::string(where) + ": axis must be a finite, non-zero direction, got " + formatVec(axis));
    }
    return axis / len;
}

JointDef baseRecord(const JointDefBase& def, JointType type) {
    JointDef r;
    r.name = def.name;
    r.type = type;
    r.bodyA = def.bodyA;
    r.bodyB = def.bodyB;
    r.breakForce = def.breakForce;
    r.breakTorque = def.breakTorque;
    r.collideConnected = def.collideConnected;
    return r;
}

JointDefBase baseOf(const JointDef& def) {
    JointDefBase b;
    b.name = def.name;
    b.bodyA = def.bodyA;
    b.bodyB = def.bodyB;
    b.breakForce = def.breakForce;
    b.breakTorque = def.breakTorque;
    b.collideConnected = def.collideConnected;
    return b;
}

void requireBreakThreshold(const Subject& who, const char* field, Real v) {
    if (std::isnan(v) || v <= 0 || v == -std::numeric_limits<Real>::infinity()) {
        fail(who, field, "must be positive (or +infinity for unbreakable), got " + formatReal(v));
    }
}

void validateLimits(const Subject& who, bool enabled, Real lower, Real upper, bool angle) {
    requireFinite(who, "lowerLimit", lower);
    requireFinite(who, "upperLimit", upper);
    if (!enabled) return;
    if (lower > upper) {
        fail(who, "lowerLimit", "(" + formatReal(lower) + ") is above upperLimit (" + formatReal(upper) + ")");
    }
    // Hinge angles are measured in (-pi, pi]: a limit outside can never be reached.
    if (angle && (lower < -kPi || upper > kPi)) {
        fail(who, lower < -kPi ? "lowerLimit" : "upperLimit",
             "must be within [-pi, pi] radians for a hinge, got [" + formatReal(lower) + ", " + formatReal(upper) + "]");
    }
}

void validateMotor(const Subject& who, const JointMotor& m) {
    requireFinite(who, "motor.speed", m.speed);
    requireNonNegative(who, "motor.maxForce", m.maxForce);
}

void validateSpring(const Subject& who, const JointSpring& s) {
    requireFinite(who, "spring.target", s.target);
    requireNonNegative(who, "spring.stiffness", s.stiffness);
    requireNonNegative(who, "spring.damping", s.damping);
    requireForceLimit(who, "spring.maxForce", s.maxForce);
}

void requireForceLimit(const Subject& who, const std::string& field, Real v) {
    if (std::isnan(v) || v < 0) fail(who, field, "must be >= 0 (+infinity: unlimited), got " + formatReal(v));
}

void requireUnitAxis(const Subject& who, const char* field, const Vec3& v) {
    requireFinite(who, field, v);
    const Real len = length(v);
    if (!(std::abs(len - 1) <= Real(1e-4))) {
        fail(who, field, "must be a unit vector, got " + formatVec(v) + " (length " + formatReal(len) + ")");
    }
}

void validateFrictionTorque(const Subject& who, Real frictionTorque) {
    requireNonNegative(who, "frictionTorque", frictionTorque);
}

void validateConeTwistRanges(const Subject& who, Real swingLimit, Real twistLower, Real twistUpper) {
    requireFinite(who, "swingLimit", swingLimit);
    if (swingLimit <= 0 || swingLimit > kPi) {
        fail(who, "swingLimit", "must be in (0, pi] radians (pi: no cone), got " + formatReal(swingLimit));
    }
    requireFinite(who, "twistLower", twistLower);
    requireFinite(who, "twistUpper", twistUpper);
    if (twistLower > twistUpper) {
        fail(who, "twistLower", "(" + formatReal(twistLower) + ") is above twistUpper (" + formatReal(twistUpper) + ")");
    }
    if (twistLower < -kPi || twistUpper > kPi) {
        fail(who, twistLower < -kPi ? "twistLower" : "twistUpper",
             "must be within [-pi, pi] radians, got [" + formatReal(twistLower) + ", " + formatReal(twistUpper) + "]");
    }
}

void validateConeTwistDrive(const Subject& who, const ConeTwistDrive& drive) {
    requireFinite(who, "drive.target", drive.target);
    const Real n = length(drive.target);
    if (!(std::abs(n - 1) <= Real(1e-4))) fail(who, "drive.target", "must be a unit quaternion, got length " + formatReal(n));
    if (std::isnan(drive.stiffness) || drive.stiffness < 0) {
        fail(who, "drive.stiffness", "must not be negative (+infinity: rigid), got " + formatReal(drive.stiffness));
    }
    requireNonNegative(who, "drive.damping", drive.damping);
    if (std::isnan(drive.maxTorque) || !(drive.maxTorque > 0)) {
        fail(who, "drive.maxTorque", "must be positive (+infinity: unlimited), got " + formatReal(drive.maxTorque));
    }
}

}  // namespace fulcrum::detail
