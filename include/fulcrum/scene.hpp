#pragma once
// Scene files: the JSON format of docs/scene-format.md and the
// plain `Scene` description it is read into. Two layers, on purpose:
//
//  1. parseScene / loadScene read and validate JSON into a Scene: plain
//     values (WorldDef, BodyDefs, JointDefs with body *names*, ...), no World.
//     Every error is a SceneError naming the file, the path in the document
//     (`bodies[3].shape.radius`), the line and what is wrong.
//  2. buildWorld turns a Scene into a World (bodies, springs, joints, ropes
//     and cloths).
//
// sceneToJson / saveScene write a Scene back (load -> save -> load gives the
// same Scene), and captureScene records a World's current state as a Scene.
// Lives in the library fulcrum::io (the only part that depends on nlohmann-json).
#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "fulcrum/body.hpp"
#include "fulcrum/error.hpp"
#include "fulcrum/joint.hpp"
#include "fulcrum/particles.hpp"
#include "fulcrum/spring.hpp"
#include "fulcrum/vehicle.hpp"
#include "fulcrum/visual.hpp"
#include "fulcrum/world.hpp"

namespace fulcrum {

// A problem in a scene file. what() is one line:
//   "scenes/x.json:12: bodies[3].mass: mass must be positive for a dynamic body, got -1"
// (line:column for malformed JSON; no line when it is unknown, no path for
// problems of the file itself).
class SceneError : public Error {
public:
    SceneError(std::string file, std::string path, int line, int column, std::string reason);

    const std::string& file() const { return file_; }
    const std::string& path() const { return path_; }      // "bodies[3].shape.radius"; empty for the file
    int line() const { return line_; }                      // 1-based; 0 when unknown
    int column() const { return column_; }                  // 1-based; 0 when unknown
    const std::string& reason() const { return reason_; }

private:
    std::string file_, path_;
    int line_ = 0, column_ = 0;
    std::string reason_;
};

// Where a scene element came from, so errors found later (by buildWorld) still
// name the path and line. Not part of a Scene's value: operator== ignores it.
struct SceneLocation {
    std::string path;
    int line = 0;
    int column = 0;
    bool operator==(const SceneLocation&) const { return true; }
};

// A shape as written in the file. Kept as a description (not a fulcrum::Shape)
// so parsing never needs the hull, mesh and heightfield builders; buildShape makes the Shape.
struct ShapeDesc {
    ShapeType type = ShapeType::Sphere;
    Real radius = 1;                                  // sphere, capsule, cylinder
    Real halfHeight = 0;                              // capsule, cylinder
    Vec3 halfExtents{Real(0.5), Real(0.5), Real(0.5)};  // box
    Vec3 normal{0, 1, 0};                             // plane
    Real offset = 0;                                  // plane: n . p = offset
    std::vector<Vec3> points;                         // convex_hull
    std::vector<Vec3> vertices;                       // mesh
    std::vector<std::array<std::uint32_t, 3>> triangles;  // mesh
    std::uint32_t rows = 0, columns = 0;              // heightfield: samples along z and x
    Real spacingX = 1, spacingZ = 1;                  // heightfield: "spacing": [dx, dz]
    std::vector<Real> heights;                        // heightfield: rows * columns, row by row
    std::vector<std::uint32_t> holes;                 // heightfield: cell indices without collision
    Real convexRadius = 0;                            // box, cylinder, convex_hull: rounding (docs/shapes.md)
    struct Child;
    std::vector<Child> children;                      // compound
    // Scaled shapes (docs/shapes.md): "scale" on any shape, applied by
    // buildShape with Shape::scaled; kept apart so a saved file keeps it.
    Vec3 scale{1, 1, 1};
    // Convex decomposition: "decompose": true on a mesh builds it as
    // Shape::convexDecomposition (a compound of hulls a dynamic body may have).
    bool decompose = false;
    bool operator==(const ShapeDesc&) const;
};
struct ShapeDesc::Child {
    ShapeDesc shape;
    Vec3 position;
    Quat orientation;
    bool operator==(const Child&) const = default;
};

struct SceneBody {
    BodyDef def;          // def.shape is filled by buildWorld from `shape`
    ShapeDesc shape;
    SceneLocation where;
    // How the body is drawn in recordings (a URDF link's visuals): display
    // data only, not written to scene files and not compared by ==.
    std::vector<BodyVisual> visuals{};
    bool operator==(const SceneBody& o) const;
};

struct SceneJoint {
    JointDef def;         // def.bodyA / def.bodyB are filled by buildWorld
    std::string bodyA;    // empty: the static world
    std::string bodyB;
    SceneLocation where;
    bool operator==(const SceneJoint& o) const;
};

struct SceneSpring {
    SpringDef def;        // def.bodyA / def.bodyB are filled by buildWorld
    std::string bodyA;    // empty: the static world
    std::string bodyB;
    SceneLocation where;
    bool operator==(const SceneSpring& o) const;
};

struct SceneRope {
    RopeDef def;          // def.attachStart / def.attachEnd are filled by buildWorld
    std::string attachStart;  // empty: not attached
    std::string attachEnd;
    SceneLocation where;
    bool operator==(const SceneRope& o) const;
};

struct SceneCloth {
    ClothDef def;
    SceneLocation where;
    bool operator==(const SceneCloth& o) const;
};

// A character (fulcrum/character.hpp): the "characters" section.
struct SceneCharacter {
    CharacterDef def;
    SceneLocation where;
    bool operator==(const SceneCharacter& o) const;
};

// A vehicle (fulcrum/vehicle.hpp): the "vehicles" section.
struct SceneVehicle {
    VehicleDef def;       // def.chassis is filled by buildWorld
    std::string chassis;  // the chassis body's name
    SceneLocation where;
    bool operator==(const SceneVehicle& o) const;
};

inline constexpr Real kSceneDefaultDt = Real(1) / Real(60);
inline constexpr int kSceneDefaultSteps = 600;
// Scene-file default of `bend_compliance` (ropes and cloths) when the key is
// absent: floppy. An explicit 0 keeps XPBD's meaning, a rigid bend constraint
// (a stiff rod, a stiff plate); docs/scene-format.md explains the choice.
inline constexpr Real kSceneDefaultBendCompliance = Real(0.1);
// Upper limits of a scene file (and of the command line's --substeps),
// documented in docs/scene-format.md: far beyond any real scene, they make a
// typo ("substeps": 1e9, a cloth of 4096 x 4096) an error naming the limit
// instead of a run that never ends.
inline constexpr int kSceneMaxSubsteps = kMaxSubsteps;  // the world's own limits (world.hpp)
inline constexpr int kSceneMaxSolverIterations = kMaxSolverIterations;
inline constexpr int kSceneMaxRopeSegments = 100000;
inline constexpr int kSceneMaxClothSide = 4096;              // particles along either side
inline constexpr long long kSceneMaxClothParticles = 1000000;  // size[0] * size[1]

struct Scene {
    std::string sourceName;   // file name used in error messages ("" for scenes built in code)
    std::string description;  // optional free text ("description" key)
    WorldDef world;
    Real dt = kSceneDefaultDt;
    int steps = kSceneDefaultSteps;
    std::vector<SceneBody> bodies;
    std::vector<SceneJoint> joints;
    std::vector<SceneSpring> springs;
    std::vector<SceneRope> ropes;
    std::vector<SceneCloth> cloths;
    std::vector<SceneCharacter> characters;
    std::vector<SceneVehicle> vehicles;
    bool operator==(const Scene& o) const;  // compares the description, not sourceName or locations
};

// Reads and validates a scene file. Throws SceneError (unreadable file, bad JSON, bad values).
Scene loadScene(const std::filesystem::path& file);
// The text of a scene file, unparsed; throws SceneError (unreadable file).
std::string readSceneText(const std::filesystem::path& file);
// Same as loadScene, from text; `sourceName` is used in error messages.
Scene parseScene(std::string_view json, std::string_view sourceName = "<scene>");

// The JSON text of a scene (pretty-printed, two-space indent).
std::string sceneToJson(const Scene& scene);
// Writes sceneToJson to `file`; throws SceneError if it cannot be written.
void saveScene(const Scene& scene, const std::filesystem::path& file);

// Handles of what buildWorld created, index-aligned with the Scene's vectors.
struct SceneHandles {
    std::vector<BodyId> bodies;
    std::vector<JointId> joints;
    std::vector<SpringId> springs;
    std::vector<ParticleSystemId> ropes;   // index-aligned with Scene::ropes
    std::vector<ParticleSystemId> cloths;  // index-aligned with Scene::cloths
    std::vector<CharacterId> characters;   // index-aligned with Scene::characters
    std::vector<VehicleId> vehicles;       // index-aligned with Scene::vehicles
};

// Builds the Shape a ShapeDesc describes (throws fulcrum::Error from the factories).
Shape buildShape(const ShapeDesc& desc);
// Creates the bodies, springs, joints, ropes and cloths of `scene` in a new World. Engine
// validation errors are re-thrown as SceneError with the element's path and line.
World buildWorld(const Scene& scene, SceneHandles* handles = nullptr);

// The current state of `world` as a Scene, starting from `base` (the Scene it
// was built from) and `handles` (from buildWorld): positions, orientations,
// velocities, awake flags and world settings come from the World; everything
// the World does not expose (damping, filters, ropes...) from `base`. Anchors
// and axes of joints and springs, which the format gives in world space at
// creation, are carried along with their bodies to the current pose. Saving
// the result and building it again continues the run (see docs/scene-format.md
// for what a capture cannot carry: solver warm-start state, and the reference
// angle of hinge limits and springs, which restarts from the captured pose).
Scene captureScene(const World& world, const Scene& base, const SceneHandles& handles);

// Display name of body `index` of a scene: its name, or "body<index>" when unnamed.
std::string sceneBodyName(const Scene& scene, std::size_t index);

}  // namespace fulcrum
