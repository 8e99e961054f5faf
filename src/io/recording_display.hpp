#pragma once
// What the two recording writers (gltf_writer.hpp, html_writer.hpp) draw the
// same way: body colours, the scene's bounds and the bodies' render meshes.
// Internal to fulcrum::io; the public Recording is fulcrum/recording.hpp.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "fulcrum/recording.hpp"
#include "io/tessellate.hpp"

namespace fulcrum::io {

// Display colours, shared by both formats: static bodies grey, kinematic
// blue, dynamic bodies a palette colour per body (golden-angle hues, so
// neighbours differ), sleeping bodies darker.
struct Rgb {
    float r = 0, g = 0, b = 0;
};
Rgb bodyColor(BodyType type, std::size_t bodyIndex, bool asleep);

// Bounds of everything recorded except planes, over frames [first, last)
// (default: all), or a unit box around the origin when there is nothing else.
AABB sceneBounds(const Recording& recording, std::size_t first = 0, std::size_t last = SIZE_MAX);

// Render meshes of every body, with plane quads centred under the recorded
// scene and large enough to hold it.
std::vector<std::vector<RenderPart>> tessellateBodies(const Recording& recording);

}  // namespace fulcrum::io
