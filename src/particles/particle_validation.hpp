#pragma once
// Input checks at the particle API boundary. Every failure throws
// fulcrum::Error naming the system ("cloth 'sail'"), the field in scene-file
// spelling ("spacing") and what is wrong, with the offending value.
#include <string>
#include <string_view>

#include "fulcrum/error.hpp"
#include "fulcrum/math.hpp"

namespace fulcrum::detail::particles {

// "rope 'r1'" (or "rope #unnamed" when the name is empty).
std::string systemLabel(std::string_view kind, std::string_view name);
std::string formatReal(Real v);
std::string formatVec(const Vec3& v);

[[noreturn]] void failField(const std::string& label, std::string_view field, const std::string& what);

void requireFinite(const std::string& label, std::string_view field, Real v);
void requireFinite(const std::string& label, std::string_view field, const Vec3& v);
void requirePositive(const std::string& label, std::string_view field, Real v);
void requireNonNegative(const std::string& label, std::string_view field, Real v);

}  // namespace fulcrum::detail::particles
