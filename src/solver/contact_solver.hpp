#pragma once
// The contact solver: Box2D v3's "soft step" (Catto, "Solver2D", 2024) in 3D.
// docs/solver.md has the long form and the formulas ("The soft step").
//
// Per step, prepare() builds
//   - one constraint per manifold, with anchors relative to the centres of
//     mass at the step's start, effective masses, softness and mixed
//     friction/restitution/rolling resistance;
//   - a graph colouring: constraints of one colour share no dynamic body.
//     Colours are solved in order, deterministically. In wide mode (the
//     default) each colour's constraints are built 4 or 8 at a time (SSE2 or
//     AVX2, chosen at run time: setSimdPath) into SoA blocks and solved with
//     SIMD (contact_wide.hpp); only the overflow colour is kept as
//     ContactConstraint. The scalar mode (SimdPath::Scalar) keeps every
//     constraint as a ContactConstraint and is the reference both wide modes
//     equal bit for bit.
// The bodies are not the solver's: it works on the body store's awake set
// (src/dynamics/body_store.hpp; solver body i is awake-list entry i - 1,
// entry 0 the static body), the same array the integrators and the joint
// solver work on, so nothing is copied between them. Per sub-step the step's
// stage list (src/world/step.cpp) runs the warm start, the biased solve
// iterations and, after the position integration, the relax pass, each as
// stages from addPassStages (one per colour). After the sub-steps:
// applyRestitution, store.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "fulcrum/math.hpp"
#include "dynamics/body_store.hpp"
#include "solver/contact_wide.hpp"
#include "solver/graph_colouring.hpp"
#include "solver/softness.hpp"

namespace fulcrum {
class TaskSystem;
}

namespace fulcrum::detail {

class ContactManager;
struct Contact;
using ContactArray = LargeArray<Contact>;  // as contacts/contact.hpp
struct JointConstraint;
class StagedParallel;

// The Jacobians are fixed for the step, so everything that depends only on
// them is computed once in prepare(): the angular parts r x n and the velocity
// changes I^-1 (r x n) per unit impulse. The inner loop is then dot products
// and multiply-adds (measured: pyramid20 solve 2.2 -> see docs/benchmarks.md).
struct ConstraintPoint {
    Vec3 rA, rB;                // anchor from each centre of mass (world, step start)
    Vec3 rAxn, rBxn;            // rA x n, rB x n
    Vec3 angA, angB;            // invIA (rA x n), invIB (rB x n)
    Real baseSeparation = 0;    // s0 at the step's start
    Real normalMass = 0;
    Real normalImpulse = 0;
    Real maxNormalImpulse = 0;
    Real relativeVelocity = 0;  // normal approach speed at impact (restitution)
    Real stepImpulse = 0;       // applied over the step: each sub-step's impulse after relax, plus restitution's
    // As relativeVelocity, but also when the point first pushes in a relax
    // pass (a speculative point can): the impact speed of hit events.
    // relativeVelocity stays as it was, so restitution's bits do not change.
    Real approachVelocity = 0;
};

struct ContactConstraint {
    std::uint32_t bodyA = 0, bodyB = 0;      // solver body indices (0: static)
    std::uint32_t contact = 0, manifold = 0; // where the results go back
    std::uint32_t pointCount = 0;
    Real friction = 0, restitution = 0, rollingResistance = 0;  // rolling: max impulse per unit normal impulse
    Real pushMax = 0;                        // fastest push-out of this contact: ContactSolver::pushLimit
    Vec3 normal, tangent1, tangent2;
    Softness softness;
    ConstraintPoint points[4];
    // Friction at the manifold's centre: 2D tangent + twist (bepu, Box3D).
    Vec3 rAc1, rAc2, rBc1, rBc2;             // rAc x t1, rAc x t2, rBc x t1, rBc x t2
    Vec3 angA1, angA2, angB1, angB2;         // invI times the above
    Vec3 twistA, twistB;                     // invIA n, invIB n
    Real k11 = 0, k12 = 0, k22 = 0;          // inverse of the 2x2 tangent effective mass
    Real tangentImpulse1 = 0, tangentImpulse2 = 0;
    Real stepTangent1 = 0, stepTangent2 = 0;  // applied over the step (as ConstraintPoint::stepImpulse)
    Real twistMass = 0, twistImpulse = 0, twistRadius = 0;
    Mat3 rollingMass = Mat3::zero();
    Vec3 rollingImpulse;
};

// The settings the contact solver reads (WorldDef's contact* and restitutionThreshold).
struct SolverSettings {
    Real contactHertz = 30, dampingRatio = 10, pushMaxVelocity = 3, restitutionThreshold = 1;
};

class ContactSolver {
public:
    ContactSolver();
    ~ContactSolver();
    ContactSolver(ContactSolver&&) noexcept;
    ContactSolver& operator=(ContactSolver&&) noexcept;
    // Grows the per-step buffers for `bodyCount` bodies (at body creation).
    void reserve(std::size_t bodyCount);
    // Builds the constraints for the contacts with an awake body, on the
    // store's awake set (filled by BodyStore::beginStep just before), in
    // three parts: the list of constraints; the greedy colouring (serial: the
    // step runs it beside the first force evaluation, step.cpp); the colour
    // slots and the constraint build.
    // colourGreedy reads only the constraint list and the solver bodies'
    // inverse masses, and writes only the colouring's arrays and the
    // deep-overlap counts of pushLimit.
    void prepareConstraintList(BodyStore& w, ContactManager& contacts, const SolverSettings& s, Real h);
    void colourGreedy();
    void finishPrepare(ContactManager& contacts);
    void applyRestitution();
    // After the sub-steps, before store: pairs the narrow phase found deeper
    // than the last step's end had them by more than a threshold
    // (Contact::grownBy: an overlap made within a step, unseen by its
    // manifold) are moved apart along their normal by what is left of it,
    // positions only (no velocity: nothing to bounce). Serial, in
    // constraint order: the same bits for any thread count. The ends of
    // `joints` are not moved (held as a static end is): a move by position
    // would open their joints until the next step's solve.
    void pushOutGrown(BodyStore& w, const ContactManager& contacts, std::span<const JointConstraint> joints);
    // pushOutGrown's gate (on by default): a pair whose bodies' motion since
    // the step's start bounds its depth's growth below the trigger, and not
    // grown unseen, is skipped without reading its manifold. The decisions,
    // and so the bits, are the same either way; off only for the tests.
    void setPushOutGate(bool on) { pushOutGate_ = on; }
    // pushOutGrown itself (WorldDef::pushOutGrownOverlaps, set by the step
    // before prepare; off by default). Off, prepare skips the gate's reach
    // and pushOutGrown returns at once: the step is main's, bit for bit.
    void setPushOut(bool on) { pushOut_ = on; }
    // Impulses (warm start) and end-of-step separations back into the contacts.
    void store(ContactManager& contacts);

    // Scalar, 4-lane (SSE2) or 8-lane (AVX2) solve; all give the same results
    // (contact_wide.hpp says why). The scalar path is the reference; the
    // default is initialSimdPath() (FULCRUM_SIMD, else the widest the CPU
    // runs). Avx2 where the CPU lacks it gives Sse2. Set before a step, not
    // during one; returns the path now in use.
    SimdPath setSimdPath(SimdPath path);
    SimdPath simdPath() const { return simd_; }
    // Wide: the machine's best wide path (as the default); else scalar.
    void setWide(bool wide) { setSimdPath(wide ? bestSimdPath() : SimdPath::Scalar); }
    bool wide() const { return simd_ != SimdPath::Scalar; }
    // Runs the prepare's loops, the constraint build and the store across
    // `tasks` (nullptr: on the calling thread); every loop writes only its own
    // indices, so the results are the same bit for bit for any thread count.
    // (The passes are stages of the step's list: addPassStages.)
    void setTaskSystem(TaskSystem* tasks) { tasks_ = tasks; }
    // The most blocks any colour has this step (a colour's stage is claimed
    // in units of kBlocksPerTask blocks: contact_solver.cpp).
    std::size_t largestColourBlocks() const;

    // ---- The sub-steps' stage list (step.cpp, threads/staged_parallel.hpp).
    // Appends one pass (warm start, solve with bias, or relax) as stages:
    // one per non-empty colour of wide blocks (units of kBlocksPerTask blocks,
    // independent: a colour's blocks share no dynamic body), then the
    // overflow colour (or, in scalar mode, every constraint) as one unit.
    // Colour after colour, so the bits do not depend on how the units are spread.
    enum class Pass : std::uint32_t { WarmStart = 0, Solve = 1, Relax = 2 };
    void addPassStages(StagedParallel& stages, std::uint32_t kind, Pass pass) const;
    static std::uint32_t maxPassStages();  // the most stages addPassStages appends
    // Whether addPassStages would append other stages than at the last call
    // of this (what they depend on: the blocks of each colour up to the last
    // non-empty one, and whether there is an overflow part). The step keeps
    // its stage list while this and its own inputs are unchanged.
    bool takePassStagesChanged();
    // Runs items [first, last) of a stage added above (its arg).
    void runPassStage(std::uint32_t arg, std::uint32_t first, std::uint32_t last);

    // Whether the wide blocks' lanes are placed by their point counts and
    // static ends within each colour (placeInLanes; the default), or in the
    // colour's slot order: the same results either way (tests compare them).
    void setLaneOrder(bool on) { laneOrder_ = on; }
    // The point iterations of this step's wide blocks: the sum over blocks
    // of their lanes' largest point count (what the lane order lowers).
    std::size_t widePointRuns() const { return blocks_ && wide_ ? blocks_->pointRuns() : 0; }
    // Whether the wide blocks whose end A is the static world in every lane
    // run the kernels that skip A's rows (WideBlocks::setStaticAKernels; the
    // default), or the general kernel: the same results either way (tests
    // compare them). And how many of this step's blocks took them.
    void setStaticAKernels(bool on) {
        staticAKernels_ = on;
        if (blocks_) blocks_->setStaticAKernels(on);
    }
    std::size_t staticABlocks() const { return blocks_ && wide_ ? blocks_->staticABlocks() : 0; }

    std::size_t constraintCount() const { return pending_.size(); }
    std::size_t colourCount() const { return colourStart_.empty() ? 0 : colourStart_.size() - 1; }
    // Every constraint's contact and solver bodies (islands).
    struct ConstraintPair {
        std::uint32_t contact, manifold, bodyA, bodyB;
    };
    const std::vector<ConstraintPair>& pairs() const { return pending_; }
    // The colouring, read by the FULCRUM_VALIDATE checks (src/world/invariants.cpp):
    // pairs()[i] has colour constraintColours()[i]; colour c holds the
    // colour-ordered slots [colourStart(c), colourStart(c + 1)), slot s being
    // pairs()[pendingOfSlot()[s]]; the last colour is the overflow (solved in order).
    const std::vector<std::uint32_t>& constraintColours() const { return colourOf_; }
    std::uint32_t colourStart(std::size_t c) const { return colourStart_[c]; }
    const std::vector<std::uint32_t>& pendingOfSlot() const { return pendingOfSlot_; }

private:
    using PendingConstraint = ConstraintPair;
    void placeInColourSlots();  // after colourGreedy: each constraint's slot in colour order
    void placeInLanes();        // wide mode, after placeInColourSlots: laneOfSlot_
    template <bool useBias>
    void solvePass(std::size_t begin, std::size_t end);
    void warmStartRange(std::size_t begin, std::size_t end);
    // fn(begin, end) over [0, count), across the task system when there is
    // one and count holds at least two ranges of minRange; each index is
    // handled by exactly one call, so per-index writes stay deterministic.
    template <class Fn>
    void forRanges(std::size_t count, std::uint32_t minRange, Fn&& fn) const;
    void packWide(const ContactArray& contacts);
    void storeRange(ContactArray& contacts, std::size_t begin, std::size_t end) const;
    void buildConstraint(const Contact& c, const PendingConstraint& pc, ContactConstraint& k) const;
    // The push-out speed limit of one constraint: contactPushMaxVelocity
    // shared among the deep overlaps of its busier dynamic body, so that the
    // pushes asked of any one body add up to at most contactPushMaxVelocity
    // however many bodies overlap it (issue 27; docs/solver.md, "Many overlaps"),
    // for pairs born inside each other; pairs driven in keep the whole speed
    // (Contact::firstTouch; docs/solver.md, "Born deep, driven deep").
    Real pushLimit(const PendingConstraint& pc, const Contact& c) const;
    // The dynamic or the stiffer static softness (the scalar and the wide
    // build both take it from here).
    Softness softnessOf(const PendingConstraint& pc) const;

    BodyStore* store_ = nullptr;                 // this step's (prepare): its awake set holds the bodies
    std::vector<ContactConstraint> constraints_;  // scalar mode: all, by colour; wide mode: the overflow colour
    std::vector<PendingConstraint> pending_;
    // Per pending constraint: bit 0, its manifold is a deep overlap
    // (pushLimit); bit 1, its pair grew deeper unseen (pushOutGrown).
    std::vector<std::uint8_t> overlapping_;
    std::vector<std::uint8_t> laneKeys_;         // per pending constraint: where in its colour its lane goes (placeInLanes)
    std::vector<std::uint32_t> overlapCount_;    // per solver body: its deep overlaps (pushLimit)
    std::vector<std::uint32_t> pushedPass_;      // per solver body: pushOutGrown's last pass that moved it
    std::vector<std::uint8_t> loaded_;           // per solver body: touches a much heavier one (pushOutGrown)
    std::vector<std::uint8_t> jointed_;          // per solver body: an end of a joint (pushOutGrown does not move it)
    // Per pending constraint: the largest distance of its contact's points
    // from body A's and body B's step-start centre of mass (pushOutGrown's gate).
    struct PairReach {
        Real a = 0, b = 0;
    };
    std::vector<PairReach> pairReach_;
    std::vector<std::uint8_t> still_;            // per pending constraint: the gate's answer before any move
    bool pushOutGate_ = true;
    bool pushOut_ = false;
    struct ContactEnds {
        std::uint32_t bodyA = 0, bodyB = 0, manifolds = 0;  // manifolds 0: not solved this step
        // Bit i: manifold i has a point deeper than the push-sharing depth
        // (the first 32 manifolds; the pending-list pass reads the rest).
        std::uint32_t overlapping = 0;
        // Bits 2i, 2i + 1: manifold i's point count less one (the first 16
        // manifolds; the pending-list pass reads the rest): the lane keys.
        std::uint32_t points = 0;
        bool grown = false;  // Contact::grownBy over kGrowthPushOut (pushOutGrown)
    };
    std::vector<ContactEnds> contactEnds_;       // per candidate contact: prepare()'s pending-list pass
    std::vector<PairReach> contactReach_;        // per candidate contact: its PairReach (only with the push-out on)
    std::vector<std::uint32_t> candidates_;      // the awake bodies' contacts, when prepare() lists only those
    std::vector<std::uint32_t> pendingBlockStart_;  // per block of contacts: its first pending entry
    std::vector<std::uint32_t> slotOf_;          // pending index -> position in constraints_
    std::vector<std::uint32_t> pendingOfSlot_;   // the inverse: colour-ordered slot -> pending index
    std::vector<std::uint32_t> slotCursor_;      // colour(): per block of constraints, each colour's next slot
    std::vector<std::uint32_t> blockColour_;     // wide mode: each block's colour
    std::vector<LaneSource> laneSources_;        // wide mode: the coloured constraints' inputs, by lane (laneOfSlot_)
    std::vector<std::uint32_t> laneOfSlot_;      // wide mode: colour-ordered slot -> its lane, in the same colour
    std::vector<std::uint32_t> colourOf_;
    std::vector<ConstraintEnds> colouredEnds_;   // the ends colourOf_ was made for (colourGreedy keeps it while they hold)
    bool coloursKept_ = false;                   // this step's colours and slots are the last step's
    bool laneOrder_ = true;                      // setLaneOrder
    bool staticAKernels_ = true;                 // setStaticAKernels (kept across setSimdPath)
    std::vector<std::uint64_t> colourBits_;      // per solver body, the colours it has (graph_colouring.hpp)
    std::vector<std::uint32_t> colourStart_;     // constraints_ of colour k: [start[k], start[k+1])
    std::unique_ptr<WideBlocks> blocks_;         // wide mode: the coloured constraints, lanes() per block
    std::vector<std::uint32_t> blockStart_;      // blocks_ of colour k: [blockStart[k], blockStart[k+1])
    std::uint32_t colourEnd_ = 0;                // wide mode: colours from here on have no block (packWide)
    std::vector<std::uint32_t> lastPassStages_;  // takePassStagesChanged: what addPassStages depended on last
    SimdPath simd_ = SimdPath::Scalar;           // set by the constructor
    bool wide_ = false;                          // simd_ != Scalar
    TaskSystem* tasks_ = nullptr;
    Softness contactSoftness_, staticSoftness_;
    Real invH_ = 0, pushMax_ = 3, restitutionThreshold_ = 1;
};

}  // namespace fulcrum::detail
