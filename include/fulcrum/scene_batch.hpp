#pragma once
// Batches from scene files (docs/scale-out.md): one scene
// with per-world overrides, or N scenes. Lives in fulcrum::io.
//
// An override names a value by its path in the scene file and gives the new
// value as JSON text:
//
//     {"bodies[ball].restitution", "0.3"}, {"world.gravity", "[0, -1.6, 0]"}
//
// A path is keys joined by '.', each optionally followed by [index] (a 0-based
// array index) or [name] (the element of the array whose "name" is name):
// `bodies[3].shape.radius`, `joints[hinge].motor.speed`, `world.gravity[1]`.
// The value replaces what is at the path; the last key may be absent (it is
// added: `bodies[ball].restitution` on a body that uses the default), and so
// may objects on the way (`world.gravity` in a scene without "world").
// Overrides are applied to the JSON before it is read, so every rule of the
// scene format applies to the result, and every error - an unknown path, a
// body name that is not there, a value the format refuses - is a SceneError
// naming the override's path and what is wrong, raised before any world is
// built.
#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fulcrum/batch.hpp"
#include "fulcrum/scene.hpp"

namespace fulcrum {

struct SceneOverride {
    std::string path;   // "bodies[ball].restitution"
    std::string value;  // JSON text: "0.3", "[0, -1.6, 0]", "\"static\""
};
using SceneOverrides = std::vector<SceneOverride>;

// The scene text with the overrides applied in order (compact JSON).
std::string applySceneOverrides(std::string_view sceneJson, std::span<const SceneOverride> overrides,
                                std::string_view sourceName = "<scene>");
// parseScene of applySceneOverrides, with a value the format refuses reported
// against the override that set it.
Scene parseSceneWithOverrides(std::string_view sceneJson, std::span<const SceneOverride> overrides,
                              std::string_view sourceName = "<scene>");

// `count` worlds from one scene; perWorld is empty (every world the scene as
// written) or holds one SceneOverrides per world (so count == perWorld.size()).
// Every world's scene is read before any is built.
Batch makeSceneBatch(std::string_view sceneJson, std::size_t count, std::span<const SceneOverrides> perWorld,
                     const BatchDef& def = {}, std::string_view sourceName = "<scene>");
// One world per scene text; sourceNames is empty or names each scene in errors.
Batch makeSceneBatch(std::span<const std::string> scenesJson, const BatchDef& def = {},
                     std::span<const std::string> sourceNames = {});

}  // namespace fulcrum
