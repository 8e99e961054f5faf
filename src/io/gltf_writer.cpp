// Animated glTF 2.0 binary writer (see gltf_writer.hpp). tinygltf builds the
// JSON and the GLB container (Debian's libtinygltf, linked as a shared
// library, so its stb/json configuration is the package's concern).
#include "io/gltf_writer.hpp"

#include <tiny_gltf.h>

#include <array>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

namespace fulcrum::io {

namespace {

// glTF's vertex and animation data are float32 (its only float component
// type): Real is narrowed here, once per value, in the double build too.
float f32(Real x) { return static_cast<float>(x); }

// The shortest rotation taking unit vector a onto unit vector b.
Quat rotationBetween(const Vec3& a, const Vec3& b) {
    const Real c = dot(a, b);
    if (c < Real(-0.999999)) {  // opposite: half a turn about any axis across a
        const Vec3 across = std::fabs(a.x) < Real(0.9) ? cross(a, Vec3{1, 0, 0}) : cross(a, Vec3{0, 1, 0});
        return Quat::fromAxisAngle(across, Real(3.14159265358979323846));
    }
    const Vec3 axis = cross(a, b);
    return normalize(Quat{1 + c, axis.x, axis.y, axis.z});
}

class GlbBuilder {
public:
    explicit GlbBuilder(const Recording& rec) : rec_(rec) {
        model_.asset.version = "2.0";
        model_.asset.generator = "Fulcrum physics engine";
        model_.buffers.emplace_back();
        model_.scenes.emplace_back();
        model_.scenes[0].name = rec.title;
        model_.defaultScene = 0;
    }

    tinygltf::Model build() {
        const auto meshes = tessellateBodies(rec_);
        visuals_ = tessellateVisuals(rec_);
        buildAnimationTimes();
        for (std::size_t b = 0; b < rec_.bodies.size(); ++b) addBody(b, meshes[b]);
        for (std::size_t t = 0; t < rec_.particles.size(); ++t) addParticleTrack(t);
        for (const RecordedVehicle& vehicle : rec_.vehicles) addWheels(vehicle);
        // glTF is y up: a recording with another up hangs under one root node
        // that turns its up onto y (a URDF robot's z-up world stands up in Blender).
        const Vec3 up = normalize(rec_.up);
        if (length(up - Vec3{0, 1, 0}) > Real(1e-6)) {
            tinygltf::Node root;
            root.name = "up_to_y";
            setTransform(root, Transform{Vec3::zero(), rotationBetween(up, Vec3{0, 1, 0})});
            root.children = model_.scenes[0].nodes;
            model_.scenes[0].nodes = {addNode(std::move(root))};
        }
        if (!animation_.channels.empty()) {
            animation_.name = "simulation";
            model_.animations.push_back(std::move(animation_));
        }
        return std::move(model_);
    }

private:
    // Appends raw bytes as a bufferView (4-byte aligned: every element here is 4 bytes).
    int addView(const void* data, std::size_t bytes, int target) {
        std::vector<unsigned char>& buf = model_.buffers[0].data;
        tinygltf::BufferView view;
        view.buffer = 0;
        view.byteOffset = buf.size();
        view.byteLength = bytes;
        view.target = target;
        const auto* p = static_cast<const unsigned char*>(data);
        buf.insert(buf.end(), p, p + bytes);
        model_.bufferViews.push_back(view);
        return static_cast<int>(model_.bufferViews.size() - 1);
    }

    int addAccessor(const std::vector<float>& values, int type, int components, int target, bool withBounds) {
        tinygltf::Accessor acc;
        acc.bufferView = addView(values.data(), values.size() * sizeof(float), target);
        acc.componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
        acc.type = type;
        acc.count = values.size() / static_cast<std::size_t>(components);
        if (withBounds && acc.count > 0) {
            acc.minValues.assign(static_cast<std::size_t>(components), 1e300);
            acc.maxValues.assign(static_cast<std::size_t>(components), -1e300);
            for (std::size_t i = 0; i < values.size(); ++i) {
                const std::size_t c = i % static_cast<std::size_t>(components);
                acc.minValues[c] = std::min(acc.minValues[c], static_cast<double>(values[i]));
                acc.maxValues[c] = std::max(acc.maxValues[c], static_cast<double>(values[i]));
            }
        }
        model_.accessors.push_back(std::move(acc));
        return static_cast<int>(model_.accessors.size() - 1);
    }

    void buildAnimationTimes() {
        std::vector<float> times;
        times.reserve(rec_.frameCount());
        for (double t : rec_.times) times.push_back(static_cast<float>(t - rec_.times.front()));
        timeAccessor_ = addAccessor(times, TINYGLTF_TYPE_SCALAR, 1, 0, true);  // sampler inputs need min/max
    }

    int material(const Rgb& c, bool doubleSided, float alpha = 1.0f) {
        const auto key = std::make_tuple(c.r, c.g, c.b, alpha, doubleSided);
        if (const auto it = materials_.find(key); it != materials_.end()) return it->second;
        tinygltf::Material m;
        m.name = "material_" + std::to_string(model_.materials.size());
        m.pbrMetallicRoughness.baseColorFactor = {c.r, c.g, c.b, alpha};
        if (alpha < 1) m.alphaMode = "BLEND";
        m.pbrMetallicRoughness.metallicFactor = 0.0;
        m.pbrMetallicRoughness.roughnessFactor = 0.6;
        m.doubleSided = doubleSided;
        model_.materials.push_back(std::move(m));
        const int index = static_cast<int>(model_.materials.size() - 1);
        materials_.emplace(key, index);
        return index;
    }

    // The vertex and index accessors of one render mesh.
    std::array<int, 3> addGeometry(const RenderMesh& mesh) {
        std::vector<float> positions, normals;
        positions.reserve(mesh.positions.size() * 3);
        normals.reserve(mesh.normals.size() * 3);
        for (const Vec3& p : mesh.positions) positions.insert(positions.end(), {f32(p.x), f32(p.y), f32(p.z)});
        for (const Vec3& n : mesh.normals) normals.insert(normals.end(), {f32(n.x), f32(n.y), f32(n.z)});
        const int pos = addAccessor(positions, TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER, true);
        const int nrm = addAccessor(normals, TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER, false);
        tinygltf::Accessor idx;
        idx.bufferView = addView(mesh.indices.data(), mesh.indices.size() * sizeof(std::uint32_t),
                                 TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        idx.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        idx.type = TINYGLTF_TYPE_SCALAR;
        idx.count = mesh.indices.size();
        model_.accessors.push_back(std::move(idx));
        return {pos, nrm, static_cast<int>(model_.accessors.size() - 1)};
    }

    int addMesh(const std::string& name, const std::array<int, 3>& geometry, int materialIndex) {
        tinygltf::Primitive prim;
        prim.attributes["POSITION"] = geometry[0];
        prim.attributes["NORMAL"] = geometry[1];
        prim.indices = geometry[2];
        prim.material = materialIndex;
        prim.mode = TINYGLTF_MODE_TRIANGLES;
        tinygltf::Mesh mesh;
        mesh.name = name;
        mesh.primitives.push_back(std::move(prim));
        model_.meshes.push_back(std::move(mesh));
        return static_cast<int>(model_.meshes.size() - 1);
    }

    int addNode(tinygltf::Node node) {
        model_.nodes.push_back(std::move(node));
        return static_cast<int>(model_.nodes.size() - 1);
    }

    static void setTransform(tinygltf::Node& node, const Transform& t) {
        if (t.p != Vec3::zero()) node.translation = {t.p.x, t.p.y, t.p.z};
        if (t.q != Quat::identity()) node.rotation = {t.q.x, t.q.y, t.q.z, t.q.w};  // glTF order: x, y, z, w
    }

    void addChannel(int node, const char* path, int output, const char* interpolation) {
        tinygltf::AnimationSampler sampler;
        sampler.input = timeAccessor_;
        sampler.output = output;
        sampler.interpolation = interpolation;
        animation_.samplers.push_back(std::move(sampler));
        tinygltf::AnimationChannel channel;
        channel.sampler = static_cast<int>(animation_.samplers.size() - 1);
        channel.target_node = node;
        channel.target_path = path;
        animation_.channels.push_back(std::move(channel));
    }

    void addBody(std::size_t b, const std::vector<RenderPart>& parts) {
        const RecordedBody& body = rec_.bodies[b];
        const std::size_t frames = rec_.frameCount();
        bool moves = body.type != BodyType::Static;
        bool sleeps = false;
        for (std::size_t f = 0; f < frames; ++f) {
            moves = moves || rec_.transform(f, b) != rec_.transform(0, b);
            sleeps = sleeps || (body.type == BodyType::Dynamic && !rec_.isAwake(f, b));
        }

        tinygltf::Node node;
        node.name = body.name.empty() ? "body_" + std::to_string(b) : body.name;
        setTransform(node, rec_.transform(0, b));
        tinygltf::Value::Object extras;
        extras["fulcrum_type"] = tinygltf::Value(std::string(toString(body.type)));
        extras["fulcrum_shape"] = tinygltf::Value(std::string(toString(body.shape.type())));
        node.extras = tinygltf::Value(extras);

        const Rgb awakeColor = bodyColor(body.type, b, false);
        const Rgb sleepColor = bodyColor(body.type, b, true);
        std::vector<int> children;
        std::vector<int> awakeNodes, sleepNodes;
        if (!body.visuals.empty()) {
            // Drawn as its visuals instead of its collision shape, in their own
            // colours (not darkened while asleep).
            addVisuals(b, node.name, awakeColor, children);
            sleeps = false;
        }
        const bool direct = parts.size() == 1 && parts[0].local == Transform::identity() && !sleeps;
        for (std::size_t p = 0; p < (body.visuals.empty() ? parts.size() : 0); ++p) {
            const RenderPart& part = parts[p];
            const auto geometry = addGeometry(part.mesh);
            const std::string meshName = node.name + (parts.size() > 1 ? "_part" + std::to_string(p) : "");
            const int awakeMesh = addMesh(meshName, geometry, material(awakeColor, part.mesh.doubleSided));
            if (direct) {
                node.mesh = awakeMesh;
                break;
            }
            tinygltf::Node child;
            child.name = meshName;
            child.mesh = awakeMesh;
            setTransform(child, part.local);
            const int childIndex = addNode(child);
            children.push_back(childIndex);
            awakeNodes.push_back(childIndex);
            if (sleeps) {
                child.name = meshName + "_asleep";
                child.mesh = addMesh(child.name, geometry, material(sleepColor, part.mesh.doubleSided));
                const int sleepIndex = addNode(child);
                children.push_back(sleepIndex);
                sleepNodes.push_back(sleepIndex);
            }
        }
        node.children = children;
        const int nodeIndex = addNode(std::move(node));
        model_.scenes[0].nodes.push_back(nodeIndex);
        bodyNodes_.push_back(nodeIndex);

        if (moves) {
            std::vector<float> translation, rotation;
            translation.reserve(frames * 3);
            rotation.reserve(frames * 4);
            Quat previous = rec_.transform(0, b).q;
            for (std::size_t f = 0; f < frames; ++f) {
                const Transform& t = rec_.transform(f, b);
                // q and -q are the same rotation; keep consecutive keys in one
                // hemisphere so interpolation (Blender's is per component) takes the short way.
                Quat q = t.q;
                if (dot(q, previous) < 0) q = -q;
                previous = q;
                translation.insert(translation.end(), {f32(t.p.x), f32(t.p.y), f32(t.p.z)});
                rotation.insert(rotation.end(), {f32(q.x), f32(q.y), f32(q.z), f32(q.w)});
            }
            addChannel(nodeIndex, "translation", addAccessor(translation, TINYGLTF_TYPE_VEC3, 3, 0, false), "LINEAR");
            addChannel(nodeIndex, "rotation", addAccessor(rotation, TINYGLTF_TYPE_VEC4, 4, 0, false), "LINEAR");
        }
        if (sleeps) {
            // Visibility as scale 1 or 0, switched with STEP keys (glTF animates only TRS and weights).
            std::vector<float> awakeScale, sleepScale;
            for (std::size_t f = 0; f < frames; ++f) {
                const float a = rec_.isAwake(f, b) ? 1.0f : 0.0f;
                awakeScale.insert(awakeScale.end(), {a, a, a});
                sleepScale.insert(sleepScale.end(), {1 - a, 1 - a, 1 - a});
            }
            const int awakeOut = addAccessor(awakeScale, TINYGLTF_TYPE_VEC3, 3, 0, false);
            const int sleepOut = addAccessor(sleepScale, TINYGLTF_TYPE_VEC3, 3, 0, false);
            for (int n : awakeNodes) addChannel(n, "scale", awakeOut, "STEP");
            for (int n : sleepNodes) addChannel(n, "scale", sleepOut, "STEP");
            // The first frame's visibility also as the rest pose, for viewers that ignore animations.
            const double a0 = rec_.isAwake(0, b) ? 1.0 : 0.0;
            for (int n : awakeNodes) model_.nodes[static_cast<std::size_t>(n)].scale = {a0, a0, a0};
            for (int n : sleepNodes) model_.nodes[static_cast<std::size_t>(n)].scale = {1 - a0, 1 - a0, 1 - a0};
        }
    }

    // A body's visuals, one child node each; a visual mesh's accessors are
    // stored once however many visuals show it.
    void addVisuals(std::size_t b, const std::string& bodyName, const Rgb& bodyRgb, std::vector<int>& children) {
        const RecordedBody& body = rec_.bodies[b];
        for (std::size_t k = 0; k < body.visuals.size(); ++k) {
            const BodyVisual& v = body.visuals[k];
            const std::size_t geometry = visuals_.meshOf[b][k];
            const RenderMesh& mesh = visuals_.meshes[geometry];
            auto accessors = visualAccessors_.find(geometry);
            if (accessors == visualAccessors_.end()) accessors = visualAccessors_.emplace(geometry, addGeometry(mesh)).first;
            const Rgb rgb = v.hasColor ? Rgb{v.color[0], v.color[1], v.color[2]} : bodyRgb;
            const int mat = material(rgb, mesh.doubleSided, v.hasColor ? v.color[3] : 1.0f);
            const std::string name = bodyName + "_visual" + std::to_string(k);
            auto meshIndex = visualMeshes_.find({geometry, mat});
            if (meshIndex == visualMeshes_.end()) {
                meshIndex = visualMeshes_.emplace(std::make_pair(geometry, mat), addMesh(name, accessors->second, mat)).first;
            }
            tinygltf::Node child;
            child.name = name;
            child.mesh = meshIndex->second;
            setTransform(child, v.local);
            if (v.geometry == BodyVisual::Geometry::Mesh && v.scale != Vec3{1, 1, 1}) child.scale = {v.scale.x, v.scale.y, v.scale.z};
            children.push_back(addNode(std::move(child)));
        }
    }

    // A rope (LINES) or cloth (TRIANGLES, double-sided) as one mesh whose base
    // positions are the first frame; frame f > 0 is morph target f - 1 holding
    // the displacement from the base, and the `weights` channel keys frame f
    // with target f - 1 at weight 1 and all others 0, so LINEAR interpolation
    // blends exactly the two neighbouring frames. Blender imports the targets
    // as shape keys driven by the action. Cost: F x N x 12 bytes of targets and
    // F x (F - 1) x 4 bytes of weights for F frames and N particles.
    void addParticleTrack(std::size_t t) {
        const ParticleTrack& track = rec_.particles[t];
        const std::size_t n = track.particleCount;
        const std::size_t frames = rec_.frameCount();
        if (n == 0) return;
        const std::string name = track.name.empty() ? (track.triangles ? "cloth_" : "rope_") + std::to_string(t) : track.name;

        std::vector<float> base;
        base.reserve(n * 3);
        for (std::size_t i = 0; i < n; ++i) base.insert(base.end(), {f32(track.positions[i].x), f32(track.positions[i].y), f32(track.positions[i].z)});
        tinygltf::Primitive prim;
        prim.attributes["POSITION"] = addAccessor(base, TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER, true);
        tinygltf::Accessor idx;
        idx.bufferView = addView(track.indices.data(), track.indices.size() * sizeof(std::uint32_t), TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);
        idx.componentType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
        idx.type = TINYGLTF_TYPE_SCALAR;
        idx.count = track.indices.size();
        model_.accessors.push_back(std::move(idx));
        prim.indices = static_cast<int>(model_.accessors.size() - 1);
        prim.mode = track.triangles ? TINYGLTF_MODE_TRIANGLES : TINYGLTF_MODE_LINE;
        const Rgb color = track.triangles ? Rgb{0.85f, 0.55f, 0.25f} : Rgb{0.9f, 0.85f, 0.6f};
        prim.material = material(color, true);
        std::vector<float> delta(n * 3);
        for (std::size_t f = 1; f < frames; ++f) {
            for (std::size_t i = 0; i < n; ++i) {
                const Vec3 d = track.positions[f * n + i] - track.positions[i];
                delta[3 * i] = f32(d.x);
                delta[3 * i + 1] = f32(d.y);
                delta[3 * i + 2] = f32(d.z);
            }
            // Morph target POSITION accessors must carry min/max (glTF 2.0, 3.7.2.2).
            prim.targets.push_back({{"POSITION", addAccessor(delta, TINYGLTF_TYPE_VEC3, 3, TINYGLTF_TARGET_ARRAY_BUFFER, true)}});
        }
        tinygltf::Mesh mesh;
        mesh.name = name;
        const std::size_t targets = frames - 1;
        mesh.weights.assign(targets, 0.0);
        mesh.primitives.push_back(std::move(prim));
        model_.meshes.push_back(std::move(mesh));

        tinygltf::Node node;
        node.name = name;
        node.mesh = static_cast<int>(model_.meshes.size() - 1);
        tinygltf::Value::Object extras;
        extras["fulcrum_type"] = tinygltf::Value(std::string(track.triangles ? "cloth" : "rope"));
        extras["fulcrum_particles"] = tinygltf::Value(static_cast<int>(n));
        node.extras = tinygltf::Value(extras);
        const int nodeIndex = addNode(std::move(node));
        model_.scenes[0].nodes.push_back(nodeIndex);

        if (targets == 0) return;
        std::vector<float> weights(frames * targets, 0.0f);
        for (std::size_t f = 1; f < frames; ++f) weights[f * targets + (f - 1)] = 1.0f;
        addChannel(nodeIndex, "weights", addAccessor(weights, TINYGLTF_TYPE_SCALAR, 1, 0, false), "LINEAR");
    }

    // A vehicle's wheels: a node per wheel, a child of the chassis's node,
    // animated (translation: the mounting point less the suspension length
    // along the chassis's +y; rotation: the steering angle about +y, then the
    // spin about the axle, x), with a child carrying the tyre, a cylinder
    // turned from y onto the axle.
    void addWheels(const RecordedVehicle& vehicle) {
        const std::size_t frames = rec_.frameCount(), n = vehicle.wheels.size();
        const Quat axleFromY = Quat::fromAxisAngle({0, 0, 1}, Real(1.5707963267948966));
        for (std::size_t i = 0; i < n; ++i) {
            const RecordedWheel& wheel = vehicle.wheels[i];
            const std::string name = vehicle.name + "_wheel" + std::to_string(i);
            tinygltf::Node tyre;
            tyre.name = name + "_tyre";
            const std::vector<RenderPart> parts = tessellate(Shape::cylinder(wheel.radius, wheel.width / 2), TessellationOptions{});
            tyre.mesh = addMesh(tyre.name, addGeometry(parts.front().mesh), material(Rgb{0.08f, 0.08f, 0.09f}, false));
            setTransform(tyre, Transform{Vec3::zero(), axleFromY});
            tinygltf::Node node;
            node.name = name;
            node.children = {addNode(std::move(tyre))};
            std::vector<float> translation, rotation;
            translation.reserve(frames * 3);
            rotation.reserve(frames * 4);
            Quat previous = Quat::identity();
            for (std::size_t f = 0; f < frames; ++f) {
                const RecordedWheelPose& pose = vehicle.poses[f * n + i];
                Quat q = Quat::fromAxisAngle({0, 1, 0}, pose.steerAngle) * Quat::fromAxisAngle({1, 0, 0}, pose.spin);
                if (dot(q, previous) < 0) q = -q;  // one hemisphere, as for the bodies
                previous = q;
                const Vec3 p = wheel.mount - Vec3{0, pose.suspensionLength, 0};
                translation.insert(translation.end(), {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
                rotation.insert(rotation.end(), {static_cast<float>(q.x), static_cast<float>(q.y), static_cast<float>(q.z),
                                                 static_cast<float>(q.w)});
            }
            setTransform(node, Transform{wheel.mount - Vec3{0, vehicle.poses[i].suspensionLength, 0}, Quat::identity()});
            const int nodeIndex = addNode(std::move(node));
            model_.nodes[static_cast<std::size_t>(bodyNodes_[static_cast<std::size_t>(vehicle.chassis)])].children.push_back(nodeIndex);
            addChannel(nodeIndex, "translation", addAccessor(translation, TINYGLTF_TYPE_VEC3, 3, 0, false), "LINEAR");
            addChannel(nodeIndex, "rotation", addAccessor(rotation, TINYGLTF_TYPE_VEC4, 4, 0, false), "LINEAR");
        }
    }

    const Recording& rec_;
    std::vector<int> bodyNodes_;  // each body's root node
    tinygltf::Model model_;
    tinygltf::Animation animation_;
    int timeAccessor_ = -1;
    std::map<std::tuple<float, float, float, float, bool>, int> materials_;
    VisualGeometry visuals_;
    std::map<std::size_t, std::array<int, 3>> visualAccessors_;              // per visual mesh: stored once
    std::map<std::pair<std::size_t, int>, int> visualMeshes_;                 // per (visual mesh, material)
};

}  // namespace

std::vector<std::uint8_t> encodeGlb(const Recording& recording) {
    recording.validate();
    if (recording.frameCount() == 0) throw Error("recording: no frames captured, nothing to write");
    tinygltf::Model model = GlbBuilder(recording).build();
    std::ostringstream out(std::ios::binary);
    tinygltf::TinyGLTF writer;
    if (!writer.WriteGltfSceneToStream(&model, out, false, true)) throw Error("recording: tinygltf failed to encode the model");
    const std::string bytes = out.str();
    return {bytes.begin(), bytes.end()};
}

void writeGlb(const Recording& recording, const std::filesystem::path& path) {
    const std::vector<std::uint8_t> bytes = encodeGlb(recording);
    std::ofstream file(path, std::ios::binary | std::ios::trunc);
    if (!file) throw Error("recording '" + path.string() + "': cannot open for writing");
    file.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!file) throw Error("recording '" + path.string() + "': write failed");
}

}  // namespace fulcrum::io
