// The built-in demo of `fulcrum run`: a showcase of everything the engine
// does, laid out so the parts never meet (x from -11 to 18 m along the front
// row, the analytic set pieces in a back row at z = -6..-9), each checked in
// the summary:
//   front row   slider (x = -11), hinged door with a motor (-8), chain of ball
//               joints (-4), box pyramid (0), pile of mixed shapes falling into a
//               heap (5), rope carrying a box (11), cloth draping over a dome (18);
//   back row    projectile (analytic parabola), spring-mass chain (static
//               equilibrium), a box spinning about its intermediate axis
//               (Dzhanibekov flips, angular momentum conserved), damped
//               oscillator (analytic envelope).
//   behind      the course of scenes/course.json (z = -50 to -10), included whole:
//               a car driving a scripted lap over heightfield terrain, a
//               character walking up stairs onto a turntable and jumping.
// The pile's round shapes have rolling resistance so they come to rest
// instead of rolling into their neighbours. It runs in about a second.
// Body names share a stem per set piece ("pyramid3", "pile_box1",
// "spring_chain_mass2"): the replay page labels each group by its stem
// (docs/recording.md, "HTML replay page").
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "fulcrum/vehicle.hpp"
#include "io/run.hpp"

namespace fulcrum::detail {

namespace {

// Written as a scene file, so the demo also exercises the reader.
constexpr const char* kDemoScene = R"json({
  "version": 1,
  "description": "Built-in demo: a box pyramid, a pile of mixed shapes (spheres, boxes, capsules, cylinders, hulls), a chain of ball joints, a motorised hinged door, a spring-loaded slider, a rope carrying a box, a cloth draping over a dome; behind them a projectile, a spring-mass chain, a box flipping about its intermediate axis and a damped oscillator, each checked against its analytic answer.",
  "world": { "gravity": [0, -9.81, 0], "dt": 0.0166667, "steps": 600, "substeps": 4, "sleeping": true },
  "bodies": [
    { "name": "ground", "type": "static", "shape": { "type": "plane", "normal": [0, 1, 0], "offset": 0 } },
    { "name": "pyramid0", "shape": { "type": "box", "half_extents": [0.2, 0.2, 0.2] }, "mass": 1, "position": [-0.615, 0.2, 0] },
    { "name": "pyramid1", "shape": { "type": "box", "half_extents": [0.2, 0.2, 0.2] }, "mass": 1, "position": [-0.205, 0.2, 0] },
    { "name": "pyramid2", "shape": { "type": "box", "half_extents": [0.2, 0.2, 0.2] }, "mass": 1, "position": [0.205, 0.2, 0], "rolling_resistance": 0.2 },
    { "name": "pyramid3", "shape": { "type": "box", "half_extents": [0.2, 0.2, 0.2] }, "mass": 1, "position": [0.615, 0.2, 0], "rolling_resistance": 0.2 },
    { "name": "pyramid4", "shape": { "type": "box", "half_extents": [0.2, 0.2, 0.2] }, "mass": 1, "position": [-0.41, 0.6, 0] },
    { "name": "pyramid5", "shape": { "type": "box", "half_extents": [0.2, 0.2, 0.2] }, "mass": 1, "position": [0, 0.6, 0], "rolling_resistance": 0.2 },
    { "name": "pyramid6", "shape": { "type": "box", "half_extents": [0.2, 0.2, 0.2] }, "mass": 1, "position": [0.41, 0.6, 0], "rolling_resistance": 0.2 },
    { "name": "pyramid7", "shape": { "type": "box", "half_extents": [0.2, 0.2, 0.2] }, "mass": 1, "position": [-0.205, 1, 0] },
    { "name": "pyramid8", "shape": { "type": "box", "half_extents": [0.2, 0.2, 0.2] }, "mass": 1, "position": [0.205, 1, 0], "rolling_resistance": 0.2 },
    { "name": "pyramid9", "shape": { "type": "box", "half_extents": [0.2, 0.2, 0.2] }, "mass": 1, "position": [0, 1.4, 0], "rolling_resistance": 0.2 },
    { "name": "pile_sphere0", "shape": { "type": "sphere", "radius": 0.2 }, "mass": 1, "position": [5.18, 0.4, 0], "rolling_resistance": 0.2 },
    { "name": "pile_box0", "shape": { "type": "box", "half_extents": [0.25, 0.15, 0.2] }, "mass": 1, "position": [4.867, 0.85, 0.122], "orientation": [0.9239, 0.2706, 0.2706, 0], "rolling_resistance": 0.2 },
    { "name": "pile_capsule0", "shape": { "type": "capsule", "radius": 0.12, "half_height": 0.2 }, "mass": 1, "position": [5.016, 1.3, -0.179], "rolling_resistance": 0.2 },
    { "name": "pile_cylinder0", "shape": { "type": "cylinder", "radius": 0.18, "half_height": 0.15 }, "mass": 1, "position": [5.11, 1.75, 0.143], "orientation": [0.9239, 0.2706, 0.2706, 0], "rolling_resistance": 0.2 },
    { "name": "pile_hull0", "shape": { "type": "convex_hull", "points": [[-0.2, 0, -0.2], [0.2, 0, -0.2], [0.2, 0, 0.2], [-0.2, 0, 0.2], [0, 0.35, 0]] }, "mass": 1, "position": [4.823, 2.2, -0.031], "rolling_resistance": 0.2 },
    { "name": "pile_sphere1", "shape": { "type": "sphere", "radius": 0.2 }, "mass": 1, "position": [5.152, 2.65, -0.097], "orientation": [0.9239, 0.2706, 0.2706, 0], "rolling_resistance": 0.2 },
    { "name": "pile_box1", "shape": { "type": "box", "half_extents": [0.25, 0.15, 0.2] }, "mass": 1, "position": [4.953, 3.1, 0.174], "rolling_resistance": 0.2 },
    { "name": "pile_capsule1", "shape": { "type": "capsule", "radius": 0.12, "half_height": 0.2 }, "mass": 1, "position": [4.917, 3.55, -0.16], "orientation": [0.9239, 0.2706, 0.2706, 0], "rolling_resistance": 0.2 },
    { "name": "pile_cylinder1", "shape": { "type": "cylinder", "radius": 0.18, "half_height": 0.15 }, "mass": 1, "position": [5.169, 4, 0.062], "rolling_resistance": 0.2 },
    { "name": "pile_hull1", "shape": { "type": "convex_hull", "points": [[-0.2, 0, -0.2], [0.2, 0, -0.2], [0.2, 0, 0.2], [-0.2, 0, 0.2], [0, 0.35, 0]] }, "mass": 1, "position": [4.834, 4.45, 0.069], "orientation": [0.9239, 0.2706, 0.2706, 0], "rolling_resistance": 0.2 },
    { "name": "chain_link0", "shape": { "type": "capsule", "radius": 0.06, "half_height": 0.14 }, "mass": 0.5, "position": [-4, 3.8, 0] },
    { "name": "chain_link1", "shape": { "type": "capsule", "radius": 0.06, "half_height": 0.14 }, "mass": 0.5, "position": [-4, 3.4, 0] },
    { "name": "chain_link2", "shape": { "type": "capsule", "radius": 0.06, "half_height": 0.14 }, "mass": 0.5, "position": [-4, 3, 0] },
    { "name": "chain_link3", "shape": { "type": "capsule", "radius": 0.06, "half_height": 0.14 }, "mass": 0.5, "position": [-4, 2.6, 0] },
    { "name": "chain_link4", "shape": { "type": "capsule", "radius": 0.06, "half_height": 0.14 }, "mass": 0.5, "position": [-4, 2.2, 0], "linear_velocity": [1.5, 0, 0] },
    { "name": "door", "shape": { "type": "box", "half_extents": [0.5, 1, 0.05] }, "mass": 10, "position": [-7.5, 1.1, 0] },
    { "name": "slider_carriage", "shape": { "type": "box", "half_extents": [0.2, 0.2, 0.2] }, "mass": 2, "position": [-11, 1.5, 0], "linear_velocity": [1, 0, 0] },
    { "name": "rope_weight", "shape": { "type": "box", "half_extents": [0.15, 0.15, 0.15] }, "mass": 1, "position": [11, 1, 0], "rolling_resistance": 0.2 },
    { "name": "cloth_dome", "type": "static", "shape": { "type": "sphere", "radius": 0.6 }, "position": [18, 0.6, 0] },
    { "name": "projectile", "shape": { "type": "sphere", "radius": 0.1 }, "mass": 0.5, "position": [-10, 0.1, -9], "linear_velocity": [5, 10, 0], "rolling_resistance": 0.2 },
    { "name": "spring_chain_mass1", "shape": { "type": "sphere", "radius": 0.1 }, "mass": 1, "position": [0, 4, -6], "allow_sleep": false },
    { "name": "spring_chain_mass2", "shape": { "type": "sphere", "radius": 0.1 }, "mass": 1, "position": [0, 3, -6], "allow_sleep": false },
    { "name": "spring_chain_mass3", "shape": { "type": "sphere", "radius": 0.1 }, "mass": 1, "position": [0, 2, -6], "allow_sleep": false },
    { "name": "spinner", "shape": { "type": "box", "half_extents": [0.05, 0.2, 0.4] }, "mass": 3, "position": [4, 5, -6], "angular_velocity": [0.01, 10, 0], "gravity_scale": 0 },
    { "name": "oscillator", "shape": { "type": "box", "half_extents": [0.1, 0.1, 0.1] }, "mass": 1, "position": [8.5, 5, -6], "gravity_scale": 0, "allow_sleep": false }
  ],
  "joints": [
    { "name": "chain_joint0", "type": "ball", "body_a": null, "body_b": "chain_link0", "anchor": [-4, 4, 0] },
    { "name": "chain_joint1", "type": "ball", "body_a": "chain_link0", "body_b": "chain_link1", "anchor": [-4, 3.6, 0] },
    { "name": "chain_joint2", "type": "ball", "body_a": "chain_link1", "body_b": "chain_link2", "anchor": [-4, 3.2, 0] },
    { "name": "chain_joint3", "type": "ball", "body_a": "chain_link2", "body_b": "chain_link3", "anchor": [-4, 2.8, 0] },
    { "name": "chain_joint4", "type": "ball", "body_a": "chain_link3", "body_b": "chain_link4", "anchor": [-4, 2.4, 0] },
    { "name": "door_hinge", "type": "hinge", "body_a": null, "body_b": "door", "anchor": [-8, 1.1, 0], "axis": [0, 1, 0], "limits": [-1.5708, 1.5708], "motor": { "speed": 1.0, "max_force": 50 } },
    { "name": "slider", "type": "slider", "body_a": null, "body_b": "slider_carriage", "anchor": [-11, 1.5, 0], "axis": [1, 0, 0], "limits": [-1, 1], "spring": { "target": 0, "stiffness": 100, "damping": 5 } }
  ],
  "springs": [
    { "body_a": null, "body_b": "spring_chain_mass1", "anchor_a": [0, 5, -6], "anchor_b": [0, 4, -6], "rest_length": 1, "stiffness": 200, "damping": 10 },
    { "body_a": "spring_chain_mass1", "body_b": "spring_chain_mass2", "anchor_a": [0, 4, -6], "anchor_b": [0, 3, -6], "rest_length": 1, "stiffness": 200, "damping": 10 },
    { "body_a": "spring_chain_mass2", "body_b": "spring_chain_mass3", "anchor_a": [0, 3, -6], "anchor_b": [0, 2, -6], "rest_length": 1, "stiffness": 200, "damping": 10 },
    { "body_a": null, "body_b": "oscillator", "anchor_a": [7, 5, -6], "anchor_b": [8.5, 5, -6], "rest_length": 1, "stiffness": 50, "damping": 1 }
  ],
  "ropes": [
    { "name": "rope", "start": [11, 3.5, 0], "end": [11, 1.15, 0], "segments": 16, "particle_mass": 0.05, "radius": 0.03,
      "pin_start": true, "pin_end": false, "attach_end": "rope_weight", "bend_compliance": 0.01 }
  ],
  "cloths": [
    { "name": "cloth", "origin": [17.25, 2, -0.75], "size": [16, 16], "spacing": 0.1, "particle_mass": 0.01,
      "radius": 0.03, "bend_compliance": 0.1 }
  ]
})json";

// Demo constants the analytic checks use (they mirror kDemoScene).
constexpr double kG = 9.81;
constexpr double kChainK = 200, kChainM = 1, kChainTop = 2;  // spring chain: lowest mass starts at y = 2
constexpr double kOscK = 50, kOscM = 1, kOscC = 1, kOscX0 = 0.5;
constexpr double kProjX0 = -10, kProjY0 = 0.1, kProjVx = 5, kProjVy = 10, kProjSampleTime = 1.0;
constexpr int kPyramidBoxes = 10;

std::string pyramidName(int i) { return "pyramid" + std::to_string(i); }

// Largest position error over the named joints (m), -1 if none exists.
double largestJointError(const World& world, const char* prefix) {
    double worst = -1;
    for (const JointId id : world.joints()) {
        if (world.name(id).rfind(prefix, 0) != 0) continue;
        worst = std::max(worst, static_cast<double>(world.jointError(id)));
    }
    return worst;
}

}  // namespace

// scenes/course.json, embedded at build time (cmake/embed_text.cmake).
std::string courseSceneText();

Scene demoScene() {
    // The demo's own pieces plus the course's: every array of the course
    // appended to the demo's (a body both have, the ground, only once), the
    // run long enough for the course's lap.
    nlohmann::json demo = nlohmann::json::parse(kDemoScene);
    const nlohmann::json course = nlohmann::json::parse(courseSceneText());
    for (const auto& [key, value] : course.items()) {
        if (!value.is_array()) continue;
        for (const auto& item : value) {
            const auto same = [&](const nlohmann::json& mine) { return mine == item; };
            if (key == "bodies" && std::any_of(demo[key].begin(), demo[key].end(), same)) continue;
            demo[key].push_back(item);
        }
    }
    demo["world"]["steps"] = std::max(demo["world"]["steps"].get<int>(), course["world"]["steps"].get<int>());
    demo["description"] = demo["description"].get<std::string>() + " Behind them: " + course["description"].get<std::string>();
    return parseScene(demo.dump(), "built-in demo");
}

void DemoChecks::observe(const World& world, const SceneHandles&, std::uint64_t step) {
    if (step == 0) {
        pyramidStart_.clear();
        for (int i = 0; i < kPyramidBoxes; ++i) {
            const BodyId id = world.findBody(pyramidName(i));
            if (!id.isNull()) pyramidStart_.push_back(world.position(id));
        }
    }
    // The projectile in flight (it lands at t = 2 s and then rolls).
    if (projectileTime_ < 0 && static_cast<double>(world.time()) >= kProjSampleTime - 1e-6) {
        if (const BodyId p = world.findBody("projectile"); !p.isNull()) {
            projectileTime_ = static_cast<double>(world.time());
            projectileAt_ = world.position(p);
        }
    }
    // The course's car: the distance its chassis drives.
    if (const BodyId car = world.findBody("car"); !car.isNull()) {
        const Vec3 p = world.position(car);
        if (step > 0) carDistance_ += static_cast<double>(length(p - carLast_));
        carLast_ = p;
    }
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
    s << "demo checks:\n";

    // ---- front row
    if (!pyramidStart_.empty()) {
        double drift = 0;
        for (int i = 0; i < static_cast<int>(pyramidStart_.size()); ++i) {
            const BodyId id = world.findBody(pyramidName(i));
            if (!id.isNull()) drift = std::max(drift, static_cast<double>(length(world.position(id) - pyramidStart_[static_cast<std::size_t>(i)])));
        }
        std::snprintf(line, sizeof line, "  pyramid: %zu boxes, largest drift %.2f mm: %s\n", pyramidStart_.size(), 1000 * drift,
                      drift < 0.01 ? "it stands (under 1 cm)" : "it did NOT stand (over 1 cm)");
        s << line;
    }
    {
        int count = 0, asleep = 0;
        double fastest = 0;
        for (const BodyId id : world.bodies()) {
            if (world.name(id).rfind("pile_", 0) != 0) continue;
            ++count;
            if (!world.isAwake(id)) ++asleep;
            fastest = std::max(fastest, static_cast<double>(length(world.linearVelocity(id))));
        }
        if (count > 0) {
            std::snprintf(line, sizeof line,
                          "  mixed pile: %d spheres, boxes, capsules, cylinders and hulls; %d asleep, fastest %.3f m/s\n", count,
                          asleep, fastest);
            s << line;
        }
    }
    if (const double e = largestJointError(world, "chain_joint"); e >= 0) {
        std::snprintf(line, sizeof line, "  chain of ball joints: largest joint error %.2f mm (a solved chain stays under 1 mm)\n", 1000 * e);
        s << line;
    }
    if (const double e = largestJointError(world, "door"); e >= 0) {
        std::snprintf(line, sizeof line, "  hinged door: joint error %.2f mm (motor 1 rad/s up to its 90 degree limit)\n", 1000 * e);
        s << line;
    }
    if (const double e = largestJointError(world, "slider"); e >= 0) {
        std::snprintf(line, sizeof line, "  slider: joint error %.2f mm (a spring pulls the carriage back to the rail's centre)\n", 1000 * e);
        s << line;
    }
    for (const ParticleSystemId id : world.particleSystems()) {
        const ParticleReport r = world.particleReport(id);
        if (world.particleSystemType(id) == ParticleSystemType::Rope) {
            std::snprintf(line, sizeof line, "  rope carrying a box: stretch max %.2f %% mean %.2f %% (inextensible: under 1 %%)\n",
                          100 * double(r.maxStretch), 100 * double(r.meanStretch));
        } else {
            std::snprintf(line, sizeof line,
                          "  cloth over a dome: centroid at y = %.3f m, deepest particle %.3f mm inside a shape (stretch max %.2f %%)\n",
                          double(r.centroid.y), 1000 * double(r.maxPenetration), 100 * double(r.maxStretch));
        }
        s << line;
    }

    // ---- behind: the course
    for (const VehicleId id : vehicles(world)) {
        const VehicleState v = vehicleState(world, id);
        int down = 0;
        for (const WheelState& w : v.wheels) down += w.inContact ? 1 : 0;
        std::snprintf(line, sizeof line,
                      "  car '%s': drove %.1f m around its lap over heightfield terrain, %d of %zu wheels on the ground, "
                      "speed %.2f m/s at the end (braked to a stop)\n",
                      vehicleDef(world, id).name.c_str(), carDistance_, down, v.wheels.size(),
                      std::abs(double(v.speed)) < 0.005 ? 0.0 : double(v.speed));  // no "-0.00"
        s << line;
    }
    for (const CharacterId id : world.characters()) {
        const CharacterState c = world.characterState(id);
        const std::string ground = c.groundBody.isNull() ? std::string("nothing") : world.name(c.groundBody);
        std::snprintf(line, sizeof line, "  character '%s': up the stairs, standing on %s (%s), feet at y = %.2f m\n",
                      world.name(id).c_str(), ground.c_str(), toString(c.ground),
                      double(c.position.y - world.characterDef(id).height / 2));
        s << line;
    }

    // ---- back row: analytic answers
    if (projectileTime_ >= 0) {
        const double tp = projectileTime_;
        const double ax = kProjX0 + kProjVx * tp, ay = kProjY0 + kProjVy * tp - 0.5 * kG * tp * tp;
        const double err = std::hypot(double(projectileAt_.x) - ax, double(projectileAt_.y) - ay);
        std::snprintf(line, sizeof line,
                      "  projectile: at t = %.3f s y = %.4f m, analytic x0 + v0 t + g t^2/2 gives %.4f m; error %.3g m "
                      "(first-order integrators: about g h t / 2 = %.3g m)\n",
                      tp, double(projectileAt_.y), ay, err, kG * h * tp / 2);
        s << line;
    }
    if (const BodyId c = world.findBody("spring_chain_mass3"); !c.isNull()) {
        // Static equilibrium: spring i carries the weight of the masses below it.
        const double yEq = kChainTop - (3 + 2 + 1) * kChainM * kG / kChainK;
        std::snprintf(line, sizeof line, "  spring chain: lowest mass settles at y = %.4f m; static equilibrium %.4f m\n",
                      double(world.position(c).y), yEq);
        s << line;
    }
    if (const BodyId b = world.findBody("spinner"); !b.isNull()) {
        // Torque-free: the angular momentum L = R I R^T w is conserved through the flips.
        const Quat q = world.orientation(b);
        const Vec3 L = rotate(q, world.localInertia(b) * inverseRotate(q, world.angularVelocity(b)));
        const Vec3 L0(Real(0.2) * Real(0.01), Real(0.1625) * 10, 0);
        std::snprintf(line, sizeof line,
                      "  spinning box: %d flips about its intermediate axis (Dzhanibekov); |L| = %.4f kg m^2/s, conserved "
                      "value %.4f\n",
                      flips_, double(length(L)), double(length(L0)));
        s << line;
    }
    if (const BodyId o = world.findBody("oscillator"); !o.isNull()) {
        // Light damping: the amplitude decays along x0 e^(-zeta w0 t). The spring's
        // world end is at x = 7 with rest length 1, so equilibrium is x = 8.
        const double w0 = std::sqrt(kOscK / kOscM), zeta = kOscC / (2 * std::sqrt(kOscK * kOscM));
        const double x = double(world.position(o).x) - 8, v = double(world.linearVelocity(o).x);
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
