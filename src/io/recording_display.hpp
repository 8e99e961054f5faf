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

// Throws fulcrum::Error naming the body when one of its visuals is not finite
// or not positive in size, or a mesh visual lacks its mesh or names a vertex
// it does not have.
void checkVisuals(const RecordedBody& body);

// The distinct visual meshes of a recording, in the order first shown (each
// stored once by the writers), and each visual's render mesh: one per
// primitive visual, one per distinct mesh (flat shaded, both sides).
struct VisualGeometry {
    std::vector<RenderMesh> meshes;
    // Per body, per visual: its index into `meshes`.
    std::vector<std::vector<std::size_t>> meshOf;
};
VisualGeometry tessellateVisuals(const Recording& recording);

// Render meshes of every body, with plane quads centred under the recorded
// scene and large enough to hold it.
std::vector<std::vector<RenderPart>> tessellateBodies(const Recording& recording);

}  // namespace fulcrum::io
