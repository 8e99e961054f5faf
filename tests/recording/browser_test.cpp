// The replay page in a real browser: headless Chromium (Debian's `chromium`)
// driven by playwright-core runs viewer/test/browser-test.mjs, which checks
// that the page renders (non-blank canvas), shows one object per body, that
// playing advances the timeline, and that nothing is fetched from the network.
// Skipped, with the reason, when node, Chromium or the node packages are
// missing (scripts/install-viewer-deps.sh installs them).
#include <gtest/gtest.h>

#include "io/html_writer.hpp"
#include "node_tools.hpp"
#include "support.hpp"

using namespace fulcrum;
using namespace fulcrum::io;
using namespace fulcrum::io::node_tools;

namespace {

TEST(Browser, ReplayPageRendersAndPlaysInHeadlessChromium) {
    const fs::path node = findOnPath("node");
    if (node.empty()) GTEST_SKIP() << "node not found on PATH (Debian: nodejs); browser check not run";
    const char* chromiumEnv = std::getenv("FULCRUM_CHROMIUM");
    const fs::path chromium = chromiumEnv ? fs::path(chromiumEnv) : fs::path("/usr/bin/chromium");
    if (!fs::exists(chromium)) {
        GTEST_SKIP() << chromium << " not found (scripts/install-viewer-deps.sh installs Debian's chromium)";
    }
    if (!hasNodePackage("playwright-core")) {
        GTEST_SKIP() << "viewer/node_modules/playwright-core missing (run scripts/install-viewer-deps.sh)";
    }

    // Artefacts in the test's working directory (build/tests), kept for inspection.
    const fs::path out = fs::current_path() / "recording-browser-test";
    fs::create_directories(out);
    const fs::path page = out / "replay.html";
    const fs::path screenshot = out / "replay.png";
    fs::remove(screenshot);
    const auto scene = synthetic::makeScene(61);
    writeHtml(scene.recording, page);

    const RunResult r = run(quote(node.string()) + " " + quote((viewerDir() / "test" / "browser-test.mjs").string()) +
                            " " + quote(page.string()) + " " + quote(screenshot.string()) + " " +
                            std::to_string(scene.recording.bodies.size()));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("\"failures\":[]"), std::string::npos) << r.output;
    EXPECT_TRUE(fs::exists(screenshot) && fs::file_size(screenshot) > 10000) << "no screenshot at " << screenshot;
    std::printf("browser check: %s  screenshot: %s\n", r.output.c_str(), screenshot.string().c_str());
}

}  // namespace
