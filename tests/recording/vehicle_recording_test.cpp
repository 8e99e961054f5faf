// Vehicles and characters in recordings (docs/recording.md): the Recorder
// keeps each wheel's suspension length, steering angle and spin per frame as
// vehicleState reports them, the page's JSON and the GLB carry them, and
// characters name their capsule bodies.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "../vehicle/car_fixture.hpp"
#include "fulcrum/recording.hpp"
#include "io/gltf_writer.hpp"
#include "io/html_writer.hpp"

namespace {

using namespace fulcrum;
using namespace fulcrum::test_car;

TEST(VehicleRecording, WheelPosesFollowTheVehicleState) {
    Car car = makeCar(CarSpec{});
    CharacterDef hero;
    hero.name = "hero";
    hero.position = {5, Real(0.91), 0};
    const CharacterId character = car.world.createCharacter(hero);
    io::Recorder recorder(car.world);
    recorder.capture(car.world);
    setVehicleInput(car.world, car.vehicle, {.throttle = Real(0.5), .steering = Real(0.5)});
    for (int i = 0; i < 90; ++i) {
        car.world.step(kDt);
        recorder.capture(car.world);
    }
    const io::Recording& rec = recorder.recording();
    ASSERT_EQ(rec.vehicles.size(), 1u);
    const io::RecordedVehicle& v = rec.vehicles[0];
    EXPECT_EQ(v.name, "car");
    EXPECT_EQ(rec.bodies[std::size_t(v.chassis)].name, "chassis");
    ASSERT_EQ(v.wheels.size(), 4u);
    ASSERT_EQ(v.poses.size(), rec.frameCount() * 4);
    // The wheels' mounting points in the chassis's frame (its origin is its centre).
    EXPECT_NEAR(v.wheels[0].mount.z, Real(1.3), Real(1e-4));
    EXPECT_NEAR(v.wheels[0].radius, kRadius, Real(1e-6));
    EXPECT_TRUE(v.wheels[0].steering && !v.wheels[0].driven && v.wheels[2].driven);
    // The last frame is the state now.
    const VehicleState s = vehicleState(car.world, car.vehicle);
    const std::size_t last = (rec.frameCount() - 1) * 4;
    for (std::size_t i = 0; i < 4; ++i) {
        EXPECT_EQ(v.poses[last + i].suspensionLength, s.wheels[i].suspensionLength);
        EXPECT_EQ(v.poses[last + i].steerAngle, s.wheels[i].steerAngle);
        EXPECT_EQ(v.poses[last + i].spin, s.wheels[i].rotation);
    }
    EXPECT_GT(v.poses[last + 0].steerAngle, Real(0.1));  // steered left
    EXPECT_GT(v.poses[last + 2].spin, Real(3));          // rolled forwards
    EXPECT_LT(v.poses[last + 2].suspensionLength, kRest);  // loaded
    ASSERT_EQ(rec.characters.size(), 1u);
    EXPECT_EQ(rec.characters[0].name, "hero");
    EXPECT_EQ(rec.bodies[std::size_t(rec.characters[0].body)].name, car.world.name(car.world.characterBody(character)));

    // The page's data and the GLB carry them.
    const nlohmann::json doc = nlohmann::json::parse(io::recordingJson(rec));
    ASSERT_EQ(doc["vehicles"].size(), 1u);
    EXPECT_EQ(doc["vehicles"][0]["chassis"], v.chassis);
    EXPECT_EQ(doc["vehicles"][0]["wheels"].size(), 4u);
    EXPECT_EQ(doc["vehicles"][0]["poses"]["length"], rec.frameCount() * 4 * 3);
    EXPECT_EQ(doc["characters"][0]["name"], "hero");
    const std::vector<std::uint8_t> glb = io::encodeGlb(rec);
    const std::string bytes(glb.begin(), glb.end());
    for (int i = 0; i < 4; ++i) EXPECT_NE(bytes.find("\"car_wheel" + std::to_string(i) + "\""), std::string::npos) << i;

    // A wheel pose that is not finite is refused, naming the vehicle.
    io::Recording broken = rec;
    broken.vehicles[0].poses[3].spin = std::numeric_limits<Real>::quiet_NaN();
    EXPECT_THROW(broken.validate(), Error);
    broken = rec;
    broken.vehicles[0].poses.pop_back();
    EXPECT_THROW(broken.validate(), Error);
}

}  // namespace
