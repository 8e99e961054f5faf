#pragma once
// Transform: a rigid motion (rotation then translation), x_world = q x_local + p.
#include "fulcrum/math/quat.hpp"

namespace fulcrum {

struct Transform {
    Vec3 p;
    Quat q;

    constexpr Transform() = default;
    constexpr Transform(const Vec3& position, const Quat& rotation) : p(position), q(rotation) {}
    static constexpr Transform identity() { return {}; }
    constexpr bool operator==(const Transform&) const = default;
};

constexpr Vec3 transformPoint(const Transform& t, const Vec3& v) { return rotate(t.q, v) + t.p; }
constexpr Vec3 inverseTransformPoint(const Transform& t, const Vec3& v) { return inverseRotate(t.q, v - t.p); }
constexpr Vec3 transformVector(const Transform& t, const Vec3& v) { return rotate(t.q, v); }
constexpr Vec3 inverseTransformVector(const Transform& t, const Vec3& v) { return inverseRotate(t.q, v); }

// a * b: apply b, then a.
constexpr Transform operator*(const Transform& a, const Transform& b) { return {transformPoint(a, b.p), a.q * b.q}; }
constexpr Transform inverse(const Transform& t) {
    const Quat qi = conjugate(t.q);
    return {rotate(qi, -t.p), qi};
}
// inverse(a) * b without forming the inverse: b expressed in a's frame.
constexpr Transform relative(const Transform& a, const Transform& b) {
    return {inverseRotate(a.q, b.p - a.p), conjugate(a.q) * b.q};
}

}  // namespace fulcrum
