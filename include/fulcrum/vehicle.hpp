#pragma once
// Wheeled vehicles (docs/vehicles.md): a dynamic chassis body with wheels
// cast to the ground, in the manner of Jolt's WheeledVehicleController and
// Bullet's raycast vehicle. Each step, before the bodies move, every wheel
// casts a ray down its suspension; a wheel on the ground pushes the chassis
// up with its spring and damper and grips the ground with a tyre whose
// longitudinal and lateral friction grow with slip up to a friction limit
// (friction ellipse). An engine with a torque curve drives the driven wheels
// through an automatic gearbox; brakes, a hand brake, Ackermann steering and
// anti-roll bars complete it.
//
// Chassis frame: up is local +y, forward local +z; steering +1 turns left
// (towards local +x).
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "fulcrum/id.hpp"
#include "fulcrum/math.hpp"

namespace fulcrum {

class World;
using VehicleId = Id<struct VehicleTag>;

struct WheelSuspension {
    Real restLength = Real(0.3);  // m, > 0: longest travel (the spring's rest length); it compresses to 0
    Real stiffness = 30000;       // N/m, > 0
    Real damping = 4000;          // N s/m, >= 0
};

struct WheelDef {
    Vec3 position;                // world-space mounting point at creation (top of the suspension), inside the chassis's bounds
    Real radius = Real(0.35);     // m, > 0
    Real width = Real(0.2);       // m, > 0 (drawing)
    WheelSuspension suspension;
    bool steering = false;        // turned by the steering input (Ackermann)
    bool driven = false;          // driven by the engine
    bool handBrake = false;       // braked by the hand brake
    Real friction = 1;            // tyre friction coefficient (peak of the curves below is 1.2 times it), > 0
    Real inertia = Real(1.0);     // kg m^2 about the axle, > 0
};

// Torque curve: (rpm / maxRpm, fraction of maxTorque) points, rpm fractions
// increasing from 0 to 1; linear between them.
struct EngineDef {
    Real maxTorque = 400;      // N m, >= 0
    Real maxRpm = 6000;        // > minRpm: no torque beyond it
    Real minRpm = 1000;        // > 0: the engine's speed never drops below it (clutch)
    std::vector<std::array<Real, 2>> torqueCurve{{0, Real(0.8)}, {Real(0.66), 1}, {1, Real(0.8)}};
};

struct GearboxDef {
    std::vector<Real> ratios{Real(2.66), Real(1.78), Real(1.3), 1, Real(0.74)};  // forward gears, > 0; reverse uses the first's
    Real differentialRatio = Real(3.42);  // > 0
    Real shiftUpRpm = 4000;    // automatic: up a gear above this engine speed
    Real shiftDownRpm = 2000;  // ... down a gear below it; < shiftUpRpm
};

struct AntiRollBar {
    std::uint32_t left = 0, right = 1;  // wheel indices
    Real stiffness = 5000;              // N/m of compression difference, >= 0
};

// An input: from `time` on (scripts) or until changed (World code).
struct VehicleInput {
    Real time = 0;
    Real throttle = 0;   // -1..1; negative drives backwards (reverse gear once stopped; until then it brakes)
    Real brake = 0;      // 0..1
    Real steering = 0;   // -1..1; +1 turns left
    bool handBrake = false;
};

struct VehicleDef {
    std::string name;
    BodyId chassis;                  // a live dynamic body
    std::vector<WheelDef> wheels;    // at least one
    EngineDef engine;
    GearboxDef gearbox;
    Real maxBrakeTorque = 3000;      // N m per wheel at brake 1, >= 0
    Real maxHandBrakeTorque = 4000;  // N m per hand-braked wheel, >= 0
    Real maxSteeringAngle = Real(0.6);  // rad, in [0, 1.2]: of the middle of the front axle (Ackermann spreads it)
    std::vector<AntiRollBar> antiRollBars;
    std::vector<VehicleInput> inputs;   // optional script, times in order
};

struct WheelState {
    bool inContact = false;
    Real suspensionLength = 0;  // m, 0 (fully compressed) to restLength
    Real suspensionForce = 0;   // N, along the chassis's up
    Real angularVelocity = 0;   // rad/s about the axle (positive rolls forward)
    Real rotation = 0;          // rad, accumulated (drawing)
    Real steerAngle = 0;        // rad
    Real longitudinalSlip = 0;  // (omega r - v) / max(|v|, 1 m/s)
    Real lateralSlip = 0;       // tan of the slip angle
    Vec3 contactPoint, contactNormal;
    BodyId contactBody;
};

struct VehicleState {
    Vec3 position;              // chassis origin
    Real speed = 0;             // m/s along the chassis's forward axis
    int gear = 1;               // 1-based forward gear; -1 in reverse
    Real engineRpm = 0;
    std::vector<WheelState> wheels;
};

// The World's vehicles (functions rather than World members, so that the
// World's header stays as it is). Errors: fulcrum::Error naming the vehicle
// and the field.
VehicleId createVehicle(World& world, const VehicleDef& def);
void destroyVehicle(World& world, VehicleId id);
bool isValid(const World& world, VehicleId id);
std::vector<VehicleId> vehicles(const World& world);  // creation order
const VehicleDef& vehicleDef(const World& world, VehicleId id);
VehicleState vehicleState(const World& world, VehicleId id);
// The held input from now on (until the script's next entry, if any).
void setVehicleInput(World& world, VehicleId id, const VehicleInput& input);

}  // namespace fulcrum
