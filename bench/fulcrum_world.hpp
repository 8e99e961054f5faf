#pragma once
// A benchmark scene (bench/scenes.hpp) built as a Fulcrum world: the one
// translation of the engine-neutral scenes into Fulcrum, used by the
// side-by-side timings (bench/benchmark_scenes.cpp), the instruction counts
// (bench/step_count.cpp) and the recorded state hashes
// (tests/determinism/golden_hash_test.cpp), so all three measure the same world.
#include <memory>
#include <vector>

#include "fulcrum/fulcrum.hpp"
#include "scenes.hpp"

namespace bench {

inline fulcrum::Vec3 toFulcrum(V3 v) {
    return {static_cast<fulcrum::Real>(v.x), static_cast<fulcrum::Real>(v.y), static_cast<fulcrum::Real>(v.z)};
}

struct FulcrumWorld {
    std::unique_ptr<fulcrum::World> world;
    std::vector<fulcrum::BodyId> bodies;  // index-aligned with SceneSpec::bodies
    fulcrum::ParticleSystemId cloth;      // null when the scene has none
};

inline FulcrumWorld buildFulcrumWorld(const SceneSpec& scene, int threads) {
    using fulcrum::Real;
    const auto real = [](double v) { return static_cast<Real>(v); };
    fulcrum::WorldDef def;
    def.sleeping = scene.sleeping;
    def.threads = threads;
    def.gravity = toFulcrum(scene.gravity);
    if (scene.substeps > 0) def.substeps = scene.substeps;
    if (scene.sleepVelocity > 0) def.linearSleepVelocity = static_cast<Real>(scene.sleepVelocity);
    FulcrumWorld out{std::make_unique<fulcrum::World>(def), {}, {}};
    fulcrum::World& world = *out.world;
    // One shape per distinct size, shared by the bodies that have it (as a
    // game would): the unit box and sphere of the piles, the scene's hull.
    const fulcrum::Shape unitBox = fulcrum::Shape::box(fulcrum::Vec3::splat(Real(0.5)));
    const fulcrum::Shape unitSphere = fulcrum::Shape::sphere(Real(0.5));
    fulcrum::Shape hull;
    if (!scene.hullPoints.empty()) {
        std::vector<fulcrum::Vec3> points;
        for (const V3& p : scene.hullPoints) points.push_back(toFulcrum(p));
        hull = fulcrum::Shape::convexHull(points);
    }
    // The mesh scenes (bench/mesh_scenes.hpp): the scene's mesh and compound, each built once.
    fulcrum::Shape mesh, compound;
    if (scene.mesh) {
        std::vector<fulcrum::Vec3> vertices;
        vertices.reserve(scene.mesh->vertices.size());
        for (const V3& v : scene.mesh->vertices) vertices.push_back(toFulcrum(v));
        mesh = fulcrum::Shape::mesh(vertices, scene.mesh->triangles);
    }
    if (!scene.compoundHulls.empty()) {
        std::vector<fulcrum::CompoundChild> children;
        for (const std::vector<V3>& part : scene.compoundHulls) {
            std::vector<fulcrum::Vec3> points;
            for (const V3& p : part) points.push_back(toFulcrum(p));
            children.push_back({fulcrum::Shape::convexHull(points), fulcrum::Transform{}});
        }
        compound = fulcrum::Shape::compound(children);
    }
    for (const BodySpec& b : scene.bodies) {
        fulcrum::BodyDef d;
        d.type = b.isStatic ? fulcrum::BodyType::Static : fulcrum::BodyType::Dynamic;
        switch (b.kind) {
            case BodySpec::Kind::Sphere: d.shape = b.half.x == 0.5 ? unitSphere : fulcrum::Shape::sphere(real(b.half.x)); break;
            case BodySpec::Kind::Capsule: d.shape = fulcrum::Shape::capsule(real(b.half.x), real(b.half.y)); break;
            case BodySpec::Kind::Box:
                d.shape = (b.half.x == 0.5 && b.half.y == 0.5 && b.half.z == 0.5) ? unitBox : fulcrum::Shape::box(toFulcrum(b.half));
                break;
            case BodySpec::Kind::Hull: d.shape = hull; break;
            case BodySpec::Kind::Mesh: d.shape = mesh; break;
            case BodySpec::Kind::Compound: d.shape = compound; break;
        }
        if (b.isKinematic) d.type = fulcrum::BodyType::Kinematic;
        if (!scene.bodyCollisions) d.filter.group = -1;  // a shared negative group never collides
        if (!b.isStatic && !b.isKinematic) d.mass = real(b.mass);
        d.position = toFulcrum(b.position);
        d.orientation = {real(b.orientation.w), real(b.orientation.x), real(b.orientation.y), real(b.orientation.z)};
        d.linearVelocity = toFulcrum(b.linearVelocity);
        d.angularVelocity = toFulcrum(b.angularVelocity);
        d.friction = real(scene.friction);  // geometric mean of equal values: the pair value
        d.restitution = real(scene.restitution);
        out.bodies.push_back(world.createBody(d));
    }
    for (const JointSpec& j : scene.joints) {
        fulcrum::JointDef d;
        d.type = fulcrum::JointType::Ball;
        d.bodyA = j.a < 0 ? fulcrum::kWorldBody : out.bodies[static_cast<std::size_t>(j.a)];
        d.bodyB = out.bodies[static_cast<std::size_t>(j.b)];
        d.anchor = toFulcrum(j.anchor);
        world.createJoint(d);
    }
    if (scene.cloth.n > 0) {
        const ClothSpec& c = scene.cloth;
        fulcrum::ClothDef d;
        d.name = "cloth";
        d.size = {c.n, c.n};
        d.spacing = real(c.spacing);
        d.particleMass = real(c.particleMass);
        d.radius = Real(0.02);
        const double half = 0.5 * c.spacing * (c.n - 1);
        d.origin = toFulcrum({-half, c.height, -half});
        d.bendCompliance = Real(0.1);  // m/N: drapes (0 would make a stiff plate); as bench/cloth.cpp
        out.cloth = world.createCloth(d);
    }
    return out;
}

// Before step `step` (from 0): sets the scene's kinematic bodies moving along
// their paths (SceneSpec::kinematicPaths).
inline void driveKinematics(const FulcrumWorld& built, const SceneSpec& scene, int step) {
    for (const KinematicPath& path : scene.kinematicPaths) {
        built.world->moveKinematic(built.bodies[static_cast<std::size_t>(path.body)],
                                   fulcrum::Transform{toFulcrum(path.origin(step)), fulcrum::Quat{}}, static_cast<fulcrum::Real>(scene.dt));
    }
}

}  // namespace bench
