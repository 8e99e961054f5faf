// Vehicles in scene files: the "vehicles" section read, checked, written back
// and built, and scenes/car_lap.json driven round its lap.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <fulcrum/fulcrum.hpp>
#include <fulcrum/scene.hpp>
#include <fulcrum/vehicle.hpp>

namespace {

using namespace fulcrum;

std::string carScene(const std::string& vehicle) {
    return R"({"bodies": [{"name": "ground", "type": "static", "shape": {"type": "plane", "normal": [0,1,0], "offset": 0}},
                          {"name": "car", "shape": {"type": "box", "half_extents": [0.9, 0.3, 2]}, "mass": 1000, "position": [0, 1, 0]}],
              "vehicles": [)" + vehicle + "]}";
}

const char* const kWheels = R"("wheels": [{"position": [0.8, 0.7, 1.3], "steering": true},
                                          {"position": [-0.8, 0.7, 1.3], "steering": true},
                                          {"position": [0.8, 0.7, -1.3], "driven": true},
                                          {"position": [-0.8, 0.7, -1.3], "driven": true}])";

TEST(VehicleScene, ReadsWritesAndBuilds) {
    const Scene scene = parseScene(carScene(std::string(R"({"name": "car", "chassis": "car", )") + kWheels +
                                            R"(, "engine": {"max_torque": 300}, "anti_roll_bars": [{"left": 0, "right": 1}],
                                               "inputs": [{"time": 0, "throttle": 1}, {"time": 1, "brake": 1},
                                                          {"time": 3, "throttle": -0.5}]})"));
    ASSERT_EQ(scene.vehicles.size(), 1u);
    EXPECT_EQ(scene.vehicles[0].def.wheels.size(), 4u);
    EXPECT_TRUE(scene.vehicles[0].def.wheels[2].handBrake);
    EXPECT_EQ(parseScene(sceneToJson(scene)), scene);
    SceneHandles handles;
    World world = buildWorld(scene, &handles);
    ASSERT_EQ(handles.vehicles.size(), 1u);
    for (int i = 0; i < 60; ++i) world.step(Real(1) / 60);
    EXPECT_GT(vehicleState(world, handles.vehicles[0]).speed, Real(1));
    for (int i = 0; i < 120; ++i) world.step(Real(1) / 60);
    EXPECT_LT(std::abs(vehicleState(world, handles.vehicles[0]).speed), Real(0.05));
    // Then backwards: the script's negative throttle engages reverse.
    for (int i = 0; i < 120; ++i) world.step(Real(1) / 60);
    EXPECT_EQ(vehicleState(world, handles.vehicles[0]).gear, -1);
    EXPECT_LT(vehicleState(world, handles.vehicles[0]).speed, Real(-1));
}

TEST(VehicleScene, BadValuesNameThePath) {
    const auto expectPath = [](const std::string& vehicle, const std::string& path, const std::string& what = "") {
        try {
            buildWorld(parseScene(carScene(vehicle)));
            ADD_FAILURE() << "no error for " << path;
        } catch (const SceneError& e) {
            EXPECT_EQ(e.path().substr(0, path.size()), path) << e.what();
            EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
        }
    };
    expectPath(std::string(R"({"name": "v", )") + kWheels + "}", "vehicles[0]", "chassis");
    expectPath(std::string(R"({"name": "v", "chassis": "truck", )") + kWheels + "}", "vehicles[0].chassis");
    expectPath(R"({"name": "v", "chassis": "car", "wheels": []})", "vehicles[0].wheels");
    expectPath(R"({"name": "v", "chassis": "car", "wheels": [{"position": [5, 0.7, 0]}]})", "vehicles[0]", "wheels[0].position");
    expectPath(std::string(R"({"name": "v", "chassis": "car", )") + kWheels + R"(, "inputs": [{"time": 0, "throttle": 2}]})",
               "vehicles[0].inputs[0].throttle");
    expectPath(std::string(R"({"name": "v", "chassis": "car", )") + kWheels + R"(, "inputs": [{"time": 0, "throttle": -1.5}]})",
               "vehicles[0].inputs[0].throttle");
    expectPath(std::string(R"({"name": "v", "chassis": "car", )") + kWheels + R"(, "anti_roll_bars": [{"left": 0, "right": 9}]})",
               "vehicles[0].anti_roll_bars[0].right");
}

TEST(VehicleScene, CarLapComesRoundAndStops) {
    const Scene scene = loadScene(std::string(FULCRUM_SOURCE_DIR) + "/scenes/car_lap.json");
    SceneHandles handles;
    World world = buildWorld(scene, &handles);
    const VehicleId car = handles.vehicles.at(0);
    const BodyId chassis = world.findBody("car");
    Real fastest = 0;
    struct {
        int quadrant = 0, count = 0;  // quadrants of the heading entered in turn (counter-clockwise)
    } heading;
    for (int i = 0; i < scene.steps; ++i) {
        world.step(scene.dt);
        fastest = std::max(fastest, vehicleState(world, car).speed);
        const Vec3 f = rotate(world.orientation(chassis), Vec3{0, 0, 1});
        const int q = f.z >= 0 ? (f.x >= 0 ? 0 : 3) : (f.x >= 0 ? 1 : 2);
        if (q == (heading.quadrant + 1) % 4) {
            heading.quadrant = q;
            ++heading.count;
        }
    }
    const VehicleState s = vehicleState(world, car);
    EXPECT_GT(fastest, Real(6));
    // Round the circle: the heading turned through the lap and back to about +z.
    EXPECT_GT(heading.count, 3);
    EXPECT_LT(std::abs(s.speed), Real(0.1));  // braked to a stop
    for (const WheelState& w : s.wheels) EXPECT_TRUE(w.inContact);
    // Upright, and it turned through the lap (heading no longer +z only).
    EXPECT_GT(rotate(world.orientation(chassis), Vec3{0, 1, 0}).y, Real(0.99));
}

}  // namespace
