// The replay page: self-contained (no external resources), the embedded
// recording decodes back to the recorded motion, and text that could close a
// <script> element cannot break out of it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <cctype>
#include <sstream>

#include "io/html_writer.hpp"
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

template <typename T>
std::vector<T> decode(const nlohmann::json& field) {
    const auto bytes = unbase64(field.get<std::string>());
    EXPECT_EQ(bytes.size() % sizeof(T), 0u);
    std::vector<T> out(bytes.size() / sizeof(T));
    std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
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

TEST(Html, PageIsSelfContained) {
    const std::string page = renderHtml(synthetic::makeScene().recording);
    EXPECT_EQ(page.rfind("<!doctype html>", 0), 0u);
    // Exactly two script elements (data, viewer), neither with a src; no stylesheets or other fetched resources.
    std::size_t scripts = 0;
    for (std::size_t at = page.find("<script"); at != std::string::npos; at = page.find("<script", at + 1)) ++scripts;
    EXPECT_EQ(scripts, 2u);
    EXPECT_EQ(std::count(page.begin(), page.end(), '\0'), 0);
    EXPECT_EQ(tagsReferencingResources(page), 0);
    EXPECT_EQ(page.find("@import"), std::string::npos);
    // The viewer bundle is inside.
    EXPECT_NE(page.find("fulcrumViewer"), std::string::npos);
    EXPECT_NE(page.find("OrbitControls"), std::string::npos) << "three.js's OrbitControls should be bundled";
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

TEST(Html, NamesCannotCloseTheScriptElement) {
    auto scene = synthetic::makeScene(3);
    scene.recording.bodies[1].name = "evil</script><script>alert(1)</script>";
    const std::string page = renderHtml(scene.recording);
    std::size_t closes = 0;
    for (std::size_t at = page.find("</script"); at != std::string::npos; at = page.find("</script", at + 1)) ++closes;
    EXPECT_EQ(closes, 2u);
    // The title (also "</script>") is escaped as HTML text.
    EXPECT_NE(page.find("<title>synthetic &lt;/script&gt; test</title>"), std::string::npos);
    // And the name survives the round trip through JSON.
    const auto doc = nlohmann::json::parse(embeddedJson(page));
    EXPECT_EQ(doc["bodies"][1]["name"], scene.recording.bodies[1].name);
}

TEST(Html, EmbeddedAssetsMatchTheViewerSources) {
    EXPECT_EQ(detail::viewerTemplate(), readFile(std::string(FULCRUM_SOURCE_DIR) + "/viewer/src/template.html"));
    EXPECT_GT(detail::viewerScript().size(), 100000u);
}

TEST(Html, RejectsAnEmptyRecording) {
    EXPECT_THROW(renderHtml(Recording{}), Error);
    EXPECT_TRUE(isRecordingPath("run.HTML"));
    EXPECT_TRUE(isRecordingPath("a/b.glb"));
    EXPECT_FALSE(isRecordingPath("run.json"));
}

}  // namespace
