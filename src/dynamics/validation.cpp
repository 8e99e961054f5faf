#include "dynamics/validation.hpp"

#include <sstream>

namespace fulcrum::detail {

std::string Subject::describe() const {
    std::string s(kind);
    if (!name.empty()) {
        s += " '";
        s += name;
        s += "'";
    } else if (index != UINT32_MAX) {
        s += " #";
        s += std::to_string(index);
    }
    return s;
}

std::string particleSystemLabel(std::string_view kind, std::string_view name) {
    std::string s(kind);
    if (name.empty()) return s + " (unnamed)";
    s += " '";
    s += name;
    s += "'";
    return s;
}

std::string formatReal(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
}

// Built with a stream: GCC 12's -Wrestrict misfires on chains of `"(" + std::string`.
std::string formatVec(const Vec3& v) {
    std::ostringstream s;
    s << '(' << v.x << ", " << v.y << ", " << v.z << ')';
    return s.str();
}

std::string formatQuat(const Quat& q) {
    std::ostringstream s;
    s << '[' << q.w << ", " << q.x << ", " << q.y << ", " << q.z << ']';
    return s.str();
}

void fail(const Subject& subject, std::string_view field, std::string_view problem) {
    std::string msg = subject.describe();
    msg += ": ";
    msg += field;
    msg += " ";
    msg += problem;
    throw Error(msg);
}

Quat requireOrientation(const Subject& s, std::string_view field, const Quat& q) {
    // The identity, the usual case, is its own normalisation bit for bit
    // (sqrt(1) = 1, q * (1 / 1) = q, signed zeros kept): ~60 instructions a
    // body of a million static boxes saved (docs/benchmarks.md, `lw8`).
    if (q.w == 1 && q.x == 0 && q.y == 0 && q.z == 0) return q;
    requireFinite(s, field, q);
    const Real len = length(q);
    if (!(len > Real(1e-6))) fail(s, field, "must be a non-zero quaternion, got " + formatQuat(q));
    return q * (Real(1) / len);
}

Vec3 requireDirection(const Subject& s, std::string_view field, const Vec3& v) {
    requireFinite(s, field, v);
    const Real len = length(v);
    if (!(len > Real(1e-6))) fail(s, field, "must be a non-zero direction, got " + formatVec(v));
    return v / len;
}

}  // namespace fulcrum::detail
