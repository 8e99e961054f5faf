#pragma once
// Small builders shared by the dynamics and world tests.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <string>

#include "fulcrum/fulcrum.hpp"

namespace fulcrum::test {

inline constexpr double kPi = std::numbers::pi;
inline constexpr Integrator kAllIntegrators[] = {Integrator::ExplicitEuler, Integrator::SemiImplicitEuler,
                                                 Integrator::Verlet};

inline WorldDef worldDef(Integrator integrator, int substeps = 1, Vec3 gravity = {0, Real(-9.81), 0}) {
    WorldDef d;
    d.integrator = integrator;
    d.substeps = substeps;
    d.gravity = gravity;
    return d;
}

// A small sphere of the given mass: a point mass for translational tests.
inline BodyDef pointMass(Real mass, Vec3 position = {}, Vec3 velocity = {}, const char* name = "") {
    BodyDef d;
    d.name = name;
    d.shape = Shape::sphere(Real(0.1));
    d.mass = mass;
    d.position = position;
    d.linearVelocity = velocity;
    return d;
}

// The message of the fulcrum::Error (or subclass E) that `f` throws; fails the test if none.
template <class E = Error, class F>
std::string errorOf(F&& f) {
    try {
        f();
    } catch (const E& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected an exception, none was thrown";
    return {};
}

inline double relErr(double value, double expected) { return std::fabs(value - expected) / std::fabs(expected); }

}  // namespace fulcrum::test
