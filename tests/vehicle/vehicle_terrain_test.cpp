// Vehicles on heightfield terrain, and the reverse gear (docs/vehicles.md):
// the wheels' rays find a heightfield as they find a plane, so a flat field
// must give the plane's sag and braking distance; a negative throttle brakes
// a car still rolling forwards, then engages reverse, whose top speed is
// where the engine's force equals drag.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "car_fixture.hpp"

namespace {

using namespace fulcrum;
using namespace fulcrum::test_car;

TEST(VehicleTerrain, StaticSagOnFlatHeightFieldEqualsThePlanes) {
    Car onPlane = makeCar(CarSpec{});
    Car onField = makeCar(CarSpec{.heightField = true});
    run(onPlane, 400);
    run(onField, 400);
    const VehicleState a = vehicleState(onPlane.world, onPlane.vehicle), b = vehicleState(onField.world, onField.vehicle);
    for (std::size_t i = 0; i < 4; ++i) {
        ASSERT_TRUE(b.wheels[i].inContact) << "wheel " << i;
        const Real sagPlane = kRest - a.wheels[i].suspensionLength, sagField = kRest - b.wheels[i].suspensionLength;
        EXPECT_GT(sagPlane, Real(0.05));
        EXPECT_NEAR(sagField, sagPlane, Real(0.01) * sagPlane) << "wheel " << i;
        std::printf("wheel %zu: sag %.5f m on the plane, %.5f m on the heightfield\n", i, double(sagPlane), double(sagField));
    }
}

TEST(VehicleTerrain, LockedWheelsOnHeightFieldStopInVSquaredOverTwoMuG) {
    Car car = makeCar(CarSpec{.speed = 20, .friction = Real(0.8), .heightField = true});
    const Real z0 = car.world.position(car.chassis).z;
    setVehicleInput(car.world, car.vehicle, {.brake = 1});
    int steps = 0;
    while (car.world.linearVelocity(car.chassis).z > Real(0.01) && steps < 1000) {
        car.world.step(kDt);
        ++steps;
    }
    const Real distance = car.world.position(car.chassis).z - z0;
    const Real expected = Real(20 * 20) / (2 * Real(0.8) * kG);
    EXPECT_NEAR(distance, expected, Real(0.05) * expected);
    std::printf("stopped in %.3f m on the heightfield, v^2/(2 mu g) = %.3f m\n", double(distance), double(expected));
    for (const WheelState& w : vehicleState(car.world, car.vehicle).wheels) EXPECT_TRUE(w.inContact);
}

TEST(VehicleReverse, ReverseTopSpeedWhereEngineForceEqualsDrag) {
    // As the forward top-speed test (flat torque curve, one gear of ratio 3
    // with the differential), backwards: reverse uses the first gear's ratio.
    VehicleDef def;
    def.engine.maxTorque = 400;
    def.engine.torqueCurve = {{0, 1}, {1, 1}};
    def.gearbox.ratios = {1};
    def.gearbox.differentialRatio = 3;
    Car car = makeCar(CarSpec{.mass = 1000, .drag = 2}, def);
    setVehicleInput(car.world, car.vehicle, {.throttle = -1});
    run(car, 2400);
    const VehicleState s = vehicleState(car.world, car.vehicle);
    const Real expected = -std::sqrt(Real(400 * 3) / kRadius / 2);
    EXPECT_EQ(s.gear, -1);
    EXPECT_NEAR(s.speed, expected, Real(0.05) * std::abs(expected));
    std::printf("reverse top speed %.3f m/s, -sqrt(F / c) = %.3f m/s\n", double(s.speed), double(expected));
}

TEST(VehicleReverse, NegativeThrottleBrakesFirstThenReverses) {
    Car car = makeCar(CarSpec{.speed = 10});
    setVehicleInput(car.world, car.vehicle, {.throttle = -1});
    run(car, 30);
    VehicleState s = vehicleState(car.world, car.vehicle);
    EXPECT_GT(s.gear, 0);  // still rolling forwards: braking, not reversing
    EXPECT_GT(s.speed, Real(1));
    EXPECT_LT(s.speed, Real(8));
    run(car, 270);
    s = vehicleState(car.world, car.vehicle);
    EXPECT_EQ(s.gear, -1);
    EXPECT_LT(s.speed, Real(-3));
    // Forward throttle: brakes the backward roll, then first gear again.
    setVehicleInput(car.world, car.vehicle, {.throttle = 1});
    run(car, 300);
    s = vehicleState(car.world, car.vehicle);
    EXPECT_GE(s.gear, 1);
    EXPECT_GT(s.speed, Real(3));
}

}  // namespace
