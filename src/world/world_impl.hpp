#pragma once
// WorldImpl: the internal state behind fulcrum::World. The collision pipeline
// and the constraint solver plug into this struct, so its layout is a contract
// inside the engine; read this comment before adding to it.
//
// Bodies
// ------
// Users hold BodyId {index, generation}. `index` names a *slot* in `bodySlots`;
// the slot stores the generation and the body's position in the *dense* arrays.
// Destroying a body frees the slot (generation + 1, pushed on `freeBodySlots`) and
// swap-removes the body from the dense arrays, so the dense arrays never have
// holes and every per-body loop is a straight walk over contiguous memory.
// A handle is valid iff its index is in range, the slot is live and the
// generations match; `resolveBody` is the only way from a handle to a dense
// index, and it throws fulcrum::Error for a null, out-of-range or stale handle.
//
// Per-body data is split by how often the step touches it (hot / warm / cold
// tiers, as Box2D v3 splits its body sim, state and body records):
//   motion[]    hot: centre of mass, orientation, velocities, inverse mass and
//               world inverse inertia. Read and written every sub-step by the
//               integrators and (later) the solver.
//   forces[]    hot scratch: the force and torque of the latest evaluation.
//   applied[]   user forces/torques from applyForce & co., summed into every
//               evaluation of the next step, then cleared.
//   params[]    warm: per-body constants the step reads (type, local inertia,
//               local centre of mass, damping, drag, gravity scale, material).
//   cold[]      cold: name, shape, callback, creation order. Never read by the
//               inner loops except to call a ForceCallback.
//   previous[]  body-origin transform at the start of the last step (interpolation).
//   denseToSlot maps a dense index back to its slot (for BodyIds in reports).
// Static bodies live in the same dense arrays with zero inverse mass; the
// step skips them.
//
// Awake list: `awakeBodies` holds the dense index of every awake non-static
// body in ascending order, so the per-body stages (forces, integration, the
// proxy update, the NaN check) cost nothing for sleeping and static bodies,
// the effect of Box2D v3's awake solver set without moving any body. It is a
// pure function of the state (ascending, awake, non-static), so it never
// changes results: it is only kept up to date cheaply. wakeBody() queues the
// bodies it wakes in `wokenBodies`; the sleep manager flags that bodies fell
// asleep; creating or destroying a body (the swap-remove renumbers) or loading
// a snapshot asks for a full rebuild. refreshAwakeList() applies all that at
// the two points of the step that need the list current: before the proxy
// update and after the contact manager's wakes. A step on a world that is
// entirely asleep then touches no body at all.
//
// previous[] (the interpolation transform) is refreshed at the start of a step
// for the awake bodies only; a body that stopped moving (fell asleep,
// teleported, created) is queued in `previousStale` for one more refresh, after
// which previous[] equals its transform for as long as it stays asleep.
//
// The integrated position is the centre of mass; the body origin (the shape's
// frame, what users see as `position`) is derived: origin = com - q * localCom.
//
// Springs and joints
// ------------------
// Stored in slot pools (dynamics/slot_pool.hpp: a generation and an `alive`
// flag per slot; they are few and rarely iterated outside the step, so holes
// are fine). They refer to
// bodies by BodyId and resolve the dense index when used; a body's
// destruction destroys its springs and joints first, so they never hold a
// stale BodyId. Anchors are stored relative to the body's centre of mass in
// body axes (world-fixed ends keep their world point).
//
// Contacts
// --------
// `contacts` holds the touching manifolds of the last step as ContactReports
// (src/contacts/contact_manager.hpp fills it). World::contacts() returns a copy of
// the first contactReportCount entries. The report is built lazily: the step
// only marks it stale, and ensureContactReport() builds it from the contacts as
// the step left them when someone reads it (World::contacts(), snapshots), or
// before anything changes those contacts between steps (a body destroyed, a
// joint resetting pairs). Same reports as building it in every step, without
// the O(all contacts) pass per step (23 % of an all-asleep box_pile step).
//
// No heap allocation per step: every scratch array is sized when bodies are
// created and reused.
#include <cstdint>
#include <string>
#include <vector>

#include "fulcrum/task_system.hpp"
#include "fulcrum/world.hpp"
#include "contacts/contact_manager.hpp"
#include "dynamics/slot_pool.hpp"
#include "solver/contact_solver.hpp"
#include "solver/joint_solver.hpp"
#include "islands/sleep.hpp"
#include "world/particle_coupling.hpp"
#include "world/stray_bodies.hpp"

namespace fulcrum {

namespace detail {

inline constexpr std::uint32_t kNoIndex = UINT32_MAX;

// Hot per-body state (the integrators' and the solver's working set).
struct BodyMotion {
    Vec3 com;                       // centre of mass, world
    Quat q;                         // orientation (unit)
    Vec3 v;                         // linear velocity of the centre of mass
    Vec3 w;                         // angular velocity, world
    Real invMass = 0;               // 0 for static and kinematic bodies
    Mat3 invInertiaWorld = Mat3::zero();  // R I_body^-1 R^T; zero for static and kinematic
};

struct ForceTorque {
    Vec3 force;   // at the centre of mass
    Vec3 torque;  // world
};

// Warm per-body constants.
struct BodyParams {
    BodyType type = BodyType::Dynamic;
    bool awake = true;
    bool allowSleep = true;
    bool isSensor = false;
    bool isBullet = false;
    Real mass = 0;                  // 0 for static and kinematic bodies
    Vec3 localCom;                  // centre of mass in the shape's frame
    Mat3 localInertia = Mat3::zero();     // about the centre of mass, body axes
    Mat3 invLocalInertia = Mat3::zero();
    Real linearDamping = 0, angularDamping = 0;
    Real linearDrag = 0, quadraticDrag = 0;
    Real gravityScale = 1;
    Real friction = Real(0.6), restitution = 0, rollingResistance = 0;
    CollisionFilter filter;
    Real extent = 0;                 // farthest shape point from the centre of mass (0 for static bodies)
    Real sleepTime = 0;              // seconds spent below the sleep speeds (islands/sleep.hpp)
    std::uint32_t sleepIsland = 0;   // while asleep: the island it fell asleep with (0: none)
};

struct BodyCold {
    std::string name;
    Shape shape;
    ForceCallback callback;         // empty: none
    std::uint64_t creationSerial = 0;  // orders World::bodies() by creation
};

struct BodySlot {
    std::uint32_t dense = kNoIndex;  // kNoIndex when the slot is free
    std::uint32_t generation = 0;
};

struct SpringData : PoolSlot {
    BodyId bodyA, bodyB;             // null: the static world
    Vec3 localA, localB;             // from the centre of mass, body axes; world point for a world end
    Real restLength = 0, stiffness = 0, damping = 0;
};

struct JointData : PoolSlot {
    JointDef def;                    // as created (validated; axis normalised)
    Vec3 localAnchorA, localAnchorB; // from each body's centre of mass, body axes (world point for the world)
    Vec3 localAxisA, localAxisB;     // unit axis in each body's axes (world axis for the world)
    Real minLength = 0, maxLength = 0;  // distance joints, resolved (no negative "use creation" values)
    // Joint solver runtime (src/solver/joint_solver.hpp).
    Quat relativeRotation;           // conj(qA) qB at creation: the rest pose angles are measured from
    Real restLength = 0;             // soft distance joints: the spring's rest length
    bool enabled = true;             // false once broken or disabled by the user
    bool broken = false;
    JointImpulses impulses;          // accumulated sub-step impulses (warm starting)
    Vec3 reactionForce, reactionTorque;  // on B, last step
};

// Scratch of the integrators, one entry per dense body.
struct IntegratorScratch {
    // Explicit Euler: the velocity change that forces caused this sub-step, so
    // the position stage can drift with the *old* velocity (plus whatever a
    // solver changes). Verlet: the half-step velocity between the two kicks.
    Vec3 dv, dw;
};

}  // namespace detail

struct WorldImpl {
    WorldDef settings;
    double time = 0;                 // double: a float clock loses sub-steps after hours
    std::uint64_t stepCount = 0;
    StepProfile profile;  // the last step's (World::lastStepProfile)
    std::uint64_t nonFiniteSinceStep = 0;  // != 0: that step threw NumericalError (World::step)
    std::uint64_t outOfMemoryAtStep = 0;   // != 0: that step ran out of memory; no more steps (World::step)
    std::vector<WorldWarning> warnings;    // World::warnings: each kind once
    bool warnedPairLimit = false;          // the contact pair limit was reached (step.cpp)
    std::uint64_t nextBodySerial = 0;

    // ---- bodies (see the comment at the top)
    std::vector<detail::BodySlot> bodySlots;
    std::vector<std::uint32_t> freeBodySlots;
    std::vector<detail::BodyMotion> motion;
    std::vector<detail::ForceTorque> forces;
    std::vector<detail::ForceTorque> applied;
    std::vector<detail::BodyParams> params;
    std::vector<detail::BodyCold> cold;
    std::vector<Transform> previous;
    std::vector<std::uint32_t> denseToSlot;
    std::vector<detail::IntegratorScratch> scratch;

    // ---- springs and joints
    detail::SlotPool<detail::SpringData, SpringId> springs;
    detail::SlotPool<detail::JointData, JointId> joints;

    // ---- contacts of the last step (filled by the collision pipeline): the
    // first contactReportCount entries are valid; the rest keep their capacity
    // so reporting allocates nothing in steady state.
    std::vector<ContactReport> contacts;
    std::size_t contactReportCount = 0;
    bool contactReportStale = false;  // the step ran since `contacts` was built (see above)
    void ensureContactReport() {
        if (!contactReportStale) return;
        contactManager.report(*this);
        contactReportStale = false;
    }

    // ---- awake list (see "Awake list" at the top)
    std::vector<std::uint32_t> awakeBodies;     // awake non-static dense bodies, ascending
    std::vector<std::uint32_t> wokenBodies;     // woken since the last refresh (any order)
    std::vector<std::uint32_t> awakeMergeScratch;
    std::vector<std::uint8_t> inAwakeList;      // per dense body: listed in awakeBodies
    bool awakeListRebuild = true;               // full rebuild at the next refresh
    bool awakeListHasSleepers = false;          // bodies fell asleep since the last refresh
    std::vector<std::uint32_t> previousStale;   // dense bodies whose previous[] needs one refresh
    bool previousAllStale = true;               // refresh every previous[] at the next step
    // Brings awakeBodies up to date: O(awake + woken) unless a rebuild is due.
    void refreshAwakeList();
    // After a change of the dense arrays (creation, destruction, loading).
    void invalidateAwakeList() {
        awakeListRebuild = true;
        previousAllStale = true;
    }
    void markPreviousStale(std::uint32_t dense) {
        if (previousStale.size() >= motion.size()) {
            previousAllStale = true;
            previousStale.clear();
        }
        if (!previousAllStale) previousStale.push_back(dense);
    }
    // Grows the awake-list buffers for `bodyCount` bodies (body creation: no allocation in a step).
    void reserveAwakeList(std::size_t bodyCount);

    // ---- collision pipeline and solver (src/solver)
    detail::ContactManager contactManager;
    detail::ContactSolver contactSolver;
    detail::JointSolver jointSolver;
    detail::SleepManager sleepManager;
    bool wasSleeping = true;         // settings.sleeping at the last step (turning it off wakes all)

    // ---- particle systems: ropes and cloths (src/world/particle_coupling.hpp)
    detail::WorldParticles particles;

    // ---- world queries (src/world/world_queries.cpp): bodies that have left
    // their broad-phase proxy since it was last moved. Rebuilt lazily per step;
    // code that moves bodies outside step() and setTransform must invalidate it.
    detail::StrayBodies strayBodies;

    // ---- threads (src/world/step.cpp, docs/threading.md): the scheduler the
    // step's parallel loops run on. A user's (setTaskSystem) if set, else the
    // inline one for threads == 1, else a pool created on first use.
    TaskSystem* userTasks = nullptr;
    std::unique_ptr<TaskSystem> ownedPool;
    int ownedPoolThreads = 0;
    InlineTaskSystem inlineTasks;
    bool stepOnCaller = false;  // this step is below settings.parallelMinBodies: inline
    TaskSystem& taskSystem();

    // Wakes a non-static body and, if it sleeps, its whole island; resets its sleep timer.
    void wakeBody(std::uint32_t dense);

    // Dense index of a live body; throws fulcrum::Error naming `where` for a
    // null, out-of-range or stale handle.
    std::uint32_t resolveBody(BodyId id, const char* where) const;
    bool isLive(BodyId id) const {
        return !id.isNull() && id.index < bodySlots.size() && bodySlots[id.index].dense != detail::kNoIndex &&
               bodySlots[id.index].generation == id.generation;
    }
    BodyId idOfDense(std::uint32_t dense) const {
        const std::uint32_t slot = denseToSlot[dense];
        return {slot, bodySlots[slot].generation};
    }
    // "body 'ball'" or "body #3", for messages.
    std::string describeBody(std::uint32_t dense) const;

    detail::SpringData& resolveSpring(SpringId id, const char* where);
    const detail::SpringData& resolveSpring(SpringId id, const char* where) const;
    detail::JointData& resolveJoint(JointId id, const char* where);
    const detail::JointData& resolveJoint(JointId id, const char* where) const;

    // Body origin (shape frame) of a dense body.
    Vec3 origin(std::uint32_t dense) const {
        return motion[dense].com - rotate(motion[dense].q, params[dense].localCom);
    }
    Transform originTransform(std::uint32_t dense) const { return {origin(dense), motion[dense].q}; }
    // R I_body^-1 R^T after an orientation change (zero for non-dynamic bodies).
    void updateWorldInertia(std::uint32_t dense) {
        detail::BodyMotion& m = motion[dense];
        const Mat3 r = toMat3(m.q);
        m.invInertiaWorld = r * params[dense].invLocalInertia * transpose(r);
    }

    // World point of an anchor stored relative to a body's centre of mass
    // (or the point itself for a world end, dense == kNoIndex).
    Vec3 anchorWorld(std::uint32_t dense, const Vec3& local) const {
        return dense == detail::kNoIndex ? local : motion[dense].com + rotate(motion[dense].q, local);
    }
    std::uint32_t denseOrNone(BodyId id) const { return id.isNull() ? detail::kNoIndex : bodySlots[id.index].dense; }

    // The step (src/world/step.cpp).
    void step(Real dt);
    void notePairLimit(StepProfile& prof);  // the step's pair-limit counts and warning
};

}  // namespace fulcrum
