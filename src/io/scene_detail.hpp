#pragma once
// Internal helpers shared by the scene reader, writer and builder.
#include <initializer_list>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fulcrum/scene.hpp"

namespace fulcrum::detail {

// The scene format version this build reads and writes (the top-level
// "version" key; optional when reading).
inline constexpr long long kSceneFormatVersion = 1;

// Shortest text that reads back to the same value ("0.1", "-1", "1e+300").
std::string formatNumber(double v);
std::string formatNumber(float v);

// The candidate closest to `word` by edit distance, if it is close enough to
// be a plausible typo; empty otherwise.
std::string_view closestMatch(std::string_view word, std::span<const std::string_view> candidates);
inline std::string_view closestMatch(std::string_view word, std::initializer_list<std::string_view> candidates) {
    return closestMatch(word, std::span<const std::string_view>(candidates.begin(), candidates.size()));
}
std::string joinList(std::initializer_list<std::string_view> items);

// The reason part of an nlohmann exception message, on one line.
std::string nlohmannReason(std::string_view what);

std::optional<ShapeType> shapeTypeFromString(std::string_view name);
std::optional<BodyType> bodyTypeFromString(std::string_view name);
std::optional<JointType> jointTypeFromString(std::string_view name);
std::string shapeTypeList();
std::string jointTypeList();
std::string integratorList();

// True when the described shape can only belong to a static body (plane, mesh,
// heightfield, or a compound holding one).
bool isStaticOnly(const ShapeDesc& shape);
// True when the described shape holds a hull, mesh or heightfield.
bool containsHullOrMesh(const ShapeDesc& shape);
// Builds a shape that holds no hull, mesh or heightfield (those need their
// builders, which buildShape uses).
Shape buildPrimitiveShape(const ShapeDesc& shape);

}  // namespace fulcrum::detail
