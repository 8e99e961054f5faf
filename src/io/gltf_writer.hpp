#pragma once
// Animated glTF 2.0 binary (.glb) of a Recording, written with tinygltf.
//
// Layout: one scene; one node per body named after it, holding its mesh (or,
// for compounds and bodies that fall asleep, child nodes holding the parts);
// one material per colour (bodyColor); one animation "simulation" with, for
// every body that moves (dynamic and kinematic bodies, and static ones whose
// transform changes), a translation and a rotation channel sampled at every
// captured frame (LINEAR, time in seconds from the first frame). A body that
// falls asleep has a second, darker copy of its mesh, and STEP scale channels
// (1 or 0) show whichever matches the frame. Units are metres, +y up, as in
// glTF. Nodes carry extras {"fulcrum_type", "fulcrum_shape"}.
#include <cstdint>
#include <filesystem>
#include <vector>

#include "io/recording_display.hpp"

namespace fulcrum::io {

// The .glb file's bytes. Throws fulcrum::Error for an invalid or empty recording.
std::vector<std::uint8_t> encodeGlb(const Recording& recording);

// Writes encodeGlb's bytes; throws fulcrum::Error naming the file if it cannot be written.
void writeGlb(const Recording& recording, const std::filesystem::path& path);

}  // namespace fulcrum::io
