// The .glb through the Khronos glTF-Validator (the reference checker of the
// glTF 2.0 specification, npm gltf-validator) run by node: no errors and no
// warnings for a recording with every shape type, a compound, a sleeping body
// and quaternion sign flips. Skipped, with the reason, when node or the
// package is missing (scripts/install-viewer-deps.sh installs it).
#include <gtest/gtest.h>

#include "io/gltf_writer.hpp"
#include "node_tools.hpp"
#include "support.hpp"

using namespace fulcrum;
using namespace fulcrum::io;
using namespace fulcrum::io::node_tools;

namespace {

TEST(GltfValidator, KhronosValidatorReportsNoIssues) {
    const fs::path node = findOnPath("node");
    if (node.empty()) GTEST_SKIP() << "node not found on PATH (Debian: nodejs); glTF-Validator not run";
    if (!hasNodePackage("gltf-validator")) {
        GTEST_SKIP() << "viewer/node_modules/gltf-validator missing (run scripts/install-viewer-deps.sh)";
    }
    const fs::path file = fs::current_path() / "recording-validator-test.glb";
    writeGlb(synthetic::makeScene().recording, file);
    const RunResult r =
        run(quote(node.string()) + " " + quote((viewerDir() / "test" / "validate-gltf.mjs").string()) + " " + quote(file.string()));
    EXPECT_EQ(r.exitCode, 0) << r.output;
    EXPECT_NE(r.output.find("\"errors\":0,\"warnings\":0"), std::string::npos) << r.output;
    std::printf("glTF-Validator: %s", r.output.c_str());
    fs::remove(file);
}

}  // namespace
