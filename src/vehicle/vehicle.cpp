// Wheeled vehicles: creation and validation, state, and the per-step update
// (vehicle_system.hpp says when and why; docs/vehicles.md the model).
#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include "dynamics/validation.hpp"
#include "fulcrum/math/deterministic_math.hpp"
#include "fulcrum/world.hpp"
#include "vehicle/vehicle_system.hpp"
#include "world/world_access.hpp"
#include "world/world_impl.hpp"

namespace fulcrum {

using detail::Subject;
using detail::VehicleData;
using detail::WheelData;

namespace {

const Vec3 kUpLocal{0, 1, 0}, kForwardLocal{0, 0, 1};
constexpr int kTyreIterations = 8;
constexpr Real kRpmPerRadPerSecond = Real(60 / (2 * 3.14159265358979323846));
// Below this forward speed (m/s) a throttle against the motion shifts into reverse
// (or back into first) instead of braking.
constexpr Real kReverseShiftSpeed = Real(0.5);
// Below this speed slips are measured against it, so that they stay finite at rest.
constexpr Real kSlipSpeedFloor = 1;

// Tyre friction as a multiple of the wheel's friction coefficient, by slip:
// longitudinal by slip ratio, lateral by tan(slip angle) (a peak of 1.2 near
// 6 % slip / 3 degrees, 1.0 when sliding), in the manner of Jolt's default curves.
Real longitudinalCurve(Real s) {
    s = std::abs(s);
    if (s < Real(0.06)) return Real(1.2) * s / Real(0.06);
    if (s < Real(0.2)) return Real(1.2) - Real(0.2) * (s - Real(0.06)) / Real(0.14);
    return 1;
}
Real lateralCurve(Real tanAlpha) {
    tanAlpha = std::abs(tanAlpha);
    if (tanAlpha < Real(0.0524)) return Real(1.2) * tanAlpha / Real(0.0524);  // 3 degrees
    if (tanAlpha < Real(0.364)) return Real(1.2) - Real(0.2) * (tanAlpha - Real(0.0524)) / Real(0.3116);  // 20 degrees
    return 1;
}

Real torqueFraction(const EngineDef& e, Real rpm) {
    const Real x = std::clamp(rpm / e.maxRpm, Real(0), Real(1));
    const auto& c = e.torqueCurve;
    if (x <= c.front()[0]) return c.front()[1];
    for (std::size_t i = 1; i < c.size(); ++i) {
        if (x <= c[i][0]) {
            const Real span = c[i][0] - c[i - 1][0];
            const Real t = span > 0 ? (x - c[i - 1][0]) / span : 1;
            return c[i - 1][1] + (c[i][1] - c[i - 1][1]) * t;
        }
    }
    return c.back()[1];
}

const VehicleData& resolve(const WorldImpl& w, VehicleId id, const char* where) {
    return detail::resolveHandle(w.vehicles.pool, id, where, "VehicleId", "vehicle");
}
VehicleData& resolve(WorldImpl& w, VehicleId id, const char* where) {
    return const_cast<VehicleData&>(resolve(std::as_const(w), id, where));
}

void validateInput(const Subject& who, const std::string& field, const VehicleInput& in) {
    const auto unit = [&](const char* name, Real v, Real lo) {
        const std::string f = field + name;
        detail::requireFinite(who, f, v);
        if (v < lo || v > 1) detail::fail(who, f, "must be in [" + detail::formatReal(lo) + ", 1], got " + detail::formatReal(v));
    };
    detail::requireFinite(who, field + "time", in.time);
    unit("throttle", in.throttle, -1);  // negative: backwards (reverse gear, docs/vehicles.md)
    unit("brake", in.brake, 0);
    unit("steering", in.steering, -1);
}

void validate(const World& world, const VehicleDef& def) {
    const Subject who{"vehicle", def.name};
    if (def.chassis.isNull()) detail::fail(who, "chassis", "is missing: a vehicle needs a dynamic chassis body");
    if (!world.isValid(def.chassis)) detail::fail(who, "chassis", "is not a live body of this world");
    if (world.bodyType(def.chassis) != BodyType::Dynamic) {
        detail::fail(who, "chassis", std::string("must be a dynamic body, got a ") + toString(world.bodyType(def.chassis)) + " one");
    }
    if (def.wheels.empty()) detail::fail(who, "wheels", "must hold at least one wheel");
    const Transform chassis = world.transform(def.chassis);
    const AABB local = world.shape(def.chassis).bounds(Transform{});
    for (std::size_t i = 0; i < def.wheels.size(); ++i) {
        const WheelDef& wd = def.wheels[i];
        const std::string f = "wheels[" + std::to_string(i) + "].";
        detail::requireFinite(who, f + "position", wd.position);
        const Vec3 p = inverseTransformPoint(chassis, wd.position);
        constexpr Real kTolerance = Real(1e-3);
        if (p.x < local.min.x - kTolerance || p.y < local.min.y - kTolerance || p.z < local.min.z - kTolerance ||
            p.x > local.max.x + kTolerance || p.y > local.max.y + kTolerance || p.z > local.max.z + kTolerance) {
            detail::fail(who, f + "position", "must lie within the chassis's bounds (the suspension's top is mounted on it), got " +
                                                  detail::formatVec(wd.position) + ", which is " + detail::formatVec(p) +
                                                  " in the chassis's frame");
        }
        detail::requirePositive(who, f + "radius", wd.radius);
        detail::requirePositive(who, f + "width", wd.width);
        detail::requirePositive(who, f + "suspension.restLength", wd.suspension.restLength);
        detail::requirePositive(who, f + "suspension.stiffness", wd.suspension.stiffness);
        detail::requireNonNegative(who, f + "suspension.damping", wd.suspension.damping);
        detail::requirePositive(who, f + "friction", wd.friction);
        detail::requirePositive(who, f + "inertia", wd.inertia);
    }
    const EngineDef& e = def.engine;
    detail::requireNonNegative(who, "engine.maxTorque", e.maxTorque);
    detail::requirePositive(who, "engine.minRpm", e.minRpm);
    detail::requireFinite(who, "engine.maxRpm", e.maxRpm);
    if (!(e.maxRpm > e.minRpm)) detail::fail(who, "engine.maxRpm", "must be above minRpm, got " + detail::formatReal(e.maxRpm));
    if (e.torqueCurve.empty()) detail::fail(who, "engine.torqueCurve", "must hold at least one point");
    for (std::size_t i = 0; i < e.torqueCurve.size(); ++i) {
        const std::string f = "engine.torqueCurve[" + std::to_string(i) + "]";
        detail::requireNonNegative(who, f, e.torqueCurve[i][0]);
        detail::requireNonNegative(who, f, e.torqueCurve[i][1]);
        if (i > 0 && e.torqueCurve[i][0] < e.torqueCurve[i - 1][0]) detail::fail(who, f, "rpm fractions must increase");
    }
    const GearboxDef& g = def.gearbox;
    if (g.ratios.empty()) detail::fail(who, "gearbox.ratios", "must hold at least one gear");
    for (std::size_t i = 0; i < g.ratios.size(); ++i) detail::requirePositive(who, "gearbox.ratios[" + std::to_string(i) + "]", g.ratios[i]);
    detail::requirePositive(who, "gearbox.differentialRatio", g.differentialRatio);
    detail::requirePositive(who, "gearbox.shiftUpRpm", g.shiftUpRpm);
    detail::requireNonNegative(who, "gearbox.shiftDownRpm", g.shiftDownRpm);
    if (!(g.shiftDownRpm < g.shiftUpRpm)) detail::fail(who, "gearbox.shiftDownRpm", "must be below shiftUpRpm, got " + detail::formatReal(g.shiftDownRpm));
    detail::requireNonNegative(who, "maxBrakeTorque", def.maxBrakeTorque);
    detail::requireNonNegative(who, "maxHandBrakeTorque", def.maxHandBrakeTorque);
    detail::requireFinite(who, "maxSteeringAngle", def.maxSteeringAngle);
    if (def.maxSteeringAngle < 0 || def.maxSteeringAngle > Real(1.2)) {
        detail::fail(who, "maxSteeringAngle", "must be in [0, 1.2] rad, got " + detail::formatReal(def.maxSteeringAngle));
    }
    for (std::size_t i = 0; i < def.antiRollBars.size(); ++i) {
        const AntiRollBar& b = def.antiRollBars[i];
        const std::string f = "antiRollBars[" + std::to_string(i) + "].";
        if (b.left >= def.wheels.size()) detail::fail(who, f + "left", "names no wheel, got " + std::to_string(b.left));
        if (b.right >= def.wheels.size()) detail::fail(who, f + "right", "names no wheel, got " + std::to_string(b.right));
        if (b.left == b.right) detail::fail(who, f + "right", "must differ from left");
        detail::requireNonNegative(who, f + "stiffness", b.stiffness);
    }
    for (std::size_t i = 0; i < def.inputs.size(); ++i) {
        const std::string f = "inputs[" + std::to_string(i) + "].";
        validateInput(who, f, def.inputs[i]);
        if (i > 0 && def.inputs[i].time < def.inputs[i - 1].time) detail::fail(who, f + "time", "must not be before the previous input's");
    }
}

// The steering angles of the wheels for a steering input (Ackermann): every
// steered wheel points at one turning centre on the line of the unsteered
// wheels' axle, the middle of the steered axle at `angle`. Returned as the
// (sin, cos) of each wheel's angle, computed from tangents (no inverse
// trigonometry in the step).
struct SteerFrame {
    Real s = 0, c = 1;
};

}  // namespace

namespace detail {

void VehicleSystem::update(World& world, double t0, Real dt) {
    WorldImpl& w = implOf(world);
    for (const std::uint32_t slot : order) {
        VehicleData& v = pool[slot];
        const VehicleDef& def = v.def;
        if (!world.isValid(def.chassis)) continue;
        while (v.nextInput < def.inputs.size() && double(def.inputs[v.nextInput].time) <= t0 + 1e-9) {
            v.input = def.inputs[v.nextInput++];
        }
        const VehicleInput& in = v.input;
        const BodyId chassis = def.chassis;
        const std::uint32_t cd = w.resolveBody(chassis, "vehicle");
        const Transform xf = world.transform(chassis);
        const Vec3 up = rotate(xf.q, kUpLocal);
        const Real invMass = w.motion[cd].invMass;
        const Mat3 invInertia = w.motion[cd].invInertiaWorld;
        const Vec3 com = w.motion[cd].com;
        QueryFilter filter;
        filter.excludeBody = chassis;

        // Ackermann: the turning centre on the unsteered axle's line, at
        // distance L / tan(angle) from the centre line (L: steered axle to that line).
        Real rearZ = 0, frontZ = 0;
        int rear = 0, front = 0;
        for (std::size_t i = 0; i < v.wheels.size(); ++i) {
            if (def.wheels[i].steering) {
                frontZ += v.wheels[i].mountLocal.z;
                ++front;
            } else {
                rearZ += v.wheels[i].mountLocal.z;
                ++rear;
            }
        }
        rearZ = rear > 0 ? rearZ / Real(rear) : 0;
        frontZ = front > 0 ? frontZ / Real(front) : 0;
        const Real wheelbase = frontZ - rearZ;
        // The steering angle's tangent, from Fulcrum's own sine and cosine (the
        // same bits on every compiler and platform: docs/determinism.md).
        double sinSteer = 0, cosSteer = 1;
        dmath::sinCos(static_cast<double>(in.steering * def.maxSteeringAngle), sinSteer, cosSteer);
        const auto tanSteer = static_cast<Real>(sinSteer / cosSteer);

        // Suspension: cast, spring and damper, anti-roll bars.
        for (std::size_t i = 0; i < v.wheels.size(); ++i) {
            WheelData& wh = v.wheels[i];
            const WheelDef& wd = def.wheels[i];
            WheelState& s = wh.state;
            const Vec3 mount = transformPoint(xf, wh.mountLocal);
            const Real reach = wd.suspension.restLength + wd.radius;
            const std::optional<RayCastHit> hit = world.castRay(Ray{mount, up * -reach, 1}, filter);
            s.inContact = hit.has_value() && dot(hit->normal, up) > Real(0.1);
            s.suspensionForce = 0;
            if (!s.inContact) {
                s.suspensionLength = wd.suspension.restLength;
                s.contactBody = BodyId{};
                continue;
            }
            s.suspensionLength = std::clamp(hit->fraction * reach - wd.radius, Real(0), wd.suspension.restLength);
            s.contactPoint = hit->point;
            s.contactNormal = hit->normal;
            s.contactBody = hit->body;
            Vec3 groundVelocity = Vec3::zero();
            if (world.bodyType(hit->body) != BodyType::Static) groundVelocity = world.velocityAtPoint(hit->body, hit->point);
            const Real extending = dot(world.velocityAtPoint(chassis, hit->point) - groundVelocity, up);
            s.suspensionForce = wd.suspension.stiffness * (wd.suspension.restLength - s.suspensionLength) -
                                wd.suspension.damping * extending;
        }
        for (const AntiRollBar& bar : def.antiRollBars) {
            WheelState &l = v.wheels[bar.left].state, &r = v.wheels[bar.right].state;
            if (!l.inContact && !r.inContact) continue;
            const Real f = bar.stiffness * (r.suspensionLength - l.suspensionLength);  // > 0: left more compressed
            if (l.inContact) l.suspensionForce += f;
            if (r.inContact) r.suspensionForce -= f;
        }
        for (WheelData& wh : v.wheels) {
            WheelState& s = wh.state;
            s.suspensionForce = std::max(s.suspensionForce, Real(0));
            wh.normalLoad = s.inContact ? s.suspensionForce : 0;
            // Along the ground's normal: the strut only carries the load the
            // ground presses up with (a push along the chassis's tilted up
            // axis would drive a pitched car along flat ground).
            if (s.inContact && s.suspensionForce > 0) {
                world.applyForce(chassis, s.contactNormal * s.suspensionForce, s.contactPoint);
                if (world.bodyType(s.contactBody) == BodyType::Dynamic) {
                    world.applyForce(s.contactBody, s.contactNormal * -s.suspensionForce, s.contactPoint);
                }
            }
        }

        // Engine and automatic gearbox, from the driven wheels' mean spin.
        Real drivenSpin = 0;
        int driven = 0;
        for (std::size_t i = 0; i < v.wheels.size(); ++i) {
            if (!def.wheels[i].driven) continue;
            drivenSpin += v.wheels[i].state.angularVelocity;
            ++driven;
        }
        drivenSpin = driven > 0 ? drivenSpin / Real(driven) : 0;
        const GearboxDef& gb = def.gearbox;
        // Reverse (gear -1) uses the first gear's ratio, turning the other way.
        const auto gearRatio = [&](int gear) { return gb.ratios[std::size_t(gear < 0 ? 0 : gear - 1)]; };
        const auto rpmIn = [&](int gear) { return std::abs(drivenSpin) * gearRatio(gear) * gb.differentialRatio * kRpmPerRadPerSecond; };
        // The throttle's sign is the direction asked for. Against the way the
        // car still moves it brakes (by its size) instead of driving; once the
        // car has (nearly) stopped, the gearbox engages reverse or first.
        Real throttle = in.throttle, brake = in.brake;
        const bool backwards = throttle < 0;
        if (backwards == (v.gear > 0) && throttle != 0) {
            const Real along = dot(w.motion[cd].v, rotate(xf.q, kForwardLocal));
            if (backwards ? along > kReverseShiftSpeed : along < -kReverseShiftSpeed) {
                brake = std::max(brake, std::abs(throttle));
                throttle = 0;
            } else {
                v.gear = backwards ? -1 : 1;
            }
        }
        if (v.gear > 0) {
            if (rpmIn(v.gear) > gb.shiftUpRpm && v.gear < int(gb.ratios.size()) && rpmIn(v.gear + 1) > gb.shiftDownRpm) ++v.gear;
            else if (rpmIn(v.gear) < gb.shiftDownRpm && v.gear > 1 && rpmIn(v.gear - 1) < gb.shiftUpRpm) --v.gear;
        }
        const Real ratio = gearRatio(v.gear) * gb.differentialRatio;
        v.engineRpm = std::max(rpmIn(v.gear), def.engine.minRpm);
        const Real engineTorque =
            v.engineRpm >= def.engine.maxRpm ? 0 : std::abs(throttle) * def.engine.maxTorque * torqueFraction(def.engine, v.engineRpm);
        const Real wheelDrive = driven > 0 ? (v.gear < 0 ? -engineTorque : engineTorque) * ratio / Real(driven) : 0;

        // Tyres: a small sequential-impulse solve over the wheels on the
        // ground (brake, rolling, side grip), on a copy of the chassis's
        // velocity, each impulse bounded by the friction ellipse whose axes
        // grow with the slip the step starts with. The impulses become forces
        // over the step.
        Vec3 lin = w.motion[cd].v, ang = w.motion[cd].w;
        for (std::size_t i = 0; i < v.wheels.size(); ++i) {
            WheelData& wh = v.wheels[i];
            const WheelDef& wd = def.wheels[i];
            WheelState& s = wh.state;
            wh.brakeImpulse = wh.longImpulse = wh.latImpulse = 0;
            if (wd.driven) s.angularVelocity += wheelDrive * dt / wd.inertia;
            // The wheel's heading: forward turned about up by its steering angle.
            SteerFrame sf;
            if (wd.steering && tanSteer != 0 && wheelbase != 0) {
                const Real lw = wh.mountLocal.z - rearZ;
                const Real t = lw * tanSteer / (wheelbase - wh.mountLocal.x * tanSteer);
                const Real c = 1 / std::sqrt(1 + t * t);
                sf = {t * c, c};
                if (wheelbase - wh.mountLocal.x * tanSteer < 0) sf = {-sf.s, -sf.c};
            }
            wh.sinSteer = sf.s;
            wh.cosSteer = sf.c;
            if (!s.inContact) continue;
            const Vec3 heading = rotate(xf.q, Vec3{sf.s, 0, sf.c});
            const Vec3 n = s.contactNormal;
            Vec3 fwd = heading - n * dot(heading, n);
            fwd = normalize(fwd);
            wh.forward = fwd;
            wh.side = cross(n, fwd);
            Vec3 groundVelocity = Vec3::zero();
            if (world.bodyType(s.contactBody) != BodyType::Static) groundVelocity = world.velocityAtPoint(s.contactBody, s.contactPoint);
            const Vec3 rel = lin + cross(ang, s.contactPoint - com) - groundVelocity;
            const Real vLong = dot(rel, fwd), vLat = dot(rel, wh.side);
            const Real floor = std::max(std::abs(vLong), kSlipSpeedFloor);
            s.longitudinalSlip = (s.angularVelocity * wd.radius - vLong) / floor;
            s.lateralSlip = vLat / floor;
            const Real limit = wd.friction * wh.normalLoad * dt;
            wh.maxLong = limit * longitudinalCurve(s.longitudinalSlip);
            wh.maxLat = limit * lateralCurve(s.lateralSlip);
            // A tyre that does not slip yet still grips a little, or it never would.
            wh.maxLong = std::max(wh.maxLong, Real(0.05) * limit);
            wh.maxLat = std::max(wh.maxLat, Real(0.05) * limit);
        }
        const auto inverseMassAlong = [&](const Vec3& point, const Vec3& dir) {
            const Vec3 rc = cross(point - com, dir);
            return invMass + dot(rc, invInertia * rc);
        };
        for (int iter = 0; iter < kTyreIterations; ++iter) {
            for (std::size_t i = 0; i < v.wheels.size(); ++i) {
                WheelData& wh = v.wheels[i];
                const WheelDef& wd = def.wheels[i];
                WheelState& s = wh.state;
                // Brakes: torque against the spin, at most the brake's over the step.
                const Real brakeTorque = brake * def.maxBrakeTorque + (in.handBrake && wd.handBrake ? def.maxHandBrakeTorque : 0);
                if (brakeTorque > 0) {
                    const Real maxB = brakeTorque * dt;
                    const Real want = -s.angularVelocity * wd.inertia;
                    const Real old = wh.brakeImpulse;
                    wh.brakeImpulse = std::clamp(old + want, -maxB, maxB);
                    s.angularVelocity += (wh.brakeImpulse - old) / wd.inertia;
                }
                if (!s.inContact || wh.normalLoad <= 0) continue;
                const Vec3 r = s.contactPoint - com;
                const auto apply = [&](const Vec3& impulse) {
                    lin += impulse * invMass;
                    ang += invInertia * cross(r, impulse);
                };
                // Rolling: the contact's forward speed equal to the tyre's surface speed.
                {
                    const Real vLong = dot(lin + cross(ang, r), wh.forward);
                    const Real err = vLong - s.angularVelocity * wd.radius;
                    const Real k = inverseMassAlong(s.contactPoint, wh.forward) + wd.radius * wd.radius / wd.inertia;
                    const Real old = wh.longImpulse;
                    Real next = old - err / k;
                    // Friction ellipse with the side impulse as it is.
                    const Real room = wh.maxLat > 0 ? std::max(Real(0), 1 - (wh.latImpulse / wh.maxLat) * (wh.latImpulse / wh.maxLat)) : 1;
                    const Real cap = wh.maxLong * std::sqrt(room);
                    next = std::clamp(next, -cap, cap);
                    const Real d = next - old;
                    wh.longImpulse = next;
                    apply(wh.forward * d);
                    s.angularVelocity -= d * wd.radius / wd.inertia;  // the ground's push forward slows the wheel
                }
                // Side grip: no sideways sliding of the contact.
                {
                    const Real vLat = dot(lin + cross(ang, r), wh.side);
                    const Real k = inverseMassAlong(s.contactPoint, wh.side);
                    const Real old = wh.latImpulse;
                    Real next = old - vLat / k;
                    const Real room = wh.maxLong > 0 ? std::max(Real(0), 1 - (wh.longImpulse / wh.maxLong) * (wh.longImpulse / wh.maxLong)) : 1;
                    const Real cap = wh.maxLat * std::sqrt(room);
                    next = std::clamp(next, -cap, cap);
                    wh.latImpulse = next;
                    apply(wh.side * (next - old));
                }
            }
        }
        for (std::size_t i = 0; i < v.wheels.size(); ++i) {
            WheelData& wh = v.wheels[i];
            WheelState& s = wh.state;
            s.rotation += s.angularVelocity * dt;
            if (!s.inContact || (wh.longImpulse == 0 && wh.latImpulse == 0)) continue;
            const Vec3 force = (wh.forward * wh.longImpulse + wh.side * wh.latImpulse) / dt;
            world.applyForce(chassis, force, s.contactPoint);
            if (world.bodyType(s.contactBody) == BodyType::Dynamic) world.applyForce(s.contactBody, -force, s.contactPoint);
        }
    }
}

}  // namespace detail

VehicleId createVehicle(World& world, const VehicleDef& def) {
    WorldImpl& w = detail::implOf(world);
    validate(world, def);
    const Transform xf = world.transform(def.chassis);
    const std::uint32_t slot = w.vehicles.pool.nextSlot();
    VehicleData& v = w.vehicles.pool.add();
    const std::uint32_t generation = v.generation;
    v = VehicleData{};
    v.alive = true;
    v.generation = generation;
    v.def = def;
    v.wheels.resize(def.wheels.size());
    // Wheels start rolling with the chassis, so a moving vehicle does not skid at first.
    const Vec3 forward = rotate(xf.q, kForwardLocal);
    for (std::size_t i = 0; i < def.wheels.size(); ++i) {
        WheelData& wh = v.wheels[i];
        wh.mountLocal = inverseTransformPoint(xf, def.wheels[i].position);
        wh.state.suspensionLength = def.wheels[i].suspension.restLength;
        wh.state.angularVelocity = dot(world.velocityAtPoint(def.chassis, def.wheels[i].position), forward) / def.wheels[i].radius;
    }
    v.engineRpm = def.engine.minRpm;
    w.vehicles.order.push_back(slot);
    return w.vehicles.pool.handleOf(slot);
}

void destroyVehicle(World& world, VehicleId id) {
    WorldImpl& w = detail::implOf(world);
    VehicleData& v = resolve(w, id, "destroyVehicle");
    v.def = VehicleDef{};
    v.wheels.clear();
    std::erase(w.vehicles.order, id.index);
    w.vehicles.pool.remove(id.index);
}

bool isValid(const World& world, VehicleId id) { return detail::implOf(world).vehicles.pool.isLive(id); }

std::vector<VehicleId> vehicles(const World& world) {
    const WorldImpl& w = detail::implOf(world);
    std::vector<VehicleId> out;
    for (const std::uint32_t slot : w.vehicles.order) out.push_back(w.vehicles.pool.handleOf(slot));
    return out;
}

const VehicleDef& vehicleDef(const World& world, VehicleId id) { return resolve(detail::implOf(world), id, "vehicleDef").def; }

VehicleState vehicleState(const World& world, VehicleId id) {
    const VehicleData& v = resolve(detail::implOf(world), id, "vehicleState");
    VehicleState s;
    if (world.isValid(v.def.chassis)) {
        const Transform xf = world.transform(v.def.chassis);
        s.position = xf.p;
        s.speed = dot(world.linearVelocity(v.def.chassis), rotate(xf.q, kForwardLocal));
    }
    s.gear = v.gear;
    s.engineRpm = v.engineRpm;
    for (const WheelData& wh : v.wheels) {
        s.wheels.push_back(wh.state);
        s.wheels.back().steerAngle = dmath::atan2(wh.sinSteer, wh.cosSteer);
    }
    return s;
}

void setVehicleInput(World& world, VehicleId id, const VehicleInput& input) {
    VehicleData& v = resolve(detail::implOf(world), id, "setVehicleInput");
    validateInput(Subject{"vehicle", v.def.name}, "input.", input);
    v.input = input;
}

}  // namespace fulcrum
