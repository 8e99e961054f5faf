// The committed viewer bundle (viewer/dist/viewer.js, embedded into every
// replay page unless FULCRUM_BUILD_VIEWER is on) is what viewer/build.mjs makes
// of viewer/src today: a change to the sources without `npm run build` fails
// here. Skipped, with the reason, when node or esbuild is missing.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "node_tools.hpp"

using namespace fulcrum::io::node_tools;

namespace {

std::string readAll(const fs::path& path) {
    std::ifstream f(path, std::ios::binary);
    std::stringstream s;
    s << f.rdbuf();
    return s.str();
}

TEST(ViewerBundle, CommittedBundleIsBuiltFromTheSources) {
    const fs::path node = findOnPath("node");
    if (node.empty()) GTEST_SKIP() << "node not found on PATH (Debian: nodejs)";
    if (!hasNodePackage("esbuild") || !hasNodePackage("three")) {
        GTEST_SKIP() << "viewer/node_modules lacks esbuild or three (run scripts/install-viewer-deps.sh)";
    }
    const fs::path out = fs::current_path() / "artifacts" / "viewer-bundle-check.js";
    fs::create_directories(out.parent_path());
    fs::remove(out);
    const RunResult r = run("cd " + quote(viewerDir().string()) + " && " + quote(node.string()) + " build.mjs " + quote(out.string()));
    ASSERT_EQ(r.exitCode, 0) << r.output;
    EXPECT_TRUE(readAll(out) == readAll(viewerDir() / "dist" / "viewer.js"))
        << "viewer/dist/viewer.js is stale: run `cd viewer && npm run build` and commit it";
}

}  // namespace
