// `fulcrum run ROBOT.urdf [--fixed-base]`: the scene a URDF file runs in
// (run.hpp, docs/robots.md).
#include <algorithm>
#include <cctype>
#include <limits>

#include "fulcrum/urdf.hpp"
#include "io/run.hpp"

namespace fulcrum::detail {

bool isUrdfPath(const std::string& path) {
    if (path.size() < 5) return false;
    std::string ext = path.substr(path.size() - 5);
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext == ".urdf";
}

Scene urdfRunScene(const std::string& path, bool fixedBase) {
    Scene scene;
    scene.sourceName = path;
    scene.description = "URDF robot " + path;
    scene.world.gravity = {0, 0, Real(-9.81)};  // URDF is z-up
    try {
        const std::string text = readUrdfText(path);
        UrdfOptions options;
        options.fixedBase = fixedBase;
        options.collisionGroup = -1;
        // Where its colliders reach at the origin, to set it 1 mm above the ground.
        UrdfOptions quiet = options;
        quiet.warn = [](const std::string&) {};
        Real lowest = std::numeric_limits<Real>::infinity();
        for (const SceneBody& b : urdfSceneParts(text, path, quiet).bodies) {
            if (b.def.filter.mask == 0) continue;  // a link without a collider
            lowest = std::min(lowest, buildShape(b.shape).bounds({b.def.position, b.def.orientation}).min.z);
        }
        if (std::isfinite(lowest)) options.position.z = Real(0.001) - lowest;
        UrdfSceneParts parts = urdfSceneParts(text, path, options);

        SceneBody ground;
        ground.def.name = "ground";
        for (const SceneBody& b : parts.bodies) {
            if (b.def.name == ground.def.name) ground.def.name = "ground_plane";
        }
        ground.def.type = BodyType::Static;
        ground.shape.type = ShapeType::Plane;
        ground.shape.normal = {0, 0, 1};
        ground.shape.offset = 0;
        scene.bodies.push_back(std::move(ground));
        for (SceneBody& b : parts.bodies) scene.bodies.push_back(std::move(b));
        scene.joints = std::move(parts.joints);
    } catch (const OptionError&) {
        throw;
    } catch (const Error& e) {
        throw OptionError(e.what());  // already names the file (and line and element)
    }
    return scene;
}

}  // namespace fulcrum::detail
