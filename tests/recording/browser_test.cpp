// The replay page in a real browser: headless Chromium (Debian's `chromium`)
// driven by playwright-core runs viewer/test/browser-test.mjs, which checks the
// first impression of the page: it renders a shaded picture, plays on load,
// frames the moving bodies, shows no debug overlay by default, labels the
// demo's set pieces, selects a clicked body and describes it, draws a
// vehicle's wheels turning and steering and follows it with the camera
// choice, logs no console error and fetches nothing. Skipped, with the reason, when node, Chromium or
// the node packages are missing (scripts/install-viewer-deps.sh installs them).
// The screenshots are kept in the build tree: tests/artifacts/replay*.png.
#include <gtest/gtest.h>

#include "io/html_writer.hpp"
#include "io/run.hpp"
#include "node_tools.hpp"
#include "support.hpp"

using namespace fulcrum;
using namespace fulcrum::io;
using namespace fulcrum::io::node_tools;

namespace {

// Why the browser check cannot run here, or empty.
std::string missingTool() {
    if (findOnPath("node").empty()) return "node not found on PATH (Debian: nodejs); browser check not run";
    const char* chromiumEnv = std::getenv("FULCRUM_CHROMIUM");
    const fs::path chromium = chromiumEnv ? fs::path(chromiumEnv) : fs::path("/usr/bin/chromium");
    if (!fs::exists(chromium)) return chromium.string() + " not found (scripts/install-viewer-deps.sh installs Debian's chromium)";
    if (!hasNodePackage("playwright-core")) return "viewer/node_modules/playwright-core missing (run scripts/install-viewer-deps.sh)";
    return {};
}

// Artefacts next to the test binary (build/<config>/tests/artifacts), kept for inspection.
fs::path artifacts() {
    const fs::path dir = fs::current_path() / "artifacts";
    fs::create_directories(dir);
    return dir;
}

// Runs browser-test.mjs on `page`; the screenshot goes to `screenshot`.
void checkInBrowser(const fs::path& page, const fs::path& screenshot, std::size_t bodies, const std::string& extra) {
    fs::remove(screenshot);
    const RunResult r = run(quote(findOnPath("node").string()) + " " +
                            quote((viewerDir() / "test" / "browser-test.mjs").string()) + " " + quote(page.string()) + " " +
                            quote(screenshot.string()) + " " + std::to_string(bodies) + " " + extra);
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("\"failures\":[]"), std::string::npos) << r.output;
    EXPECT_TRUE(fs::exists(screenshot) && fs::file_size(screenshot) > 10000) << "no screenshot at " << screenshot;
    std::printf("browser check: %s\nscreenshot: %s\n", r.output.c_str(), screenshot.string().c_str());
}

// The built-in demo (`fulcrum run --record X.html`, scripts/run.sh): every set
// piece labelled, the door picked by a click, the course's car drawn with
// wheels that spin and steer between t = 1 s and 5 s, and followed by the
// camera choice.
TEST(Browser, DemoReplayOpensPlayingFramedLabelledAndPickable) {
    if (const std::string missing = missingTool(); !missing.empty()) GTEST_SKIP() << missing;
    const fs::path page = artifacts() / "replay.html";
    fulcrum::detail::RunOutputs outputs;
    outputs.recordPath = page.string();
    const fulcrum::detail::RunResult result = fulcrum::detail::runScene(fulcrum::detail::demoScene(), outputs);
    checkInBrowser(page, artifacts() / "replay.png", result.world.bodyCount(),
                   "--labels " + quote("pyramid,pile,chain,door,slider,rope,cloth,projectile,spring chain,spinner,oscillator,car,hero") +
                       " --pick door --vehicle car --vehicle-times 1,5");
}

// A synthetic recording with every shape type, a compound, a static mesh and joints.
TEST(Browser, SyntheticReplayRendersAndPlays) {
    if (const std::string missing = missingTool(); !missing.empty()) GTEST_SKIP() << missing;
    const fs::path page = artifacts() / "replay-synthetic.html";
    const auto scene = synthetic::makeScene(61);
    writeHtml(scene.recording, page);
    checkInBrowser(page, artifacts() / "replay-synthetic.png", scene.recording.bodies.size(), "--labels box,ball,gem --pick box");
}

// A robot with URDF visuals (scenes/quadruped.json, 2 s): its 14 visuals are
// drawn in their materials' colours in place of the collision shapes, the
// "collision shapes" toggle swaps them, the camera stands on the world's z
// (URDF is z-up), and a click on the torso selects it.
TEST(Browser, RobotReplayDrawsItsVisuals) {
    if (const std::string missing = missingTool(); !missing.empty()) GTEST_SKIP() << missing;
    const fs::path page = artifacts() / "replay-robot.html";
    fulcrum::Scene scene = loadScene(fs::path(FULCRUM_SOURCE_DIR) / "scenes" / "quadruped.json");
    scene.steps = 240;
    fulcrum::detail::RunOutputs outputs;
    outputs.recordPath = page.string();
    const fulcrum::detail::RunResult result = fulcrum::detail::runScene(scene, outputs);
    // sRGB hex of the quadruped's materials: shell, graphite, rubber, lens.
    checkInBrowser(page, artifacts() / "replay-robot.png", result.world.bodyCount(),
                   "--visuals 14 --visual-colors 296bbf,2e3036,0d0d0d,e6d94c --up 0,0,1 --pick torso");
}

}  // namespace
