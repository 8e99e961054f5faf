// A fixed number of steps of one benchmark scene (bench/scenes.hpp, the quick
// sizes), on one thread, with no timing: for callgrind, whose instruction
// counts are repeatable on a loaded machine where clocks are not. Compares
// builds, e.g. float against FULCRUM_DOUBLE (docs/double-precision.md):
//   valgrind --tool=callgrind --toggle-collect='fulcrum::World::step(*)'
//       build/release/bench/bench_step_count pyramid20 60
// Prints the scene, the steps and a checksum of the final positions (so the
// two builds' runs can be told apart from a broken one).
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "fulcrum/fulcrum.hpp"
#include "scenes.hpp"

using namespace fulcrum;

namespace {

// The rigid-body part of a benchmark scene (boxes, spheres, capsules, hulls,
// ball joints), built as bench/benchmark_scenes.cpp builds it for Fulcrum.
World build(const bench::SceneSpec& scene, std::vector<BodyId>& ids) {
    const auto real = [](double v) { return static_cast<Real>(v); };
    const auto vec = [&](bench::V3 v) { return Vec3{real(v.x), real(v.y), real(v.z)}; };
    WorldDef def;
    def.sleeping = scene.sleeping;
    def.threads = 1;
    def.gravity = vec(scene.gravity);
    if (scene.substeps > 0) def.substeps = scene.substeps;
    World world(def);
    std::vector<Vec3> hullPoints;
    for (const bench::V3& p : scene.hullPoints) hullPoints.push_back(vec(p));
    for (const bench::BodySpec& b : scene.bodies) {
        BodyDef d;
        d.type = b.isStatic ? BodyType::Static : BodyType::Dynamic;
        switch (b.kind) {
            case bench::BodySpec::Kind::Sphere: d.shape = Shape::sphere(real(b.half.x)); break;
            case bench::BodySpec::Kind::Capsule: d.shape = Shape::capsule(real(b.half.x), real(b.half.y)); break;
            case bench::BodySpec::Kind::Box: d.shape = Shape::box(vec(b.half)); break;
            case bench::BodySpec::Kind::Hull: d.shape = Shape::convexHull(hullPoints); break;
        }
        if (!scene.bodyCollisions) d.filter.group = -1;
        if (!b.isStatic) d.mass = real(b.mass);
        d.position = vec(b.position);
        d.orientation = {real(b.orientation.w), real(b.orientation.x), real(b.orientation.y), real(b.orientation.z)};
        d.linearVelocity = vec(b.linearVelocity);
        d.angularVelocity = vec(b.angularVelocity);
        d.friction = real(scene.friction);
        ids.push_back(world.createBody(d));
    }
    for (const bench::JointSpec& j : scene.joints) {
        JointDef d;
        d.type = JointType::Ball;
        d.bodyA = j.a < 0 ? kWorldBody : ids[static_cast<std::size_t>(j.a)];
        d.bodyB = ids[static_cast<std::size_t>(j.b)];
        d.anchor = vec(j.anchor);
        world.createJoint(d);
    }
    return world;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 3) {
        std::fprintf(stderr, "usage: %s SCENE STEPS   (SCENE: a name from bench/scenes.hpp, quick sizes)\n", argv[0]);
        return 2;
    }
    const std::string name = argv[1];
    const int steps = std::atoi(argv[2]);
    for (const bench::SceneSpec& scene : bench::allScenes(true)) {
        if (scene.name != name) continue;
        std::vector<BodyId> ids;
        World world = build(scene, ids);
        for (int i = 0; i < steps; ++i) world.step(static_cast<Real>(scene.dt));
        double checksum = 0;
        for (const BodyId id : ids) {
            const Vec3 p = world.position(id);
            checksum += double(p.x) + double(p.y) + double(p.z);
        }
        std::printf("%s: %d steps, sizeof(Real) %zu, position checksum %.9g\n", name.c_str(), steps, sizeof(Real), checksum);
        return 0;
    }
    std::fprintf(stderr, "no scene named '%s'\n", name.c_str());
    return 2;
}
