#pragma once
// Shared helpers for the shape tests: a deterministic random source and small
// geometric references written independently of the code under test.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "fulcrum/error.hpp"
#include "fulcrum/shape.hpp"

namespace fulcrum::test {

// `make()` must throw fulcrum::Error whose message contains `fragment`.
template <typename F>
void expectErrorContaining(F&& make, const std::string& fragment) {
    try {
        make();
        ADD_FAILURE() << "expected an error containing '" << fragment << "'";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
}

// Deterministic uniform numbers (mt19937 with an explicit mapping, so results
// do not depend on the standard library's distribution implementation).
class Rng {
public:
    explicit Rng(std::uint32_t seed) : gen_(seed) {}
    double uniform() { return static_cast<double>(gen_()) / 4294967296.0; }
    Real uniform(Real lo, Real hi) { return lo + static_cast<Real>(uniform()) * (hi - lo); }
    Vec3 inBox(const Vec3& lo, const Vec3& hi) { return {uniform(lo.x, hi.x), uniform(lo.y, hi.y), uniform(lo.z, hi.z)}; }
    Vec3 inBall(Real r) {
        for (;;) {
            const Vec3 v = inBox(Vec3::splat(-1), Vec3::splat(1));
            if (lengthSquared(v) <= 1) return v * r;
        }
    }
    Vec3 onSphere() {
        for (;;) {
            const Vec3 v = inBox(Vec3::splat(-1), Vec3::splat(1));
            const Real l = length(v);
            if (l > Real(0.1) && l <= 1) return v / l;
        }
    }
    Quat rotation() {
        const Quat q(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
        return normalize(q);
    }

private:
    std::mt19937 gen_;
};

// Closest point on triangle abc to p (Ericson, "Real-Time Collision Detection", 5.1.5).
inline Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
    const Vec3 ab = b - a, ac = c - a, ap = p - a;
    const Real d1 = dot(ab, ap), d2 = dot(ac, ap);
    if (d1 <= 0 && d2 <= 0) return a;
    const Vec3 bp = p - b;
    const Real d3 = dot(ab, bp), d4 = dot(ac, bp);
    if (d3 >= 0 && d4 <= d3) return b;
    const Real vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + ab * (d1 / (d1 - d3));
    const Vec3 cp = p - c;
    const Real d5 = dot(ab, cp), d6 = dot(ac, cp);
    if (d6 >= 0 && d5 <= d6) return c;
    const Real vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + ac * (d2 / (d2 - d6));
    const Real va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    const Real denom = 1 / (va + vb + vc);
    return a + ab * (vb * denom) + ac * (vc * denom);
}

inline Real maxAbsDiff(const Mat3& a, const Mat3& b) {
    Real m = 0;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) m = std::max(m, std::fabs(a(r, c) - b(r, c)));
    return m;
}

}  // namespace fulcrum::test
