// Vehicles in snapshots (format version 6): a drive saved mid-turn and
// restored continues bit for bit.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include <fulcrum/fulcrum.hpp>
#include <fulcrum/scene.hpp>
#include <fulcrum/snapshot.hpp>
#include <fulcrum/vehicle.hpp>

namespace {

using namespace fulcrum;

TEST(VehicleSnapshot, MidDriveContinuesBitForBit) {
    const Scene scene = loadScene(std::string(FULCRUM_SOURCE_DIR) + "/scenes/course.json");
    World original = buildWorld(scene);
    for (int i = 0; i < 200; ++i) original.step(scene.dt);  // turning, the character on the stairs
    World restored = loadSnapshotFromMemory(saveSnapshotToMemory(original));
    ASSERT_EQ(vehicles(restored).size(), 1u);
    for (int i = 0; i < 300; ++i) {
        original.step(scene.dt);
        restored.step(scene.dt);
    }
    const VehicleState a = vehicleState(original, vehicles(original)[0]);
    const VehicleState b = vehicleState(restored, vehicles(restored)[0]);
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.speed, b.speed);
    EXPECT_EQ(a.gear, b.gear);
    for (std::size_t i = 0; i < a.wheels.size(); ++i) {
        EXPECT_EQ(a.wheels[i].angularVelocity, b.wheels[i].angularVelocity);
        EXPECT_EQ(a.wheels[i].suspensionLength, b.wheels[i].suspensionLength);
    }
    EXPECT_EQ(original.characterState(original.characters()[0]).position,
              restored.characterState(restored.characters()[0]).position);
}

TEST(VehicleSnapshot, MidReverseContinuesBitForBit) {
    // Saved in reverse (gear -1, which a restored snapshot must accept).
    const Scene scene = loadScene(std::string(FULCRUM_SOURCE_DIR) + "/scenes/course.json");
    World original = buildWorld(scene);
    const VehicleId car = vehicles(original)[0];
    for (int i = 0; i < 600; ++i) original.step(scene.dt);  // the lap, braked to a stop: the script is done
    setVehicleInput(original, car, {.throttle = -1});
    for (int i = 0; i < 90; ++i) original.step(scene.dt);
    ASSERT_EQ(vehicleState(original, car).gear, -1);
    World restored = loadSnapshotFromMemory(saveSnapshotToMemory(original));
    for (int i = 0; i < 120; ++i) {
        original.step(scene.dt);
        restored.step(scene.dt);
    }
    const VehicleState a = vehicleState(original, car), b = vehicleState(restored, vehicles(restored)[0]);
    EXPECT_EQ(b.gear, -1);
    EXPECT_LT(a.speed, -1);
    EXPECT_EQ(a.position, b.position);
    EXPECT_EQ(a.speed, b.speed);
}

}  // namespace
