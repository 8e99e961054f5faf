// Ropes and cloths through scene files, the `fulcrum` command line and
// recordings: buildWorld creates them (attachments by body name), errors name
// the path, --json reports every particle_systems key, --csv-particles adds
// particle rows, and recordings carry the tracks (glTF morph targets checked
// by the Khronos validator when node has it).
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "fulcrum/scene.hpp"
#include "io/gltf_writer.hpp"
#include "io/html_writer.hpp"
#include "fulcrum/recording.hpp"
#include "recording/node_tools.hpp"

using namespace fulcrum;
namespace fs = std::filesystem;

namespace {

constexpr const char* kHangingBox = R"({
  "world": {"gravity": [0, -9.81, 0], "dt": 0.0166667, "steps": 180},
  "bodies": [{"name": "crate", "shape": {"type": "box", "half_extents": [0.1, 0.1, 0.1]}, "mass": 2,
              "position": [0, 1.9, 0]}],
  "ropes": [{"name": "r1", "start": [0, 3, 0], "end": [0, 2, 0], "segments": 10, "particle_mass": 0.05,
             "attach_end": "crate"}]
})";

fs::path tempDir() {
    const fs::path dir = fs::temp_directory_path() / ("fulcrum_particles_world_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    return dir;
}

std::string readFile(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

struct CliResult {
    int status = -1;
    std::string out, err;
};

CliResult fulcrumCli(const std::string& args) {
    const fs::path out = tempDir() / "stdout.txt", err = tempDir() / "stderr.txt";
    const std::string cmd = std::string("cd '") + FULCRUM_SOURCE_DIR + "' && '" + FULCRUM_CLI_PATH + "' " + args + " >'" +
                            out.string() + "' 2>'" + err.string() + "' </dev/null";
    const int raw = std::system(cmd.c_str());
    return {WIFEXITED(raw) ? WEXITSTATUS(raw) : -1, readFile(out), readFile(err)};
}

}  // namespace

// The scene's rope holds its crate by name: after 3 s the crate hangs at rest
// with its top face at the rope's length below the pin (1 %).
TEST(SceneParticles, RopeFromASceneHoldsItsBody) {
    SceneHandles handles;
    World world = buildWorld(parseScene(kHangingBox, "hanging.json"), &handles);
    ASSERT_EQ(handles.ropes.size(), 1u);
    EXPECT_TRUE(handles.cloths.empty());
    for (int i = 0; i < 180; ++i) world.step(Real(1) / 60);
    const BodyId crate = handles.bodies[0];
    const Vec3 top = transformPoint(world.transform(crate), Vec3(0, Real(0.1f), 0));
    EXPECT_NEAR(top.y, 2, 0.01);
    EXPECT_LT(length(world.linearVelocity(crate)), Real(0.05));
    EXPECT_EQ(world.name(handles.ropes[0]), "r1");
}

// An attachment naming no body: the parser reports the path and the name.
TEST(SceneParticles, UnknownAttachBodyNamesThePath) {
    std::string text = kHangingBox;
    text.replace(text.find("\"attach_end\": \"crate\""), 21, "\"attach_end\": \"crat\"");
    try {
        parseScene(text, "bad.json");
        FAIL() << "an unknown body was accepted";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.path(), "ropes[0].attach_end");
        EXPECT_NE(e.reason().find("unknown body 'crat'"), std::string::npos) << e.what();
    }
    // A Scene built in code is checked by buildWorld, with the same path.
    Scene scene = parseScene(kHangingBox, "code.json");
    scene.ropes[0].attachEnd = "crate2";
    try {
        buildWorld(scene);
        FAIL() << "an unknown body was accepted";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.path(), "ropes[0].attach_end");
        EXPECT_NE(std::string(e.what()).find("ropes[0].attach_end: unknown body 'crate2'"), std::string::npos) << e.what();
    }
    // Engine validation errors carry the rope's path too.
    scene = parseScene(kHangingBox, "code.json");
    scene.ropes[0].def.radius = -1;
    try {
        buildWorld(scene);
        FAIL() << "a negative radius was accepted";
    } catch (const SceneError& e) {
        EXPECT_EQ(e.path(), "ropes[0]");
        EXPECT_NE(e.reason().find("radius"), std::string::npos) << e.what();
    }
}

// bend_compliance: absent means the floppy scene default, an explicit 0 keeps
// XPBD's meaning (rigid), and both survive save -> load.
TEST(SceneParticles, BendComplianceDefaultIsFloppyAndExplicitZeroIsKept) {
    const Scene absent = parseScene(kHangingBox);
    EXPECT_EQ(absent.ropes[0].def.bendCompliance, kSceneDefaultBendCompliance);
    std::string text = kHangingBox;
    text.replace(text.find("\"attach_end\""), 0, "\"bend_compliance\": 0, ");
    const Scene zero = parseScene(text);
    EXPECT_EQ(zero.ropes[0].def.bendCompliance, 0);
    EXPECT_EQ(parseScene(sceneToJson(zero)), zero);
    EXPECT_EQ(parseScene(sceneToJson(absent)), absent);
}

// docs/cli.md's --json contract for particle systems, on the example scene.
TEST(SceneParticles, CliJsonReportsEveryParticleSystemKey) {
    const CliResult r = fulcrumCli("run scenes/rope_and_cloth.json --steps 30 --json");
    ASSERT_EQ(r.status, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    ASSERT_TRUE(j.contains("particle_systems"));
    const auto& systems = j["particle_systems"];
    ASSERT_EQ(systems.size(), 2u);
    EXPECT_EQ(systems[0]["name"], "r1");
    EXPECT_EQ(systems[0]["particles"], 21);
    EXPECT_EQ(systems[1]["name"], "c1");
    EXPECT_EQ(systems[1]["particles"], 256);
    for (const auto& s : systems) {
        for (const char* key : {"name", "particles", "centroid", "max_stretch", "mean_stretch", "max_penetration"}) {
            EXPECT_TRUE(s.contains(key)) << key;
        }
        EXPECT_EQ(s["centroid"].size(), 3u);
        EXPECT_GE(s["max_stretch"].get<double>(), s["mean_stretch"].get<double>());
        EXPECT_GE(s["max_penetration"].get<double>(), 0.0);
    }
    EXPECT_EQ(r.out.find("not simulated"), std::string::npos);
}

// --csv-particles: the body rows are unchanged, and each particle adds a row
// named "r1[3]" whose position is the particle's.
TEST(SceneParticles, CliCsvParticleRows) {
    const fs::path csv = tempDir() / "particles.csv";
    const CliResult r = fulcrumCli("run scenes/rope_and_cloth.json --steps 2 --csv '" + csv.string() + "' --csv-particles");
    ASSERT_EQ(r.status, 0) << r.err;
    std::istringstream in(readFile(csv));
    std::string line;
    std::getline(in, line);
    EXPECT_EQ(line, "step,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz");
    std::size_t bodyRows = 0, particleRows = 0;
    bool sawRopeTop = false;
    while (std::getline(in, line)) {
        if (line.find(",weight,") != std::string::npos) ++bodyRows;
        if (line.find("[") != std::string::npos) ++particleRows;
        if (line.rfind("0,0,r1[0],0,4,0,1,0,0,0,", 0) == 0) sawRopeTop = true;  // step 0: the pinned top of r1
    }
    EXPECT_EQ(bodyRows, 3u);
    EXPECT_EQ(particleRows, 3u * (21 + 256));
    EXPECT_TRUE(sawRopeTop);
    const CliResult bad = fulcrumCli("run scenes/rope_and_cloth.json --steps 2 --csv-particles");
    EXPECT_EQ(bad.status, 2);
    EXPECT_NE(bad.err.find("--csv-particles"), std::string::npos);
}

// Every example scene with particles builds and runs a few steps.
TEST(SceneParticles, ExampleScenesRun) {
    for (const char* name : {"rope_and_cloth.json", "rope_bridge.json", "cloth_on_sphere.json"}) {
        SceneHandles handles;
        World world = buildWorld(loadScene(fs::path(FULCRUM_SOURCE_DIR) / "scenes" / name), &handles);
        EXPECT_FALSE(handles.ropes.empty() && handles.cloths.empty()) << name;
        for (int i = 0; i < 3; ++i) world.step(Real(1) / 60);
    }
}

// Recordings: the tracks hold every particle's position per frame; the .glb
// keeps them as morph targets (one per frame after the first) with a weights
// channel, and passes the Khronos glTF-Validator; the page embeds them.
TEST(SceneParticles, RecordingsCarryRopesAndCloths) {
    World world = buildWorld(parseScene(R"({
      "bodies": [{"name": "ground", "type": "static", "shape": {"type": "plane", "normal": [0, 1, 0], "offset": 0}},
                 {"name": "crate", "shape": {"type": "box", "half_extents": [0.1, 0.1, 0.1]}, "mass": 1, "position": [0, 1.4, 0]}],
      "ropes": [{"name": "r1", "start": [0, 2, 0], "end": [0, 1.5, 0], "segments": 5, "attach_end": "crate"}],
      "cloths": [{"name": "c1", "origin": [0.5, 1, 0], "size": [4, 3], "spacing": 0.1, "pinned": [[0, 0]]}]})"));
    io::Recorder recorder(world, {.title = "particles"});
    recorder.capture(world);
    for (int i = 0; i < 10; ++i) {
        world.step(Real(1) / 60);
        recorder.capture(world);
    }
    const io::Recording& rec = recorder.recording();
    ASSERT_EQ(rec.particles.size(), 2u);
    EXPECT_FALSE(rec.particles[0].triangles);
    EXPECT_EQ(rec.particles[0].indices.size(), 2u * 5);
    EXPECT_TRUE(rec.particles[1].triangles);
    EXPECT_EQ(rec.particles[1].indices.size(), 3u * 2 * 3 * 2);
    EXPECT_EQ(rec.particles[1].positions.size(), 11u * 12);
    const auto cloth = world.particlePositions(world.particleSystems()[1]);
    EXPECT_EQ(rec.particles[1].positions[10 * 12 + 5], cloth[5]) << "the last frame holds the world's positions";

    const fs::path glb = tempDir() / "particles.glb";
    recorder.write(glb);
    const std::string bytes = readFile(glb);
    const std::uint32_t jsonLength = *reinterpret_cast<const std::uint32_t*>(bytes.data() + 12);
    const auto gltf = nlohmann::json::parse(bytes.substr(20, jsonLength));
    int morphMeshes = 0;
    for (const auto& mesh : gltf["meshes"]) {
        if (mesh["primitives"][0].contains("targets")) {
            ++morphMeshes;
            EXPECT_EQ(mesh["primitives"][0]["targets"].size(), 10u);
            EXPECT_EQ(mesh["weights"].size(), 10u);
        }
    }
    EXPECT_EQ(morphMeshes, 2);
    bool weightsChannel = false;
    for (const auto& c : gltf["animations"][0]["channels"]) weightsChannel = weightsChannel || c["target"]["path"] == "weights";
    EXPECT_TRUE(weightsChannel);

    const std::string page = io::renderHtml(rec);
    EXPECT_NE(page.find("\"particles\":[{"), std::string::npos);
    EXPECT_NE(page.find("\"kind\":\"cloth\""), std::string::npos);

    namespace nt = io::node_tools;
    const fs::path node = nt::findOnPath("node");
    if (node.empty() || !nt::hasNodePackage("gltf-validator")) GTEST_SKIP() << "node or the gltf-validator package is missing";
    const nt::RunResult v = nt::run(nt::quote(node.string()) + " " + nt::quote((nt::viewerDir() / "test" / "validate-gltf.mjs").string()) +
                                    " " + nt::quote(glb.string()));
    EXPECT_EQ(v.exitCode, 0) << v.output;
}
