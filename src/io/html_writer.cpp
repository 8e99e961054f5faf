// HTML replay page writer (see html_writer.hpp).
#include "io/html_writer.hpp"

#include <bit>
#include <cstring>
#include <fstream>
#include <type_traits>
#include <nlohmann/json.hpp>
#include <zlib.h>

#include "io/markup_escape.hpp"

namespace fulcrum::io {

namespace {

static_assert(std::endian::native == std::endian::little, "the page decodes base64 arrays as little-endian");

using json = nlohmann::json;

std::string base64(const void* data, std::size_t bytes) {
    static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    const auto* p = static_cast<const unsigned char*>(data);
    std::string out;
    out.reserve((bytes + 2) / 3 * 4);
    std::size_t i = 0;
    for (; i + 2 < bytes; i += 3) {
        const std::uint32_t v = (std::uint32_t{p[i]} << 16) | (std::uint32_t{p[i + 1]} << 8) | p[i + 2];
        out += kAlphabet[(v >> 18) & 63];
        out += kAlphabet[(v >> 12) & 63];
        out += kAlphabet[(v >> 6) & 63];
        out += kAlphabet[v & 63];
    }
    if (i < bytes) {
        const bool two = i + 1 < bytes;
        const std::uint32_t v = (std::uint32_t{p[i]} << 16) | (two ? std::uint32_t{p[i + 1]} << 8 : 0u);
        out += kAlphabet[(v >> 18) & 63];
        out += kAlphabet[(v >> 12) & 63];
        out += two ? kAlphabet[(v >> 6) & 63] : '=';
        out += '=';
    }
    return out;
}

// The page's geometry and motion arrays are float32 (what the viewer draws
// with), so Real is narrowed here, once per value, in the double build too
// (docs/double-precision.md).
float f32(Real x) { return static_cast<float>(x); }

// The element type as the page names it (a typed array's).
template <typename T>
constexpr const char* typeName() {
    if constexpr (std::is_same_v<T, float>) return "float32";
    else if constexpr (std::is_same_v<T, double>) return "float64";
    else if constexpr (std::is_same_v<T, std::uint32_t>) return "uint32";
    else {
        static_assert(std::is_same_v<T, std::uint8_t>, "no typed array for this element type");
        return "uint8";
    }
}

// The zlib stream (RFC 1950) of `size` bytes: what the browser's
// DecompressionStream("deflate") inflates.
std::vector<unsigned char> deflated(const unsigned char* data, std::size_t size) {
    uLongf deflatedSize = compressBound(static_cast<uLong>(size));
    std::vector<unsigned char> out(deflatedSize);
    if (compress2(out.data(), &deflatedSize, data, static_cast<uLong>(size), Z_BEST_COMPRESSION) != Z_OK) {
        throw Error("recording: zlib could not compress " + std::to_string(size) + " bytes");
    }
    out.resize(deflatedSize);
    return out;
}

// A binary array as the page embeds it (docs/recording.md, "The embedded
// data"): {"type", "length", "xor", "deflate"}. Lossless: every byte comes back.
// Frame-major arrays XOR each element with the one `xorStride` elements before
// (the same body or particle a frame earlier), so whatever did not change (a
// sleeping body, a static one, a settled cloth) becomes zero bytes and noise
// sits only in the low mantissa bytes; the bytes are then split into planes
// (every element's byte 0, then every byte 1, ...) so the sign/exponent planes
// are long runs, and zlib deflates the result. The browser inflates with its
// DecompressionStream("deflate").
template <typename T>
json packed(const std::vector<T>& values, std::size_t xorStride = 0) {
    constexpr std::size_t size = sizeof(T);
    const std::size_t n = values.size();
    std::vector<unsigned char> bytes(n * size);
    if (n > 0) std::memcpy(bytes.data(), values.data(), bytes.size());
    const std::size_t distance = xorStride * size;
    if (distance > 0) {
        for (std::size_t i = bytes.size(); i-- > distance;) bytes[i] ^= bytes[i - distance];
    }
    std::vector<unsigned char> planes(bytes.size());
    for (std::size_t i = 0; i < n; ++i) {
        for (std::size_t b = 0; b < size; ++b) planes[b * n + i] = bytes[i * size + b];
    }
    const std::vector<unsigned char> zipped = deflated(planes.data(), planes.size());
    return {{"type", typeName<T>()}, {"length", n}, {"xor", xorStride}, {"deflate", base64(zipped.data(), zipped.size())}};
}

json vec(const Vec3& v) { return json::array({v.x, v.y, v.z}); }

// A render mesh's arrays: "positions", "normals", "indices", "doubleSided".
json meshArrays(const RenderMesh& mesh) {
    std::vector<float> positions, normals;
    for (const Vec3& p : mesh.positions) positions.insert(positions.end(), {f32(p.x), f32(p.y), f32(p.z)});
    for (const Vec3& n : mesh.normals) normals.insert(normals.end(), {f32(n.x), f32(n.y), f32(n.z)});
    return {{"positions", packed(positions)}, {"normals", packed(normals)}, {"indices", packed(mesh.indices)},
            {"doubleSided", mesh.doubleSided}};
}

json renderParts(const std::vector<RenderPart>& parts) {
    json out = json::array();
    for (const RenderPart& part : parts) {
        const Quat& q = part.local.q;
        json p = meshArrays(part.mesh);
        p["position"] = vec(part.local.p);
        p["rotation"] = json::array({q.x, q.y, q.z, q.w});
        out.push_back(std::move(p));
    }
    return out;
}

// A body's visuals: each names its render mesh in the document's
// "visualMeshes" (a mesh file shown by several visuals is stored once).
json visualParts(const RecordedBody& body, const std::vector<std::size_t>& meshOf, const Rgb& bodyRgb) {
    json out = json::array();
    for (std::size_t k = 0; k < body.visuals.size(); ++k) {
        const BodyVisual& v = body.visuals[k];
        const Quat& q = v.local.q;
        const auto& c = v.color;
        out.push_back({{"mesh", meshOf[k]},
                       {"position", vec(v.local.p)},
                       {"rotation", json::array({q.x, q.y, q.z, q.w})},
                       {"scale", vec(v.geometry == BodyVisual::Geometry::Mesh ? v.scale : Vec3{1, 1, 1})},
                       {"color", v.hasColor ? json::array({c[0], c[1], c[2], c[3]}) : json::array({bodyRgb.r, bodyRgb.g, bodyRgb.b, 1.0f})}});
    }
    return out;
}

// Replaces every occurrence of `from` by `to`.
std::string replaceAll(std::string s, const std::string& from, const std::string& to) {
    for (std::size_t pos = s.find(from); pos != std::string::npos; pos = s.find(from, pos + to.size())) {
        s.replace(pos, from.size(), to);
    }
    return s;
}

}  // namespace

std::string recordingJson(const Recording& rec) {
    rec.validate();
    const std::size_t frames = rec.frameCount();
    const std::size_t n = rec.bodies.size();
    const auto meshes = tessellateBodies(rec);
    const VisualGeometry visuals = tessellateVisuals(rec);
    const AABB scene = sceneBounds(rec);

    json doc;
    doc["format"] = "fulcrum-recording";
    doc["version"] = 2;
    doc["title"] = rec.title;
    doc["up"] = vec(rec.up);
    doc["frames"] = frames;
    // The camera frames the first frame (what the run starts from); "scene" spans every frame.
    const AABB start = sceneBounds(rec, 0, 1);
    doc["scene"] = {{"center", vec(scene.center())}, {"radius", length(scene.halfExtents())}};
    doc["start"] = {{"center", vec(start.center())}, {"radius", length(start.halfExtents())}};

    json bodies = json::array();
    for (std::size_t b = 0; b < n; ++b) {
        const RecordedBody& body = rec.bodies[b];
        const Rgb c = bodyColor(body.type, b, false), s = bodyColor(body.type, b, true);
        bodies.push_back({{"name", body.name},
                          {"type", toString(body.type)},
                          {"shape", toString(body.shape.type())},
                          {"mass", body.mass},
                          {"color", json::array({c.r, c.g, c.b})},
                          {"sleepColor", json::array({s.r, s.g, s.b})},
                          {"parts", renderParts(meshes[b])},
                          {"visuals", visualParts(body, visuals.meshOf[b], c)}});
    }
    doc["bodies"] = std::move(bodies);
    json visualMeshes = json::array();
    for (const RenderMesh& mesh : visuals.meshes) visualMeshes.push_back(meshArrays(mesh));
    doc["visualMeshes"] = std::move(visualMeshes);

    json joints = json::array();
    for (const RecordedJoint& j : rec.joints) {
        joints.push_back({{"name", j.name},
                          {"type", toString(j.type)},
                          {"bodyA", j.bodyA},
                          {"bodyB", j.bodyB},
                          {"anchorA", vec(j.localAnchorA)},
                          {"anchorB", vec(j.localAnchorB)}});
    }
    doc["joints"] = std::move(joints);

    // Ropes and cloths: topology, and positions float32 [F][particles][3].
    json particles = json::array();
    for (const ParticleTrack& track : rec.particles) {
        std::vector<float> positions;
        positions.reserve(track.positions.size() * 3);
        for (const Vec3& x : track.positions) positions.insert(positions.end(), {f32(x.x), f32(x.y), f32(x.z)});
        particles.push_back({{"name", track.name},
                             {"kind", track.triangles ? "cloth" : "rope"},
                             {"count", track.particleCount},
                             {"radius", track.radius},
                             {"indices", packed(track.indices)},
                             {"positions", packed(positions, track.particleCount * 3)}});
    }
    doc["particles"] = std::move(particles);

    // Vehicles' wheels: geometry, and poses float32 [F][wheels][3] (suspension
    // length, steering angle, spin); characters: their capsule bodies.
    json vehicles = json::array();
    for (const RecordedVehicle& vehicle : rec.vehicles) {
        json wheels = json::array();
        for (const RecordedWheel& w : vehicle.wheels) {
            wheels.push_back({{"mount", vec(w.mount)}, {"radius", w.radius}, {"width", w.width}, {"steering", w.steering},
                              {"driven", w.driven}});
        }
        std::vector<float> poses;
        poses.reserve(vehicle.poses.size() * 3);
        for (const RecordedWheelPose& p : vehicle.poses) {
            poses.insert(poses.end(), {static_cast<float>(p.suspensionLength), static_cast<float>(p.steerAngle), static_cast<float>(p.spin)});
        }
        vehicles.push_back({{"name", vehicle.name},
                            {"chassis", vehicle.chassis},
                            {"wheels", std::move(wheels)},
                            {"poses", packed(poses, vehicle.wheels.size() * 3)}});
    }
    doc["vehicles"] = std::move(vehicles);
    json characters = json::array();
    for (const RecordedCharacter& c : rec.characters) characters.push_back({{"name", c.name}, {"body", c.body}});
    doc["characters"] = std::move(characters);

    std::vector<float> transforms;
    transforms.reserve(rec.transforms.size() * 7);
    for (const Transform& t : rec.transforms) transforms.insert(transforms.end(), {f32(t.p.x), f32(t.p.y), f32(t.p.z), f32(t.q.x), f32(t.q.y), f32(t.q.z), f32(t.q.w)});
    std::vector<float> bounds;
    bounds.reserve(rec.bounds.size() * 6);
    for (const AABB& box : rec.bounds) bounds.insert(bounds.end(), {f32(box.min.x), f32(box.min.y), f32(box.min.z), f32(box.max.x), f32(box.max.y), f32(box.max.z)});
    std::vector<float> contacts;
    contacts.reserve(rec.contactPoints.size() * 7);
    for (const RecordedContactPoint& c : rec.contactPoints) {
        contacts.insert(contacts.end(), {f32(c.point.x), f32(c.point.y), f32(c.point.z), f32(c.normal.x), f32(c.normal.y), f32(c.normal.z), f32(c.depth)});
    }
    std::vector<std::uint32_t> offsets = rec.contactOffsets;
    if (offsets.empty()) offsets.assign(frames + 1, 0);
    std::vector<double> energy;
    energy.reserve(frames * 3);
    for (const EnergyReport& e : rec.energy) energy.insert(energy.end(), {e.kinetic, e.potential, e.total});
    std::vector<float> momentum;
    for (const Vec3& p : rec.linearMomentum) momentum.insert(momentum.end(), {f32(p.x), f32(p.y), f32(p.z)});

    doc["times"] = packed(rec.times, 1);
    doc["transforms"] = packed(transforms, n * 7);
    doc["awake"] = packed(rec.awake, n);
    doc["bounds"] = packed(bounds, n * 6);
    doc["contactOffsets"] = packed(offsets, 1);
    doc["contacts"] = packed(contacts);
    doc["jointErrors"] = packed(rec.jointErrors, rec.joints.size());
    doc["energy"] = packed(energy, 3);
    doc["momentum"] = packed(momentum, 3);
    return doc.dump(-1, ' ', false, json::error_handler_t::replace);
}

std::string renderHtml(const Recording& recording) {
    if (recording.frameCount() == 0) throw Error("recording: no frames captured, nothing to write");
    // Inside <script> elements the HTML parser only looks for "</script" and
    // "<!--": no '<' may reach it from the data. JSON strings may spell it
    // \u003c; base64 has none.
    const std::string data = replaceAll(recordingJson(recording), "<", "\\u003c");
    // The viewer bundle deflated (a quarter of its size), inflated and run by
    // the template's loader script; the same for every page, so made once.
    static const std::string script = [] {
        const std::string bundle = detail::viewerScript();
        const auto zipped = deflated(reinterpret_cast<const unsigned char*>(bundle.data()), bundle.size());
        return base64(zipped.data(), zipped.size());
    }();
    std::string page = detail::viewerTemplate();
    page = replaceAll(page, "{{FULCRUM_TITLE}}", fulcrum::detail::escapeMarkup(recording.title));
    // Data and script last, so nothing inside them is mistaken for a placeholder.
    const std::size_t dataAt = page.find("<!--FULCRUM_DATA-->");
    const std::size_t scriptAt = page.find("<!--FULCRUM_SCRIPT-->");
    if (dataAt == std::string::npos || scriptAt == std::string::npos || scriptAt < dataAt) {
        throw Error("recording: the embedded page template lacks its data or script placeholder");
    }
    std::string out;
    out.reserve(page.size() + data.size() + script.size());
    out.append(page, 0, dataAt);
    out += data;
    out.append(page, dataAt + 19, scriptAt - dataAt - 19);
    out += script;
    out.append(page, scriptAt + 21, std::string::npos);
    return out;
}

void writeHtml(const Recording& recording, const std::filesystem::path& path) {
    const std::string page = renderHtml(recording);
    std::ofstream file(path, std::ios::binary | std::ios::trunc);
    if (!file) throw Error("recording '" + path.string() + "': cannot open for writing");
    file.write(page.data(), static_cast<std::streamsize>(page.size()));
    if (!file) throw Error("recording '" + path.string() + "': write failed");
}

}  // namespace fulcrum::io
