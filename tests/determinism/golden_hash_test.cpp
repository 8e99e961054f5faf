// The same bits on every compiler, optimisation level and SIMD path
// (docs/determinism.md): every benchmark scene (bench/scenes.hpp, the quick
// sizes) and every example scene (scenes/*.json) is stepped a fixed number
// of steps on one thread, its whole state hashed (state_hash.hpp), and the
// hash compared with the one recorded in golden_hashes.txt (the double
// build: golden_hashes_double.txt), for each SIMD
// path this CPU runs. scripts/test.sh runs this in the GCC Release build and
// in the Clang sanitizer build (-O1), so both compilers are held to the same
// recorded bits.
//
// When a change alters the simulation on purpose, regenerate the file once
// (and say so in the commit):
//   FULCRUM_WRITE_GOLDEN=1 build/release/tests/test_determinism --gtest_filter='GoldenHash.*'
// (and for the double build: the same with build/double).
#include <gtest/gtest.h>

#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <algorithm>
#include <filesystem>
#include <functional>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "../../bench/fulcrum_world.hpp"
#include "determinism/state_hash.hpp"
#include "fulcrum/scene.hpp"
#include "solver/contact_wide.hpp"
#include "world/world_access.hpp"
#include "world/world_impl.hpp"

namespace fulcrum {
namespace {

using detail::SimdPath;

// Few enough steps for the sanitizer build (seconds), enough for every scene
// to have contacts, warm starting, joints and (the piles) sleeping at work.
constexpr int kSteps = 60;

std::filesystem::path goldenFile() {
    // The double build (FULCRUM_DOUBLE, docs/double-precision.md) has bits of its own, recorded apart.
    const char* name = sizeof(Real) == sizeof(double) ? "golden_hashes_double.txt" : "golden_hashes.txt";
    return std::filesystem::path(FULCRUM_SOURCE_DIR) / "tests" / "determinism" / name;
}

struct NamedScene {
    std::string name;
    Real dt;
    std::function<World()> build;
};

std::vector<NamedScene> allScenes() {
    std::vector<NamedScene> scenes;
    for (const bench::LazyScene& lazy : bench::allScenes(true)) {
        const bench::SceneSpec s = lazy.build();
        scenes.push_back({"bench/" + s.name, static_cast<Real>(s.dt), [s] { return std::move(*bench::buildFulcrumWorld(s, 1).world); }});
    }
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(FULCRUM_SOURCE_DIR) / "scenes")) {
        if (entry.path().extension() == ".json") files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
        const Scene scene = loadScene(file);
        scenes.push_back({"scenes/" + file.filename().string(), scene.dt, [scene] {
                              Scene oneThread = scene;
                              oneThread.world.threads = 1;
                              return buildWorld(oneThread);
                          }});
    }
    return scenes;
}

std::uint64_t hashAfterSteps(const NamedScene& scene, SimdPath path) {
    World world = scene.build();
    WorldImpl& impl = detail::implOf(world);
    impl.contactSolver.setSimdPath(path);
    impl.jointSolver.setSimdPath(path);
    for (int i = 0; i < kSteps; ++i) world.step(scene.dt);
    return test::stateHash(world);
}

std::vector<SimdPath> pathsThisCpuRuns() {
    std::vector<SimdPath> paths{SimdPath::Scalar, SimdPath::Sse2};
    if (detail::avx2Available()) paths.push_back(SimdPath::Avx2);
    return paths;
}

std::map<std::string, std::uint64_t> readGolden() {
    std::map<std::string, std::uint64_t> golden;
    std::ifstream in(goldenFile());
    std::string line;
    while (std::getline(in, line)) {
        if (line.empty() || line[0] == '#') continue;
        std::istringstream fields(line);
        std::string name, hex;
        fields >> name >> hex;
        golden[name] = std::stoull(hex, nullptr, 16);
    }
    return golden;
}

TEST(GoldenHash, EveryScenesStateMatchesTheRecordedBitsOnEverySimdPath) {
    const std::vector<NamedScene> scenes = allScenes();
    if (std::getenv("FULCRUM_WRITE_GOLDEN") != nullptr) {
        std::ofstream out(goldenFile());
        out << "# State hash (tests/determinism/state_hash.hpp) of each scene after " << kSteps
            << " steps on one thread,\n# the same for every SIMD path and compiler "
               "(tests/determinism/golden_hash_test.cpp; docs/determinism.md).\n";
        for (const NamedScene& scene : scenes) {
            char hex[17];
            std::snprintf(hex, sizeof hex, "%016" PRIx64, hashAfterSteps(scene, SimdPath::Scalar));
            out << scene.name << ' ' << hex << '\n';
        }
        GTEST_SKIP() << "wrote " << goldenFile();
    }
    const std::map<std::string, std::uint64_t> golden = readGolden();
    ASSERT_FALSE(golden.empty()) << "no hashes in " << goldenFile();
    for (const NamedScene& scene : scenes) {
        const auto recorded = golden.find(scene.name);
        ASSERT_NE(recorded, golden.end()) << scene.name << " has no recorded hash in " << goldenFile()
                                          << " (regenerate it: see golden_hash_test.cpp)";
        for (const SimdPath path : pathsThisCpuRuns()) {
            EXPECT_EQ(hashAfterSteps(scene, path), recorded->second)
                << scene.name << " on SIMD path " << static_cast<int>(path) << std::hex
                << ": the state's bits differ from the recorded ones";
        }
    }
}

}  // namespace
}  // namespace fulcrum
