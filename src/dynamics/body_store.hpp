#pragma once
// BodyStore: every body's data, and during a step the one home of the awake
// bodies' state. It sits below the solver: the collision pipeline, the
// contact and joint solvers, time of impact, islands, the integrators and the
// force evaluation take a BodyStore (plus the settings and the task system
// they need) and never the world. WorldImpl (src/world/world_impl.hpp) is a
// BodyStore plus the rest of the world.
//
// Records
// -------
// Users hold BodyId {index, generation}. `index` names a *slot* in `bodySlots`;
// the slot stores the generation and the body's position in the *dense* arrays.
// Destroying a body frees the slot (generation + 1, pushed on `freeBodySlots`) and
// swap-removes the body from the dense arrays, so the dense arrays never have
// holes and every per-body loop is a straight walk over contiguous memory.
// A handle is valid iff its index is in range, the slot is live and the
// generations match; `resolveBody` is the only way from a handle to a dense
// index, and it throws fulcrum::Error for a null, out-of-range or stale handle.
//
// Per-body data is split by how often the step touches it (Box2D v3's hot /
// warm / cold tiers):
//   motion[]    the body's record: centre of mass, orientation, velocities,
//               inverse mass and world inverse inertia. Between steps it is
//               the truth; during the sub-steps an awake body's record is
//               stale (its state lives in the awake set, below) and is written
//               once when the sub-steps end.
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
// Awake list
// ----------
// `awakeBodies` holds the dense index of every awake non-static body in
// ascending order, so the per-body stages cost nothing for sleeping and static
// bodies. It is a pure function of the state (ascending, awake, non-static),
// so it never changes results: it is only kept up to date cheaply. wakeBody()
// queues the bodies it wakes in `wokenBodies` (the wake queue: subsystems that
// wake bodies call it and the world applies the queue at its next refresh);
// the sleep manager flags that bodies fell asleep; creating or destroying a
// body (the swap-remove renumbers) or loading a snapshot asks for a full
// rebuild. refreshAwakeList() applies all that at the two points of the step
// that need the list current: before the proxy update and after the contact
// manager's wakes. A step on a world that is entirely asleep then touches no
// body at all.
//
// previous[] (the interpolation transform) is refreshed at the start of a step
// for the awake bodies only; a body that stopped moving (fell asleep,
// teleported, created) is queued in `previousStale` for one more refresh, after
// which previous[] equals its transform for as long as it stays asleep.
//
// The awake set: the one home of awake state during a step
// ---------------------------------------------------------
// beginStep() copies the awake bodies' records into the awake set, indexed by
// *solver index* i = k + 1 for awakeBodies[k]; entry 0 is an all-zero static
// body that stands for every static body (writes to it add zero, so
// constraints need no branch for a static end). From then until
// writeRecords() every stage of the step reads and writes an awake body there
// and only there: force evaluation, the three integrators, the contact and
// joint kernels, the joint position projection and the time of impact.
// writeRecords() writes the records back once, after the time of impact
// (sleeping, particles, queries and users read the records).
// Before, the integrators worked on motion[] and the kernels on the contact
// solver's own copy, and velocities crossed between them four times per
// sub-step (docs/solver.md, "Solver bodies").
//   state[i]   SolverBody: velocities, inverse mass, the step-start world
//              inverse inertia and the pose change since the step's start
//              (dp, dtheta) — exactly what the constraint kernels read (96
//              bytes, the rows the wide kernels load).
//   pose[i]    BodyPose: centre of mass, orientation and the current world
//              inverse inertia — what the integrators and the projection
//              move. A separate array so the kernels' rows stay 96 bytes.
//   startCom[i], startQ[i]: the pose at the step's start (deltas, time of
//              impact, the sleep test).
// Every stage that writes the awake set writes only the entries of the
// indices it was given (or runs alone), so the results are the same for any
// thread count.
//
// No heap allocation per step: every array is sized when bodies are created.
#include <cstdint>
#include <string>
#include <vector>

#include "dynamics/zero_tail_array.hpp"
#include "math/large_array.hpp"
#include "fulcrum/world.hpp"

namespace fulcrum::detail {

inline constexpr std::uint32_t kNoIndex = UINT32_MAX;

// A body's record (see "Records" above).
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

// Scratch of the integrators, one entry per dense body.
struct IntegratorScratch {
    // Explicit Euler: the velocity change that forces caused this sub-step, so
    // the position stage can drift with the *old* velocity (plus whatever a
    // solver changes). Verlet: the half-step velocity between the two kicks.
    Vec3 dv, dw;
};

// An awake body's velocity state in the awake set (see the top): what the
// constraint kernels read and write.
struct SolverBody {
    Vec3 v;                     // linear velocity of the centre of mass
    Real invMass = 0;
    Vec3 w;                     // angular velocity, world
    Vec3 dp;                    // centre-of-mass displacement since the step's start
    Vec3 dtheta;                // rotation since the step's start as a rotation vector (R = exp(dtheta) R0)
    Mat3 invI = Mat3::zero();   // world inverse inertia at the step's start
    Real padding[2] = {0, 0};   // 96 bytes: the wide kernels read whole rows of 4 floats (contact_wide.cpp)
};

// An awake body's pose in the awake set. com and q lead, as in BodyMotion:
// the joint projection's check loads both as 7 consecutive floats.
struct BodyPose {
    Vec3 com;                             // centre of mass, world
    Quat q;                               // orientation (unit)
    Mat3 invInertiaWorld = Mat3::zero();  // R I_body^-1 R^T now; zero for kinematic bodies
};

// toRotationVector for the small turns of one step, without atan2 (with the
// atan2f/atanf calls, the deltas were 5.4 % of a sphere pile's instructions):
// 2 atan(s / w) / s = (2 / w)(1 - x^2/3 + x^4/5 - x^6/7 + ...), x = s / w. For
// x < 0.1 (turns under ~11 degrees since the step's start) the first omitted
// term, x^8/9 < 1.2e-9, is far below float precision; larger turns take the
// exact path.
inline Vec3 stepRotationVector(const Quat& q) {
    const Quat p = q.w < 0 ? -q : q;  // shortest arc
    const Real s2 = lengthSquared(p.vec());
    const Real w2 = p.w * p.w;
    if (s2 < Real(0.01) * w2) {
        const Real x2 = s2 / w2;
        const Real series = 1 - x2 * (Real(1) / 3 - x2 * (Real(1) / 5 - x2 * (Real(1) / 7)));
        return p.vec() * (Real(2) / p.w * series);
    }
    return toRotationVector(p);
}

struct BodyStore {
    // ---- records (see the top)
    LargeArray<BodySlot> bodySlots;
    std::vector<std::uint32_t> freeBodySlots;
    LargeArray<BodyMotion> motion;
    // forces, applied and scratch: entries a static or sleeping body never
    // writes stay unwritten (no pages touched: dynamics/zero_tail_array.hpp).
    ZeroTailArray<ForceTorque> forces;
    ZeroTailArray<ForceTorque> applied;
    LargeArray<BodyParams> params;
    LargeArray<BodyCold> cold;
    LargeArray<Transform> previous;
    LargeArray<std::uint32_t> denseToSlot;
    ZeroTailArray<IntegratorScratch> scratch;
    // Whether any body was ever given a ForceCallback (World::setForceCallback;
    // never cleared): while false, the force evaluation does not read cold[]
    // to look for one (a 64-byte line per awake body and evaluation, for
    // nothing in nearly every world).
    bool anyForceCallback = false;

    // ---- awake list (see "Awake list" at the top)
    std::vector<std::uint32_t> awakeBodies;     // awake non-static dense bodies, ascending
    std::vector<std::uint32_t> wokenBodies;     // the wake queue: woken since the last refresh (any order)
    std::vector<std::uint32_t> awakeMergeScratch;
    LargeArray<std::uint8_t> inAwakeList;      // per dense body: listed in awakeBodies
    bool awakeListRebuild = true;               // full rebuild at the next refresh
    bool awakeListHasSleepers = false;          // bodies fell asleep since the last refresh
    std::vector<std::uint32_t> previousStale;   // dense bodies whose previous[] needs one refresh
    bool previousAllStale = true;               // refresh every previous[] at the next step

    // ---- the awake set (see the top): per solver index, entry 0 the static body
    std::vector<SolverBody> state;
    std::vector<BodyPose> pose;
    std::vector<Vec3> startCom;
    std::vector<Quat> startQ;
    std::vector<std::uint32_t> denseOfSolver;   // solver index -> dense (entry 0: kNoIndex)
    LargeArray<std::uint32_t> solverOfDense;   // dense -> solver index (0: static or asleep)

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
    // Grows the awake-list and awake-set buffers for `bodyCount` bodies (body
    // creation: no allocation in a step).
    void reserveAwakeList(std::size_t bodyCount);
    // The most bodies those buffers hold without growing, as of the last
    // reserveAwakeList that grew them (nothing else grows or shrinks them).
    std::size_t awakeListRoom = 0;
    // Wakes a non-static body and, if it sleeps, its whole island; resets its
    // sleep timer. The woken bodies join the awake list at its next refresh.
    void wakeBody(std::uint32_t dense);

    // Dense index of a live body; throws fulcrum::Error naming `where` for a
    // null, out-of-range or stale handle.
    std::uint32_t resolveBody(BodyId id, const char* where) const;
    bool isLive(BodyId id) const {
        return !id.isNull() && id.index < bodySlots.size() && bodySlots[id.index].dense != kNoIndex &&
               bodySlots[id.index].generation == id.generation;
    }
    BodyId idOfDense(std::uint32_t dense) const {
        const std::uint32_t slot = denseToSlot[dense];
        return {slot, bodySlots[slot].generation};
    }
    // "body 'ball'" or "body #3", for messages.
    std::string describeBody(std::uint32_t dense) const;

    // Body origin (shape frame) of a dense body, from its record.
    Vec3 origin(std::uint32_t dense) const { return motion[dense].com - rotate(motion[dense].q, params[dense].localCom); }
    Transform originTransform(std::uint32_t dense) const { return {origin(dense), motion[dense].q}; }
    // R I_body^-1 R^T after an orientation change of the record (zero for non-dynamic bodies).
    void updateWorldInertia(std::uint32_t dense) {
        BodyMotion& m = motion[dense];
        const Mat3 r = toMat3(m.q);
        m.invInertiaWorld = r * params[dense].invLocalInertia * transpose(r);
    }
    // World point of an anchor stored relative to a body's centre of mass
    // (or the point itself for a world end, dense == kNoIndex), from the record.
    Vec3 anchorWorld(std::uint32_t dense, const Vec3& local) const {
        return dense == kNoIndex ? local : motion[dense].com + rotate(motion[dense].q, local);
    }
    std::uint32_t denseOrNone(BodyId id) const { return id.isNull() ? kNoIndex : bodySlots[id.index].dense; }

    // ---- the awake set during a step
    // Fills the awake set from the records of the awake list (each entry by
    // one index: `forRanges(count, fn)` may spread them over threads).
    template <class ForRanges>
    void beginStep(ForRanges&& forRanges);
    // The pose and velocities of dense body d as they are now: the awake set's
    // for an awake body during the sub-steps, else its record.
    std::uint32_t solverIndexOf(std::uint32_t dense) const {
        return dense < solverOfDense.size() ? solverOfDense[dense] : 0;
    }
    const Vec3& comNow(std::uint32_t d) const {
        const std::uint32_t i = solverIndexOf(d);
        return i != 0 ? pose[i].com : motion[d].com;
    }
    const Quat& orientationNow(std::uint32_t d) const {
        const std::uint32_t i = solverIndexOf(d);
        return i != 0 ? pose[i].q : motion[d].q;
    }
    const Vec3& velocityNow(std::uint32_t d) const {
        const std::uint32_t i = solverIndexOf(d);
        return i != 0 ? state[i].v : motion[d].v;
    }
    const Vec3& angularVelocityNow(std::uint32_t d) const {
        const std::uint32_t i = solverIndexOf(d);
        return i != 0 ? state[i].w : motion[d].w;
    }
    Vec3 anchorNow(std::uint32_t dense, const Vec3& local) const {
        return dense == kNoIndex ? local : comNow(dense) + rotate(orientationNow(dense), local);
    }
    // dp and dtheta of solver body i from its pose now vs the step's start.
    void updateDeltas(std::uint32_t i) {
        state[i].dp = pose[i].com - startCom[i];
        state[i].dtheta = stepRotationVector(pose[i].q * conjugate(startQ[i]));
    }
    // The same for the solver bodies of awake-list entries [begin, end).
    void updateDeltas(std::size_t begin, std::size_t end);
    // Per solver index: whether a contact constraint of this step reads the
    // body's deltas (zeroed by beginStep, set by the contact solver's
    // prepare). A step with contacts and no joints updates only those bodies'
    // deltas after each sub-step's positions (updateContactDeltas): nothing
    // else reads them, and a body in free flight has no constraint (Jolt's
    // HighSpeed: 5000 tumbling bullets, ~200 in contact at a time; the
    // deltas of all of them, a rotation vector with atan2 each, were 5.7 %
    // of its step). Steps with joints update every body's (the joint
    // solver's rows read them too).
    std::vector<std::uint8_t> contactDeltas;
    // Per solver index: the body's MotionKind for this step (integrators.hpp,
    // classifyMotion; written in the step's prepare, entry 0 unused).
    std::vector<std::uint8_t> motionKind;
    void updateContactDeltas(std::size_t begin, std::size_t end);
    // The awake set back into the records of awake-list entries [begin, end)
    // (solver bodies begin + 1 .. end): once, after the sub-steps.
    void writeRecords(std::size_t begin, std::size_t end);
};

template <class ForRanges>
void BodyStore::beginStep(ForRanges&& forRanges) {
    const std::size_t count = motion.size();
    const std::size_t solverCount = awakeBodies.size() + 1;
    // solverOfDense is zero but at the last step's awake set (only this
    // function writes either map): clear those entries, not the whole array.
    // Assigning it whole cost every step O(all bodies): 4 MB of memset a step
    // for Box3D's large_world (a million static boxes, a hundred spheres).
    for (std::size_t i = 1; i < denseOfSolver.size(); ++i) {
        if (denseOfSolver[i] < solverOfDense.size()) solverOfDense[denseOfSolver[i]] = 0;
    }
    solverOfDense.resize(count, 0);
    state.resize(solverCount);
    pose.resize(solverCount);
    denseOfSolver.resize(solverCount);
    startCom.resize(solverCount);
    startQ.resize(solverCount);
    contactDeltas.assign(solverCount, 0);
    motionKind.resize(solverCount);
    state[0] = SolverBody{};
    pose[0] = BodyPose{};
    denseOfSolver[0] = kNoIndex;
    startCom[0] = {};
    startQ[0] = {};
    forRanges(awakeBodies.size(), [this](std::size_t begin, std::size_t end) {
        for (std::size_t k = begin; k < end; ++k) {
            const std::uint32_t d = awakeBodies[k];
            const std::size_t i = k + 1;
            const BodyMotion& m = motion[d];
            solverOfDense[d] = static_cast<std::uint32_t>(i);
            SolverBody b;
            b.v = m.v;
            b.w = m.w;
            b.invMass = m.invMass;
            b.invI = m.invInertiaWorld;
            state[i] = b;
            pose[i] = BodyPose{m.com, m.q, m.invInertiaWorld};
            denseOfSolver[i] = d;
            startCom[i] = m.com;
            startQ[i] = m.q;
        }
    });
}

}  // namespace fulcrum::detail
