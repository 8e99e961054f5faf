// The .glb against the glTF 2.0 container rules (header, chunk headers, 4-byte
// alignment) and, parsed back with tinygltf's loader, against the recorded
// motion: one animated node per moving body, a key per captured frame, and
// keys that reproduce the closed-form ballistic trajectories.
#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "io/gltf_writer.hpp"
#include "support.hpp"

using namespace fulcrum;
using namespace fulcrum::io;

namespace {

std::uint32_t u32(const std::vector<std::uint8_t>& b, std::size_t at) {
    std::uint32_t v;
    std::memcpy(&v, b.data() + at, 4);  // GLB is little-endian, as is every target we build for
    return v;
}

template <typename T>
std::vector<T> readAccessor(const tinygltf::Model& m, int index) {
    const tinygltf::Accessor& a = m.accessors.at(static_cast<std::size_t>(index));
    const tinygltf::BufferView& v = m.bufferViews.at(static_cast<std::size_t>(a.bufferView));
    const std::size_t components = static_cast<std::size_t>(tinygltf::GetNumComponentsInType(static_cast<std::uint32_t>(a.type)));
    std::vector<T> out(a.count * components);
    std::memcpy(out.data(), m.buffers.at(static_cast<std::size_t>(v.buffer)).data.data() + v.byteOffset + a.byteOffset,
                out.size() * sizeof(T));
    return out;
}

tinygltf::Model load(const std::vector<std::uint8_t>& bytes) {
    tinygltf::Model model;
    tinygltf::TinyGLTF loader;
    std::string err, warn;
    const bool ok = loader.LoadBinaryFromMemory(&model, &err, &warn, bytes.data(), static_cast<unsigned>(bytes.size()));
    EXPECT_TRUE(ok) << err;
    EXPECT_TRUE(err.empty()) << err;
    EXPECT_TRUE(warn.empty()) << warn;
    return model;
}

TEST(Gltf, ContainerHeaderAndChunksFollowTheSpec) {
    const auto scene = synthetic::makeScene();
    const std::vector<std::uint8_t> glb = encodeGlb(scene.recording);
    ASSERT_GE(glb.size(), 28u);
    EXPECT_EQ(std::memcmp(glb.data(), "glTF", 4), 0);
    EXPECT_EQ(u32(glb, 4), 2u);                          // container version
    EXPECT_EQ(u32(glb, 8), glb.size());                  // total length
    EXPECT_EQ(glb.size() % 4, 0u);
    const std::uint32_t jsonLength = u32(glb, 12);
    EXPECT_EQ(u32(glb, 16), 0x4E4F534Au);                // "JSON"
    EXPECT_EQ(jsonLength % 4, 0u);
    const std::size_t binHeader = 20 + jsonLength;
    ASSERT_LE(binHeader + 8, glb.size());
    EXPECT_EQ(binHeader % 4, 0u);
    const std::uint32_t binLength = u32(glb, binHeader);
    EXPECT_EQ(u32(glb, binHeader + 4), 0x004E4942u);     // "BIN\0"
    EXPECT_EQ(binLength % 4, 0u);
    EXPECT_EQ(binHeader + 8 + binLength, glb.size());    // nothing after the BIN chunk
    // The JSON chunk is JSON (padded with spaces, per the spec) naming glTF 2.0.
    const std::string json(reinterpret_cast<const char*>(glb.data() + 20), jsonLength);
    EXPECT_NE(json.find("\"version\":\"2.0\""), std::string::npos);
    EXPECT_EQ(json.find_last_not_of(' '), json.rfind('}'));

    // Every bufferView starts 4-byte aligned inside the BIN chunk and fits in it.
    const tinygltf::Model model = load(glb);
    ASSERT_EQ(model.buffers.size(), 1u);
    EXPECT_LE(model.buffers[0].data.size(), binLength);
    for (const tinygltf::BufferView& v : model.bufferViews) {
        EXPECT_EQ(v.byteOffset % 4, 0u);
        EXPECT_LE(v.byteOffset + v.byteLength, model.buffers[0].data.size());
    }
}

TEST(Gltf, OneAnimatedNodePerMovingBodyWithAKeyPerFrame) {
    const auto scene = synthetic::makeScene();
    const Recording& rec = scene.recording;
    const tinygltf::Model model = load(encodeGlb(rec));

    ASSERT_EQ(model.scenes.size(), 1u);
    ASSERT_EQ(model.scenes[0].nodes.size(), rec.bodies.size());   // one root node per body
    ASSERT_EQ(model.animations.size(), 1u);
    const tinygltf::Animation& anim = model.animations[0];

    for (std::size_t b = 0; b < rec.bodies.size(); ++b) {
        const int nodeIndex = model.scenes[0].nodes[b];
        const tinygltf::Node& node = model.nodes.at(static_cast<std::size_t>(nodeIndex));
        EXPECT_EQ(node.name, rec.bodies[b].name);
        EXPECT_TRUE(node.mesh >= 0 || !node.children.empty()) << node.name << " has no geometry";
        int translation = -1, rotation = -1;
        for (const tinygltf::AnimationChannel& c : anim.channels) {
            if (c.target_node != nodeIndex) continue;
            if (c.target_path == "translation") translation = c.sampler;
            if (c.target_path == "rotation") rotation = c.sampler;
        }
        if (rec.bodies[b].type == BodyType::Static) {
            EXPECT_EQ(translation, -1) << "a static body that never moves needs no channel";
            EXPECT_EQ(rotation, -1);
            continue;
        }
        ASSERT_GE(translation, 0) << node.name;
        ASSERT_GE(rotation, 0) << node.name;
        for (int s : {translation, rotation}) {
            const tinygltf::AnimationSampler& sampler = anim.samplers.at(static_cast<std::size_t>(s));
            EXPECT_EQ(sampler.interpolation, "LINEAR");
            const tinygltf::Accessor& input = model.accessors.at(static_cast<std::size_t>(sampler.input));
            EXPECT_EQ(input.count, rec.frameCount());
            ASSERT_EQ(input.minValues.size(), 1u);   // required for sampler inputs
            EXPECT_NEAR(input.minValues[0], 0, 1e-9);
            EXPECT_NEAR(input.maxValues[0], rec.times.back() - rec.times.front(), 1e-6);
            EXPECT_EQ(model.accessors.at(static_cast<std::size_t>(sampler.output)).count, rec.frameCount());
        }
        // Keys reproduce the closed-form motion at the frame times.
        const auto keysT = readAccessor<float>(model, anim.samplers[static_cast<std::size_t>(translation)].output);
        const auto keysR = readAccessor<float>(model, anim.samplers[static_cast<std::size_t>(rotation)].output);
        const auto times = readAccessor<float>(model, anim.samplers[static_cast<std::size_t>(translation)].input);
        const synthetic::Ballistic& m = scene.motion[b];
        const Vec3 g = rec.bodies[b].type == BodyType::Dynamic ? synthetic::kGravity : Vec3::zero();
        for (std::size_t f = 0; f < rec.frameCount(); ++f) {
            const Vec3 p = m.position(times[f], g);
            EXPECT_NEAR(keysT[3 * f + 0], p.x, 1e-5);
            EXPECT_NEAR(keysT[3 * f + 1], p.y, 1e-5);
            EXPECT_NEAR(keysT[3 * f + 2], p.z, 1e-5);
            // Same rotation (q or -q), stored x, y, z, w.
            const Quat q = m.orientation(times[f]);
            const Quat k{keysR[4 * f + 3], keysR[4 * f + 0], keysR[4 * f + 1], keysR[4 * f + 2]};
            EXPECT_NEAR(std::fabs(dot(q, k)), 1, 1e-5) << node.name << " frame " << f;
            if (f > 0) {
                const Quat prev{keysR[4 * f - 1], keysR[4 * f - 4], keysR[4 * f - 3], keysR[4 * f - 2]};
                EXPECT_GE(dot(prev, k), 0) << node.name << ": consecutive keys in opposite hemispheres";
            }
        }
    }
}

// A glTF viewer interpolates keys linearly. For uniformly accelerated motion
// the chord of a parabola misses the curve at mid-interval by g h^2 / 8 at
// most, so sampling the keys between frames must land within that of the
// analytic trajectory (and not exactly on it: the deviation is physical).
TEST(Gltf, LinearKeysMatchTheTrajectoryWithinTheChordError) {
    const double dt = 0.1;
    const auto scene = synthetic::makeScene(21, dt);
    const Recording& rec = scene.recording;
    const tinygltf::Model model = load(encodeGlb(rec));
    const tinygltf::Animation& anim = model.animations[0];
    const int node = model.scenes[0].nodes[1];  // "box", dynamic
    int sampler = -1;
    for (const auto& c : anim.channels) {
        if (c.target_node == node && c.target_path == "translation") sampler = c.sampler;
    }
    ASSERT_GE(sampler, 0);
    const auto keys = readAccessor<float>(model, anim.samplers[static_cast<std::size_t>(sampler)].output);
    const double bound = 9.81 * dt * dt / 8;
    double worst = 0;
    for (std::size_t f = 0; f + 1 < rec.frameCount(); ++f) {
        const double t = (static_cast<double>(f) + 0.5) * dt;
        const double y = 0.5 * (keys[3 * f + 1] + keys[3 * f + 4]);
        worst = std::max(worst, std::fabs(y - scene.motion[1].position(t, synthetic::kGravity).y));
    }
    EXPECT_NEAR(worst, bound, 1e-4);
}

TEST(Gltf, SleepingBodiesSwitchToADarkerCopy) {
    const auto scene = synthetic::makeScene();
    const Recording& rec = scene.recording;
    const tinygltf::Model model = load(encodeGlb(rec));
    const tinygltf::Node& spinner = model.nodes.at(static_cast<std::size_t>(model.scenes[0].nodes[6]));
    ASSERT_EQ(spinner.children.size(), 2u);  // awake and asleep copies
    const auto& anim = model.animations[0];
    const std::size_t frames = rec.frameCount();
    for (std::size_t c = 0; c < 2; ++c) {
        const int child = spinner.children[c];
        int sampler = -1;
        for (const auto& ch : anim.channels) {
            if (ch.target_node == child && ch.target_path == "scale") sampler = ch.sampler;
        }
        ASSERT_GE(sampler, 0);
        EXPECT_EQ(anim.samplers[static_cast<std::size_t>(sampler)].interpolation, "STEP");
        const auto scale = readAccessor<float>(model, anim.samplers[static_cast<std::size_t>(sampler)].output);
        for (std::size_t f = 0; f < frames; ++f) {
            const bool visible = scale[3 * f] > 0.5f;
            EXPECT_EQ(visible, c == 0 ? rec.isAwake(f, 6) : !rec.isAwake(f, 6)) << "frame " << f;
        }
    }
    // The asleep copy is darker than the awake one.
    auto brightness = [&](int nodeIndex) {
        const auto& mesh = model.meshes.at(static_cast<std::size_t>(model.nodes.at(static_cast<std::size_t>(nodeIndex)).mesh));
        const auto& c = model.materials.at(static_cast<std::size_t>(mesh.primitives[0].material)).pbrMetallicRoughness.baseColorFactor;
        return c[0] + c[1] + c[2];
    };
    EXPECT_LT(brightness(spinner.children[1]), 0.6 * brightness(spinner.children[0]));
}

TEST(Gltf, MeshBoundsAndCompoundParts) {
    const auto scene = synthetic::makeScene();
    const tinygltf::Model model = load(encodeGlb(scene.recording));
    // The compound body has one child node per part; the sphere part sits at its offset.
    const tinygltf::Node& dumbbell = model.nodes.at(static_cast<std::size_t>(model.scenes[0].nodes[5]));
    ASSERT_EQ(dumbbell.children.size(), 2u);
    const tinygltf::Node& knob = model.nodes.at(static_cast<std::size_t>(dumbbell.children[1]));
    ASSERT_EQ(knob.translation.size(), 3u);
    EXPECT_NEAR(knob.translation[1], 0.35, 1e-6);
    // POSITION min/max (required by the spec) bound the sphere of radius 0.4 tightly.
    const tinygltf::Node& ball = model.nodes.at(static_cast<std::size_t>(model.scenes[0].nodes[2]));
    const auto& prim = model.meshes.at(static_cast<std::size_t>(ball.mesh)).primitives.at(0);
    const auto& pos = model.accessors.at(static_cast<std::size_t>(prim.attributes.at("POSITION")));
    ASSERT_EQ(pos.maxValues.size(), 3u);
    EXPECT_NEAR(pos.maxValues[1], 0.4, 1e-6);
    EXPECT_NEAR(pos.minValues[1], -0.4, 1e-6);
    EXPECT_EQ(prim.attributes.count("NORMAL"), 1u);
}

TEST(Gltf, WritesAFileAndRejectsBadRecordings) {
    auto scene = synthetic::makeScene(5);
    const auto path = std::filesystem::temp_directory_path() / "fulcrum_recording_test.glb";
    writeGlb(scene.recording, path);
    EXPECT_EQ(std::filesystem::file_size(path), encodeGlb(scene.recording).size());
    std::filesystem::remove(path);

    Recording empty;
    EXPECT_THROW(encodeGlb(empty), Error);
    scene.recording.awake.pop_back();
    try {
        encodeGlb(scene.recording);
        FAIL() << "a short awake array must be rejected";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("awake"), std::string::npos) << e.what();
    }
    auto backwards = synthetic::makeScene(5);
    backwards.recording.times[3] = backwards.recording.times[2];
    EXPECT_THROW(encodeGlb(backwards.recording), Error);
    EXPECT_THROW(writeGlb(synthetic::makeScene(3).recording, "/nonexistent-dir/x.glb"), Error);
}

}  // namespace
