#pragma once
// The test car of tests/vehicle: a box chassis on four wheels (front steered,
// rear driven and hand-braked) on flat ground, a plane or a heightfield.
#include <vector>

#include <fulcrum/fulcrum.hpp>
#include <fulcrum/vehicle.hpp>

namespace fulcrum::test_car {

constexpr Real kDt = Real(1) / Real(60);
constexpr Real kG = Real(9.81);
constexpr Real kRadius = Real(0.35), kRest = Real(0.3), kStiffness = 30000;

struct Car {
    World world;
    BodyId chassis;
    VehicleId vehicle;
};

struct CarSpec {
    Real mass = 1500;
    Vec3 halfExtents{Real(0.9), Real(0.3), 2};
    Real frontZ = Real(1.3), rearZ = Real(-1.3), halfTrack = Real(0.8);
    Real speed = 0;        // initial, along +z
    Real friction = 1;
    Real drag = 0;         // chassis quadratic drag
    int threads = 1;
    // The ground: an infinite plane, or a flat heightfield (x in [-10, 10],
    // z in [-10, 70], 1 m cells) whose surface is the same y = 0.
    bool heightField = false;
};

inline Car makeCar(const CarSpec& spec, VehicleDef def = {}) {
    Car car{World(WorldDef{.threads = spec.threads}), {}, {}};
    car.world.setParallelMinBodies(0);
    BodyDef ground;
    ground.type = BodyType::Static;
    if (spec.heightField) {
        constexpr int kColumns = 21, kRows = 81;
        ground.shape = Shape::heightField(kRows, kColumns, 1, 1, std::vector<Real>(kRows * kColumns, Real(0)));
        ground.position = {-10, 0, -10};
    } else {
        ground.shape = Shape::plane({0, 1, 0}, 0);
    }
    car.world.createBody(ground);
    BodyDef chassis;
    chassis.name = "chassis";
    chassis.shape = Shape::box(spec.halfExtents);
    chassis.mass = spec.mass;
    chassis.position = {0, kRadius + kRest + spec.halfExtents.y, 0};
    chassis.linearVelocity = {0, 0, spec.speed};
    chassis.quadraticDrag = spec.drag;
    chassis.allowSleep = false;
    car.chassis = car.world.createBody(chassis);
    def.name = "car";
    def.chassis = car.chassis;
    const Real bottom = chassis.position.y - spec.halfExtents.y;
    for (int i = 0; i < 4; ++i) {
        WheelDef w;
        const bool front = i < 2;
        w.position = {i % 2 == 0 ? spec.halfTrack : -spec.halfTrack, bottom, front ? spec.frontZ : spec.rearZ};
        w.radius = kRadius;
        w.suspension = {kRest, kStiffness, 4000};
        w.steering = front;
        w.driven = !front;
        w.handBrake = !front;
        w.friction = spec.friction;
        def.wheels.push_back(w);
    }
    car.vehicle = createVehicle(car.world, def);
    return car;
}

inline void run(Car& car, int steps) {
    for (int i = 0; i < steps; ++i) car.world.step(kDt);
}

}  // namespace fulcrum::test_car
