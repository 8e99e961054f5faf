// The replay page: self-contained (no external resources), the embedded
// recording decodes back to the recorded motion, and text that could close a
// <script> element cannot break out of it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <cctype>
#include <sstream>

#include <zlib.h>

#include "io/html_writer.hpp"
#include "io/run.hpp"
#include "support.hpp"

using namespace fulcrum;
using namespace fulcrum::io;

namespace {

std::vector<std::uint8_t> unbase64(const std::string& s) {
    auto value = [](char c) -> int {
        if (c >= 'A' && c <= 'Z') return c - 'A';
        if (c >= 'a' && c <= 'z') return c - 'a' + 26;
        if (c >= '0' && c <= '9') return c - '0' + 52;
        return c == '+' ? 62 : (c == '/' ? 63 : -1);
    };
    std::vector<std::uint8_t> out;
    std::uint32_t acc = 0;
    int bits = 0;
    for (char c : s) {
        const int v = value(c);
        if (v < 0) break;  // '=' padding
        acc = (acc << 6) | static_cast<std::uint32_t>(v);
        bits += 6;
        if (bits >= 8) {
            bits -= 8;
            out.push_back(static_cast<std::uint8_t>((acc >> bits) & 0xFF));
        }
    }
    return out;
}

// A packed array of the page ({"type", "length", "xor", "deflate"}), decoded
// as the viewer does: base64, inflate, gather the byte planes, undo the XOR.
template <typename T>
std::vector<T> decode(const nlohmann::json& field) {
    const std::size_t n = field["length"].get<std::size_t>(), size = sizeof(T);
    const std::size_t distance = field["xor"].get<std::size_t>() * size;
    const auto deflated = unbase64(field["deflate"].get<std::string>());
    std::vector<std::uint8_t> planes(n * size);
    uLongf inflated = static_cast<uLongf>(planes.size());
    EXPECT_EQ(uncompress(planes.data(), &inflated, deflated.data(), static_cast<uLong>(deflated.size())), Z_OK);
    EXPECT_EQ(inflated, planes.size());
    std::vector<std::uint8_t> bytes(n * size);
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t b = 0; b < size; ++b) bytes[i * size + b] = planes[b * n + i];
    }
    for (std::size_t i = distance; distance > 0 && i < bytes.size(); ++i) bytes[i] ^= bytes[i - distance];
    std::vector<T> out(n);
    if (n > 0) std::memcpy(out.data(), bytes.data(), bytes.size());
    return out;
}

std::string readFile(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

// The JSON text between <script type="application/json" id="fulcrum-recording"> and </script>.
std::string embeddedJson(const std::string& page) {
    const std::string open = "<script type=\"application/json\" id=\"fulcrum-recording\">";
    const std::size_t a = page.find(open);
    EXPECT_NE(a, std::string::npos);
    const std::size_t b = page.find("</script>", a);
    return page.substr(a + open.size(), b - a - open.size());
}

// Tags (script, link, img, iframe, source, object, embed) carrying a src= or href= attribute.
int tagsReferencingResources(const std::string& page) {
    std::string lower(page.size(), ' ');
    std::transform(page.begin(), page.end(), lower.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    int found = 0;
    for (const char* tag : {"<script", "<link", "<img", "<iframe", "<source", "<object", "<embed"}) {
        for (std::size_t at = lower.find(tag); at != std::string::npos; at = lower.find(tag, at + 1)) {
            const std::string inside = lower.substr(at, lower.find('>', at) - at);
            if (inside.find("src=") != std::string::npos || inside.find("href=") != std::string::npos) ++found;
        }
    }
    return found;
}

// The text of the element `<script ... id="ID">`.
std::string scriptText(const std::string& page, const std::string& id) {
    const std::size_t at = page.find("id=\"" + id + "\">");
    EXPECT_NE(at, std::string::npos) << "no element " << id;
    const std::size_t from = page.find('>', at) + 1;
    return page.substr(from, page.find("</script>", from) - from);
}

TEST(Html, PageIsSelfContained) {
    const std::string page = renderHtml(synthetic::makeScene().recording);
    EXPECT_EQ(page.rfind("<!doctype html>", 0), 0u);
    // Exactly three script elements (data, deflated viewer, its loader), none
    // with a src; no stylesheets or other fetched resources.
    std::size_t scripts = 0;
    for (std::size_t at = page.find("<script"); at != std::string::npos; at = page.find("<script", at + 1)) ++scripts;
    EXPECT_EQ(scripts, 3u);
    EXPECT_EQ(std::count(page.begin(), page.end(), '\0'), 0);
    EXPECT_EQ(tagsReferencingResources(page), 0);
    EXPECT_EQ(page.find("@import"), std::string::npos);
    // The viewer bundle is inside, deflated: it inflates to the bundle exactly.
    const std::string bundle = io::detail::viewerScript();
    const auto deflated = unbase64(scriptText(page, "fulcrum-viewer"));
    std::vector<std::uint8_t> inflated(bundle.size() + 1);
    uLongf size = static_cast<uLongf>(inflated.size());
    ASSERT_EQ(uncompress(inflated.data(), &size, deflated.data(), static_cast<uLong>(deflated.size())), Z_OK);
    EXPECT_EQ(std::string(inflated.begin(), inflated.begin() + static_cast<std::ptrdiff_t>(size)), bundle);
    EXPECT_NE(bundle.find("fulcrumViewer"), std::string::npos);
    EXPECT_NE(bundle.find("OrbitControls"), std::string::npos) << "three.js's OrbitControls should be bundled";
    EXPECT_LT(deflated.size(), bundle.size() / 3);
}

TEST(Html, EmbeddedDataDecodesToTheRecordedMotion) {
    const auto scene = synthetic::makeScene();
    const Recording& rec = scene.recording;
    const auto doc = nlohmann::json::parse(embeddedJson(renderHtml(rec)));
    EXPECT_EQ(doc["format"], "fulcrum-recording");
    EXPECT_EQ(doc["frames"].get<std::size_t>(), rec.frameCount());
    ASSERT_EQ(doc["bodies"].size(), rec.bodies.size());
    EXPECT_EQ(doc["bodies"][5]["parts"].size(), 2u);          // compound: two parts
    EXPECT_EQ(doc["bodies"][0]["shape"], "plane");
    ASSERT_EQ(doc["joints"].size(), rec.joints.size());
    EXPECT_EQ(doc["joints"][1]["bodyA"], -1);

    const auto times = decode<double>(doc["times"]);
    const auto xf = decode<float>(doc["transforms"]);
    const auto energy = decode<double>(doc["energy"]);
    const auto offsets = decode<std::uint32_t>(doc["contactOffsets"]);
    const auto contacts = decode<float>(doc["contacts"]);
    const std::size_t n = rec.bodies.size();
    ASSERT_EQ(times.size(), rec.frameCount());
    ASSERT_EQ(xf.size(), rec.frameCount() * n * 7);
    ASSERT_EQ(energy.size(), rec.frameCount() * 3);
    ASSERT_EQ(offsets.size(), rec.frameCount() + 1);
    ASSERT_EQ(contacts.size(), offsets.back() * 7);
    for (std::size_t f = 0; f < rec.frameCount(); ++f) {
        const Vec3 p = scene.motion[2].position(times[f], synthetic::kGravity);  // the ball
        const std::size_t i = (f * n + 2) * 7;
        EXPECT_NEAR(xf[i + 1], p.y, 1e-5);
        // Energy is conserved in ballistic flight: the total stays at its initial value
        // (to float rounding of the positions it was computed from).
        EXPECT_NEAR(energy[3 * f + 2], energy[2], 1e-3 * std::fabs(energy[2]));
        EXPECT_NEAR(energy[3 * f + 0] + energy[3 * f + 1], energy[3 * f + 2], 1e-9);
    }
    // Contact normals are unit vectors.
    for (std::size_t c = 0; c < offsets.back(); ++c) {
        EXPECT_NEAR(std::hypot(contacts[7 * c + 3], contacts[7 * c + 4], contacts[7 * c + 5]), 1, 1e-6);
    }
}

TEST(Html, PackedArraysComeBackBitForBit) {
    const auto scene = synthetic::makeScene();
    const Recording& rec = scene.recording;
    const auto doc = nlohmann::json::parse(embeddedJson(renderHtml(rec)));
    EXPECT_EQ(doc["version"], 2);
    EXPECT_EQ(doc["transforms"]["type"], "float32");
    const auto times = decode<double>(doc["times"]);
    const auto xf = decode<float>(doc["transforms"]);
    const auto awake = decode<std::uint8_t>(doc["awake"]);
    ASSERT_EQ(times.size(), rec.times.size());
    ASSERT_EQ(xf.size(), rec.transforms.size() * 7);
    ASSERT_EQ(awake, rec.awake);
    EXPECT_EQ(std::memcmp(times.data(), rec.times.data(), times.size() * sizeof(double)), 0);
    for (std::size_t i = 0; i < rec.transforms.size(); ++i) {
        const Transform& t = rec.transforms[i];
        const float expected[7] = {float(t.p.x), float(t.p.y), float(t.p.z), float(t.q.x), float(t.q.y), float(t.q.z), float(t.q.w)};
        ASSERT_EQ(std::memcmp(&xf[7 * i], expected, sizeof expected), 0) << "transform " << i << " changed in the page";
    }
    // The masses are in the page for the picked body's readout.
    EXPECT_FLOAT_EQ(doc["bodies"][1]["mass"].get<float>(), float(rec.bodies[1].mass));
    EXPECT_GT(rec.bodies[1].mass, 0);
}

TEST(Html, BodiesAtRestCostAlmostNothing) {
    // 40 boxes resting for 600 frames: their transforms repeat, so the packed
    // array must be a small fraction of the raw float32 bytes (base64 of the
    // raw bytes, the version 1 page, was 4/3 of them).
    Recording rec;
    rec.title = "resting";
    for (int b = 0; b < 40; ++b) {
        rec.bodies.push_back({"box" + std::to_string(b), BodyType::Dynamic, Shape::box(Vec3::splat(Real(0.2))), 1});
    }
    rec.contactOffsets.push_back(0);
    for (int f = 0; f < 600; ++f) {
        rec.times.push_back(f / 60.0);
        for (int b = 0; b < 40; ++b) {
            const Transform xf{{Real(0.5) * Real(b) + Real(0.0123), Real(0.2), Real(-0.731)}, normalize(Quat{Real(0.9), Real(0.1), Real(0.2), Real(0.3)})};
            rec.transforms.push_back(xf);
            rec.awake.push_back(0);
        }
        rec.contactOffsets.push_back(0);
        rec.energy.push_back({});
        rec.linearMomentum.push_back({});
    }
    const auto doc = nlohmann::json::parse(embeddedJson(renderHtml(rec)));
    const std::size_t raw = rec.transforms.size() * 7 * sizeof(float);
    const std::size_t inPage = doc["transforms"]["deflate"].get<std::string>().size();
    EXPECT_LT(inPage, raw / 50) << "transforms: " << inPage << " characters for " << raw << " bytes";
    EXPECT_EQ(decode<float>(doc["transforms"]).size(), rec.transforms.size() * 7);
}

TEST(Html, DemoPageIsUnderTwoMegabytes) {
    // The built-in demo's page (scripts/run.sh writes it to build/demo.html):
    // 7.3 MB when the arrays were base64 of raw floats, ~1.8 MB packed with the
    // viewer deflated.
    const std::filesystem::path page = std::filesystem::temp_directory_path() / "fulcrum-html-test-demo.html";
    fulcrum::detail::RunOutputs outputs;
    outputs.recordPath = page.string();
    fulcrum::detail::runScene(fulcrum::detail::demoScene(), outputs);
    const auto size = std::filesystem::file_size(page);
    std::filesystem::remove(page);
    std::printf("demo page: %ju bytes\n", static_cast<std::uintmax_t>(size));
    EXPECT_LT(size, 2u * 1000 * 1000);
}

TEST(Html, NamesCannotCloseTheScriptElement) {
    auto scene = synthetic::makeScene(3);
    scene.recording.bodies[1].name = "evil</script><script>alert(1)</script>";
    const std::string page = renderHtml(scene.recording);
    std::size_t closes = 0;
    for (std::size_t at = page.find("</script"); at != std::string::npos; at = page.find("</script", at + 1)) ++closes;
    EXPECT_EQ(closes, 3u);
    // The title (also "</script>") is escaped as HTML text.
    EXPECT_NE(page.find("<title>synthetic &lt;/script&gt; test</title>"), std::string::npos);
    // And the name survives the round trip through JSON.
    const auto doc = nlohmann::json::parse(embeddedJson(page));
    EXPECT_EQ(doc["bodies"][1]["name"], scene.recording.bodies[1].name);
}

TEST(Html, EmbeddedAssetsMatchTheViewerSources) {
    EXPECT_EQ(io::detail::viewerTemplate(), readFile(std::string(FULCRUM_SOURCE_DIR) + "/viewer/src/template.html"));
    EXPECT_GT(io::detail::viewerScript().size(), 100000u);
}

TEST(Html, RejectsAnEmptyRecording) {
    EXPECT_THROW(renderHtml(Recording{}), Error);
    EXPECT_TRUE(isRecordingPath("run.HTML"));
    EXPECT_TRUE(isRecordingPath("a/b.glb"));
    EXPECT_FALSE(isRecordingPath("run.json"));
}

}  // namespace
