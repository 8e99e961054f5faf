#pragma once
// Batches: N independent worlds stepped together (docs/scale-out.md).
// Parameter sweeps, Monte Carlo runs and learning
// roll-outs run many small worlds; one world rarely fills the cores, so a
// Batch gives each world to one task instead: the worlds are stepped on the
// built-in thread pool, one world per task, and the pool's work stealing
// balances worlds of different cost (a tower that collapses next to a ball at
// rest). Inside its task a world steps on one thread, exactly as it would
// alone, so a world's result in a batch is bit for bit its result run alone,
// whatever the batch size and the thread count (tests/batch).
//
// State is gathered into flat arrays and actions are applied from them, in
// world-major order: element [w][b][k] of a (worlds, bodies, k) array is at
// (w * bodies + b) * k + k'. Bodies are each world's live bodies in creation
// order (World::bodies()), statics included; the arrays need every world to
// have the same number of bodies (and joints, for the motor speeds), which a
// batch built from one scene has. A span of the wrong size is a fulcrum::Error
// naming the function, the size given and the size expected.
//
// Each world can go back to its start, or to a snapshot (fulcrum/snapshot.hpp),
// on its own, since episodes end at different times. ForceCallbacks are code,
// not state: a reset world has none (set them again after reset()).
//
// The scene-file side (one scene with per-world overrides, or N scenes) is
// in fulcrum/scene_batch.hpp (library fulcrum::io).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "fulcrum/world.hpp"

namespace fulcrum {

class TaskSystem;

struct BatchDef {
    // Threads stepping the worlds (>= 1), the calling thread included.
    int threads = 1;
};

class Batch {
public:
    // Takes the worlds over. Each is switched to one internal thread (results
    // do not depend on it) and its start is recorded for reset(). Throws
    // fulcrum::Error for an empty batch or threads < 1.
    explicit Batch(std::vector<World> worlds, const BatchDef& def = {});
    ~Batch();
    Batch(Batch&&) noexcept;
    Batch& operator=(Batch&&) noexcept;
    Batch(const Batch&) = delete;
    Batch& operator=(const Batch&) = delete;

    std::size_t size() const;
    int threads() const;
    World& world(std::size_t index);               // throws fulcrum::Error for an index out of range
    const World& world(std::size_t index) const;

    // Bodies per world, and joints per world; throws fulcrum::Error naming the
    // first world that differs from world 0 (the arrays need one count).
    std::size_t bodyCount() const;
    std::size_t jointCount() const;

    // Steps every world `steps` times by dt. A world that fails (a NaN state)
    // is reported after all worlds have finished, as a fulcrum::Error naming
    // the world and the engine's message; the other worlds have stepped.
    void step(Real dt, int steps = 1);

    // ---- state, into (size() * bodyCount() * k) arrays
    void positions(std::span<Real> out) const;          // k = 3
    void orientations(std::span<Real> out) const;       // k = 4: w, x, y, z
    void linearVelocities(std::span<Real> out) const;   // k = 3
    void angularVelocities(std::span<Real> out) const;  // k = 3

    // ---- actions, from arrays of the same shapes
    void setLinearVelocities(std::span<const Real> values);   // ignored for static bodies
    void setAngularVelocities(std::span<const Real> values);  // ignored for static bodies
    // Forces at the centres of mass for the next step (World::applyForceAtCenter);
    // ignored for static bodies.
    void applyForces(std::span<const Real> values);
    // Hinge and slider motor speeds, (size() * jointCount()) values: each
    // joint's motor keeps its enabled flag and maximum force. Ignored for
    // joints of other types.
    void setJointMotorSpeeds(std::span<const Real> values);

    // ---- resets
    void reset(std::size_t index);  // back to the state the world had when the batch was made
    // To a snapshot (saveSnapshotToMemory of any world); throws fulcrum::Error
    // for a bad snapshot, leaving the world as it was.
    void reset(std::size_t index, std::span<const std::uint8_t> snapshot);
    std::vector<std::uint8_t> snapshot(std::size_t index) const;

private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
};

}  // namespace fulcrum
