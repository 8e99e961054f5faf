#pragma once
// Shared by tests/determinism and tests/snapshot: a hash of the whole visible
// state of a World, and the mixed test scene (box pile, joint chain, rope,
// cloth on a sphere) the determinism proofs run.
#include <bit>
#include <cstdint>
#include <cstring>
#include <string>

#include "fulcrum/scene.hpp"
#include "fulcrum/world.hpp"

namespace fulcrum::test {

// FNV-1a over the bits of every body's position, orientation and velocities,
// its awake flag, and every particle's position and velocity. Two states hash
// equal only if all of these are bit-identical (up to a 2^-64 collision).
class StateHasher {
public:
    void add(Real v) {
        std::uint64_t bits = 0;
        std::memcpy(&bits, &v, sizeof v);
        add64(bits);
    }
    void add(const Vec3& v) { add(v.x), add(v.y), add(v.z); }
    void add(const Quat& q) { add(q.w), add(q.x), add(q.y), add(q.z); }
    void add64(std::uint64_t bits) {
        for (int i = 0; i < 8; ++i) {
            h_ ^= (bits >> (8 * i)) & 0xFF;
            h_ *= 1099511628211ull;
        }
    }
    std::uint64_t value() const { return h_; }

private:
    std::uint64_t h_ = 14695981039346656037ull;
};

inline std::uint64_t stateHash(const World& world) {
    StateHasher h;
    h.add64(world.stepCount());
    for (const BodyId id : world.bodies()) {
        h.add(world.position(id));
        h.add(world.orientation(id));
        h.add(world.linearVelocity(id));
        h.add(world.angularVelocity(id));
        h.add64(world.isAwake(id) ? 1 : 0);
    }
    for (const ParticleSystemId id : world.particleSystems()) {
        const auto x = world.particlePositions(id);
        for (std::size_t i = 0; i < x.size(); ++i) {
            h.add(x[i]);
            h.add(world.particleVelocity(id, i));
        }
    }
    return h.value();
}

// A box pile (16 boxes and 4 spheres dropped in a heap), a 5-link ball-joint
// chain, a rope tied to a box, and a 12 x 12 cloth falling on a sphere; all
// within a few metres so the parts meet the ground and settle.
inline constexpr const char* kMixedScene = R"json({
  "world": { "gravity": [0, -9.81, 0], "dt": 0.0166667, "steps": 240, "substeps": 4 },
  "bodies": [
    { "name": "ground", "type": "static", "shape": { "type": "plane", "normal": [0, 1, 0], "offset": 0 } },
    { "name": "b0", "shape": { "type": "box", "half_extents": [0.25, 0.25, 0.25] }, "mass": 1, "position": [0, 0.3, 0] },
    { "name": "b1", "shape": { "type": "box", "half_extents": [0.25, 0.25, 0.25] }, "mass": 1, "position": [0.52, 0.3, 0] },
    { "name": "b2", "shape": { "type": "box", "half_extents": [0.25, 0.25, 0.25] }, "mass": 1, "position": [0, 0.3, 0.52] },
    { "name": "b3", "shape": { "type": "box", "half_extents": [0.25, 0.25, 0.25] }, "mass": 1, "position": [0.52, 0.3, 0.52] },
    { "name": "b4", "shape": { "type": "box", "half_extents": [0.25, 0.25, 0.25] }, "mass": 1, "position": [0.26, 0.9, 0.26], "orientation": [0.9659, 0, 0.2588, 0] },
    { "name": "b5", "shape": { "type": "box", "half_extents": [0.25, 0.25, 0.25] }, "mass": 1, "position": [0.1, 1.5, 0.3], "orientation": [0.9239, 0.3827, 0, 0] },
    { "name": "b6", "shape": { "type": "box", "half_extents": [0.2, 0.1, 0.3] }, "mass": 1, "position": [0.4, 2.0, 0.2] },
    { "name": "b7", "shape": { "type": "box", "half_extents": [0.2, 0.1, 0.3] }, "mass": 1, "position": [0.2, 2.4, 0.4], "orientation": [0.9659, 0.2588, 0, 0] },
    { "name": "s0", "shape": { "type": "sphere", "radius": 0.2 }, "mass": 1, "position": [0.3, 2.9, 0.25] },
    { "name": "s1", "shape": { "type": "sphere", "radius": 0.2 }, "mass": 1, "position": [0.15, 3.4, 0.3] },
    { "name": "c0", "shape": { "type": "capsule", "radius": 0.1, "half_height": 0.2 }, "mass": 1, "position": [0.35, 3.9, 0.2], "orientation": [0.7071, 0, 0, 0.7071] },
    { "name": "link0", "shape": { "type": "capsule", "radius": 0.05, "half_height": 0.15 }, "mass": 0.5, "position": [-3, 3.8, 0] },
    { "name": "link1", "shape": { "type": "capsule", "radius": 0.05, "half_height": 0.15 }, "mass": 0.5, "position": [-3, 3.4, 0] },
    { "name": "link2", "shape": { "type": "capsule", "radius": 0.05, "half_height": 0.15 }, "mass": 0.5, "position": [-3, 3.0, 0] },
    { "name": "link3", "shape": { "type": "capsule", "radius": 0.05, "half_height": 0.15 }, "mass": 0.5, "position": [-3, 2.6, 0], "linear_velocity": [1, 0, 0] },
    { "name": "weight", "shape": { "type": "box", "half_extents": [0.15, 0.15, 0.15] }, "mass": 2, "position": [3, 1.0, 0] },
    { "name": "ball", "type": "static", "shape": { "type": "sphere", "radius": 0.5 }, "position": [0, 0.5, 3] }
  ],
  "joints": [
    { "name": "j0", "type": "ball", "body_a": null, "body_b": "link0", "anchor": [-3, 4, 0] },
    { "name": "j1", "type": "ball", "body_a": "link0", "body_b": "link1", "anchor": [-3, 3.6, 0] },
    { "name": "j2", "type": "ball", "body_a": "link1", "body_b": "link2", "anchor": [-3, 3.2, 0] },
    { "name": "j3", "type": "ball", "body_a": "link2", "body_b": "link3", "anchor": [-3, 2.8, 0] }
  ],
  "ropes": [
    { "name": "rope", "start": [3, 3, 0], "end": [3, 1.15, 0], "segments": 12, "particle_mass": 0.05, "radius": 0.03,
      "pin_start": true, "pin_end": false, "attach_end": "weight" }
  ],
  "cloths": [
    { "name": "cloth", "origin": [-0.55, 1.6, 2.45], "size": [12, 12], "spacing": 0.1, "particle_mass": 0.01,
      "radius": 0.03, "bend_compliance": 0.1 }
  ]
})json";

}  // namespace fulcrum::test
