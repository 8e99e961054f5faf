#pragma once
// Helpers shared by the joint tests: bodies, joints and the measurements the
// tests compare with analytic results.
#include <gmock/gmock.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <string>

#include "fulcrum/fulcrum.hpp"

namespace fulcrum::jointtest {

inline constexpr double kPi = std::numbers::pi;
inline constexpr Real kDt = Real(1) / 60;
inline constexpr double kG = 9.81;

inline WorldDef worldDef(int substeps = 4, Vec3 gravity = {0, Real(-9.81), 0}) {
    WorldDef d;
    d.substeps = substeps;
    d.gravity = gravity;
    d.sleeping = false;
    return d;
}

inline BodyDef sphereBody(Real mass, Vec3 position, Real radius = Real(0.1), const char* name = "") {
    BodyDef d;
    d.name = name;
    d.shape = Shape::sphere(radius);
    d.mass = mass;
    d.position = position;
    return d;
}

inline BodyDef boxBody(Real mass, Vec3 position, Vec3 half, const char* name = "") {
    BodyDef d;
    d.name = name;
    d.shape = Shape::box(half);
    d.mass = mass;
    d.position = position;
    return d;
}

inline JointDef jointDef(JointType type, BodyId a, BodyId b, Vec3 anchor, Vec3 axis = {0, 1, 0}) {
    JointDef j;
    j.type = type;
    j.bodyA = a;
    j.bodyB = b;
    j.anchor = anchor;
    j.anchorB = anchor;
    j.axis = axis;
    return j;
}

// Complete elliptic integral of the first kind K(k) by the arithmetic-geometric
// mean: K = pi / (2 AGM(1, sqrt(1 - k^2))).
inline double ellipticK(double k) {
    double a = 1, b = std::sqrt(1 - k * k);
    for (int i = 0; i < 40 && std::fabs(a - b) > 1e-15 * a; ++i) {
        const double an = 0.5 * (a + b);
        b = std::sqrt(a * b);
        a = an;
    }
    return kPi / (2 * a);
}

// Exact period of a pendulum of equivalent length L released from rest at theta0.
inline double pendulumPeriod(double L, double theta0) { return 4 * std::sqrt(L / kG) * ellipticK(std::sin(theta0 / 2)); }

// Mean period of a signal from its upward zero crossings (linear interpolation
// between steps), stepping the world until `crossings` crossings were seen.
inline double measurePeriod(World& world, const std::function<double()>& signal, int crossings, int maxSteps) {
    double prev = signal();
    double first = -1, last = -1;
    int count = 0;
    for (int i = 0; i < maxSteps && count < crossings; ++i) {
        world.step(kDt);
        const double now = signal();
        if (prev < 0 && now >= 0) {
            const double t = (static_cast<double>(i) + prev / (prev - now)) * kDt;
            if (count == 0) first = t;
            last = t;
            ++count;
        }
        prev = now;
    }
    return count > 1 ? (last - first) / (count - 1) : 0;
}

template <class F>
std::string errorOf(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected an exception, none was thrown";
    return {};
}

}  // namespace fulcrum::jointtest
