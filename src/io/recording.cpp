// Recording: consistency checks shared by the writers. The Recorder, which
// reads a World, lives in recorder.cpp so that code using only the data and
// the writers does not pull in the World.
#include "io/recording_display.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <string>

namespace fulcrum::io {

namespace {

void requireSize(std::size_t actual, std::size_t expected, const char* field) {
    if (actual != expected) {
        throw Error(std::string("recording: ") + field + " holds " + std::to_string(actual) + " entries, expected " +
                    std::to_string(expected));
    }
}

std::string lowerExtension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

}  // namespace

void Recording::validate() const {
    const std::size_t frames = frameCount();
    const std::size_t n = bodies.size();
    for (std::size_t f = 0; f < frames; ++f) {
        if (!std::isfinite(times[f])) throw Error("recording: times[" + std::to_string(f) + "] is not finite");
        if (f > 0 && !(times[f] > times[f - 1])) {
            throw Error("recording: times[" + std::to_string(f) + "] = " + std::to_string(times[f]) +
                        " does not increase (previous " + std::to_string(times[f - 1]) + ")");
        }
    }
    requireSize(transforms.size(), frames * n, "transforms");
    requireSize(awake.size(), frames * n, "awake");
    if (!bounds.empty()) requireSize(bounds.size(), frames * n, "bounds");
    requireSize(jointErrors.size(), frames * joints.size(), "jointErrors");
    requireSize(energy.size(), frames, "energy");
    requireSize(linearMomentum.size(), frames, "linearMomentum");
    if (!contactOffsets.empty() || frames > 0) {
        requireSize(contactOffsets.size(), frames + 1, "contactOffsets");
        for (std::size_t f = 0; f < frames; ++f) {
            if (contactOffsets[f] > contactOffsets[f + 1]) {
                throw Error("recording: contactOffsets[" + std::to_string(f + 1) + "] decreases");
            }
        }
        requireSize(contactPoints.size(), contactOffsets.back(), "contactPoints");
    }
    for (std::size_t j = 0; j < joints.size(); ++j) {
        const RecordedJoint& joint = joints[j];
        const int count = static_cast<int>(n);
        if (joint.bodyA < -1 || joint.bodyA >= count || joint.bodyB < -1 || joint.bodyB >= count) {
            throw Error("recording: joints[" + std::to_string(j) + "] ('" + joint.name + "') refers to a body index out of range");
        }
    }
    for (const RecordedBody& body : bodies) checkVisuals(body);
    if (!isFinite(up) || !(length(up) > Real(0.5))) throw Error("recording: up must be a finite, non-zero direction");
    for (std::size_t i = 0; i < transforms.size(); ++i) {
        if (!isFinite(transforms[i].p) || !isFinite(transforms[i].q)) {
            throw Error("recording: body '" + bodies[i % n].name + "' has a non-finite transform in frame " +
                        std::to_string(i / n));
        }
    }
    for (std::size_t t = 0; t < particles.size(); ++t) {
        const ParticleTrack& track = particles[t];
        requireSize(track.positions.size(), frames * track.particleCount, "particles[].positions");
        for (std::uint32_t index : track.indices) {
            if (index >= track.particleCount) {
                throw Error("recording: particle system '" + track.name + "' indexes particle " + std::to_string(index) +
                            " of " + std::to_string(track.particleCount));
            }
        }
    }
    for (const RecordedVehicle& vehicle : vehicles) {
        if (vehicle.chassis < 0 || vehicle.chassis >= static_cast<int>(n)) {
            throw Error("recording: vehicle '" + vehicle.name + "' refers to a chassis body index out of range");
        }
        requireSize(vehicle.poses.size(), frames * vehicle.wheels.size(), "vehicles[].poses");
        for (const RecordedWheelPose& pose : vehicle.poses) {
            if (!std::isfinite(pose.suspensionLength) || !std::isfinite(pose.steerAngle) || !std::isfinite(pose.spin)) {
                throw Error("recording: vehicle '" + vehicle.name + "' has a non-finite wheel pose");
            }
        }
    }
    for (const RecordedCharacter& character : characters) {
        if (character.body < 0 || character.body >= static_cast<int>(n)) {
            throw Error("recording: character '" + character.name + "' refers to a body index out of range");
        }
    }
}

bool isRecordingPath(const std::filesystem::path& path) {
    const std::string ext = lowerExtension(path);
    return ext == ".glb" || ext == ".html" || ext == ".htm";
}

}  // namespace fulcrum::io

namespace fulcrum::io {

namespace {

bool containsPlane(const Shape& shape) {
    if (shape.type() == ShapeType::Plane) return true;
    for (const CompoundChild& c : shape.children()) {
        if (containsPlane(c.shape)) return true;
    }
    return false;
}

Rgb hsv(float h, float s, float v) {
    const float i = std::floor(h * 6), f = h * 6 - i, p = v * (1 - s), q = v * (1 - f * s), t = v * (1 - (1 - f) * s);
    switch (static_cast<int>(i) % 6) {
        case 0: return {v, t, p};
        case 1: return {q, v, p};
        case 2: return {p, v, t};
        case 3: return {p, q, v};
        case 4: return {t, p, v};
        default: return {v, p, q};
    }
}

}  // namespace

Rgb bodyColor(BodyType type, std::size_t bodyIndex, bool asleep) {
    Rgb c;
    switch (type) {
        case BodyType::Static: c = {0.42f, 0.44f, 0.47f}; break;
        case BodyType::Kinematic: c = {0.35f, 0.55f, 0.90f}; break;
        case BodyType::Dynamic: {
            // Golden-angle hue steps keep consecutive bodies far apart on the colour wheel.
            const double hue = std::fmod(0.08 + 0.618033988749895 * static_cast<double>(bodyIndex), 1.0);
            c = hsv(static_cast<float>(hue), 0.65f, 0.92f);
            break;
        }
    }
    if (asleep) {
        c.r *= 0.4f;
        c.g *= 0.4f;
        c.b *= 0.4f;
    }
    return c;
}

AABB sceneBounds(const Recording& recording, std::size_t first, std::size_t last) {
    AABB box;
    const std::size_t n = recording.bodies.size();
    last = std::min(last, recording.frameCount());
    for (std::size_t b = 0; b < n; ++b) {
        const Shape& shape = recording.bodies[b].shape;
        if (containsPlane(shape)) continue;
        for (std::size_t f = first; f < last; ++f) {
            box.grow(recording.bounds.empty() ? shape.bounds(recording.transform(f, b)) : recording.bounds[f * n + b]);
        }
    }
    for (const ParticleTrack& track : recording.particles) {
        const std::size_t end = std::min(last, track.particleCount > 0 ? track.positions.size() / track.particleCount : 0);
        for (std::size_t f = first; f < end; ++f) {
            for (std::size_t i = 0; i < track.particleCount; ++i) box.grow(track.positions[f * track.particleCount + i]);
        }
    }
    if (box.isEmpty()) box = AABB::fromCenterHalf(Vec3::zero(), Vec3::splat(1));
    return box;
}

void checkVisuals(const RecordedBody& body) {
    for (std::size_t k = 0; k < body.visuals.size(); ++k) {
        const BodyVisual& v = body.visuals[k];
        const auto fail = [&](const std::string& what) {
            throw Error("recording: body '" + body.name + "', visual " + std::to_string(k) + ": " + what);
        };
        if (!isFinite(v.local.p) || !isFinite(v.local.q)) fail("its pose is not finite");
        for (const float c : v.color) {
            if (!(c >= 0 && c <= 1)) fail("its colour components must lie in [0, 1]");
        }
        const auto positive = [](Real x) { return std::isfinite(x) && x > 0; };
        switch (v.geometry) {
            case BodyVisual::Geometry::Box:
                if (!positive(v.halfExtents.x) || !positive(v.halfExtents.y) || !positive(v.halfExtents.z)) fail("a box needs positive half extents");
                break;
            case BodyVisual::Geometry::Sphere:
                if (!positive(v.radius)) fail("a sphere needs a positive radius");
                break;
            case BodyVisual::Geometry::Cylinder:
            case BodyVisual::Geometry::Capsule:
                if (!positive(v.radius) || !(std::isfinite(v.halfHeight) && v.halfHeight >= 0)) {
                    fail("a cylinder or capsule needs a positive radius and a half height >= 0");
                }
                break;
            case BodyVisual::Geometry::Mesh:
                if (v.mesh == nullptr) fail("a mesh visual has no mesh");
                if (!isFinite(v.scale)) fail("its scale is not finite");
                for (const Vec3& p : v.mesh->vertices) {
                    if (!isFinite(p)) fail("mesh '" + v.mesh->name + "' has a non-finite vertex");
                }
                for (const auto& t : v.mesh->triangles) {
                    for (const std::uint32_t i : t) {
                        if (i >= v.mesh->vertices.size()) fail("mesh '" + v.mesh->name + "' names a vertex it does not have");
                    }
                }
                break;
        }
    }
}

namespace {

// A visual mesh flat shaded (one normal per triangle), drawn from both sides:
// meshes made for display are often open or wound either way.
RenderMesh renderVisualMesh(const VisualMesh& source) {
    RenderMesh mesh;
    mesh.doubleSided = true;
    mesh.positions.reserve(source.triangles.size() * 3);
    mesh.normals.reserve(source.triangles.size() * 3);
    mesh.indices.reserve(source.triangles.size() * 3);
    for (const auto& tri : source.triangles) {
        const Vec3 &a = source.vertices[tri[0]], &b = source.vertices[tri[1]], &c = source.vertices[tri[2]];
        const Vec3 n = cross(b - a, c - a);
        const Real len = length(n);
        const Vec3 unit = len > 0 ? n / len : Vec3{0, 0, 1};
        for (const Vec3* p : {&a, &b, &c}) {
            mesh.indices.push_back(static_cast<std::uint32_t>(mesh.positions.size()));
            mesh.positions.push_back(*p);
            mesh.normals.push_back(unit);
        }
    }
    return mesh;
}

RenderMesh renderVisualPrimitive(const BodyVisual& v) {
    switch (v.geometry) {
        case BodyVisual::Geometry::Box: return tessellateBox(v.halfExtents);
        case BodyVisual::Geometry::Sphere: return tessellateSphere(v.radius);
        case BodyVisual::Geometry::Cylinder: return tessellateCylinder(v.radius, v.halfHeight);
        case BodyVisual::Geometry::Capsule: return tessellateCapsule(v.radius, v.halfHeight);
        case BodyVisual::Geometry::Mesh: break;
    }
    return renderVisualMesh(*v.mesh);
}

}  // namespace

VisualGeometry tessellateVisuals(const Recording& recording) {
    VisualGeometry out;
    std::map<const VisualMesh*, std::size_t> seen;
    out.meshOf.resize(recording.bodies.size());
    for (std::size_t b = 0; b < recording.bodies.size(); ++b) {
        for (const BodyVisual& v : recording.bodies[b].visuals) {
            if (v.geometry == BodyVisual::Geometry::Mesh) {
                const auto [it, isNew] = seen.try_emplace(v.mesh.get(), out.meshes.size());
                if (isNew) out.meshes.push_back(renderVisualMesh(*v.mesh));
                out.meshOf[b].push_back(it->second);
            } else {
                out.meshOf[b].push_back(out.meshes.size());
                out.meshes.push_back(renderVisualPrimitive(v));
            }
        }
    }
    return out;
}

std::vector<std::vector<RenderPart>> tessellateBodies(const Recording& recording) {
    const AABB scene = sceneBounds(recording);
    const Real extent = maxComponent(scene.halfExtents());
    std::vector<std::vector<RenderPart>> meshes;
    meshes.reserve(recording.bodies.size());
    for (std::size_t b = 0; b < recording.bodies.size(); ++b) {
        TessellationOptions options;
        // A plane is shown as a quad under the scene, twice as wide as what moves on it (at least 20 m).
        options.planeHalfSize = std::max(Real(10), Real(2) * extent);
        const Transform frame0 = recording.frameCount() > 0 ? recording.transform(0, b) : Transform{};
        options.planeCenter = inverseTransformPoint(frame0, scene.center());
        meshes.push_back(tessellate(recording.bodies[b].shape, options));
    }
    return meshes;
}

}  // namespace fulcrum::io
