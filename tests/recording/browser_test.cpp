// The replay page in a real browser: headless Chromium (Debian's `chromium`)
// driven by playwright-core runs viewer/test/browser-test.mjs, which checks
// that the page renders (non-blank canvas), shows one object per body, that
// playing advances the timeline, and that nothing is fetched from the network.
// Skipped, with the reason, when node, Chromium or the node packages are
// missing (scripts/install-viewer-deps.sh installs them).
#include <gtest/gtest.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <sys/wait.h>

#include "io/html_writer.hpp"
#include "support.hpp"

using namespace fulcrum;
using namespace fulcrum::io;

namespace {

namespace fs = std::filesystem;

std::string sourceDir() {
    const char* env = std::getenv("FULCRUM_SOURCE_DIR");
    return env ? env : FULCRUM_SOURCE_DIR;
}

// The first executable called `name` on PATH, or empty.
fs::path findOnPath(const std::string& name) {
    const char* path = std::getenv("PATH");
    std::string dirs = path ? path : "";
    std::size_t start = 0;
    while (start <= dirs.size()) {
        const std::size_t end = std::min(dirs.find(':', start), dirs.size());
        const fs::path candidate = fs::path(dirs.substr(start, end - start)) / name;
        std::error_code ec;
        if (!candidate.parent_path().empty() && fs::is_regular_file(candidate, ec)) return candidate;
        start = end + 1;
    }
    return {};
}

std::string quote(const std::string& s) {
    std::string out = "'";
    for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

TEST(Browser, ReplayPageRendersAndPlaysInHeadlessChromium) {
    const fs::path node = findOnPath("node");
    if (node.empty()) GTEST_SKIP() << "node not found on PATH (Debian: nodejs); browser check not run";
    const char* chromiumEnv = std::getenv("FULCRUM_CHROMIUM");
    const fs::path chromium = chromiumEnv ? fs::path(chromiumEnv) : fs::path("/usr/bin/chromium");
    if (!fs::exists(chromium)) {
        GTEST_SKIP() << chromium << " not found (scripts/install-viewer-deps.sh installs Debian's chromium)";
    }
    const fs::path viewer = fs::path(sourceDir()) / "viewer";
    if (!fs::exists(viewer / "node_modules" / "playwright-core")) {
        GTEST_SKIP() << "viewer/node_modules/playwright-core missing (run scripts/install-viewer-deps.sh)";
    }

    // Artefacts next to the test binary's working directory, kept for inspection.
    const fs::path out = fs::current_path() / "recording-browser-test";
    fs::create_directories(out);
    const fs::path page = out / "replay.html";
    const fs::path screenshot = out / "replay.png";
    fs::remove(screenshot);
    const auto scene = synthetic::makeScene(61);
    writeHtml(scene.recording, page);

    const std::string command = quote(node.string()) + " " + quote((viewer / "test" / "browser-test.mjs").string()) + " " +
                                quote(page.string()) + " " + quote(screenshot.string()) + " " +
                                std::to_string(scene.recording.bodies.size()) + " 2>&1";
    FILE* pipe = popen(command.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string output;
    std::array<char, 4096> buffer{};
    while (std::fgets(buffer.data(), static_cast<int>(buffer.size()), pipe)) output += buffer.data();
    const int status = pclose(pipe);
    ASSERT_TRUE(WIFEXITED(status)) << output;
    EXPECT_EQ(WEXITSTATUS(status), 0) << output;
    EXPECT_NE(output.find("\"failures\":[]"), std::string::npos) << output;
    EXPECT_TRUE(fs::exists(screenshot) && fs::file_size(screenshot) > 10000) << "no screenshot at " << screenshot;
    std::printf("browser check: %s  screenshot: %s\n", output.c_str(), screenshot.string().c_str());
}

}  // namespace
