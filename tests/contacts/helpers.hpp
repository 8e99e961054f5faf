#pragma once
// Scene builders shared by the contact and solver tests.
#include <cmath>

#include "fulcrum/fulcrum.hpp"

namespace fulcrum::test {

inline constexpr Real kDt = Real(1) / 60;

// A static ground box whose top face is y = 0.
inline BodyId addGround(World& world, Real friction = Real(0.6), Real restitution = 0) {
    BodyDef g;
    g.name = "ground";
    g.type = BodyType::Static;
    g.shape = Shape::box({50, Real(0.5), 50});
    g.position = {0, Real(-0.5), 0};
    g.friction = friction;
    g.restitution = restitution;
    return world.createBody(g);
}

inline BodyId addBox(World& world, const Vec3& position, const Vec3& half = Vec3::splat(Real(0.5)), Real mass = 1,
                     Real friction = Real(0.6)) {
    BodyDef d;
    d.shape = Shape::box(half);
    d.mass = mass;
    d.position = position;
    d.friction = friction;
    return world.createBody(d);
}

inline BodyId addSphere(World& world, const Vec3& position, Real radius, Real mass = 1, Real restitution = 0) {
    BodyDef d;
    d.shape = Shape::sphere(radius);
    d.mass = mass;
    d.position = position;
    d.restitution = restitution;
    return world.createBody(d);
}

inline void run(World& world, int steps) {
    for (int i = 0; i < steps; ++i) world.step(kDt);
}

// A 0.5 m cube of 1 kg (friction mu) set on a slope in `world`: `onSlope` turns
// +y onto the slope's normal and `down` is the unit down-slope direction.
// Returns how far it slides along `down` in `seconds` after `settleSteps` steps.
// Shared by the tilted-box and the heightfield slope tests, so both surfaces
// are held to the same measurement.
inline Real slideDistance(World& world, const Quat& onSlope, const Vec3& down, Real mu, Real seconds, int settleSteps) {
    BodyDef d;
    d.shape = Shape::box(Vec3::splat(Real(0.25)));
    d.mass = 1;
    d.friction = mu;
    d.orientation = onSlope;
    d.position = rotate(onSlope, {0, Real(0.25), 0});
    const BodyId box = world.createBody(d);
    run(world, settleSteps);
    const Vec3 start = world.position(box);
    run(world, static_cast<int>(std::lround(seconds / kDt)));
    return dot(world.position(box) - start, down);
}

// pyramid20 of bench/scenes.hpp (base row n): returns the top box.
inline BodyId buildPyramid(World& world, int base) {
    addGround(world);
    BodyId top;
    for (int row = 0; row < base; ++row) {
        const int count = base - row;
        for (int i = 0; i < count; ++i) {
            const Real x = static_cast<Real>(i) - Real(0.5) * static_cast<Real>(count - 1);
            top = addBox(world, {x, Real(0.5) + static_cast<Real>(row), 0});
        }
    }
    return top;
}

}  // namespace fulcrum::test
