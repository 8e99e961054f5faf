#pragma once
// The World's vehicles (fulcrum/vehicle.hpp, docs/vehicles.md): definitions,
// state, and the forces each applies at the start of a step.
//
// Why at the start of World::step, serially: the wheels' casts and the tyre
// impulses need the state the step starts from, and what they produce are
// forces on the chassis (and on dynamic ground) that the step then
// integrates with everything else over its sub-steps, as a user's forces.
// The step's parallel stages are untouched; the queries and the small tyre
// solve are the same for every thread count.
#include <cstdint>
#include <vector>

#include "dynamics/slot_pool.hpp"
#include "fulcrum/vehicle.hpp"

namespace fulcrum::detail {

struct WheelData {
    Vec3 mountLocal;    // chassis frame
    WheelState state;
    Real brakeImpulse = 0, longImpulse = 0, latImpulse = 0;  // tyre solve scratch
    Vec3 forward, side; // tyre solve scratch: contact frame
    Real normalLoad = 0, maxLong = 0, maxLat = 0;
    Real sinSteer = 0, cosSteer = 1;  // the steering angle's
};

struct VehicleData : PoolSlot {
    VehicleDef def;
    std::vector<WheelData> wheels;
    VehicleInput input;
    std::uint32_t nextInput = 0;
    int gear = 1;
    Real engineRpm = 0;
};

class VehicleSystem {
public:
    SlotPool<VehicleData, VehicleId> pool;
    std::vector<std::uint32_t> order;  // live slots in creation order

    bool empty() const { return order.empty(); }
    // Casts the wheels and applies the suspension and tyre forces for the
    // step of `dt` starting at world time t0.
    void update(World& world, double t0, Real dt);
};

}  // namespace fulcrum::detail
