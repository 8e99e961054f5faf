#pragma once
// Recordings of a run, for replay outside the engine: an animated glTF 2.0
// binary or a self-contained HTML replay page. See docs/recording.md. Part of
// the library fulcrum::io (link fulcrum::io to use it).
//
// The Recording is plain data, independent of the World: what was simulated
// (bodies with their shapes, joints with their body-local anchors) and, per
// captured frame, the time, every body's transform, awake flag and world AABB,
// the contact points, the joint errors and the energy. The writers read only a
// Recording, so they are tested without a World and a recording could be
// produced by another tool.
//
// The Recorder fills a Recording from a World through its public API only.
//
// Vehicles are recorded as their wheels (mounting point, radius, width) and,
// per frame, each wheel's suspension length, steering angle and spin, which
// the replay page draws on the chassis body; characters by the name and body
// index of their capsule.
//
// Particle systems (ropes, cloth) are recorded as ParticleTrack values: a
// fixed topology (line segments for ropes, triangles for cloth) and one
// position per particle per frame. In glTF they become a mesh with one morph
// target per frame and a weights animation (one-hot keyframes, so LINEAR
// interpolation blends neighbouring frames); in the HTML page, a
// BufferGeometry whose positions are rewritten each frame.
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "fulcrum/vehicle.hpp"
#include "fulcrum/visual.hpp"
#include "fulcrum/world.hpp"

namespace fulcrum::io {

struct RecordOptions {
    // Seconds of simulated time between captured frames; 0 captures at every
    // call of Recorder::capture (typically once per step).
    double captureInterval = 0;
    bool contacts = true;    // record contact points, normals and depths
    bool bounds = true;      // record every body's world AABB per frame
    std::string title = "Fulcrum recording";
};

struct RecordedBody {
    std::string name;
    BodyType type = BodyType::Dynamic;
    Shape shape;
    Real mass = 0;           // kg; 0 for static and kinematic bodies (World::mass)
    // How it is drawn (a URDF link's visuals; Recorder::setVisuals): empty,
    // its collision shape. The writers draw these instead of the shape (the
    // replay page can show the shape as well); a mesh shared by several
    // visuals is stored once.
    std::vector<BodyVisual> visuals{};
};

// A joint as drawn: a segment between its two anchors, stored body-local so
// the viewer places them from the recorded body transforms.
struct RecordedJoint {
    std::string name;
    JointType type = JointType::Ball;
    int bodyA = -1;          // index into Recording::bodies; -1 is the static world
    int bodyB = -1;
    Vec3 localAnchorA;       // in body A's frame (world space when bodyA is -1)
    Vec3 localAnchorB;       // in body B's frame
};

struct RecordedContactPoint {
    Vec3 point;              // world space
    Vec3 normal;             // unit, from body A to body B
    Real depth = 0;          // positive when overlapping
};

// A rope or cloth (see the header comment).
struct ParticleTrack {
    std::string name;
    bool triangles = false;                  // false: line segments (rope); true: triangles (cloth)
    std::vector<std::uint32_t> indices;      // pairs or triples into the particles
    std::size_t particleCount = 0;
    Real radius = 0;                         // m: the particles' collision radius (for display)
    std::vector<Vec3> positions;             // frame-major: [frame * particleCount + particle]
};

// A vehicle's wheel as drawn (docs/vehicles.md): mounted on the chassis at
// `mount` (chassis frame, the suspension's top), its centre `suspension
// length` below it along the chassis's up (local +y), turned about that axis
// by the steering angle and spun about its axle (local x after steering).
struct RecordedWheel {
    Vec3 mount;              // chassis frame
    Real radius = 0;         // m
    Real width = 0;          // m
    bool steering = false;
    bool driven = false;
};

// A wheel's pose in one frame.
struct RecordedWheelPose {
    Real suspensionLength = 0;  // m, mount to wheel centre
    Real steerAngle = 0;        // rad about the chassis's up, +: towards local +x (left)
    Real spin = 0;              // rad about the axle, accumulated; +: rolling forwards (+z)
};

struct RecordedVehicle {
    std::string name;
    int chassis = -1;                        // index into Recording::bodies
    std::vector<RecordedWheel> wheels;
    std::vector<RecordedWheelPose> poses;    // frame-major: [frame * wheels.size() + wheel]
};

// A character: its capsule is a body of the recording (drawn as any body);
// this names it for the replay page's camera choice.
struct RecordedCharacter {
    std::string name;
    int body = -1;                           // index into Recording::bodies
};

struct Recording {
    std::string title = "Fulcrum recording";
    // The world's up: the axis most against gravity (the Recorder's choice;
    // +y without gravity). The page's camera, sky and sun stand on it, and
    // the GLB turns a z-up recording to glTF's y up with a root node.
    Vec3 up{0, 1, 0};
    std::vector<RecordedBody> bodies;
    std::vector<RecordedJoint> joints;

    // Per frame. Arrays marked frame-major hold frameCount() * bodies.size()
    // (or joints.size()) entries, frame after frame.
    std::vector<double> times;                          // seconds, strictly increasing
    std::vector<Transform> transforms;                  // frame-major, of the body origin
    std::vector<std::uint8_t> awake;                    // frame-major, 1 awake, 0 asleep
    std::vector<AABB> bounds;                           // frame-major; empty when not recorded
    std::vector<std::uint32_t> contactOffsets;          // frameCount() + 1 offsets into contactPoints
    std::vector<RecordedContactPoint> contactPoints;
    std::vector<Real> jointErrors;                      // frame-major, metres
    std::vector<EnergyReport> energy;
    std::vector<Vec3> linearMomentum;

    std::vector<ParticleTrack> particles;               // ropes and cloths, in the World's creation order
    std::vector<RecordedVehicle> vehicles;              // in the World's creation order
    std::vector<RecordedCharacter> characters;          // in the World's creation order

    std::size_t frameCount() const { return times.size(); }
    const Transform& transform(std::size_t frame, std::size_t body) const {
        return transforms[frame * bodies.size() + body];
    }
    bool isAwake(std::size_t frame, std::size_t body) const { return awake[frame * bodies.size() + body] != 0; }

    // Throws fulcrum::Error naming the array whose size does not match the
    // frame count, or a non-finite or non-increasing time.
    void validate() const;
};

// Captures a World into a Recording. Construct it after the scene is built
// (joint anchors are world space at creation: they are converted to body-local
// anchors with the bodies' transforms at construction). Bodies and particle
// systems created later are not recorded; a body destroyed later keeps its
// last pose, marked asleep, and a destroyed particle system its last positions.
//
//     io::Recorder recorder(world, {.title = "pendulum"});
//     recorder.capture(world);                 // the initial state
//     for (int i = 0; i < steps; ++i) { world.step(dt); recorder.capture(world); }
//     recorder.write("run.html");              // or .glb
class Recorder {
public:
    explicit Recorder(const World& world, RecordOptions options = {});

    // Appends a frame if at least captureInterval has passed since the last
    // one (always for the first). Throws fulcrum::Error if the world's time
    // went backwards.
    void capture(const World& world);

    // How body `body` is drawn instead of its collision shape (a URDF link's
    // RobotLink::visuals), in its frame. Throws fulcrum::Error for a body
    // that is not recorded, or a visual that is not finite or lacks its mesh.
    void setVisuals(BodyId body, std::vector<BodyVisual> visuals);

    const Recording& recording() const { return recording_; }
    std::size_t frameCount() const { return recording_.frameCount(); }

    void writeGlb(const std::filesystem::path& path) const;
    void writeHtml(const std::filesystem::path& path) const;
    // By extension: .glb or .html (case-insensitive); anything else throws fulcrum::Error.
    void write(const std::filesystem::path& path) const;

private:
    RecordOptions options_;
    std::vector<BodyId> ids_;
    std::vector<JointId> jointIds_;
    std::vector<ParticleSystemId> particleIds_;
    std::vector<VehicleId> vehicleIds_;
    Recording recording_;
};

// True when `path` names a recording format the writers know (.glb, .html).
bool isRecordingPath(const std::filesystem::path& path);

}  // namespace fulcrum::io
