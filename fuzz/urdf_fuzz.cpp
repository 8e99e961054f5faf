// Fuzz target: the URDF importer (include/fulcrum/urdf.hpp). Bytes -> a
// robot read from memory (no file behind it: relative mesh paths resolve
// against the working directory, which holds none) -> its bodies and joints
// in a world -> a few steps. A fulcrum::Error is a correct answer to bad
// input; a crash, hang, leak or sanitizer report is not.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fulcrum/error.hpp"
#include "fulcrum/urdf.hpp"
#include "fulcrum/world.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace fulcrum;
    const std::string_view xml(reinterpret_cast<const char*>(data), size);
    try {
        WorldDef def;
        def.threads = 1;
        World world(def);
        UrdfOptions options;
        options.warn = [](const std::string&) {};  // missing meshes are expected here; stay quiet
        (void)loadUrdfFromString(world, xml, "fuzz.urdf", options);
        for (int i = 0; i < 3; ++i) world.step(Real(1) / Real(60));
    } catch (const Error&) {
    }
    return 0;
}
