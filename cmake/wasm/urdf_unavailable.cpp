// The WebAssembly build's URDF reader (cmake/wasm/README.md): Debian ships
// tinyxml2 as a host library only, so that build has no XML parser and
// refuses URDF files with a clear error instead of reading them.
#include "fulcrum/error.hpp"
#include "io/urdf_model.hpp"

namespace fulcrum::detail {

UrdfModel parseUrdf(std::string_view, const std::string& source) {
    throw Error(source + ": URDF files cannot be read by the WebAssembly build (it has no XML library); "
                         "use the native build");
}

}  // namespace fulcrum::detail
