#pragma once
// What a body looks like where that differs from its collision shape: a robot
// link's URDF <visual> elements (docs/robots.md), carried into recordings
// (docs/recording.md). Display data of the fulcrum::io library: the World
// never holds it; the URDF loader hands it out per link, and a Recorder is
// given it per body (Recorder::setVisuals).
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fulcrum/math.hpp"

namespace fulcrum {

// A mesh file's triangles, unscaled, in metres and the link's axes (z up).
// Shared by every visual that shows the same file, so a recording stores it
// once however many links and frames show it.
struct VisualMesh {
    std::string name;                                      // the file it was read from
    std::vector<Vec3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;   // counter-clockwise seen from outside, as written
};

struct BodyVisual {
    enum class Geometry : std::uint8_t { Box, Sphere, Cylinder, Capsule, Mesh };
    Geometry geometry = Geometry::Box;
    Vec3 halfExtents{Real(0.5), Real(0.5), Real(0.5)};     // box
    Real radius = 0;                                       // sphere, cylinder, capsule
    Real halfHeight = 0;                                   // cylinder, capsule: along the visual's y (as Fulcrum's shapes)
    std::shared_ptr<const VisualMesh> mesh;                // Geometry::Mesh
    Vec3 scale{1, 1, 1};                                   // mesh (URDF `scale`)
    Transform local;                                       // the visual's frame in the body frame
    std::array<float, 4> color{0.7f, 0.7f, 0.7f, 1.0f};    // RGBA in [0, 1], as written (display colour)
    bool hasColor = false;                                 // false: drawn in the body's own display colour
};

}  // namespace fulcrum
