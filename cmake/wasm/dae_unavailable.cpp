// The WebAssembly build's COLLADA reader (cmake/wasm/README.md): Debian ships
// assimp as a host library only, so that build reads no .dae file; a URDF
// mesh in one gets the documented fallback with a warning.
#include "io/mesh_import.hpp"

namespace fulcrum::detail {

std::optional<ImportedMesh> importColladaMesh(const std::filesystem::path&, std::string& why) {
    why = "the WebAssembly build reads no COLLADA files (it has no assimp)";
    return std::nullopt;
}

}  // namespace fulcrum::detail
