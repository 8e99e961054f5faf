// Built against an installed Fulcrum, with the headers the docs name
// (README.md, docs/api.md, docs/scene-format.md, docs/snapshots.md,
// docs/recording.md). Three checks; any failure exits non-zero:
//  1. the core (fulcrum::fulcrum): a ball dropped on a plane comes to rest
//     touching it (centre at its radius, within 2 mm) and falls asleep;
//  2. the io library (fulcrum::io): a scene file loaded and built, run with a
//     Recorder, gives the projectile's analytic range and writes a glTF binary;
//  3. a snapshot of that world, loaded back, continues bit for bit.
#include <fulcrum/fulcrum.hpp>
#include <fulcrum/recording.hpp>
#include <fulcrum/scene.hpp>
#include <fulcrum/snapshot.hpp>
#include <fulcrum/world.hpp>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

namespace {

bool ballComesToRest() {
    fulcrum::World world;
    fulcrum::BodyDef ground;
    ground.type = fulcrum::BodyType::Static;
    ground.shape = fulcrum::Shape::plane({0, 1, 0}, 0);
    world.createBody(ground);
    fulcrum::BodyDef ball;
    ball.shape = fulcrum::Shape::sphere(0.25f);
    ball.position = {0, 10, 0};
    ball.restitution = 0.5f;
    const fulcrum::BodyId id = world.createBody(ball);
    for (int i = 0; i < 600; ++i) world.step(1.0f / 60);
    const float y = world.position(id).y;
    std::printf("ball at y = %.4f m, %s\n", static_cast<double>(y), world.isAwake(id) ? "awake" : "asleep");
    return std::fabs(y - 0.25f) < 0.002f && !world.isAwake(id);
}

// A ball thrown at (5, 10, 0) m/s with no drag flies x = 5 t exactly (no
// force along x), and the scene's 60 steps of 1/60 s end at t = 1 s.
bool sceneRecordingAndSnapshot() {
    {
        std::ofstream scene("consumer_scene.json");
        scene << R"({"world": {"dt": 0.0166666667, "steps": 60},
                     "bodies": [{"name": "ball", "shape": {"type": "sphere", "radius": 0.1}, "mass": 0.5,
                                 "linear_velocity": [5, 10, 0]}]})";
    }
    const fulcrum::Scene scene = fulcrum::loadScene("consumer_scene.json");
    fulcrum::SceneHandles handles;
    fulcrum::World world = fulcrum::buildWorld(scene, &handles);
    fulcrum::io::Recorder recorder(world, {.title = "consumer"});
    recorder.capture(world);
    for (int i = 0; i < scene.steps; ++i) {
        world.step(scene.dt);
        recorder.capture(world);
    }
    recorder.write("consumer_run.glb");
    std::ifstream glb("consumer_run.glb", std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(glb)), std::istreambuf_iterator<char>());
    const double x = world.position(handles.bodies.at(0)).x;
    std::printf("scene ball at x = %.5f m after %d steps; recording %zu frames, %zu bytes\n", x, scene.steps,
                recorder.frameCount(), bytes.size());
    if (std::fabs(x - 5.0) > 1e-3 || recorder.frameCount() != 61 || bytes.compare(0, 4, "glTF") != 0) return false;

    fulcrum::saveSnapshot(world, "consumer.snap");
    fulcrum::World resumed = fulcrum::loadSnapshot("consumer.snap");
    for (int i = 0; i < 10; ++i) {
        world.step(scene.dt);
        resumed.step(scene.dt);
    }
    const fulcrum::Vec3 a = world.position(handles.bodies[0]), b = resumed.position(handles.bodies[0]);
    std::printf("after 10 more steps: original y = %.9g, resumed y = %.9g\n", static_cast<double>(a.y), static_cast<double>(b.y));
    return a.x == b.x && a.y == b.y && a.z == b.z;
}

}  // namespace

int main() {
    const bool core = ballComesToRest();
    bool io = false;
    try {
        io = sceneRecordingAndSnapshot();
    } catch (const fulcrum::Error& e) {
        std::printf("error: %s\n", e.what());
    }
    return core && io ? 0 : 1;
}
