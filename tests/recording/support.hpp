#pragma once
// A synthetic recording whose motion is known in closed form, so the writers'
// output can be checked against physics rather than against itself: bodies in
// ballistic flight under gravity (p = p0 + v0 t + g t^2 / 2) spinning at a
// constant rate (q = exp(w t / 2) q0), over a static ground plane, with the
// energy of that motion. No World is needed.
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "fulcrum/recording.hpp"

namespace fulcrum::io::synthetic {

struct Ballistic {
    Vec3 p0, v0;
    Vec3 omega;       // rad/s, constant
    Real mass = 1;

    Vec3 position(double t, const Vec3& g) const {
        const auto tt = static_cast<Real>(t);
        return p0 + v0 * tt + g * (Real(0.5) * tt * tt);
    }
    Vec3 velocity(double t, const Vec3& g) const { return v0 + g * static_cast<Real>(t); }
    Quat orientation(double t) const {
        return normalize(Quat::fromAxisAngle(omega, length(omega) * static_cast<Real>(t)));
    }
};

inline const Vec3 kGravity{0, Real(-9.81), 0};

struct SyntheticScene {
    Recording recording;
    std::vector<Ballistic> motion;   // per body; static bodies stand still
};

// Bodies: 0 ground plane (static), 1 box, 2 sphere, 3 capsule, 4 cylinder,
// 5 compound (box + offset sphere), 7 a convex hull, 8 a static triangle mesh, 6 a box that spins fast (several turns
// per second, stored with alternating quaternion signs) and is
// asleep in the second half. `frames` frames at `dt` apart from t = 0.
inline SyntheticScene makeScene(int frames = 61, double dt = 1.0 / 60.0) {
    SyntheticScene s;
    Recording& r = s.recording;
    r.title = "synthetic </script> test";
    r.bodies.push_back({"ground", BodyType::Static, Shape::plane({0, 1, 0}, 0)});
    r.bodies.push_back({"box", BodyType::Dynamic, Shape::box({Real(0.5), Real(0.25), Real(0.3)})});
    r.bodies.push_back({"ball", BodyType::Dynamic, Shape::sphere(Real(0.4))});
    r.bodies.push_back({"capsule", BodyType::Dynamic, Shape::capsule(Real(0.2), Real(0.5))});
    r.bodies.push_back({"cylinder", BodyType::Kinematic, Shape::cylinder(Real(0.3), Real(0.2))});
    const CompoundChild children[] = {{Shape::box(Vec3::splat(Real(0.2))), Transform{}},
                                      {Shape::sphere(Real(0.15)), Transform{{0, Real(0.35), 0}, Quat::identity()}}};
    r.bodies.push_back({"dumbbell", BodyType::Dynamic, Shape::compound(children)});
    r.bodies.push_back({"spinner", BodyType::Dynamic, Shape::box({Real(0.3), Real(0.1), Real(0.2)})});
    const Vec3 gem[] = {{0, Real(0.4), 0}, {Real(0.3), 0, 0}, {Real(-0.15), 0, Real(0.26)}, {Real(-0.15), 0, Real(-0.26)},
                        {0, Real(-0.3), 0}};
    r.bodies.push_back({"gem", BodyType::Dynamic, Shape::convexHull(gem)});
    const Vec3 ramp[] = {{-1, 0, -1}, {1, Real(0.5), -1}, {1, Real(0.5), 1}, {-1, 0, 1}};
    const std::array<std::uint32_t, 3> rampTriangles[] = {{0, 2, 1}, {0, 3, 2}};
    r.bodies.push_back({"ramp", BodyType::Static, Shape::mesh(ramp, rampTriangles)});

    s.motion = {
        {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}, 0},
        {{0, 5, 0}, {1, 2, 0}, {0, 0, 3}, 2},
        {{2, 4, -1}, {-1, 0, 0.5f}, {1, 1, 0}, 1},
        {{-2, 3, 1}, {0, 4, 0}, {0, 2, 0}, 1.5f},
        {{1, 1, 2}, {0.5f, 0, 0}, {0, 1, 0}, 0},    // kinematic: not under gravity below
        {{0, 6, 2}, {0, 0, -1}, {2, 0, 1}, 0.8f},
        {{-1, 2, -2}, {0, 1, 0}, {0, 0, 150}, 0.5f},
        {{3, 3, -1}, {-0.5f, 1, 0}, {1, 0, 1}, 0.7f},
        {{4, 0, 3}, {0, 0, 0}, {0, 0, 0}, 0},
    };
    r.joints.push_back({"tether", JointType::Distance, 1, 2, {Real(0.5), 0, 0}, {0, Real(0.4), 0}});
    r.joints.push_back({"pin", JointType::Ball, -1, 3, {-2, 6, 1}, {0, Real(0.7), 0}});

    const std::size_t n = r.bodies.size();
    for (std::size_t b = 0; b < n; ++b) {
        if (r.bodies[b].type == BodyType::Dynamic) r.bodies[b].mass = s.motion[b].mass;
    }
    r.contactOffsets.push_back(0);
    for (int f = 0; f < frames; ++f) {
        const double t = f * dt;
        r.times.push_back(t);
        EnergyReport e;
        Vec3 momentum;
        for (std::size_t b = 0; b < n; ++b) {
            const Ballistic& m = s.motion[b];
            const Vec3 g = r.bodies[b].type == BodyType::Dynamic ? kGravity : Vec3::zero();
            Transform xf{m.position(t, g), m.orientation(t)};
            if (b == 6 && f % 2 == 1) xf.q = -xf.q;  // the same rotation, the other sign: writers must cope
            r.transforms.push_back(xf);
            r.awake.push_back(b == 6 && f > frames / 2 ? 0 : 1);
            r.bounds.push_back(r.bodies[b].shape.bounds(xf));
            if (r.bodies[b].type == BodyType::Dynamic) {
                const Vec3 v = m.velocity(t, g);
                e.kinetic += 0.5 * m.mass * static_cast<double>(dot(v, v));
                e.potential += m.mass * 9.81 * static_cast<double>(xf.p.y);
                momentum += v * m.mass;
            }
        }
        e.total = e.kinetic + e.potential;
        r.energy.push_back(e);
        r.linearMomentum.push_back(momentum);
        // One contact per frame under the ball while it is low, none otherwise.
        const Vec3 ball = r.transforms.back().p;
        if (f % 3 == 0) r.contactPoints.push_back({{ball.x, 0, ball.z}, {0, 1, 0}, Real(0.01)});
        r.contactOffsets.push_back(static_cast<std::uint32_t>(r.contactPoints.size()));
        r.jointErrors.push_back(Real(0.001) * static_cast<Real>(f));
        r.jointErrors.push_back(0);
    }
    return s;
}

}  // namespace fulcrum::io::synthetic
