#pragma once
// The joint solver: joints as constraints in the contact solver's soft step
// (docs/joints.md has the long form).
//
// It works on the body store's awake set (src/dynamics/body_store.hpp:
// awake dynamic and kinematic bodies, entry 0 the static stand-in), as the
// contact solver and the integrators do, so joints and contacts act on the
// same velocities inside one sub-step: a ragdoll lying on the floor is one
// problem. Per step the step calls prepare() after the contact solver's
// prepare; per sub-step warmStart() and solve(true) before the contacts',
// projectPositions() after the position integration, and solve(false)
// (relax) before theirs; after the sub-steps store(), which keeps the
// impulses for warm starting, computes reaction forces and breaks joints
// over their thresholds (the world re-examines the broken joints' pairs).
//
// Order: joints before contacts in every pass (Box2D v3's order). Joints are
// graph-coloured on their own (greedy, creation order; contacts have their
// colouring in the contact solver) and solved colour by colour: a large
// colour runs across the task system with the same result, and so do the
// joint trees, side by side (docs/threading.md, "Joints across the task system").
// Point rows of joint trees (chains, ragdolls) are solved exactly by the tree
// solver (joints/tree_solver.hpp) after the Gauss-Seidel rows of each pass.
// The Gauss-Seidel ball joints, hinges and cone-twists of a colour run 4 or 8
// at a time in SIMD lanes (joints/joint_wide.hpp) with the scalar kernels'
// bits; setSimdPath.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "fulcrum/world.hpp"
#include "dynamics/body_store.hpp"
#include "solver/joint_data.hpp"
#include "solver/joints/joint_common.hpp"
#include "solver/joints/joint_graph.hpp"
#include "solver/joints/joint_wide.hpp"
#include "solver/joints/tree_solver.hpp"

namespace fulcrum::detail {

// The settings the joint solver reads (WorldDef's joint*).
struct JointSettings {
    Real hertz = 60, dampingRatio = 2, projectionSlop = Real(0.005);
    bool directSolve = true;
};

// Joint stiffness: soft at WorldDef::jointHertz (60) with damping ratio
// jointDampingRatio (2), capped at a quarter of the sub-step rate (solver
// notes; half the rate exploded); anchor separations beyond
// jointProjectionSlop (5 mm) are removed at the position level after each
// sub-step. docs/joints.md records the measurements behind the values (chain
// scene, Gauss-Seidel rows: zeta 5 -> 11.5 cm worst stretch, zeta 2 -> 8.3 cm,
// + projection -> 5.6 cm; rigid rows lost half a double pendulum's energy in
// 20 s; with the tree solver 1.1 cm).
struct JointTuning {
    static constexpr Real kMaxHertzPerSubstepRate = Real(0.25);
    // Position projection: Gauss-Seidel passes at most (JointSolver::projectPositions).
    static constexpr int kMaxProjectionPasses = 4;
};

class JointSolver {
public:
    JointSolver() { setSimdPath(initialSimdPath()); }
    // Which code solves the wide joints (joints/joint_wide.hpp, wideKind):
    // the scalar kernels (the reference) or 4 / 8 SIMD lanes, with the same
    // bits either way. The default is the contact solver's: initialSimdPath()
    // (FULCRUM_SIMD=scalar|sse2|avx2, else the widest this CPU runs). Returns
    // the path taken (Avx2 falls back to Sse2 where the CPU lacks it); takes
    // effect at the next step.
    SimdPath setSimdPath(SimdPath path);
    SimdPath simdPath() const { return simd_; }
    // The joints this step solves in SIMD lanes, and their blocks (tests).
    std::size_t wideJointCount() const { return wideJoints_.size(); }
    std::size_t wideBlockCount() const { return wideBlockStart_.empty() ? 0 : wideBlockStart_.back(); }
    std::size_t wideJointsInColour(std::size_t c) const {
        return wideJointStart_.empty() ? 0 : wideJointStart_[c + 1] - wideJointStart_[c];
    }
    // Grows the per-step buffers for `jointCount` joints (at joint creation).
    void reserve(std::size_t jointCount);
    // Builds the constraints of the enabled joints whose bodies are awake (or static).
    // On the store's awake set (filled by BodyStore::beginStep just before).
    void prepare(BodyStore& w, std::vector<JointData>& joints, const JointSettings& settings, TaskSystem& tasks, Real h);
    void warmStart();  // also computes the bodies' rotations for the biased pass
    void solve(bool useBias);
    // After the sub-step's position integration: moves the joined bodies so the
    // anchors meet again (one nonlinear Gauss-Seidel pass, no velocity change),
    // in the awake set. The step computes the pose changes (dp, dtheta) after it.
    // Its check runs across the task system of the last prepare().
    void projectPositions(BodyStore& w);
    // projectPositions in two stages, for the step's stage list: the check
    // of every point joint against the slop (read-only) in groups of four,
    // [beginGroup, endGroup) of projectionGroupCount(), on any threads; then,
    // once all are checked, the passes (one thread), which run only if a
    // group found a joint beyond the slop: the same decisions, the same bits.
    std::uint32_t projectionGroupCount() const;
    void checkProjection(const BodyStore& w, std::uint32_t beginGroup, std::uint32_t endGroup);
    void projectCheckedPositions(BodyStore& w);
    // Tests: whether the passes skip the joints they know within the slop
    // (withinAt_; on by default). Off, every pass checks every joint again:
    // the same decisions, the same bits.
    void setProjectionMemory(bool on) { projectionMemory_ = on; }
    // Impulses back into the joints, reaction forces, breaking (events; the
    // broken joints' bodies are woken through the store's wake queue).
    void store(BodyStore& w, std::vector<JointData>& joints);

    std::size_t constraintCount() const { return constraints_.size(); }
    // Graph colouring: the joints of colour k, [colourStart(k), colourStart(k + 1))
    // in the solve order, share no dynamic body, so one colour may run in
    // parallel with identical results; the last colour holds the overflow and
    // must run in order. The tree solver's trees share no body with each other.
    std::size_t colourCount() const { return colourStart_.empty() ? 0 : colourStart_.size() - 1; }
    std::uint32_t colourStart(std::size_t k) const { return colourStart_[k]; }
    std::span<const JointConstraint> constraints() const { return constraints_; }  // in colour order
    std::span<const JointBreakEvent> breakEvents() const { return events_; }
    // Per-body joint lists (joint_graph.hpp): World keeps them on joint
    // creation and destruction; the contact manager asks them which pairs
    // joints keep from colliding.
    // The joint-tree solver (tests and benchmarks read its counters and set its reuse).
    JointTreeSolver& trees() { return trees_; }
    const JointTreeSolver& trees() const { return trees_; }
    JointGraph& graph() { return graph_; }
    const JointGraph& graph() const { return graph_; }

private:
    static constexpr std::uint32_t kColourCount = 24;
    void colour(const std::vector<SolverBody>& bodies, bool sameStructure);
    bool sameStructureAsLastStep(const std::vector<JointData>& joints, const std::vector<SolverBody>& bodies, bool directSolve);
    void refreshRotations();
    bool projectionPass(BodyStore& w, Real slop);  // true if it moved a body
    // Whether a projection pass could move anything: every point joint's
    // anchor separation, four joints at a time in SIMD lanes, up to the
    // first group of four holding one beyond the slop; returns that group
    // (the group count if none: all within the slop, the pass would move
    // nothing).
    std::size_t firstGroupBeyondSlop(const BodyStore& w, Real slop) const;
    // Whether the point joints projection_[4 first, 4 first + 4) hold one beyond the slop.
    bool groupBeyondSlop(const BodyStore& w, std::size_t group, Real slop) const;
    // The passes, after a check that found the groups of four flagged in
    // `beyond` (nullptr: those from `firstBeyond` on) holding a joint beyond
    // the slop, the others within it.
    void runProjectionPasses(BodyStore& w, const std::uint8_t* beyond, std::size_t firstBeyond);
    std::vector<std::uint8_t> groupBeyond_;  // checkProjection's verdict per group of four
    // What the passes already know (runProjectionPasses): a joint found
    // within the slop at clock withinAt_[k] (the check or a pass) whose
    // bodies have not moved since (movedAt_, per solver body: the clock of
    // its last shift) is within it still, on the same positions, and is
    // skipped: the same decisions, the same bits. The clock ticks at every
    // shift and at every run's start (verdicts of an earlier run are older).
    std::vector<std::uint32_t> withinAt_, movedAt_;
    std::uint32_t projectionClock_ = 0, projectionRunStart_ = 0;
    bool projectionMemory_ = true;
    std::vector<std::uint8_t> overBreakLimit_;  // store(): per constraint, its reaction exceeds a break threshold
    // |pB - pA|^2 of the point joints projection_[first, first + count)
    // (count <= 4) into e2[0 .. count), four lanes at once with the pass's
    // float steps (x86-64 builds; elsewhere the check is not made).
    void squaredSeparations4(const BodyStore& w, std::size_t first, std::size_t count, float* e2) const;
    // The joints of each colour across the task system (docs/threading.md,
    // "Joints"): kernel(constraint, a, b) for the constraints
    // indices[first[c] .. first[c + 1]) of every colour c in order (indices
    // nullptr: the constraints themselves, first[c] .. first[c + 1]), where a
    // range of one colour may run beside another range of it. A static or
    // kinematic end is passed as a copy (see forEachJointByColour).
    // wide(firstBlock, blockCount) runs first in each colour over that
    // colour's wide blocks (in ranges of blocks on the task system); kernel
    // then over its scalar joints.
    template <class Kernel, class WideKernel>
    void forEachJointByColour(const std::uint32_t* indices, const std::uint32_t* first, Kernel&& kernel, WideKernel&& wide);
    // Sorts this step's joints into the wide ones (blocks of lanes of one
    // kind, per colour but the overflow colour) and the rest (scalarJoints_,
    // scalarRows_), after the colouring and the trees; the scalar path keeps
    // none wide.
    void buildWide();
    bool wideActive() const { return !wideBlockStart_.empty(); }
    void solveTrees();
    // What the colouring and the joint trees depend on, per constraint in
    // creation order (prepare() compares it with the last step's and, if
    // equal, keeps both): the joint, its solver bodies and type, and whether
    // each end is dynamic and has an invertible inertia.
    struct StructureKey {
        std::uint32_t slot, bodyA, bodyB;
        std::uint32_t typeAndFlags;
        bool operator==(const StructureKey&) const = default;
    };
    std::vector<StructureKey> structure_, nextStructure_;
    std::size_t structureBodies_ = 0;
    bool structureDirect_ = false, structureValid_ = false;
    std::vector<JointConstraint> constraints_;
    std::vector<JointConstraint> empty_;
    // prepare(): the joints taking part this step, in creation order, and
    // each one's place in colour order (colour()).
    struct ActiveJoint {
        std::uint32_t slot, bodyA, bodyB, denseA, denseB;  // solver bodies (0: static), dense (kNoIndex: the world)
        std::uint32_t projection;  // its entry in projection_ (kNoIndex: none, a slider or six-DOF)
    };
    // The constraint records and projection entries of active_[begin, end)
    // (prepare(), in ranges across the task system).
    void buildConstraints(BodyStore& w, const std::vector<JointData>& joints, std::uint32_t begin, std::uint32_t end, Real h);
    std::vector<ActiveJoint> active_;
    std::vector<std::uint32_t> placeOf_;
    std::vector<std::uint32_t> colourOf_, colourStart_;
    // What the position projection reads of each joint but a slider, in
    // creation order (its order), packed: the check and the pass walk it
    // front to back instead of jumping through the colour-ordered constraints
    // (~0.6 kB each). Built in colour().
    struct ProjectionJoint {
        Vec3 localAnchorA;
        std::uint32_t denseA = 0;  // kNoIndex: the world
        Vec3 localAnchorB;
        std::uint32_t denseB = 0;
        std::uint32_t bodyA = 0, bodyB = 0;  // solver bodies
        std::uint32_t constraint = 0;        // in constraints_ (a distance joint's limits)
        JointType type = JointType::Ball;
        // Each end's com x y z, q w x y z (7 floats) for the check in lanes:
        // an awake end's pose in the awake set, a static end's record, or a
        // world end's constants (set in prepare, valid for the step).
        const Real* poseA = nullptr;
        const Real* poseB = nullptr;
    };
    std::vector<ProjectionJoint> projection_;
    std::vector<std::uint32_t> rowJoints_;  // constraints with Gauss-Seidel rows, in solve (colour) order
    std::vector<std::uint8_t> bodyHasRows_;  // per solver body: a dynamic end of one of rowJoints_
    std::vector<std::uint32_t> rowColourStart_;  // rowJoints_ of colour c: [rowColourStart_[c], rowColourStart_[c + 1])
    TaskSystem* tasks_ = nullptr;  // this step's; one worker: everything runs in order on the caller
    std::vector<std::uint64_t> colourBits_;
    // refreshRotations' cache, per solver body: the deltas its rotation was
    // computed from, the rotation, and the refresh (generation_) at which its
    // deltas last changed; framesStale_: prepare() rebuilt the constraints.
    struct BodyDeltas {
        Vec3 dp, dtheta;
    };
    std::vector<BodyDeltas> frameDeltas_;
    std::vector<Quat> rotations_;
    std::vector<std::uint64_t> changedAt_;
    std::uint64_t generation_ = 0;
    bool framesStale_ = true;
    // A relax pass refreshed the rotations since prepare(): the deltas are
    // those of the last position update until the next relax pass.
    bool refreshedSincePositions_ = false;
    const std::vector<SolverBody>* allBodies_ = nullptr;
    JointTreeSolver trees_;
    JointGraph graph_;
    Real projectionSlop_ = 0;
    std::vector<JointBreakEvent> events_;
    SolverBody* bodies_ = nullptr;
    JointContext ctx_;
    // SIMD lanes (buildWide). Empty wideBlockStart_: everything scalar.
    SimdPath simd_ = SimdPath::Scalar;
    std::unique_ptr<WideJoints> wide_;
    std::size_t reservedJoints_ = 0;
    std::vector<std::uint8_t> isWide_;             // per constraint
    std::vector<std::uint32_t> wideJoints_;        // the wide ones, in colour order
    std::vector<std::uint32_t> wideJointStart_;    // wideJoints_ of colour c: [wideJointStart_[c], wideJointStart_[c + 1])
    std::vector<std::uint32_t> wideBlockStart_;    // their blocks: [wideBlockStart_[c], wideBlockStart_[c + 1])
    std::vector<std::uint32_t> scalarJoints_, scalarJointStart_;  // the others, per colour (warm start)
    std::vector<std::uint32_t> scalarRows_, scalarRowStart_;      // the others of rowJoints_, per colour (passes)
};

}  // namespace fulcrum::detail
