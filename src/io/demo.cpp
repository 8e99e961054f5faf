// The built-in demo of `fulcrum run`: what the engine simulates so far, each
// part checked against its analytic answer in the summary. Collisions don't
// exist yet, so the four systems are set far apart and never touch.
#include <cmath>
#include <cstdio>
#include <sstream>

#include "io/run.hpp"

namespace fulcrum::detail {

namespace {

// Written as a scene file, so the demo also exercises the reader.
constexpr const char* kDemoScene = R"json({
  "description": "Built-in demo: a projectile, a damped spring-mass chain, a box spinning about its intermediate axis (Dzhanibekov flips), a damped oscillator.",
  "world": { "gravity": [0, -9.81, 0], "dt": 0.0166667, "steps": 600, "substeps": 4, "sleeping": false },
  "bodies": [
    { "name": "projectile", "shape": { "type": "sphere", "radius": 0.1 }, "mass": 0.5,
      "position": [0, 0, 0], "linear_velocity": [5, 10, 0] },
    { "name": "chain1", "shape": { "type": "sphere", "radius": 0.1 }, "mass": 1, "position": [0, 4, 10] },
    { "name": "chain2", "shape": { "type": "sphere", "radius": 0.1 }, "mass": 1, "position": [0, 3, 10] },
    { "name": "chain3", "shape": { "type": "sphere", "radius": 0.1 }, "mass": 1, "position": [0, 2, 10] },
    { "name": "spinner", "shape": { "type": "box", "half_extents": [0.05, 0.2, 0.4] }, "mass": 3,
      "position": [0, 5, 20], "angular_velocity": [0.01, 10, 0], "gravity_scale": 0 },
    { "name": "oscillator", "shape": { "type": "box", "half_extents": [0.1, 0.1, 0.1] }, "mass": 1,
      "position": [0.5, 5, 30], "gravity_scale": 0 }
  ],
  "springs": [
    { "body_a": null, "body_b": "chain1", "anchor_a": [0, 5, 10], "anchor_b": [0, 4, 10], "rest_length": 1, "stiffness": 200, "damping": 10 },
    { "body_a": "chain1", "body_b": "chain2", "anchor_a": [0, 4, 10], "anchor_b": [0, 3, 10], "rest_length": 1, "stiffness": 200, "damping": 10 },
    { "body_a": "chain2", "body_b": "chain3", "anchor_a": [0, 3, 10], "anchor_b": [0, 2, 10], "rest_length": 1, "stiffness": 200, "damping": 10 },
    { "body_a": null, "body_b": "oscillator", "anchor_a": [-1.5, 5, 30], "anchor_b": [0.5, 5, 30], "rest_length": 1.5, "stiffness": 50, "damping": 1 }
  ]
})json";

// Demo constants the analytic checks use (they mirror kDemoScene).
constexpr double kG = 9.81;
constexpr double kChainK = 200, kChainM = 1;
constexpr double kOscK = 50, kOscM = 1, kOscC = 1, kOscX0 = 0.5;

}  // namespace

Scene demoScene() { return parseScene(kDemoScene, "built-in demo"); }

void DemoChecks::observe(const World& world, const SceneHandles&, std::uint64_t) {
    // The spinner's angular velocity in its own frame: its y component changes
    // sign at each flip (the angular momentum stays fixed in space while the
    // body turns over). Hysteresis ignores the wobble between flips.
    const BodyId id = world.findBody("spinner");
    if (id.isNull()) return;
    const Vec3 w = inverseRotate(world.orientation(id), world.angularVelocity(id));
    const Real threshold = Real(0.5) * length(w);
    const int sign = w.y > threshold ? 1 : (w.y < -threshold ? -1 : 0);
    if (sign != 0) {
        if (lastSign_ != 0 && sign != lastSign_) ++flips_;
        lastSign_ = sign;
    }
}

std::string DemoChecks::report(const Scene& scene, const RunResult& result) const {
    const World& world = result.world;
    const double t = static_cast<double>(world.time());
    const double h = static_cast<double>(scene.dt) / scene.world.substeps;
    std::ostringstream s;
    char line[400];
    s << "demo checks (analytic answers):\n";

    if (const BodyId p = world.findBody("projectile"); !p.isNull()) {
        const Vec3 x = world.position(p);
        const double ax = 5 * t, ay = 10 * t - 0.5 * kG * t * t;
        const double err = std::hypot(double(x.x) - ax, double(x.y) - ay);
        std::snprintf(line, sizeof line,
                      "  projectile: at t = %.3f s y = %.4f m, analytic x0 + v0 t + g t^2/2 gives %.4f m; error %.3g m "
                      "(first-order integrators: about g h t / 2 = %.3g m)\n",
                      t, double(x.y), ay, err, kG * h * t / 2);
        s << line;
    }
    if (const BodyId c = world.findBody("chain3"); !c.isNull()) {
        // Static equilibrium: spring i carries the weight of the masses below it.
        const double yEq = 2 - (3 + 2 + 1) * kChainM * kG / kChainK;
        std::snprintf(line, sizeof line, "  spring chain: lowest mass settles at y = %.4f m; static equilibrium %.4f m\n",
                      double(world.position(c).y), yEq);
        s << line;
    }
    if (const BodyId b = world.findBody("spinner"); !b.isNull()) {
        // Torque-free: the angular momentum L = R I R^T w is conserved through the flips.
        const Quat q = world.orientation(b);
        const Vec3 L = rotate(q, world.localInertia(b) * inverseRotate(q, world.angularVelocity(b)));
        const Vec3 L0 = scene.bodies.size() > 4 ? Vec3(Real(0.2) * Real(0.01), Real(0.1625) * 10, 0) : Vec3{};
        std::snprintf(line, sizeof line,
                      "  spinning box: %d flips about its intermediate axis (Dzhanibekov); |L| = %.4f kg m^2/s, conserved "
                      "value %.4f\n",
                      flips_, double(length(L)), double(length(L0)));
        s << line;
    }
    if (const BodyId o = world.findBody("oscillator"); !o.isNull()) {
        // Light damping: the amplitude decays along x0 e^(-zeta w0 t).
        const double w0 = std::sqrt(kOscK / kOscM), zeta = kOscC / (2 * std::sqrt(kOscK * kOscM));
        const double x = double(world.position(o).x), v = double(world.linearVelocity(o).x);
        const double amplitude = std::sqrt(x * x + (v / w0) * (v / w0));
        std::snprintf(line, sizeof line,
                      "  damped oscillator: amplitude %.5f m; analytic envelope x0 e^(-zeta w0 t) = %.5f m "
                      "(zeta = %.3f; within about zeta of it)\n",
                      amplitude, kOscX0 * std::exp(-zeta * w0 * t), zeta);
        s << line;
    }
    return s.str();
}

}  // namespace fulcrum::detail
