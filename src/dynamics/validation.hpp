#pragma once
// Validation helpers for the public API boundary. Every check is cheap when
// the input is good: the message (with its heap-allocated string) is only
// built when a check fails, so setters called every frame stay allocation-free.
//
// Messages follow one pattern: "<subject>: <field> <what is wrong>, got <value>",
// e.g. "body 'crate': mass must be positive for a dynamic body, got -1".
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

#include "fulcrum/error.hpp"
#include "fulcrum/math.hpp"

namespace fulcrum::detail {

// The object an error is about: "body 'ball'", or "body #3" when unnamed.
struct Subject {
    std::string_view kind;   // "body", "spring", "joint", "world"
    std::string_view name;   // may be empty
    std::uint32_t index = UINT32_MAX;  // slot index, UINT32_MAX when none

    std::string describe() const;
};

std::string formatReal(double v);
std::string formatVec(const Vec3& v);
std::string formatQuat(const Quat& q);

[[noreturn]] void fail(const Subject& subject, std::string_view field, std::string_view problem);

inline void requireFinite(const Subject& s, std::string_view field, Real v) {
    if (!std::isfinite(v)) fail(s, field, "must be finite, got " + formatReal(v));
}
inline void requireFinite(const Subject& s, std::string_view field, const Vec3& v) {
    if (!isFinite(v)) fail(s, field, "must be finite, got " + formatVec(v));
}
inline void requireFinite(const Subject& s, std::string_view field, const Quat& q) {
    if (!isFinite(q)) fail(s, field, "must be finite, got " + formatQuat(q));
}
inline void requireNonNegative(const Subject& s, std::string_view field, Real v) {
    requireFinite(s, field, v);
    if (v < 0) fail(s, field, "must not be negative, got " + formatReal(v));
}
inline void requirePositive(const Subject& s, std::string_view field, Real v) {
    requireFinite(s, field, v);
    if (v <= 0) fail(s, field, "must be positive, got " + formatReal(v));
}
// A finite, non-zero quaternion, returned normalised (a non-unit orientation
// is accepted and normalised; a zero one has no meaning and is an error).
Quat requireOrientation(const Subject& s, std::string_view field, const Quat& q);
// A finite, non-zero direction, returned normalised.
Vec3 requireDirection(const Subject& s, std::string_view field, const Vec3& v);

}  // namespace fulcrum::detail
