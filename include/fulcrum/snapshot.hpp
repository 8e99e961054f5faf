#pragma once
// Snapshots: the whole state of a World as bytes, so a run can stop and resume
// later - in another process, on another day - and continue bit for bit as if
// it had never stopped (same build: the same binary, or one compiled the same
// way). tests/snapshot and tests/determinism prove it.
//
// What is saved: the settings, time and step count; every body with all its
// state (transform, velocities, the previous transform, forces applied for
// the next step, awake flag, sleep timer and island, material, filter, name,
// shape); springs; joints; particle systems (positions, previous positions,
// constraints and their multipliers, pins, attachments); the contact cache
// with its warm-start impulses; the broad phase (both trees, node for node,
// and the pending moves); the handles' slot and generation tables, so every
// BodyId, JointId, SpringId and ParticleSystemId of the saved world is valid
// in the loaded one and names the same object.
// The contact and sensor events and contact reports of the last step come
// along too. What is not saved: ForceCallbacks (code, not data: set them again
// after loading, e.g. by body name).
//
// The format (docs/snapshots.md): a 32-byte header - magic "FULCSNAP", format
// version, sizeof(Real), payload size, FNV-1a 64 checksum of the payload -
// then the payload, little-endian. A file from an unsupported version, a corrupt or a
// truncated file is rejected with a fulcrum::Error naming the file, the byte
// and the part being read ("run.snap: truncated at byte 1234 (bodies[17])").
//
// `userData` is an opaque string stored alongside (the command line keeps the
// scene's dt and step count there).
#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fulcrum/world.hpp"

namespace fulcrum {

// The format version this build writes. It also reads versions 2 and 3 (the
// fields later versions added take their defaults); older or newer versions
// are refused. 2: joint solver runtime state; 3: joint friction
// (JointDef::frictionTorque and its impulse) and the WorldDef joint solver
// settings; 4: WorldDef::maxContactPairs; 5: contact forces (the last step's
// impulses per point and manifold, the report's forces) and WorldDef::hitEventThreshold;
// 6: characters and vehicles (their definitions, inputs and state);
// 7: the six-DOF joint (JointDef::axisY and axes, its frame and drive impulses);
// 8: rounded shapes' convex radius (Shape::convexRadius).
// 9: the position drives' force limits (JointSpring::maxForce).
// 10: how each contact's pair first touched (the solver's push-out sharing).
// 11: each contact's triangle axis cache (a box or hull against a mesh).
// 12: each contact's GJK warm start (two hulls).
// 13: each contact's piece poses (recycling a box or hull piece's mesh contacts).
// 14: WorldDef::pushOutGrownOverlaps.
inline constexpr std::uint32_t kSnapshotVersion = 14;

std::vector<std::uint8_t> saveSnapshotToMemory(const World& world, std::string_view userData = {});
// Throws fulcrum::Error when the file cannot be written.
void saveSnapshot(const World& world, const std::filesystem::path& path, std::string_view userData = {});

// Throws fulcrum::Error (naming `sourceName`) for a bad, truncated or foreign snapshot.
World loadSnapshotFromMemory(std::span<const std::uint8_t> bytes, std::string* userData = nullptr,
                             std::string_view sourceName = "snapshot");
World loadSnapshot(const std::filesystem::path& path, std::string* userData = nullptr);

}  // namespace fulcrum
