// URDF visuals in recordings (docs/robots.md, docs/recording.md): the loader
// keeps each link's <visual> elements (box, cylinder, sphere, capsule, STL/OBJ
// and COLLADA meshes) with their poses in the link frame and their colours
// (inline, by the name of a material defined elsewhere in the file, or a
// COLLADA file's own); the Recorder carries them; the replay page's data and
// the GLB draw them on the link's body, each mesh file stored once.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <numbers>
#include <set>
#include <string>
#include <vector>

#include <unistd.h>

#include "fulcrum/recording.hpp"
#include "fulcrum/urdf.hpp"
#include "io/gltf_writer.hpp"
#include "io/html_writer.hpp"
#include "io/run.hpp"

namespace {

using namespace fulcrum;
namespace fs = std::filesystem;

fs::path robotsDir() { return fs::path(FULCRUM_SOURCE_DIR) / "tests" / "robots"; }

const std::string kInertial = R"(<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial>)";

// Every visual kind. "blue" is defined at the robot level after the links,
// "glass" inline in one visual and named by another; the tetrahedron (red in
// its COLLADA file) is shown by both links; "nowhere" is no material.
const std::string kRobot =
    R"(<robot name="shapes"><link name="body">)" + kInertial +
    R"(<visual><origin xyz="0.1 0 0.2" rpy="0 0 1.5707963267948966"/><geometry><box size="0.4 0.2 0.1"/></geometry><material name="blue"/></visual>)"
    R"(<visual><origin xyz="0 0 0.3"/><geometry><cylinder radius="0.05" length="0.2"/></geometry>)"
    R"(<material name="glass"><color rgba="0.2 0.9 0.9 0.5"/></material></visual>)"
    R"(<visual><geometry><sphere radius="0.07"/></geometry></visual>)"
    R"(<visual><origin xyz="0 0.1 0"/><geometry><mesh filename="meshes/tetra.dae"/></geometry></visual>)"
    R"(<visual><geometry><mesh filename="package://robots/meshes/cube.obj" scale="2 1 1"/></geometry><material name="glass"/></visual>)"
    R"(<collision><geometry><box size="0.4 0.2 0.1"/></geometry></collision></link>)"
    R"(<link name="arm">)" + kInertial +
    R"(<visual><origin xyz="0 0 0.1"/><geometry><capsule radius="0.03" length="0.2"/></geometry><material name="blue"/></visual>)"
    R"(<visual><geometry><mesh filename="meshes/tetra.dae" scale="1 1 2"/></geometry><material name="nowhere"/></visual>)"
    R"(<visual><geometry><sphere radius="0.02"/></geometry><material name="nowhere"/></visual>)"
    R"(<visual><geometry><mesh filename="meshes/absent.obj"/></geometry></visual>)"
    R"(<collision><geometry><sphere radius="0.03"/></geometry></collision></link>)"
    R"(<joint name="j" type="revolute"><parent link="body"/><child link="arm"/><origin xyz="0 0 0.5"/><axis xyz="0 1 0"/>)"
    R"(<limit lower="-1" upper="1"/></joint>)"
    R"(<material name="blue"><color rgba="0 0 0.8 1"/></material></robot>)";

struct Loaded {
    World world;
    Robot robot;
    std::vector<std::string> warnings;
};

Loaded load() {
    WorldDef def;
    def.gravity = {0, 0, Real(-9.81)};
    Loaded l{World(def), Robot{}, {}};
    UrdfOptions o;
    o.searchPath = {fs::path(FULCRUM_SOURCE_DIR) / "tests"};  // package://robots/... -> tests/robots/...
    o.warn = [&](const std::string& w) { l.warnings.push_back(w); };
    l.robot = loadUrdfFromString(l.world, kRobot, (robotsDir() / "inline.urdf").string(), o);
    return l;
}

void expectColor(const BodyVisual& v, float r, float g, float b, float a) {
    EXPECT_TRUE(v.hasColor);
    EXPECT_FLOAT_EQ(v.color[0], r);
    EXPECT_FLOAT_EQ(v.color[1], g);
    EXPECT_FLOAT_EQ(v.color[2], b);
    EXPECT_FLOAT_EQ(v.color[3], a);
}

void expectQuat(const Quat& q, const Quat& expected) {
    EXPECT_NEAR(std::abs(dot(q, expected)), 1, 1e-6) << q.w << " " << q.x << " " << q.y << " " << q.z;
}

TEST(RobotVisuals, LoaderKeepsGeometryPosesAndColours) {
    Loaded l = load();
    const auto& body = l.robot.links[0].visuals;
    const auto& arm = l.robot.links[1].visuals;
    ASSERT_EQ(body.size(), 5u);
    ASSERT_EQ(arm.size(), 3u);  // the missing mesh is left out
    const Real halfPi = std::numbers::pi_v<Real> / 2;
    const Quat zUp = Quat::fromAxisAngle({1, 0, 0}, halfPi);  // Fulcrum's y-axis cylinders onto URDF's z

    EXPECT_EQ(body[0].geometry, BodyVisual::Geometry::Box);
    EXPECT_NEAR(body[0].halfExtents.x, 0.2, 1e-7);
    EXPECT_NEAR(body[0].halfExtents.y, 0.1, 1e-7);
    EXPECT_NEAR(body[0].halfExtents.z, 0.05, 1e-7);
    EXPECT_NEAR(length(body[0].local.p - Vec3{Real(0.1), 0, Real(0.2)}), 0, 1e-7);
    expectQuat(body[0].local.q, Quat::fromAxisAngle({0, 0, 1}, halfPi));
    expectColor(body[0], 0, 0, 0.8f, 1);

    EXPECT_EQ(body[1].geometry, BodyVisual::Geometry::Cylinder);
    EXPECT_NEAR(body[1].radius, 0.05, 1e-7);
    EXPECT_NEAR(body[1].halfHeight, 0.1, 1e-7);
    expectQuat(body[1].local.q, zUp);
    EXPECT_NEAR(rotate(body[1].local.q, Vec3{0, 1, 0}).z, 1, 1e-6);  // its axis along the link's z
    expectColor(body[1], 0.2f, 0.9f, 0.9f, 0.5f);

    EXPECT_EQ(body[2].geometry, BodyVisual::Geometry::Sphere);
    EXPECT_NEAR(body[2].radius, 0.07, 1e-7);
    EXPECT_FALSE(body[2].hasColor);

    ASSERT_EQ(body[3].geometry, BodyVisual::Geometry::Mesh);
    ASSERT_NE(body[3].mesh, nullptr);
    EXPECT_EQ(body[3].mesh->triangles.size(), 4u);
    EXPECT_NEAR(body[3].local.p.y, 0.1, 1e-7);
    expectColor(body[3], 0.8f, 0.1f, 0.2f, 1);  // the COLLADA file's colour
    // In metres, y up turned to z up (tetra.dae: legs 10, 20, 30 cm along x, y, z).
    AABB box;
    for (const Vec3& p : body[3].mesh->vertices) box.grow(p);
    EXPECT_NEAR(box.max.x, 0.1, 1e-6);
    EXPECT_NEAR(box.max.z, 0.2, 1e-6);
    EXPECT_NEAR(box.min.y, -0.3, 1e-6);

    EXPECT_EQ(body[4].geometry, BodyVisual::Geometry::Mesh);
    EXPECT_EQ(body[4].scale, (Vec3{2, 1, 1}));
    expectColor(body[4], 0.2f, 0.9f, 0.9f, 0.5f);  // "glass", named

    EXPECT_EQ(arm[0].geometry, BodyVisual::Geometry::Capsule);
    EXPECT_NEAR(arm[0].halfHeight, 0.1, 1e-7);
    EXPECT_NEAR(arm[0].local.p.z, 0.1, 1e-7);
    expectColor(arm[0], 0, 0, 0.8f, 1);
    EXPECT_EQ(arm[1].mesh, body[3].mesh);  // read once, shared
    EXPECT_EQ(arm[1].scale, (Vec3{1, 1, 2}));
    EXPECT_FALSE(arm[2].hasColor);

    // The material named but defined nowhere (the sphere; the mesh has its
    // file's colour) and the missing mesh are warned about.
    ASSERT_EQ(l.warnings.size(), 2u) << l.warnings[0];
    EXPECT_NE(l.warnings[0].find("link 'arm', visual: material 'nowhere' has no colour"), std::string::npos) << l.warnings[0];
    EXPECT_NE(l.warnings[1].find("link 'arm', visual: mesh 'meshes/absent.obj' not found; this visual is left out"),
              std::string::npos)
        << l.warnings[1];
}

// Recorded with the robot's visuals: the page's data lists each visual on its
// body with its pose and colour, and every render mesh once.
io::Recording record(Loaded& l) {
    io::Recorder recorder(l.world);
    for (const RobotLink& link : l.robot.links) recorder.setVisuals(link.body, link.visuals);
    recorder.capture(l.world);
    for (int i = 0; i < 5; ++i) {
        l.world.step(Real(1) / 60);
        recorder.capture(l.world);
    }
    return recorder.recording();
}

TEST(RobotVisuals, ReplayDataDrawsEachVisualOnItsBodyMeshesStoredOnce) {
    Loaded l = load();
    const io::Recording rec = record(l);
    ASSERT_EQ(rec.bodies[0].visuals.size(), 5u);
    const auto doc = nlohmann::json::parse(io::recordingJson(rec));
    // Three primitives on the body, two on the arm, and two mesh files (the tetrahedron shown twice).
    const auto& meshes = doc["visualMeshes"];
    ASSERT_EQ(meshes.size(), 7u);
    const auto& body = doc["bodies"][0]["visuals"];
    const auto& arm = doc["bodies"][1]["visuals"];
    ASSERT_EQ(body.size(), 5u);
    ASSERT_EQ(arm.size(), 3u);
    EXPECT_EQ(body[3]["mesh"], arm[1]["mesh"]);
    std::set<int> used;
    for (const auto* list : {&body, &arm}) {
        for (const auto& v : *list) used.insert(v["mesh"].get<int>());
    }
    EXPECT_EQ(used.size(), 7u);
    // The tetrahedron flat shaded: 4 triangles of 3 corners of 3 floats.
    EXPECT_EQ(meshes[body[3]["mesh"].get<std::size_t>()]["positions"]["length"], 36);
    EXPECT_EQ(meshes[body[3]["mesh"].get<std::size_t>()]["doubleSided"], true);
    EXPECT_NEAR(body[0]["position"][0].get<double>(), 0.1, 1e-7);
    EXPECT_NEAR(body[0]["position"][2].get<double>(), 0.2, 1e-7);
    EXPECT_NEAR(body[1]["color"][3].get<double>(), 0.5, 1e-7);
    EXPECT_NEAR(body[4]["scale"][0].get<double>(), 2, 1e-7);
    // No colour of its own: the body's display colour, opaque.
    const io::Rgb own = io::bodyColor(BodyType::Dynamic, 0, false);
    EXPECT_NEAR(body[2]["color"][0].get<double>(), own.r, 1e-6);
    EXPECT_NEAR(body[2]["color"][3].get<double>(), 1, 1e-7);
    // URDF is z-up: the page's camera stands on z.
    EXPECT_EQ(doc["up"], nlohmann::json::array({0, 0, 1}));
    // Collision parts are still there, for the page's "collision shapes" toggle.
    EXPECT_EQ(doc["bodies"][0]["parts"].size(), 1u);
}

TEST(RobotVisuals, GlbDrawsTheVisualsWithSharedGeometry) {
    Loaded l = load();
    const io::Recording rec = record(l);
    const std::vector<std::uint8_t> bytes = io::encodeGlb(rec);
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    ASSERT_TRUE(loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), static_cast<unsigned>(bytes.size()))) << err;
    std::map<std::string, const tinygltf::Node*> nodes;
    for (const tinygltf::Node& n : model.nodes) nodes[n.name] = &n;
    for (const char* name : {"body_visual0", "body_visual1", "body_visual2", "body_visual3", "body_visual4", "arm_visual0",
                             "arm_visual1", "arm_visual2"}) {
        ASSERT_TRUE(nodes.count(name)) << name;
    }
    // The body's node holds the visuals, not its collision box.
    const tinygltf::Node& bodyNode = *nodes.at("body");
    EXPECT_EQ(bodyNode.mesh, -1);
    EXPECT_EQ(bodyNode.children.size(), 5u);
    const tinygltf::Node& box = *nodes.at("body_visual0");
    ASSERT_EQ(box.translation.size(), 3u);
    EXPECT_NEAR(box.translation[0], 0.1, 1e-7);
    EXPECT_NEAR(box.translation[2], 0.2, 1e-7);
    ASSERT_EQ(box.rotation.size(), 4u);
    EXPECT_NEAR(std::abs(box.rotation[2]), std::sqrt(0.5), 1e-6);  // 90 degrees about z
    const auto materialOf = [&](const char* node) -> const tinygltf::Material& {
        const int mesh = nodes.at(node)->mesh;
        return model.materials.at(static_cast<std::size_t>(model.meshes.at(static_cast<std::size_t>(mesh)).primitives[0].material));
    };
    EXPECT_NEAR(materialOf("body_visual0").pbrMetallicRoughness.baseColorFactor[2], 0.8, 1e-6);
    EXPECT_EQ(materialOf("body_visual1").alphaMode, "BLEND");
    EXPECT_NEAR(materialOf("body_visual1").pbrMetallicRoughness.baseColorFactor[3], 0.5, 1e-6);
    ASSERT_EQ(nodes.at("body_visual4")->scale.size(), 3u);
    EXPECT_NEAR(nodes.at("body_visual4")->scale[0], 2, 1e-7);
    EXPECT_NEAR(nodes.at("arm_visual1")->scale[2], 2, 1e-7);
    // The z-up world hangs under one root turned -90 degrees about x (z onto glTF's y).
    ASSERT_EQ(model.scenes[0].nodes.size(), 1u);
    const tinygltf::Node& root = model.nodes.at(static_cast<std::size_t>(model.scenes[0].nodes[0]));
    EXPECT_EQ(root.name, "up_to_y");
    ASSERT_EQ(root.rotation.size(), 4u);
    EXPECT_NEAR(root.rotation[0], -std::sqrt(0.5), 1e-6);
    EXPECT_NEAR(root.rotation[3], std::sqrt(0.5), 1e-6);
    EXPECT_EQ(root.children.size(), l.world.bodyCount());
    // The tetrahedron's geometry is stored once: both nodes draw the same mesh.
    EXPECT_EQ(nodes.at("body_visual3")->mesh, nodes.at("arm_visual1")->mesh);
    std::set<int> positions;
    for (const auto& [name, node] : nodes) {
        if (name.find("_visual") == std::string::npos) continue;
        positions.insert(model.meshes.at(static_cast<std::size_t>(node->mesh)).primitives[0].attributes.at("POSITION"));
    }
    EXPECT_EQ(positions.size(), 7u);
}

TEST(RobotVisuals, RecorderRejectsBadVisuals) {
    Loaded l = load();
    io::Recorder recorder(l.world);
    BodyVisual bad;
    bad.geometry = BodyVisual::Geometry::Mesh;  // no mesh
    EXPECT_THROW(recorder.setVisuals(l.robot.links[0].body, {bad}), Error);
    EXPECT_TRUE(recorder.recording().bodies[0].visuals.empty());
    EXPECT_THROW(recorder.setVisuals(BodyId{}, {}), Error);
}

// `fulcrum run scenes/quadruped.json --record X.glb`: the robot written for
// Fulcrum is drawn as its visuals (its torso: the blue shell and a lens).
TEST(RobotVisuals, RunRecordsTheScenesRobotWithItsVisuals) {
    fulcrum::Scene scene = loadScene(fs::path(FULCRUM_SOURCE_DIR) / "scenes" / "quadruped.json");
    scene.steps = 10;
    const fs::path out = fs::temp_directory_path() / ("fulcrum_quadruped_visuals_" + std::to_string(::getpid()) + ".glb");
    fulcrum::detail::RunOutputs outputs;
    outputs.recordPath = out.string();
    fulcrum::detail::runScene(scene, outputs);
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    ASSERT_TRUE(loader.LoadBinaryFromFile(&model, &err, &warn, out.string())) << err;
    fs::remove(out);
    int visuals = 0;
    bool lens = false;
    for (const tinygltf::Node& n : model.nodes) {
        if (n.name.find("_visual") == std::string::npos) continue;
        ++visuals;
        if (n.name == "torso_visual1") {
            const auto& m = model.materials.at(static_cast<std::size_t>(model.meshes.at(static_cast<std::size_t>(n.mesh)).primitives[0].material));
            lens = std::abs(m.pbrMetallicRoughness.baseColorFactor[0] - 0.9) < 1e-6;
        }
    }
    EXPECT_EQ(visuals, 14);
    EXPECT_TRUE(lens);
}

}  // namespace
