#pragma once
// Validation helpers for the public API boundary: bodies, joints, springs,
// the world's settings and the particle systems all check their input here.
// Every check is cheap when the input is good: the message (with its
// heap-allocated string) is only built when a check fails, so setters called
// every frame stay allocation-free.
//
// Messages follow one pattern: "<subject>: <field> <what is wrong>, got <value>",
// e.g. "body 'crate': mass must be positive for a dynamic body, got -1" or
// "rope 'r1': segments must be positive, got 0".
#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>

#include "fulcrum/error.hpp"
#include "fulcrum/math.hpp"

namespace fulcrum::detail {

// The object an error is about: "body 'ball'", or "body #3" when unnamed.
// The strings are viewed, not copied: they must outlive the Subject.
struct Subject {
    std::string_view kind;   // "body", "spring", "joint", "world"
    std::string_view name;   // may be empty
    std::uint32_t index = UINT32_MAX;  // slot index, UINT32_MAX when none

    constexpr Subject(std::string_view kindOf, std::string_view nameOf = {}, std::uint32_t slot = UINT32_MAX)
        : kind(kindOf), name(nameOf), index(slot) {}
    constexpr Subject(const char* kindOf) : kind(kindOf) {}  // NOLINT(google-explicit-constructor)
    // An object already spelled out (particle systems: particleSystemLabel);
    // implicit, so a label passes wherever a Subject is expected.
    Subject(const std::string& label) : kind(label) {}  // NOLINT(google-explicit-constructor)

    std::string describe() const;
};

// "rope 'r1'", or "rope (unnamed)" when the name is empty: how a particle
// system is named in messages (it has no slot index to fall back on).
std::string particleSystemLabel(std::string_view kind, std::string_view name);

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
