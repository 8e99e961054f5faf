// Snapshots and the two builds (docs/double-precision.md): a snapshot stores
// Real as written (4 bytes in the float build, 8 in the FULCRUM_DOUBLE build)
// and its header says which (sizeof(Real) at byte 12). A build reads only its
// own kind, bit for bit, and refuses the other with an error naming both,
// rather than guessing at a conversion that could not resume the run exactly.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "determinism/state_hash.hpp"
#include "fulcrum/scene.hpp"
#include "fulcrum/snapshot.hpp"
#include "fulcrum/world.hpp"

namespace fulcrum {
namespace {

constexpr std::size_t kRealSizeField = 12;  // magic 8, version 4, then sizeof(Real) 4 (little-endian)

std::vector<std::uint8_t> mixedSnapshot() {
    const Scene scene = parseScene(test::kMixedScene, "mixed");
    World w = buildWorld(scene);
    for (int i = 0; i < 20; ++i) w.step(scene.dt);
    return saveSnapshotToMemory(w);
}

TEST(PrecisionSnapshot, TheHeaderRecordsThisBuildsReal) {
    const std::vector<std::uint8_t> bytes = mixedSnapshot();
    ASSERT_GT(bytes.size(), kRealSizeField + 4);
    EXPECT_EQ(bytes[kRealSizeField], sizeof(Real));
    EXPECT_EQ(bytes[kRealSizeField + 1] | bytes[kRealSizeField + 2] | bytes[kRealSizeField + 3], 0);
    // And this build reads its own back exactly (the round trip itself: snapshot_test.cpp).
    EXPECT_EQ(saveSnapshotToMemory(loadSnapshotFromMemory(bytes)), bytes);
}

TEST(PrecisionSnapshot, TheOtherBuildsSnapshotIsRefusedByName) {
    std::vector<std::uint8_t> bytes = mixedSnapshot();
    const std::size_t other = sizeof(Real) == 4 ? 8 : 4;
    bytes[kRealSizeField] = static_cast<std::uint8_t>(other);
    const std::string expected = "snap.bin: written with " + std::to_string(other * 8) + "-bit reals, this build uses " +
                                 std::to_string(sizeof(Real) * 8) + "-bit reals";
    try {
        (void)loadSnapshotFromMemory(bytes, nullptr, "snap.bin");
        FAIL() << "a snapshot of the other precision must be refused";
    } catch (const Error& e) {
        EXPECT_EQ(std::string(e.what()), expected);
    }
}

}  // namespace
}  // namespace fulcrum
