#pragma once
// World: owns bodies, springs, joints and particle systems, and advances them
// with step(dt). All methods taking handles validate them and throw
// fulcrum::Error for null or stale handles; inputs are checked for NaN/inf and
// physical sense at this boundary, so the step itself can trust its data.
#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "fulcrum/body.hpp"
#include "fulcrum/character.hpp"
#include "fulcrum/error.hpp"
#include "fulcrum/joint.hpp"
#include "fulcrum/particles.hpp"
#include "fulcrum/query.hpp"
#include "fulcrum/spring.hpp"

namespace fulcrum {

// Thrown by World::step when the state turns NaN or infinite; names the body.
class NumericalError : public Error {
public:
    using Error::Error;
};

enum class Integrator : std::uint8_t { ExplicitEuler, SemiImplicitEuler, Verlet };

// WorldDef::maxContactPairs = 0 (automatic) allows kAutoContactPairsPerBody
// pairs per body plus kAutoContactPairsBase. A dense pile holds 3-8 pairs per
// body (docs/solver.md, "Contact pair limit"), so only bodies crowded far
// beyond touching reach it; the base leaves every world of a few hundred
// bodies unlimited (N bodies at one spot make N(N-1)/2 pairs: 362 make 65,341).
inline constexpr std::int64_t kAutoContactPairsPerBody = 16;
inline constexpr std::int64_t kAutoContactPairsBase = 65536;
inline constexpr std::int64_t kMaxContactPairs = 2147483647;  // the largest limit
// Upper limits of WorldDef (docs/reliability.md, "Bad input"): far beyond any
// real world, they turn a typo (substeps = 1e9) into an error naming the
// setting instead of a step that never ends or a stage list that exhausts memory.
inline constexpr int kMaxSubsteps = 1000;
inline constexpr int kMaxSolverIterations = 1000;
inline constexpr int kMaxThreads = 1024;
const char* toString(Integrator integrator);                        // "explicit_euler", ...
std::optional<Integrator> integratorFromString(std::string_view name);

struct WorldDef {
    Vec3 gravity{0, Real(-9.81), 0};
    Integrator integrator = Integrator::SemiImplicitEuler;
    int substeps = 5;           // sub-steps per step (1 to kMaxSubsteps)
    int solverIterations = 1;   // constraint iterations per sub-step (1 to kMaxSolverIterations)
    bool sleeping = true;
    int threads = 1;            // 1 to kMaxThreads; results are identical for every count
    // Steps with fewer awake bodies than this run on the calling thread alone
    // even when threads > 1: handing each small loop to the pool's workers costs
    // more than it saves (docs/threading.md, "Small steps"). 0: always use the
    // pool. A task system of the user's (World::setTaskSystem) is always used.
    std::uint32_t parallelMinBodies = 512;

    // ---- contact solver tuning (docs/solver.md explains each one)
    Real contactHertz = 60;             // stiffness of the soft contact (capped at 1/6 of the sub-step rate, static contacts 2x under 1/4); > 0
    Real contactDampingRatio = Real(1.5);  // > 0; >= 1: overlaps are pushed out without bounce (1 = critically damped)
    Real contactPushMaxVelocity = 3;    // m/s: the fastest an overlap is pushed apart; > 0
    Real speculativeMargin = Real(0.02);  // m: contact points are made this far before touching (plus the motion of a step); >= 0
    Real restitutionThreshold = 1;      // m/s: slower impacts don't bounce; >= 0
    Real hitEventThreshold = 1;         // m/s: slower impacts make no ContactHitEvent (World::contactHitEvents); >= 0
    // Pairs the narrow phase finds grown deeper within a step (a hull struck
    // into its neighbour, a landing the soft contact did not hold) pushed
    // apart by position after the sub-steps (docs/solver.md, "Grown
    // overlaps"): piles of fast-landing hulls keep their overlaps under ~2 cm
    // instead of 5-40 cm. Off by default for now: on, it redraws chaotic
    // landings (box_pile falls asleep at another time: a different draw, not
    // a worse one) and the default keeps the results of earlier builds.
    bool pushOutGrownOverlaps = false;
    // ---- joint solver tuning (docs/joints.md explains each one)
    Real jointHertz = 60;                  // stiffness of the soft joint rows (capped at 1/4 of the sub-step rate); > 0
    Real jointDampingRatio = 2;            // > 0
    // A body turns at most this far per sub-step (rad): a faster spin is scaled
    // down to it when positions are integrated, as in Box2D. Beyond ~1 rad per
    // sub-step the joints' and contacts' linearisation fails: a chain yanked
    // taut after falling loose spun a link up to 670 rad/s and blew up
    // (docs/integrators.md, "Spin limit"). > 0; inf: no limit.
    Real maxRotationPerSubstep = Real(0.25 * 3.14159265358979);
    Real jointProjectionSlop = Real(0.005);  // m: anchor separations beyond it are removed at the position level; >= 0 (inf: never)
    bool jointDirectSolve = true;          // joints forming trees (chains, ragdolls) solved exactly, in linear time
    // ---- sleeping: a group of touching bodies falls asleep once, for `timeToSleep`
    // seconds, its mass-weighted RMS speed stayed below linearSleepVelocity, no
    // body of it moved faster than twice that, and none spun faster than
    // angularSleepVelocity unless its farthest point moved slower than
    // linearSleepVelocity (a lone body: its own speed below linearSleepVelocity
    // and its spin below angularSleepVelocity). Each speed is the smaller of the
    // velocity and how far the body moved over the step (docs/solver.md, "Held bodies").
    Real linearSleepVelocity = Real(0.05);   // m/s, >= 0
    Real angularSleepVelocity = Real(0.05);  // rad/s, >= 0
    Real timeToSleep = Real(0.5);            // s, >= 0
    // ---- continuous collision: time of impact for fast bodies against static ones
    // (and `isBullet` bodies against dynamic ones as well).
    bool continuousCollision = true;
    // ---- capacity (docs/solver.md, "Contact pair limit"): the most contact
    // pairs (bodies whose fattened bounds overlap) the world holds, and so
    // the memory and work of a step. Pairs the limit leaves out are searched
    // again as pairs end and make room; meanwhile their bodies pass through
    // each other. The same bits for every thread count either way, and
    // World::warnings() says when it happened. 0: automatic
    // (kAutoContactPairsPerBody per body plus kAutoContactPairsBase);
    // otherwise 1 to kMaxContactPairs.
    std::int64_t maxContactPairs = 0;
};

// A contact or sensor event of the last step. Contacts: the two bodies (bodyA
// has the smaller handle index). Sensors: bodyA is the sensor, bodyB the visitor.
struct ContactEvent {
    BodyId bodyA, bodyB;
};

// An impact of the last step (World::contactHitEvents; Box2D v3's hit
// events, for sounds and damage): a manifold of two bodies that pushed in the
// step after approaching along its normal faster than
// WorldDef::hitEventThreshold. The point of the manifold that approached fastest.
struct ContactHitEvent {
    BodyId bodyA, bodyB;   // as ContactEvent
    Vec3 point;            // world, at the step's start
    Vec3 normal;           // unit, from A to B
    Real approachSpeed = 0;  // m/s, > 0: the normal speed when the point first pushed
};

// A joint that broke in the last step: its reaction force or torque exceeded
// JointDef::breakForce / breakTorque. The joint stays valid but disabled.
struct JointBreakEvent {
    JointId joint;
    BodyId bodyA, bodyB;
    Vec3 force;    // N, on body B, when it broke
    Vec3 torque;   // N m
};

struct EnergyReport {
    double kinetic = 0;    // translational + rotational
    double potential = 0;  // gravity (relative to y = 0 along -gravity) + springs
    double total = 0;
};

// Where the last step's time went (World::lastStepProfile; docs/api.md,
// "Profiling"): wall-clock milliseconds per phase of the step pipeline
// (docs/architecture.md), and what the step worked on. The phases follow one
// another, so they add up to `total` but for the few microseconds between them.
// Timed by steady_clock, its phases by shares of a cheaper counter (x86-64: rdtsc)
// read at their boundaries, so it is always on; it is a diagnostic, not part of
// the simulation: two runs of one scene give the same state, not the same times.
struct StepProfile {
    double total = 0;       // World::step from entry to return
    double collide = 0;     // start transforms, broad phase, narrow phase, contact begin/end
    double prepare = 0;     // contact and joint constraints, graph colouring, first forces
    double solve = 0;       // the sub-steps: forces, integration, warm start, solve, relax, joint projection
    double store = 0;       // restitution, impulses kept for warm starting, joint reactions and breaking
    double continuous = 0;  // time of impact for fast bodies
    double particles = 0;   // ropes and cloths
    double sleep = 0;       // islands and sleeping
    double finish = 0;      // user forces cleared, NaN/inf check
    std::uint32_t awakeBodies = 0;         // bodies that moved in the step
    std::uint32_t contactConstraints = 0;  // touching manifolds the solver worked on
    std::uint32_t jointConstraints = 0;    // enabled joints with an awake body
    std::uint32_t workers = 0;             // the task system's worker count (1: the calling thread alone)
    // The contact pair limit (WorldDef::maxContactPairs, docs/solver.md "Contact pair limit").
    std::uint32_t contactPairs = 0;        // pairs held after the collide phase
    std::uint32_t contactPairLimit = 0;    // the limit in effect
    std::uint32_t pairsLeftOut = 0;        // new pairs the limit kept out in this step (a lower bound)
    std::uint32_t bodiesOverPairLimit = 0; // bodies whose new pairs wait for room (0: none missing)
};

// Something the world noticed that the user should know (World::warnings):
// each kind is raised once per world, at the step it first happened.
struct WorldWarning {
    std::uint64_t step = 0;  // World::stepCount() of the step that raised it
    std::string message;
};

// One contact manifold of the last step, as reported to users and --json.
//
// The forces are what the solver applied over the last step in which the pair
// was solved (a sleeping pair keeps those of the step it fell asleep in; a
// pair without a dynamic body has none): per point, the sum over the
// step's sub-steps of the normal impulse each sub-step applied (its warm
// start, biased iterations and relax pass: the accumulated impulse after the
// relax) plus the restitution applied after the sub-steps (docs/solver.md,
// "Contact forces").
struct ContactReport {
    BodyId bodyA, bodyB;
    Vec3 normal;                // unit, from A to B
    Real depth = 0;             // deepest point; positive when overlapping
    std::vector<Vec3> points;   // world space
    Real normalImpulse = 0;     // N s, on B along `normal`, summed over the points
    Vec3 frictionImpulse;       // N s, tangent impulse on B (world), at the manifold's centre
    Vec3 force;                 // N, on B, averaged over the step: (normalImpulse normal + frictionImpulse) / dt
    std::vector<Real> pointNormalImpulses;  // N s, per point (as points)
};

// Two bodies left overlapping far deeper than contacts rest (World::deepOverlaps):
// a pair the contact solver did not hold apart.
struct DeepOverlap {
    BodyId bodyA, bodyB;  // as in ContactReport
    Real depth = 0;       // m: the deepest point of their contact at the end of the last step
    Real size = 0;        // m: the smallest extent of the smaller dynamic body (what depth is compared with)
};

// ---- particle systems (ParticleReport, the figures of one rope or cloth: fulcrum/particles.hpp;
// docs/cli.md's `particle_systems` entry of `--json`; World::particleReport)
enum class ParticleSystemType : std::uint8_t { Rope, Cloth };

struct WorldImpl;
class TaskSystem;  // fulcrum/task_system.hpp
namespace detail {
struct WorldAccess;  // the engine's own way in (tests, io, tools); not installed
}

class World {
public:
    explicit World(const WorldDef& def = {});
    ~World();
    World(World&&) noexcept;
    World& operator=(World&&) noexcept;
    World(const World&) = delete;
    World& operator=(const World&) = delete;

    // ---- settings
    const WorldDef& settings() const;
    void setGravity(const Vec3& g);
    void setIntegrator(Integrator integrator);
    void setSubsteps(int substeps);
    void setSolverIterations(int iterations);
    void setSleepingEnabled(bool enabled);
    void setThreadCount(int threads);
    void setParallelMinBodies(std::uint32_t minimum);  // WorldDef::parallelMinBodies
    void setHitEventThreshold(Real threshold);         // WorldDef::hitEventThreshold (>= 0), from the last step's events on
    void setPushOutGrownOverlaps(bool enabled);        // WorldDef::pushOutGrownOverlaps, from the next step on
    // WorldDef::maxContactPairs (validated the same way). A limit below the
    // pairs held now keeps them; new ones wait until they end.
    void setMaxContactPairs(std::int64_t limit);
    // Runs the step's parallel loops on a user's scheduler (docs/threading.md)
    // instead of the built-in pool sized by `threads`. Not owned: it must
    // outlive the world or be replaced first; nullptr goes back to the built-in
    // pool. Results are bit-identical whatever scheduler and thread count.
    void setTaskSystem(TaskSystem* tasks);

    // ---- bodies
    BodyId createBody(const BodyDef& def);
    // Makes room for `count` more bodies (capacity only: creates nothing), so
    // that a world of very many bodies made one createBody at a time does not
    // regrow (copy, and touch new pages for) every per-body array on the way:
    // a million static boxes, 0.25 s less kernel time (docs/benchmarks.md,
    // "Building a million static bodies"). Like Box3D's world capacity.
    void reserveBodies(std::size_t count);
    void destroyBody(BodyId id);
    bool isValid(BodyId id) const;
    std::size_t bodyCount() const;
    std::vector<BodyId> bodies() const;               // live bodies in creation order
    BodyId findBody(std::string_view name) const;      // null handle if none
    const std::string& name(BodyId id) const;
    BodyType bodyType(BodyId id) const;
    const Shape& shape(BodyId id) const;
    Real mass(BodyId id) const;                        // 0 for static and kinematic bodies
    Mat3 localInertia(BodyId id) const;                // about the centre of mass, body axes
    Vec3 localCenterOfMass(BodyId id) const;
    Real friction(BodyId id) const;
    Real restitution(BodyId id) const;

    Transform transform(BodyId id) const;              // of the body origin
    Vec3 position(BodyId id) const;
    Quat orientation(BodyId id) const;
    Vec3 centerOfMass(BodyId id) const;                // world space
    Vec3 linearVelocity(BodyId id) const;              // of the centre of mass
    Vec3 angularVelocity(BodyId id) const;
    Vec3 velocityAtPoint(BodyId id, const Vec3& worldPoint) const;
    Transform previousTransform(BodyId id) const;      // at the start of the last step (for interpolation)

    void setTransform(BodyId id, const Vec3& position, const Quat& orientation);  // wakes the body
    void setLinearVelocity(BodyId id, const Vec3& v);
    // Kinematic targets: sets a kinematic body's velocities so that a step of
    // `dt` brings it to `target` (its origin and orientation): the linear one
    // moves the centre of mass in a straight line, the angular one turns along
    // the shortest arc. Dynamic bodies it touches are pushed and carried by the
    // solver as by any moving kinematic body. The velocities stay after the
    // step (call it every step to follow a path; zero velocities to stop).
    // Wakes the body. Throws fulcrum::Error for a body that is not kinematic,
    // a non-finite target or a dt that is not finite and > 0.
    void moveKinematic(BodyId id, const Transform& target, Real dt);
    void setAngularVelocity(BodyId id, const Vec3& w);
    void setFriction(BodyId id, Real friction);
    void setRestitution(BodyId id, Real restitution);
    void setGravityScale(BodyId id, Real scale);
    void setDamping(BodyId id, Real linear, Real angular);
    void setDrag(BodyId id, Real linear, Real quadratic);

    bool isAwake(BodyId id) const;
    void wake(BodyId id);

    // ---- forces: accumulated until the end of the next step, then cleared
    void applyForce(BodyId id, const Vec3& force, const Vec3& worldPoint);
    void applyForceAtCenter(BodyId id, const Vec3& force);
    void applyTorque(BodyId id, const Vec3& torque);
    // Impulses change the velocity at once.
    void applyLinearImpulse(BodyId id, const Vec3& impulse, const Vec3& worldPoint);
    void applyLinearImpulseAtCenter(BodyId id, const Vec3& impulse);
    void applyAngularImpulse(BodyId id, const Vec3& impulse);
    // A custom force evaluated by the integrator (empty callback removes it).
    void setForceCallback(BodyId id, ForceCallback callback);

    // ---- springs (force elements)
    SpringId createSpring(const SpringDef& def);
    void destroySpring(SpringId id);
    bool isValid(SpringId id) const;
    std::size_t springCount() const;
    Real springLength(SpringId id) const;

    // ---- joints (constraints)
    JointId createJoint(const JointDef& def);
    // The per-type definitions (fulcrum/joint.hpp): local anchors and axes.
    JointId createJoint(const BallJointDef& def);
    JointId createJoint(const HingeJointDef& def);
    JointId createJoint(const SliderJointDef& def);
    JointId createJoint(const DistanceJointDef& def);
    JointId createJoint(const FixedJointDef& def);
    JointId createJoint(const ConeTwistJointDef& def);
    JointId createJoint(const SixDofJointDef& def);
    void destroyJoint(JointId id);
    bool isValid(JointId id) const;
    std::vector<JointId> joints() const;
    const JointDef& jointDef(JointId id) const;       // as created (anchors world space at creation)
    const std::string& name(JointId id) const;
    Real jointError(JointId id) const;                 // position error in metres
    // Force (N) and torque (N m) the joint applied to body B in the last step
    // (its accumulated impulses over the sub-step); zero while disabled or asleep.
    Vec3 jointReactionForce(JointId id) const;
    Vec3 jointReactionTorque(JointId id) const;
    // Hinge angle and cone-twist twist (rad), slider translation (m), distance
    // length (m), measured from the pose at creation; 0 for ball and fixed joints.
    Real jointPosition(JointId id) const;
    // Hinge: B's spin relative to A about the axis (rad/s); slider: the anchors'
    // relative velocity along the axis (m/s); 0 for the other types.
    Real jointVelocity(JointId id) const;
    // Hinge and slider: the torque (N m) or force (N) the joint applied to B
    // along its axis in the last step, i.e. jointReactionTorque along B's axis
    // now (hinge) or jointReactionForce along A's (slider): its spring (drive),
    // motor, friction and limits (what the actuator at a robot's joint
    // delivers); 0 for the other types and before the first step.
    Real jointEffort(JointId id) const;
    // A disabled joint is not solved and doesn't keep its bodies from colliding.
    void setJointEnabled(JointId id, bool enabled);    // re-enabling a broken joint mends it
    bool isJointEnabled(JointId id) const;
    bool isJointBroken(JointId id) const;              // broke over its threshold (events below)
    // Hinge and slider settings after creation (validated as in createJoint; wake the bodies).
    void setJointMotor(JointId id, const JointMotor& motor);
    void setJointLimits(JointId id, bool enabled, Real lower, Real upper);
    void setJointSpring(JointId id, const JointSpring& spring);
    // Six-DOF joints: one axis's limits, motor and spring after creation
    // (axis: SixDofAxisIndex; its mode stays the one it was created with:
    // a different mode is an error), and every axis's position, velocity and
    // effort now (efforts: the last step's reaction, as jointEffort).
    void setSixDofAxis(JointId id, int axis, const SixDofAxis& settings);
    // Cone-twist joints: the drive towards a target orientation (ConeTwistDrive).
    void setConeTwistDrive(JointId id, const ConeTwistDrive& drive);
    SixDofReading sixDofReading(JointId id) const;

    // ---- particle systems (Verlet ropes and cloths; docs/particles.md, "In the World")
    // They step inside step() after the rigid bodies, with the world's gravity,
    // collide with every body's shape (two-way) and may be attached to bodies
    // (RopeDef::attachStart / attachEnd: live BodyIds, else fulcrum::Error).
    // Destroying an attached body frees the particle it held.
    ParticleSystemId createRope(const RopeDef& def);
    ParticleSystemId createCloth(const ClothDef& def);
    void destroyParticleSystem(ParticleSystemId id);
    bool isValid(ParticleSystemId id) const;
    std::vector<ParticleSystemId> particleSystems() const;       // live systems in creation order
    const std::string& name(ParticleSystemId id) const;
    ParticleSystemType particleSystemType(ParticleSystemId id) const;
    std::array<int, 2> clothSize(ParticleSystemId id) const;      // cloth: particle (i, j) is j * size[0] + i; rope: {n, 1}
    std::size_t particleCount(ParticleSystemId id) const;
    Real particleRadius(ParticleSystemId id) const;               // largest particle radius, m
    std::span<const Vec3> particlePositions(ParticleSystemId id) const;  // valid until the next step or change
    Vec3 particleVelocity(ParticleSystemId id, std::size_t particle) const;  // over the last particle sub-step
    ParticleReport particleReport(ParticleSystemId id) const;

    // ---- characters (fulcrum/character.hpp, docs/characters.md)
    // Each character owns a kinematic capsule body (characterBody; category
    // kCharacterCategory) and moves at the end of every step, after the
    // bodies, in creation order, on the calling thread: it sees the poses the
    // step made, so it rides a moving platform without lagging a step behind.
    CharacterId createCharacter(const CharacterDef& def);
    void destroyCharacter(CharacterId id);               // and its capsule body
    bool isValid(CharacterId id) const;
    std::vector<CharacterId> characters() const;         // live characters in creation order
    const std::string& name(CharacterId id) const;
    const CharacterDef& characterDef(CharacterId id) const;  // as created
    BodyId characterBody(CharacterId id) const;
    CharacterState characterState(CharacterId id) const;
    // The held input from now on (until the script's next entry, if any):
    // desired velocity (m/s, horizontal part used; relative to the ground it
    // stands on) and whether to jump. Finite, else fulcrum::Error.
    void setCharacterInput(CharacterId id, const Vec3& velocity, bool jump);
    // Teleports the character (no collision on the way); it keeps its velocity.
    void setCharacterPosition(CharacterId id, const Vec3& position);

    // ---- simulation
    void step(Real dt);                                // throws NumericalError if the state goes NaN
    Real time() const;
    std::uint64_t stepCount() const;

    // ---- diagnostics
    // Energy and momenta include the particle systems (kinetic from their last
    // sub-step's velocity, gravity, elastic energy of compliant constraints).
    EnergyReport energy() const;
    // The last step's phase times and sizes (zeros before the first step).
    StepProfile lastStepProfile() const;
    // What the world warned about so far, oldest first (e.g. the contact pair
    // limit reached). Each kind once; not saved in snapshots.
    std::span<const WorldWarning> warnings() const;
    Vec3 linearMomentum() const;
    Vec3 angularMomentum() const;                      // about the world origin
    // The touching manifolds of the last step, built when first read after it
    // (const, but not safe to call from two threads at once).
    std::vector<ContactReport> contacts() const;
    // The sum of the contact forces on a body over the last step (N, world:
    // the contacts() forces, on B as reported and their opposite on A), and
    // the same for several bodies in one pass over the report (a robot's
    // links; a body listed twice gets its sum twice). Reads the contact report
    // (as contacts()); a stale handle is a fulcrum::Error.
    Vec3 contactForce(BodyId body) const;
    std::vector<Vec3> contactForces(std::span<const BodyId> bodies) const;
    // The touching pairs of the last step whose depth is more than `fraction`
    // of their `size` (DeepOverlap), deepest first. Resting contacts overlap
    // by millimetres; a pair listed here is one the solver did not hold apart,
    // e.g. a heavy body on a light one beyond the mass ratio the solver holds
    // (docs/solver.md, "Mass ratios"). fraction must be finite and > 0
    // (else fulcrum::Error). Reads the contact report (as contacts()).
    std::vector<DeepOverlap> deepOverlaps(Real fraction = Real(0.1)) const;

    // ---- events of the last step (valid until the next step; no allocation)
    std::span<const ContactEvent> contactBeginEvents() const;  // pairs that started touching
    std::span<const ContactEvent> contactEndEvents() const;    // pairs that stopped touching (or were destroyed)
    std::span<const ContactEvent> sensorBeginEvents() const;   // a body started overlapping a sensor
    std::span<const ContactEvent> sensorEndEvents() const;     // ... stopped overlapping it
    std::span<const JointBreakEvent> jointBreakEvents() const; // joints that broke
    // Impacts faster than WorldDef::hitEventThreshold (ContactHitEvent), in
    // the solver's constraint order (the same for every thread count). Built
    // when first read after a step, like contacts().
    std::span<const ContactHitEvent> contactHitEvents() const;

    // ---- queries (include/fulcrum/query.hpp, docs/queries.md) ----------------
    // Read-only and valid at any time between steps: bodies created, moved
    // (setTransform) or destroyed since the last step are seen as they are now.
    // Shapes are tested exactly, after a broad-phase cull. Bad input (NaN/inf,
    // a zero ray, maxFraction outside [0, 1], a negative radius, a shape that
    // cannot be used) throws fulcrum::Error naming the query and the field.
    // Results list each body once; overlaps are in creation order (as
    // bodies()), ray hits by fraction, ties broken by creation order. The
    // overloads taking `out` clear it and fill it, allocating only when it
    // must grow.
    //
    // Ray casts: the closest hit, or every body the ray enters (its first hit
    // on each body), sorted by fraction. A ray starting inside a solid shape
    // hits it at fraction 0.
    std::optional<RayCastHit> castRay(const Ray& ray, const QueryFilter& filter = {}) const;
    std::vector<RayCastHit> castRayAll(const Ray& ray, const QueryFilter& filter = {}) const;
    void castRayAll(const Ray& ray, std::vector<RayCastHit>& out, const QueryFilter& filter = {}) const;
    // Bodies whose shape's tight bounds (Shape::bounds at the current pose)
    // overlap `box`; planes are tested as exact half-spaces.
    std::vector<BodyId> overlapAABB(const AABB& box, const QueryFilter& filter = {}) const;
    void overlapAABB(const AABB& box, std::vector<BodyId>& out, const QueryFilter& filter = {}) const;
    // Bodies whose shape truly overlaps (or touches) a sphere / an oriented
    // box / any non-static-only Shape at a transform (GJK on the convex parts).
    // Meshes count as surfaces: a shape wholly inside a closed mesh does not overlap it.
    std::vector<BodyId> overlapSphere(const Vec3& center, Real radius, const QueryFilter& filter = {}) const;
    void overlapSphere(const Vec3& center, Real radius, std::vector<BodyId>& out, const QueryFilter& filter = {}) const;
    std::vector<BodyId> overlapBox(const Vec3& center, const Vec3& halfExtents, const Quat& orientation,
                                   const QueryFilter& filter = {}) const;
    void overlapBox(const Vec3& center, const Vec3& halfExtents, const Quat& orientation, std::vector<BodyId>& out,
                    const QueryFilter& filter = {}) const;
    std::vector<BodyId> overlapShape(const Shape& shape, const Transform& transform, const QueryFilter& filter = {}) const;
    void overlapShape(const Shape& shape, const Transform& transform, std::vector<BodyId>& out,
                      const QueryFilter& filter = {}) const;
    // Sweeps a convex shape (or a compound of convex shapes) from `transform`
    // along `translation` (no rotation) and returns its first contact with any
    // body. Starting in contact gives fraction 0.
    std::optional<ShapeCastHit> castShape(const Shape& shape, const Transform& transform, const Vec3& translation,
                                          const QueryFilter& filter = {}) const;
    // Closest points and distance between two bodies, or a shape placed at
    // `transform` and a body (GJK; EPA for the depth when they overlap):
    // convex shapes, planes and compounds of them (the closest pair of
    // children). Meshes and heightfields are refused (no bound on the search).
    ClosestPoints closestPoints(BodyId a, BodyId b) const;
    ClosestPoints closestPoints(const Shape& shape, const Transform& transform, BodyId body) const;
    Real distanceBetween(BodyId a, BodyId b) const;  // closestPoints(a, b).distance (not "distance": World members call the Vec3 one)

private:
    friend struct detail::WorldAccess;
    std::unique_ptr<WorldImpl> impl_;
};

// Fixed-step accumulator for variable frame rates: call advance(frameSeconds)
// each frame; it runs whole steps of `dt` (at most `maxSteps` per frame, to
// avoid the spiral of death) and alpha() says how far the render time sits
// between the last two steps, for interpolated transforms.
class FixedStepper {
public:
    FixedStepper(World& world, Real dt, int maxSteps = 8);
    int advance(Real frameSeconds);
    Real alpha() const { return alpha_; }
    Transform interpolatedTransform(BodyId id) const;

private:
    World* world_;
    Real dt_;
    int maxSteps_;
    Real accumulator_ = 0;
    Real alpha_ = 0;
};

}  // namespace fulcrum
