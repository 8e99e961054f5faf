// Fuzz target: the C++ half of the sweep's --set (python/fulcrum/sweep.py
// splits PATH=VALUES in Python; the path is parsed here, by hand, in
// applySceneOverrides). The input is "PATH\nVALUE\nSCENE": the path and the
// JSON value are applied to the scene, then the result is read, saved and
// read again, and built and stepped as in the scene target.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fulcrum/scene_batch.hpp"
#include "fuzz_scene_common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    using namespace fulcrum;
    std::string_view rest(reinterpret_cast<const char*>(data), size);
    const auto line = [&rest] {
        const std::size_t end = rest.find('\n');
        const std::string_view head = rest.substr(0, end);
        rest = end == std::string_view::npos ? std::string_view{} : rest.substr(end + 1);
        return std::string(head);
    };
    const SceneOverride override{line(), line()};
    Scene scene;
    try {
        scene = parseSceneWithOverrides(rest, {&override, 1}, "fuzz.json");
    } catch (const Error&) {
        return 0;
    }
    fuzz::checkRoundTrip(scene);
    fuzz::buildAndStep(std::move(scene));
    return 0;
}
