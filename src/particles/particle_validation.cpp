#include "particles/particle_validation.hpp"

#include <cmath>
#include <sstream>

namespace fulcrum::detail::particles {

std::string systemLabel(std::string_view kind, std::string_view name) {
    std::string s(kind);
    if (name.empty()) return s + " (unnamed)";
    s += " '";
    s += name;
    s += "'";
    return s;
}

std::string formatReal(Real v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

std::string formatVec(const Vec3& v) {
    // (A stream, not string concatenation: GCC 12 reports a false -Wrestrict on "[" + std::string.)
    std::ostringstream s;
    s << '[' << v.x << ", " << v.y << ", " << v.z << ']';
    return s.str();
}

void failField(const std::string& label, std::string_view field, const std::string& what) {
    throw Error(label + ": " + std::string(field) + " " + what);
}

void requireFinite(const std::string& label, std::string_view field, Real v) {
    if (!std::isfinite(v)) failField(label, field, "must be a finite number, got " + formatReal(v));
}

void requireFinite(const std::string& label, std::string_view field, const Vec3& v) {
    if (!isFinite(v)) failField(label, field, "must be finite, got " + formatVec(v));
}

void requirePositive(const std::string& label, std::string_view field, Real v) {
    requireFinite(label, field, v);
    if (!(v > 0)) failField(label, field, "must be positive, got " + formatReal(v));
}

void requireNonNegative(const std::string& label, std::string_view field, Real v) {
    requireFinite(label, field, v);
    if (v < 0) failField(label, field, "must not be negative, got " + formatReal(v));
}

}  // namespace fulcrum::detail::particles
