#pragma once
// Snapshot format versions this build reads, and writing an older one (for
// tests that prove an old file still loads; docs/snapshots.md).
#include <cstdint>
#include <string_view>
#include <vector>

#include "fulcrum/snapshot.hpp"

namespace fulcrum::detail {

// Versions 2 (before the joint friction and joint tuning settings) and 3
// (before the contact pair limit) still load: the fields later versions added
// keep their defaults.
inline constexpr std::uint32_t kOldestSnapshotVersion = 2;

// saveSnapshotToMemory in format `version` (kOldestSnapshotVersion..kSnapshotVersion).
// Fields the version lacks are left out, so only a world whose values equal
// their defaults round-trips through an old version.
std::vector<std::uint8_t> saveSnapshotAsVersion(const World& world, std::uint32_t version, std::string_view userData = {});

}  // namespace fulcrum::detail
