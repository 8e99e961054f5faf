#pragma once
// The benchmark scenes and accuracy probes of docs/benchmarks.md as
// engine-neutral descriptions (bodies, ball joints, one cloth), so Fulcrum and
// the peer engines (bench/peers/) build exactly the same thing; and the
// interface every engine implements for the harness (bench/benchmark_scenes.cpp).
// Header-only: bench/CMakeLists.txt makes an executable of every bench/*.cpp.
//
// Everything here is double: the adapters cast to their engine's scalar.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace bench {

// ---- small math, enough for building scenes and measuring them --------------
struct V3 {
    double x = 0, y = 0, z = 0;
};
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator*(V3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
inline double dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline double length(V3 a) { return std::sqrt(dot(a, a)); }

struct Q {  // unit quaternion, w first
    double w = 1, x = 0, y = 0, z = 0;
};
inline Q operator*(Q a, Q b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
inline Q conjugate(Q q) { return {q.w, -q.x, -q.y, -q.z}; }
inline Q axisAngle(V3 axis, double angle) {
    const double n = length(axis), s = std::sin(0.5 * angle) / n;
    return {std::cos(0.5 * angle), axis.x * s, axis.y * s, axis.z * s};
}
inline V3 rotate(Q q, V3 v) {
    const V3 u{q.x, q.y, q.z};
    const V3 t = cross(u, v) * 2;
    return v + t * q.w + cross(u, t);
}

// ---- scene description ---------------------------------------------------------
// One piece of a body made of several (Box3D's washer drum, a ragdoll bone's
// off-centre capsule, Jolt's high-speed compound), in the body's frame.
struct ShapePart {
    enum class Kind { Box, Sphere, Capsule, Hull } kind = Kind::Box;
    V3 position;
    Q orientation;
    V3 half{0.5, 0.5, 0.5};   // as BodySpec::half
    std::vector<V3> points;   // Hull
};

struct BodySpec {
    // Hull: the scene's hullPoints. SharedCompound: one compound of every hull
    // in the scene's sharedCompoundHulls, shared by all such bodies, `position`
    // its origin (the frame of the hulls' points); unlike `parts` (a body's own
    // shapes, each placed in the body's frame), engines build it once for the
    // scene and Bullet shifts it to its centre of mass (bench/mesh_scenes.hpp).
    enum class Kind { Box, Sphere, Capsule, Hull, SharedCompound } kind = Kind::Box;
    V3 position;                  // centre (= centre of mass: every shape here is symmetric)
    Q orientation;
    V3 half{0.5, 0.5, 0.5};       // box: half extents; sphere: radius in x; capsule: radius x, half height y (axis: local y)
    V3 linearVelocity, angularVelocity;  // world frame, at the start
    bool isStatic = false;
    // Pushed by nothing: moves at its velocities (the washer's drum), or, when
    // a scene's kinematicPaths names it, along that path (the junkyard's pusher).
    bool isKinematic = false;
    double mass = 1;
    // The peers' churn and mesh scenes (bench/churn_scenes.hpp, bench/mesh_scenes.hpp):
    bool isBullet = false;         // continuous collision against moving bodies too
    std::vector<ShapePart> parts;  // non-empty: the body is these (kind and half unused), position = the body's origin
    int mesh = -1;                 // >= 0: a static body whose shape is the scene's meshes[mesh], position = the mesh's origin
    int filterGroup = 0;           // bodies sharing a negative group never collide
    double friction = -1;          // >= 0: this body's own (else the scene's)
    double restitution = -1;       // >= 0: this body's own (else the scene's)
};

struct JointSpec {  // ball-and-socket; a = -1 is the static world
    int a = -1, b = -1;
    V3 anchor;      // world space at creation
    // Churn scenes' ragdolls (bench/churn_scenes.hpp): a joint given by a frame
    // in each body (the anchor, and the twist or hinge axis as the frame's z).
    enum class Type { Ball, ConeTwist, Hinge } type = Type::Ball;
    bool localFrames = false;     // true: anchor unused, frameA/frameB hold it
    V3 localA{}, localB{};
    Q frameA{}, frameB{};
    double swing = 0;             // ConeTwist: cone half-angle, rad
    double lower = 0, upper = 0;  // ConeTwist: twist limits; Hinge: angle limits (rad)
    double frictionTorque = 0;    // N m
};

// Bodies and joints a scene's script creates and destroys while stepping
// (joint body indices count within the group; -1 is the static world).
struct BodyGroup {
    std::vector<BodySpec> bodies;
    std::vector<JointSpec> joints;
};
struct ScriptEvent {
    int step = 0;                 // before this step (0-based)
    bool create = true;           // false: destroy the group's joints, then its bodies
    int group = 0;
};

// nx x nz static boxes of half extents `half` side by side, `cell` apart,
// centred on x = z = 0 at height y (Box3D's large_world: a million of them,
// described without a million BodySpecs).
struct StaticGrid {
    int nx = 0, nz = 0;
    double cell = 1, y = 0;
    V3 half;
};

// A static triangle mesh (the rain's ground cells, the trees' and Jolt's
// terrains), counter-clockwise seen from its front (solid) side.
struct MeshSpec {
    std::vector<V3> vertices;
    std::vector<std::array<std::uint32_t, 3>> triangles;
};

// A kinematic body's path (BodySpec::isKinematic): before step k (from 0) the
// harness asks the engine to bring the body's origin to origin(k) by the end
// of the step (orientation kept at the identity).
struct KinematicPath {
    int body = -1;
    std::function<V3(int)> origin;
};

// docs/benchmarks.md's cloth (the harness measures it from particle positions).
struct ClothSpec {
    int n = 0;                    // n x n particles; 0: no cloth
    double spacing = 0.05;
    double particleMass = 0.01;
    double height = 3;            // held horizontal at this y, centred on x = z = 0
    V3 sphereCenter{0, 1, 0};
    double sphereRadius = 0.8;
};

enum class Probe { None, FreeFall, Pendulum, Slope20, Slope30, Spin };

struct SceneSpec {
    std::string name;
    // Jointed: bodies held by ball joints other than the chain (quality: joint error).
    // Churn: bench/churn_scenes.hpp's (quality: what stays inside `bounds`, the deepest overlap).
    enum class Kind { Bodies, Chain, Jointed, Cloth, Probe, Churn } kind = Kind::Bodies;
    Probe probe = Probe::None;
    std::vector<BodySpec> bodies;
    std::vector<JointSpec> joints;
    ClothSpec cloth;
    int steps = 600;
    double dt = 1.0 / 60;
    V3 gravity{0, -9.81, 0};
    double friction = 0.6;     // effective pair coefficient
    bool sleeping = true;
    bool pyramid = false;      // quality = drift and top sink
    int topIndex = -1;         // the top box of a pyramid; the free end of the chain
    bool fixedCost = false;    // report microseconds per step: the cost of a step with almost nothing to do
    // Peers' own suites (bench/box3d_scenes.hpp) fix what the shared scenes leave to each engine:
    int substeps = 0;          // 0: the engine's default; otherwise engines with sub-steps use this many
    bool bodyCollisions = true;  // false: no body collides with any other (Box3D's joint_grid)
    std::vector<V3> hullPoints;  // the one convex hull Kind::Hull bodies use, in their body frame
    double restitution = 0;    // effective pair coefficient (BodySpec::restitution overrides it)
    double sleepVelocity = 0;  // m/s a body must stay below to sleep; 0: the engine's default
    // The static meshes bodies name by BodySpec::mesh (shared: the trees' are large).
    std::vector<std::shared_ptr<const MeshSpec>> meshes;
    // Mesh scenes (bench/mesh_scenes.hpp):
    std::vector<std::vector<V3>> sharedCompoundHulls;  // the hulls of every Kind::SharedCompound body, in its body frame
    std::vector<KinematicPath> kinematicPaths;
    // Churn and scale (bench/churn_scenes.hpp):
    std::vector<BodyGroup> groups;
    std::vector<ScriptEvent> script;  // in step order
    StaticGrid staticGrid;
    V3 boundsMin{-1e30, -1e30, -1e30}, boundsMax{1e30, 1e30, 1e30};  // Churn: a dynamic body outside has escaped
    double restHeight = -1e30;        // Churn, when set: the height the dynamic bodies' origins should rest at
};

// One scene of a suite, built only when it is run: a run of one scene builds
// that one, as the peers' programs build only the benchmark they are asked
// for (a whole suite built up front cost the harness's process about 0.3 s of
// its 0.85 s on trees100: trees25's mesh alone is 960,000 triangles).
struct LazyScene {
    std::string name;
    std::function<SceneSpec()> build;
};
// The scene Build(args...), named Name(args...) without building it.
template <auto Build, auto Name, typename... Args>
LazyScene lazyScene(Args... args) {
    return {Name(args...), [=] { return Build(args...); }};
}
// The scene Build(name, args...), named by its first argument.
template <auto Build, typename... Args>
LazyScene lazyNamedScene(const std::string& name, Args... args) {
    return {name, [=] { return Build(name, args...); }};
}
// A scene's name: `base` at its reference size, else `base(size)`.
inline std::string sizedName(const char* base, bool referenceSize, const std::string& size) {
    return referenceSize ? std::string(base) : std::string(base) + "(" + size + ")";
}
// The scene of `suite` named `name`, built; none when no scene has that name.
inline std::optional<SceneSpec> buildNamed(const std::vector<LazyScene>& suite, const std::string& name) {
    for (const LazyScene& scene : suite) {
        if (scene.name == name) return scene.build();
    }
    return std::nullopt;
}

// ---- what an engine implements -------------------------------------------------
struct BodyState {
    V3 position;
    Q orientation;
    V3 linearVelocity, angularVelocity;  // world frame
};

class Engine {
public:
    virtual ~Engine() = default;
    virtual std::string name() const = 0;
    virtual int threads() const { return 1; }
    // Builds the whole scene (bodies in order, then joints, then the cloth).
    // Returns false, with the reason in `why`, when the engine can't hold it.
    virtual bool build(const SceneSpec& scene, std::string& why) = 0;
    virtual void step() = 0;
    // Sets kinematic body `index` moving so that its origin reaches `origin` in
    // `dt` (SceneSpec::kinematicPaths; called before each step).
    virtual void moveKinematic(std::size_t /*index*/, V3 /*origin*/, double /*dt*/) {}
    // Before reading state after steps (MuJoCo computes poses lazily); not timed.
    virtual void sync() {}
    virtual BodyState body(std::size_t index) const = 0;
    virtual bool asleep(std::size_t index) const = 0;
    virtual double deepestPenetration() const = 0;   // m, over the contacts of the last step
    virtual std::vector<V3> clothParticles() const { return {}; }  // particle (i, j) at j * n + i
    virtual std::string settings() const = 0;       // the defaults it runs with, for the docs
    virtual std::string note() const { return {}; } // anything odd in the last run (e.g. an overflow)
    // Churn scenes (bench/churn_scenes.hpp): the script's groups, and every
    // live dynamic body's origin (scene bodies and live groups', any order).
    // An engine that builds churn scenes implements all three.
    virtual void createGroup(int /*group*/) {}
    virtual void destroyGroup(int /*group*/) {}
    virtual std::vector<V3> dynamicPositions() const { return {}; }
};

// ---- the scenes ---------------------------------------------------------------
inline void addGround(SceneSpec& s, double half) {
    BodySpec g;
    g.isStatic = true;
    g.half = {half, 0.5, half};
    g.position = {0, -0.5, 0};
    s.bodies.push_back(g);
}

inline SceneSpec pyramid(const std::string& name, int base, int steps) {
    SceneSpec s;
    s.name = name;
    s.steps = steps;
    s.sleeping = false;  // a sleeping pyramid costs nothing: measure the solver
    s.pyramid = true;
    addGround(s, 50);
    for (int row = 0; row < base; ++row) {
        const int count = base - row;
        for (int i = 0; i < count; ++i) {
            BodySpec b;
            b.position = {i - 0.5 * (count - 1), 0.5 + row, 0};
            s.bodies.push_back(b);
        }
    }
    s.topIndex = static_cast<int>(s.bodies.size()) - 1;
    return s;
}

// Floor 40 x 40 m (top at y = 0) inside four static walls 10 m tall, inner size 32 x 32 m.
inline void addArena(SceneSpec& s) {
    addGround(s, 20);
    const double inner = 16, t = 0.5, hh = 5;
    const double xs[4] = {inner + t, -(inner + t), 0, 0};
    const double zs[4] = {0, 0, inner + t, -(inner + t)};
    for (int i = 0; i < 4; ++i) {
        BodySpec w;
        w.isStatic = true;
        w.position = {xs[i], hh, zs[i]};
        w.half = {i < 2 ? t : inner + 2 * t, hh, i < 2 ? inner + 2 * t : t};
        s.bodies.push_back(w);
    }
}

// nx x ny x nz grid spaced `spacing`, lowest layer at y = 2, layer k shifted by
// ((k mod 2) 0.25, 0, (floor(k/2) mod 2) 0.25) so columns don't line up.
inline SceneSpec pile(const std::string& name, BodySpec::Kind kind, int nx, int ny, int nz, double spacing, int steps) {
    SceneSpec s;
    s.name = name;
    s.steps = steps;
    addArena(s);
    for (int k = 0; k < ny; ++k) {
        const double sx = (k % 2) * 0.25, sz = ((k / 2) % 2) * 0.25;
        for (int i = 0; i < nx; ++i) {
            for (int j = 0; j < nz; ++j) {
                BodySpec b;
                b.kind = kind;
                b.position = {(i - 0.5 * (nx - 1)) * spacing + sx, 2 + k * spacing, (j - 0.5 * (nz - 1)) * spacing + sz};
                s.bodies.push_back(b);
            }
        }
    }
    return s;
}

// 100 capsule links (radius 0.1, half-height 0.4, 1 m between anchors, 1 kg)
// along +x from the world anchor (0, 60, 0), ball joints end to end.
inline std::string chainName(int /*links*/, int /*steps*/) { return "chain"; }
inline SceneSpec chain(int links, int steps) {
    SceneSpec s;
    s.name = chainName(links, steps);
    s.kind = SceneSpec::Kind::Chain;
    s.steps = steps;
    const Q alongX = axisAngle({0, 0, 1}, 1.5707963267948966);  // capsule axis y -> x
    for (int i = 0; i < links; ++i) {
        BodySpec b;
        b.kind = BodySpec::Kind::Capsule;
        b.half = {0.1, 0.4, 0.1};
        b.position = {0.5 + i, 60, 0};
        b.orientation = alongX;
        s.bodies.push_back(b);
        s.joints.push_back({i - 1, i, {static_cast<double>(i), 60, 0}});
    }
    s.topIndex = links - 1;
    return s;
}

inline std::string clothName(int n, int /*steps*/) { return sizedName("cloth", n == 64, std::to_string(n)); }
inline SceneSpec cloth(int n, int steps) {
    SceneSpec s;
    s.name = clothName(n, steps);
    s.kind = SceneSpec::Kind::Cloth;
    s.steps = steps;
    addGround(s, 50);
    BodySpec sphere;
    sphere.kind = BodySpec::Kind::Sphere;
    sphere.isStatic = true;
    sphere.half = {0.8, 0.8, 0.8};
    sphere.position = {0, 1, 0};
    s.bodies.push_back(sphere);
    s.cloth.n = n;
    return s;
}

// ---- accuracy probes ----------------------------------------------------------
inline SceneSpec freeFall() {  // sphere from rest, 1 s: analytic y = -4.905
    SceneSpec s;
    s.name = "free fall 1 s";
    s.kind = SceneSpec::Kind::Probe;
    s.probe = Probe::FreeFall;
    s.steps = 60;
    s.sleeping = false;
    BodySpec b;
    b.kind = BodySpec::Kind::Sphere;
    s.bodies.push_back(b);
    return s;
}

// 1 m pendulum from 10 degrees: a sphere of radius 0.1 on a ball joint 1 m
// above its centre. Its own inertia lengthens the period by sqrt(1 + 0.4 r^2/L^2)
// = 1.002: expected 2.014 s. (A smaller bob is a worse test of the engines, not
// a better pendulum: with radius 0.02 the lever-arm-to-inertia ratio is 6000:1
// and Bullet's and ODE's iterative solvers swing at a 4 s and 2.5 s period.)
inline SceneSpec pendulum() {
    SceneSpec s;
    s.name = "pendulum period";
    s.kind = SceneSpec::Kind::Probe;
    s.probe = Probe::Pendulum;
    s.steps = 1500;  // 25 s: 10 periods and some
    s.sleeping = false;  // it would fall asleep at a turning point in some engines
    const double a = 10 * 3.14159265358979323846 / 180;
    BodySpec b;
    b.kind = BodySpec::Kind::Sphere;
    b.half = {0.1, 0.1, 0.1};
    b.position = {std::sin(a), 10 - std::cos(a), 0};
    s.bodies.push_back(b);
    s.joints.push_back({-1, 0, {0, 10, 0}});
    return s;
}

// A unit cube (1 kg, pair friction 0.5) resting on a static slope tilted by `degrees` about z.
inline SceneSpec slope(int degrees) {
    SceneSpec s;
    s.name = "slope " + std::to_string(degrees) + " deg, 2 s";
    s.kind = SceneSpec::Kind::Probe;
    s.probe = degrees == 20 ? Probe::Slope20 : Probe::Slope30;
    s.steps = 120;
    s.friction = 0.5;
    s.sleeping = false;
    const double a = degrees * 3.14159265358979323846 / 180;
    const Q tilt = axisAngle({0, 0, 1}, a);
    const V3 normal = rotate(tilt, {0, 1, 0});
    BodySpec ground;
    ground.isStatic = true;
    ground.half = {20, 0.5, 20};
    ground.orientation = tilt;
    ground.position = normal * -0.5;  // top face through the origin
    s.bodies.push_back(ground);
    BodySpec box;
    box.orientation = tilt;
    box.position = normal * 0.5;
    s.bodies.push_back(box);
    return s;
}

// A free box (half extents 0.1, 0.5, 1.0), spun about its intermediate axis
// (y) at (0, 5, 0.01) rad/s in zero gravity for 10 s.
inline SceneSpec spin() {
    SceneSpec s;
    s.name = "intermediate-axis spin 10 s";
    s.kind = SceneSpec::Kind::Probe;
    s.probe = Probe::Spin;
    s.steps = 600;
    s.gravity = {0, 0, 0};
    s.sleeping = false;
    BodySpec b;
    b.half = {0.1, 0.5, 1.0};
    b.position = {0, 5, 0};
    b.angularVelocity = {0, 5, 0.01};
    s.bodies.push_back(b);
    return s;
}

// Fixed cost per step: ten unit boxes resting on the ground 2 m apart (no
// box-box contacts), sleeping off so every step does the whole pipeline.
inline std::string tenBoxesName() { return "ten_boxes"; }
inline SceneSpec tenBoxes() {
    SceneSpec s;
    s.name = tenBoxesName();
    s.steps = 600;
    s.sleeping = false;
    s.fixedCost = true;
    addGround(s, 50);
    for (int i = 0; i < 10; ++i) {
        BodySpec b;
        b.position = {2.0 * i - 9, 0.5, 0};
        s.bodies.push_back(b);
    }
    return s;
}

inline std::vector<LazyScene> allScenes(bool quick) {
    const int steps = quick ? 120 : 600;
    using Kind = BodySpec::Kind;
    if (quick) {
        return {lazyScene<tenBoxes, tenBoxesName>(),
                lazyNamedScene<pyramid>("pyramid20", 20, steps),
                lazyNamedScene<pyramid>("pyramid_large(30)", 30, steps),
                lazyNamedScene<pile>("box_pile(500)", Kind::Box, 10, 5, 10, 1.5, steps),
                lazyNamedScene<pile>("sphere_pile(1000)", Kind::Sphere, 10, 10, 10, 1.2, steps),
                lazyScene<chain, chainName>(100, steps),
                lazyScene<cloth, clothName>(32, steps)};
    }
    return {lazyScene<tenBoxes, tenBoxesName>(),
            lazyNamedScene<pyramid>("pyramid20", 20, steps),
            lazyNamedScene<pyramid>("pyramid_large", 60, steps),
            lazyNamedScene<pile>("box_pile", Kind::Box, 20, 10, 20, 1.5, steps),
            lazyNamedScene<pile>("sphere_pile", Kind::Sphere, 25, 16, 25, 1.2, steps),
            lazyScene<chain, chainName>(100, steps),
            lazyScene<cloth, clothName>(64, steps)};
}

inline std::vector<SceneSpec> allProbes() {
    return {freeFall(), pendulum(), slope(20), slope(30), spin()};
}

}  // namespace bench
