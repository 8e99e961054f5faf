#pragma once
// A benchmark scene (bench/scenes.hpp) built as a Fulcrum world: the one
// translation of the engine-neutral scenes into Fulcrum, used by the
// side-by-side timings (bench/benchmark_scenes.cpp), the instruction counts
// (bench/step_count.cpp) and the recorded state hashes
// (tests/determinism/golden_hash_test.cpp), so all three measure the same world.
#include <cstdlib>
#include <map>
#include <memory>
#include <vector>

#include "fulcrum/fulcrum.hpp"
#include "scenes.hpp"

namespace bench {

inline fulcrum::Vec3 toFulcrum(V3 v) {
    return {static_cast<fulcrum::Real>(v.x), static_cast<fulcrum::Real>(v.y), static_cast<fulcrum::Real>(v.z)};
}


// Shapes the peers' scenes' bodies need (bench/churn_scenes.hpp,
// bench/mesh_scenes.hpp): a body of parts (a compound; one part off the
// origin too), a scene mesh, the scene's shared compound, a box of any size;
// made once per distinct description and shared, as a game shares them.
class FulcrumShapes {
public:
    // One shape per distinct size, shared by the bodies that have it (as a
    // game would): the unit box and sphere of the piles, the scene's hull.
    explicit FulcrumShapes(const SceneSpec& scene)
        : scene_(&scene),
          unitBox_(fulcrum::Shape::box(fulcrum::Vec3::splat(fulcrum::Real(0.5)))),
          unitSphere_(fulcrum::Shape::sphere(fulcrum::Real(0.5))) {
        if (!scene.hullPoints.empty()) {
            std::vector<fulcrum::Vec3> points;
            for (const V3& p : scene.hullPoints) points.push_back(bench::toFulcrum(p));
            hull_ = fulcrum::Shape::convexHull(points);
        }
        if (!scene.sharedCompoundHulls.empty()) {
            std::vector<fulcrum::CompoundChild> children;
            for (const std::vector<V3>& hull : scene.sharedCompoundHulls) {
                std::vector<fulcrum::Vec3> points;
                for (const V3& p : hull) points.push_back(bench::toFulcrum(p));
                children.push_back({fulcrum::Shape::convexHull(points), fulcrum::Transform{}});
            }
            sharedCompound_ = fulcrum::Shape::compound(children);
        }
    }

    // The definition of a scene's (or a script group's) body.
    fulcrum::BodyDef bodyDef(const BodySpec& b) {
        using fulcrum::Real;
        const auto real = [](double v) { return static_cast<Real>(v); };
        fulcrum::BodyDef d;
        d.type = b.isStatic ? fulcrum::BodyType::Static : fulcrum::BodyType::Dynamic;
        switch (b.kind) {
            case BodySpec::Kind::Sphere: d.shape = b.half.x == 0.5 ? unitSphere_ : fulcrum::Shape::sphere(real(b.half.x)); break;
            case BodySpec::Kind::Capsule: d.shape = fulcrum::Shape::capsule(real(b.half.x), real(b.half.y)); break;
            case BodySpec::Kind::Box:
                d.shape = (b.half.x == 0.5 && b.half.y == 0.5 && b.half.z == 0.5) ? unitBox_ : fulcrum::Shape::box(bench::toFulcrum(b.half));
                break;
            case BodySpec::Kind::Hull: d.shape = hull_; break;
            case BodySpec::Kind::SharedCompound: d.shape = sharedCompound_; break;
        }
        if (b.parts.size() == 1) {
            // One part (a ragdoll bone's capsule): the body's frame on the part
            // itself, a plain shape rather than a compound of one (as a Fulcrum
            // user builds a bone: a symmetric body gets the integrator's fast
            // path); its joints' frames move with it (createFulcrumJoint).
            const ShapePart& part = b.parts.front();
            d.shape = plain(part);
        } else if (!b.parts.empty()) {
            d.shape = parts(b.parts);
        }
        if (b.mesh >= 0) d.shape = mesh(b.mesh);
        if (b.isKinematic) d.type = fulcrum::BodyType::Kinematic;
        d.isBullet = b.isBullet;
        d.filter.group = b.filterGroup;
        if (!scene_->bodyCollisions) d.filter.group = -1;  // a shared negative group never collides
        if (d.type == fulcrum::BodyType::Dynamic) d.mass = real(b.mass);
        d.position = bench::toFulcrum(b.position);
        d.orientation = toFulcrum(b.orientation);
        if (b.parts.size() == 1) {
            d.position = bench::toFulcrum(b.position + rotate(b.orientation, b.parts.front().position));
            d.orientation = toFulcrum(b.orientation * b.parts.front().orientation);
        }
        d.linearVelocity = bench::toFulcrum(b.linearVelocity);
        d.angularVelocity = bench::toFulcrum(b.angularVelocity);
        // The scene's: the geometric mean of equal values is the pair value.
        d.friction = real(b.friction >= 0 ? b.friction : scene_->friction);
        d.restitution = real(b.restitution >= 0 ? b.restitution : scene_->restitution);
        return d;
    }

    static fulcrum::Quat toFulcrum(Q q) {
        using fulcrum::Real;
        return {static_cast<Real>(q.w), static_cast<Real>(q.x), static_cast<Real>(q.y), static_cast<Real>(q.z)};
    }

    const fulcrum::Shape& parts(const std::vector<ShapePart>& parts) {
        std::vector<double> key;
        for (const ShapePart& p : parts) {
            key.insert(key.end(), {double(static_cast<int>(p.kind)), p.position.x, p.position.y, p.position.z, p.orientation.w,
                                   p.orientation.x, p.orientation.y, p.orientation.z, p.half.x, p.half.y, p.half.z});
            for (const V3& v : p.points) key.insert(key.end(), {v.x, v.y, v.z});
        }
        const auto found = cache_.find(key);
        if (found != cache_.end()) return found->second;
        std::vector<fulcrum::CompoundChild> children;
        for (const ShapePart& p : parts) {
            children.push_back({plain(p), {bench::toFulcrum(p.position), toFulcrum(p.orientation)}});
        }
        return cache_.emplace(std::move(key), fulcrum::Shape::compound(children)).first->second;
    }

    // A part's shape in its own frame.
    static fulcrum::Shape plain(const ShapePart& p) {
        switch (p.kind) {
            case ShapePart::Kind::Box: return fulcrum::Shape::box(bench::toFulcrum(p.half));
            case ShapePart::Kind::Sphere: return fulcrum::Shape::sphere(static_cast<fulcrum::Real>(p.half.x));
            case ShapePart::Kind::Capsule:
                return fulcrum::Shape::capsule(static_cast<fulcrum::Real>(p.half.x), static_cast<fulcrum::Real>(p.half.y));
            case ShapePart::Kind::Hull: break;
        }
        std::vector<fulcrum::Vec3> points;
        for (const V3& v : p.points) points.push_back(bench::toFulcrum(v));
        return fulcrum::Shape::convexHull(points);
    }

    const fulcrum::Shape& mesh(int index) {
        const auto found = meshes_.find(index);
        if (found != meshes_.end()) return found->second;
        const MeshSpec& m = *scene_->meshes[static_cast<std::size_t>(index)];
        std::vector<fulcrum::Vec3> vertices;
        vertices.reserve(m.vertices.size());
        for (const V3& v : m.vertices) vertices.push_back(bench::toFulcrum(v));
        return meshes_.emplace(index, fulcrum::Shape::mesh(vertices, m.triangles)).first->second;
    }

    const fulcrum::Shape& box(V3 half) {
        const std::vector<double> key{-1, half.x, half.y, half.z};
        const auto found = cache_.find(key);
        if (found != cache_.end()) return found->second;
        return cache_.emplace(key, fulcrum::Shape::box(bench::toFulcrum(half))).first->second;
    }

private:
    const SceneSpec* scene_;
    fulcrum::Shape unitBox_, unitSphere_, hull_, sharedCompound_;
    std::map<std::vector<double>, fulcrum::Shape> cache_;
    std::map<int, fulcrum::Shape> meshes_;
};

struct FulcrumWorld {
    std::unique_ptr<fulcrum::World> world;
    std::vector<fulcrum::BodyId> bodies;  // index-aligned with SceneSpec::bodies
    fulcrum::ParticleSystemId cloth;      // null when the scene has none
    std::unique_ptr<FulcrumShapes> shapes;  // the scene's, for the bodies its script creates
};

// A churn scene's joint (bench/churn_scenes.hpp: given by a frame in each body).
// specA, specB: the bodies' descriptions (null: the world), whose frame
// FulcrumShapes::bodyDef may have moved onto their one part.
inline fulcrum::JointId createFulcrumJoint(fulcrum::World& world, const JointSpec& j, fulcrum::BodyId a, fulcrum::BodyId b,
                                           const BodySpec* specA = nullptr, const BodySpec* specB = nullptr) {
    using fulcrum::Real;
    const auto real = [](double v) { return static_cast<Real>(v); };
    const auto onPart = [](const BodySpec* spec, V3 p, bool isPoint) {
        if (spec == nullptr || spec->parts.size() != 1) return p;
        const ShapePart& part = spec->parts.front();
        return rotate(conjugate(part.orientation), isPoint ? p - part.position : p);
    };
    const auto local = [&](fulcrum::BodyId body, V3 p) {
        const fulcrum::Vec3 v = toFulcrum(onPart(body == a ? specA : specB, p, true));
        return body.isNull() ? v : v - world.localCenterOfMass(body);
    };
    const auto axisA = [&](Q q) { return toFulcrum(onPart(specA, rotate(q, {0, 0, 1}), false)); };
    const auto axisB = [&](Q q) { return toFulcrum(onPart(specB, rotate(q, {0, 0, 1}), false)); };
    // Both joint kinds take the bodies, anchors and axes the same way.
    const auto placeFrames = [&](auto& d) {
        d.bodyA = a;
        d.bodyB = b;
        d.localAnchorA = local(a, j.localA);
        d.localAnchorB = local(b, j.localB);
        d.localAxisA = axisA(j.frameA);
        d.localAxisB = axisB(j.frameB);
    };
    if (j.type == JointSpec::Type::Hinge) {
        fulcrum::HingeJointDef d;
        placeFrames(d);
        d.hasLimits = true;
        d.lowerLimit = real(j.lower);
        d.upperLimit = real(j.upper);
        d.frictionTorque = real(j.frictionTorque);
        return world.createJoint(d);
    }
    if (j.type == JointSpec::Type::ConeTwist) {
        fulcrum::ConeTwistJointDef d;
        placeFrames(d);
        d.swingLimit = real(j.swing);
        d.twistLower = real(j.lower);
        d.twistUpper = real(j.upper);
        d.frictionTorque = real(j.frictionTorque);
        return world.createJoint(d);
    }
    fulcrum::BallJointDef d = fulcrum::BallJointDef::fromWorld(world, a, b, toFulcrum(j.anchor));
    if (j.localFrames) {
        d.localAnchorA = local(a, j.localA);
        d.localAnchorB = local(b, j.localB);
    }
    return world.createJoint(d);
}

// FULCRUM_BENCH_PUSH_OUT=1 (bench_benchmark_scenes, bench_step_count):
// WorldDef::pushOutGrownOverlaps on after building, for the quality and
// cost figures with the push-out (docs/solver.md, "Grown overlaps"). The
// scenes themselves keep the default, off; buildFulcrumWorld never reads it.
inline void pushOutFromEnvironment(fulcrum::World& world) {
    const char* on = std::getenv("FULCRUM_BENCH_PUSH_OUT");
    if (on != nullptr && std::atoi(on) != 0) world.setPushOutGrownOverlaps(true);
}

inline FulcrumWorld buildFulcrumWorld(const SceneSpec& scene, int threads) {
    using fulcrum::Real;
    const auto real = [](double v) { return static_cast<Real>(v); };
    fulcrum::WorldDef def;
    def.sleeping = scene.sleeping;
    def.threads = threads;
    def.gravity = toFulcrum(scene.gravity);
    if (scene.substeps > 0) def.substeps = scene.substeps;
    if (scene.sleepVelocity > 0) def.linearSleepVelocity = static_cast<Real>(scene.sleepVelocity);
    FulcrumWorld out{std::make_unique<fulcrum::World>(def), {}, {}, {}};
    fulcrum::World& world = *out.world;
    out.shapes = std::make_unique<FulcrumShapes>(scene);
    FulcrumShapes& shapes = *out.shapes;
    for (const BodySpec& b : scene.bodies) out.bodies.push_back(world.createBody(shapes.bodyDef(b)));
    if (scene.staticGrid.nx > 0) {
        const StaticGrid& g = scene.staticGrid;
        fulcrum::BodyDef d;
        d.type = fulcrum::BodyType::Static;
        d.shape = shapes.box(g.half);
        d.friction = real(scene.friction);
        const double halfX = 0.5 * g.cell * g.nx, halfZ = 0.5 * g.cell * g.nz;
        // Room for the grid and the bodies the script adds, as Box3D's benchmark gives its world a capacity.
        std::size_t room = static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.nz);
        for (const BodyGroup& group : scene.groups) room += group.bodies.size();
        world.reserveBodies(room);
        for (int i = 0; i < g.nx; ++i) {
            for (int k = 0; k < g.nz; ++k) {
                d.position = toFulcrum({-halfX + (i + 0.5) * g.cell, g.y, -halfZ + (k + 0.5) * g.cell});
                world.createBody(d);
            }
        }
    }
    for (const JointSpec& j : scene.joints) {
        if (j.localFrames || j.type != JointSpec::Type::Ball) {
            const auto a = static_cast<std::size_t>(j.a), b = static_cast<std::size_t>(j.b);
            createFulcrumJoint(world, j, j.a < 0 ? fulcrum::kWorldBody : out.bodies[a], out.bodies[b],
                               j.a < 0 ? nullptr : &scene.bodies[a], &scene.bodies[b]);
            continue;
        }
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

// A churn scene's script (bench/churn_scenes.hpp) run on a Fulcrum world:
// its groups' bodies and joints created and destroyed before the steps the
// events name.
class FulcrumScript {
public:
    FulcrumScript(const SceneSpec& scene, FulcrumWorld& built)
        : scene_(&scene), built_(&built), bodies_(scene.groups.size()), joints_(scene.groups.size()) {}

    // The events of step `step` (call before each step, in order).
    void beforeStep(int step) {
        while (next_ < scene_->script.size() && scene_->script[next_].step <= step) {
            const ScriptEvent& e = scene_->script[next_++];
            if (e.create) {
                create(e.group);
            } else {
                destroy(e.group);
            }
        }
    }

    void create(int group) {
        fulcrum::World& world = *built_->world;
        const BodyGroup& g = scene_->groups[static_cast<std::size_t>(group)];
        std::vector<fulcrum::BodyId>& ids = bodies_[static_cast<std::size_t>(group)];
        for (const BodySpec& b : g.bodies) ids.push_back(world.createBody(built_->shapes->bodyDef(b)));
        for (const JointSpec& j : g.joints) {
            const auto a = static_cast<std::size_t>(j.a), b = static_cast<std::size_t>(j.b);
            joints_[static_cast<std::size_t>(group)].push_back(createFulcrumJoint(world, j, j.a < 0 ? fulcrum::kWorldBody : ids[a], ids[b],
                                                                                  j.a < 0 ? nullptr : &g.bodies[a], &g.bodies[b]));
        }
    }

    void destroy(int group) {
        fulcrum::World& world = *built_->world;
        for (const fulcrum::JointId id : joints_[static_cast<std::size_t>(group)]) world.destroyJoint(id);
        for (const fulcrum::BodyId id : bodies_[static_cast<std::size_t>(group)]) world.destroyBody(id);
        joints_[static_cast<std::size_t>(group)].clear();
        bodies_[static_cast<std::size_t>(group)].clear();
    }

    // Every live group's bodies.
    std::vector<fulcrum::BodyId> liveBodies() const {
        std::vector<fulcrum::BodyId> out;
        for (const auto& ids : bodies_) out.insert(out.end(), ids.begin(), ids.end());
        return out;
    }

    // Every live group's joints (a probe's joint error).
    std::vector<fulcrum::JointId> liveJoints() const {
        std::vector<fulcrum::JointId> out;
        for (const auto& ids : joints_) out.insert(out.end(), ids.begin(), ids.end());
        return out;
    }

private:
    const SceneSpec* scene_;
    FulcrumWorld* built_;
    std::vector<std::vector<fulcrum::BodyId>> bodies_;
    std::vector<std::vector<fulcrum::JointId>> joints_;
    std::size_t next_ = 0;
};

// Before step `step` (from 0): sets the scene's kinematic bodies moving along
// their paths (SceneSpec::kinematicPaths).
inline void driveKinematics(const FulcrumWorld& built, const SceneSpec& scene, int step) {
    for (const KinematicPath& path : scene.kinematicPaths) {
        built.world->moveKinematic(built.bodies[static_cast<std::size_t>(path.body)],
                                   fulcrum::Transform{toFulcrum(path.origin(step)), fulcrum::Quat{}}, static_cast<fulcrum::Real>(scene.dt));
    }
}

}  // namespace bench
