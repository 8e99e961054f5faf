// Fuzz target: bytes -> scene JSON -> (save -> parse again) -> world -> a few
// steps. A SceneError (or any fulcrum::Error) is the right answer to bad
// bytes; anything else - a crash, a sanitizer report, another exception, a
// saved scene that does not read back - is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_scene_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace fulcrum;
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    Scene scene;
    try {
        scene = parseScene(text, "fuzz.json");
    } catch (const Error&) {
        return 0;
    }
    fuzz::checkRoundTrip(scene);
    fuzz::buildAndStep(std::move(scene));
    return 0;
}
