#pragma once
// Mesh files that need a general importer: COLLADA (.dae) through Debian's
// assimp (libassimp-dev). Only mesh_import.cpp sees assimp's headers, so the
// rest of fulcrum::io, and the engine core, build without them.
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "fulcrum/math.hpp"

namespace fulcrum::detail {

struct ImportedMesh {
    std::vector<Vec3> vertices;                            // metres, z up (URDF's frame)
    std::vector<std::array<std::uint32_t, 3>> triangles;
    std::optional<std::array<float, 4>> color;             // the first material's diffuse colour, if any
};

// Every mesh of a COLLADA file, with its nodes' transforms applied, as one
// triangle list. assimp applies the file's <unit meter> and turns its
// <up_axis> into y up; this turns y up into z up, so a Z_UP file (what CAD
// and Blender write for robots) keeps its coordinates and a Y_UP file stands
// up in the link frame. nullopt with `why` set when assimp cannot read it or
// it holds no triangles.
std::optional<ImportedMesh> importColladaMesh(const std::filesystem::path& file, std::string& why);

}  // namespace fulcrum::detail
