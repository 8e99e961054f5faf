// Fuzz target: bytes -> snapshot -> world -> a few steps.
//
// Each input is loaded twice: as it is (the header, version, size and
// checksum checks), and with its checksum made right for its payload, so
// that changed bytes reach the payload's reader and the checks after loading
// (src/world/snapshot.cpp, validateLoaded) instead of stopping at the
// checksum. A fulcrum::Error is the right answer to a bad snapshot; a world
// that loads must step without a crash, a sanitizer report or another
// exception.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "fulcrum/error.hpp"
#include "fulcrum/snapshot.hpp"
#include "fulcrum/world.hpp"

namespace {

constexpr std::size_t kHeaderSize = 32;    // docs/snapshots.md: magic, version, sizeof(Real), payload size, checksum
constexpr std::size_t kChecksumAt = 24;

std::uint64_t fnv1a(std::span<const std::uint8_t> bytes) {  // the format's checksum
    std::uint64_t h = 14695981039346656037ull;
    for (const std::uint8_t b : bytes) {
        h ^= b;
        h *= 1099511628211ull;
    }
    return h;
}

void loadAndStep(std::span<const std::uint8_t> bytes) {
    using namespace fulcrum;
    try {
        World world = loadSnapshotFromMemory(bytes, nullptr, "fuzz.snap");
        // As the scene target: bad bytes, not big legal worlds (the payload
        // bounds the counts, but not the settings' work per step).
        world.setThreadCount(1);
        if (world.settings().substeps > 8) world.setSubsteps(8);
        if (world.settings().solverIterations > 8) world.setSolverIterations(8);
        for (int i = 0; i < 3; ++i) world.step(Real(1) / Real(60));
    } catch (const Error&) {
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::span<const std::uint8_t> input(data, size);
    loadAndStep(input);
    if (size < kHeaderSize) return 0;
    std::vector<std::uint8_t> fixed(input.begin(), input.end());
    const std::uint64_t checksum = fnv1a(input.subspan(kHeaderSize));
    for (std::size_t i = 0; i < 8; ++i) fixed[kChecksumAt + i] = static_cast<std::uint8_t>(checksum >> (8 * i));
    loadAndStep(fixed);
    return 0;
}
