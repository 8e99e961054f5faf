// Recorder: fills a Recording from a World through its public API only.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <span>
#include <string>

#include "io/gltf_writer.hpp"
#include "io/html_writer.hpp"
#include "fulcrum/recording.hpp"
#include "io/recording_display.hpp"

namespace fulcrum::io {

namespace {

int indexOf(const std::vector<BodyId>& ids, BodyId id) {
    if (id.isNull()) return -1;
    const auto it = std::find(ids.begin(), ids.end(), id);
    return it == ids.end() ? -1 : static_cast<int>(it - ids.begin());
}

}  // namespace

Recorder::Recorder(const World& world, RecordOptions options) : options_(std::move(options)) {
    if (!std::isfinite(options_.captureInterval) || options_.captureInterval < 0) {
        throw Error("recorder: captureInterval must be a finite number >= 0, got " +
                    std::to_string(options_.captureInterval));
    }
    recording_.title = options_.title;
    // Up: the axis most against gravity (a URDF robot's world is z-up).
    const Vec3 g = world.settings().gravity;
    const Vec3 a{std::fabs(g.x), std::fabs(g.y), std::fabs(g.z)};
    if (a.z > a.y && a.z > a.x) recording_.up = {0, 0, g.z < 0 ? Real(1) : Real(-1)};
    else if (a.x > a.y) recording_.up = {g.x < 0 ? Real(1) : Real(-1), 0, 0};
    else if (a.y > 0 && g.y > 0) recording_.up = {0, -1, 0};
    ids_ = world.bodies();
    recording_.bodies.reserve(ids_.size());
    for (BodyId id : ids_) recording_.bodies.push_back({world.name(id), world.bodyType(id), world.shape(id), world.mass(id), {}});

    // Joint anchors are world space at creation; with the bodies' current
    // transforms they become body-local, which is exact when the recorder is
    // built before the first step (as documented).
    for (JointId jid : world.joints()) {
        const JointDef& def = world.jointDef(jid);
        RecordedJoint joint;
        joint.name = world.name(jid);
        joint.type = def.type;
        joint.bodyA = indexOf(ids_, def.bodyA);
        joint.bodyB = indexOf(ids_, def.bodyB);
        const Vec3 anchorB = def.type == JointType::Distance ? def.anchorB : def.anchor;
        joint.localAnchorA = joint.bodyA >= 0 ? inverseTransformPoint(world.transform(def.bodyA), def.anchor) : def.anchor;
        joint.localAnchorB = joint.bodyB >= 0 ? inverseTransformPoint(world.transform(def.bodyB), anchorB) : anchorB;
        recording_.joints.push_back(std::move(joint));
        jointIds_.push_back(jid);
    }
    recording_.contactOffsets.push_back(0);

    // Ropes and cloths: topology now, positions per frame.
    for (ParticleSystemId pid : world.particleSystems()) {
        ParticleTrack track;
        track.name = world.name(pid);
        track.particleCount = world.particleCount(pid);
        if (world.particleSystemType(pid) == ParticleSystemType::Cloth) {
            track.triangles = true;
            const std::array<int, 2> size = world.clothSize(pid);
            const auto index = [&](int i, int j) { return static_cast<std::uint32_t>(j * size[0] + i); };
            for (int j = 0; j + 1 < size[1]; ++j) {
                for (int i = 0; i + 1 < size[0]; ++i) {
                    // Two triangles per cell, counter-clockwise seen along u x v.
                    track.indices.insert(track.indices.end(), {index(i, j), index(i, j + 1), index(i + 1, j)});
                    track.indices.insert(track.indices.end(), {index(i + 1, j), index(i, j + 1), index(i + 1, j + 1)});
                }
            }
        } else {
            for (std::uint32_t i = 0; i + 1 < track.particleCount; ++i) track.indices.insert(track.indices.end(), {i, i + 1});
        }
        track.radius = world.particleRadius(pid);
        recording_.particles.push_back(std::move(track));
        particleIds_.push_back(pid);
    }

    // Vehicles: wheels in the chassis's frame now, their poses per frame.
    for (VehicleId vid : vehicles(world)) {
        const VehicleDef& def = vehicleDef(world, vid);
        RecordedVehicle vehicle;
        vehicle.name = def.name;
        vehicle.chassis = indexOf(ids_, def.chassis);
        if (vehicle.chassis < 0) continue;
        const Transform chassis = world.transform(def.chassis);
        for (const WheelDef& wd : def.wheels) {
            vehicle.wheels.push_back({inverseTransformPoint(chassis, wd.position), wd.radius, wd.width, wd.steering, wd.driven});
        }
        recording_.vehicles.push_back(std::move(vehicle));
        vehicleIds_.push_back(vid);
    }
    for (CharacterId cid : world.characters()) {
        const int body = indexOf(ids_, world.characterBody(cid));
        if (body >= 0) recording_.characters.push_back({world.name(cid), body});
    }
}

void Recorder::setVisuals(BodyId body, std::vector<BodyVisual> visuals) {
    const int index = indexOf(ids_, body);
    if (index < 0) throw Error("recorder: setVisuals names a body that is not recorded (created after the recorder, or null)");
    RecordedBody& recorded = recording_.bodies[static_cast<std::size_t>(index)];
    recorded.visuals = std::move(visuals);
    try {
        checkVisuals(recorded);
    } catch (const Error&) {
        recorded.visuals.clear();
        throw;
    }
}

void Recorder::capture(const World& world) {
    const double time = static_cast<double>(world.time());
    Recording& rec = recording_;
    if (!rec.times.empty()) {
        const double last = rec.times.back();
        if (time < last) {
            throw Error("recorder: world time " + std::to_string(time) + " is before the last captured frame (" +
                        std::to_string(last) + ")");
        }
        // A small tolerance so an interval equal to the step size captures every step despite rounding.
        if (time <= last || time - last < options_.captureInterval * (1 - 1e-6)) return;
    }
    rec.times.push_back(time);
    const std::size_t n = ids_.size();
    const std::size_t frame = rec.times.size() - 1;
    for (std::size_t i = 0; i < n; ++i) {
        const BodyId id = ids_[i];
        if (world.isValid(id)) {
            const Transform xf = world.transform(id);
            rec.transforms.push_back(xf);
            rec.awake.push_back(world.isAwake(id) ? 1 : 0);
            if (options_.bounds) rec.bounds.push_back(rec.bodies[i].shape.bounds(xf));
        } else {
            // Destroyed since: hold the last pose (or the identity if never seen).
            rec.transforms.push_back(frame > 0 ? rec.transforms[(frame - 1) * n + i] : Transform{});
            rec.awake.push_back(0);
            if (options_.bounds) rec.bounds.push_back(frame > 0 ? rec.bounds[(frame - 1) * n + i] : AABB{});
        }
    }
    for (JointId jid : jointIds_) rec.jointErrors.push_back(world.isValid(jid) ? world.jointError(jid) : Real(0));
    if (options_.contacts) {
        for (const ContactReport& c : world.contacts()) {
            for (const Vec3& p : c.points) rec.contactPoints.push_back({p, c.normal, c.depth});
        }
    }
    rec.contactOffsets.push_back(static_cast<std::uint32_t>(rec.contactPoints.size()));
    for (std::size_t t = 0; t < particleIds_.size(); ++t) {
        ParticleTrack& track = rec.particles[t];
        if (world.isValid(particleIds_[t])) {
            const std::span<const Vec3> x = world.particlePositions(particleIds_[t]);
            track.positions.insert(track.positions.end(), x.begin(), x.end());
        } else {
            // Destroyed since: hold the last positions (the track's size stays frame-major).
            const std::size_t count = track.particleCount;
            for (std::size_t i = 0; i < count; ++i) {
                track.positions.push_back(frame > 0 ? track.positions[(frame - 1) * count + i] : Vec3{});
            }
        }
    }
    for (std::size_t v = 0; v < vehicleIds_.size(); ++v) {
        RecordedVehicle& vehicle = rec.vehicles[v];
        const std::size_t wheels = vehicle.wheels.size();
        if (isValid(world, vehicleIds_[v])) {
            for (const WheelState& s : vehicleState(world, vehicleIds_[v]).wheels) {
                vehicle.poses.push_back({s.suspensionLength, s.steerAngle, s.rotation});
            }
        } else {
            // Destroyed since: hold the last poses (the array stays frame-major).
            for (std::size_t i = 0; i < wheels; ++i) {
                vehicle.poses.push_back(frame > 0 ? vehicle.poses[(frame - 1) * wheels + i] : RecordedWheelPose{});
            }
        }
    }
    rec.energy.push_back(world.energy());
    rec.linearMomentum.push_back(world.linearMomentum());
}

void Recorder::writeGlb(const std::filesystem::path& path) const { io::writeGlb(recording_, path); }

void Recorder::writeHtml(const std::filesystem::path& path) const { io::writeHtml(recording_, path); }

void Recorder::write(const std::filesystem::path& path) const {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    if (ext == ".glb") {
        writeGlb(path);
    } else if (ext == ".html" || ext == ".htm") {
        writeHtml(path);
    } else {
        throw Error("recording '" + path.string() + "': unknown format '" + ext +
                    "', expected .glb (animated glTF 2.0) or .html (replay page)");
    }
}

}  // namespace fulcrum::io
