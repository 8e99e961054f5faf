#pragma once
// Direct solve of the point rows of joints that form trees (chains, ragdolls),
// exact in linear time (Baraff, "Linear-Time Dynamics using Lagrange
// Multipliers", SIGGRAPH 1996; MuJoCo and Featherstone's articulated-body
// methods rest on the same sparsity).
//
// Why: a soft point row solved by Gauss-Seidel sees only its own two bodies'
// effective mass, so the stiffness it gets is relative to the lighter link. A
// heavy load on light links (mass ratio 100:1) then stretches every joint by
// (M / m) g / omega^2 (2.4 cm measured per joint at 60 Hz), and a long
// whipping chain (the benchmark's 100 links) opens by 5 cm however many
// iterations run. Solved together, the rows see the whole tree's inertia: the
// softness becomes the stated spring-damper for the whole system, and the
// deflection under load falls to g / omega^2 (0.07 mm at 60 Hz).
//
// The system. Bodies (6 unknowns: v, w) and joints (3 unknowns: the point
// impulse) are the nodes of a tree; the matrix
//     H = [ M   J^T ]      M: block-diagonal body masses (m I, I_world)
//         [ J    0  ]      J: point-row Jacobians, [I, -[rB]x] on B, [-I, [rA]x] on A
// has the tree's sparsity, so eliminating nodes leaves first (children before
// parents) gives H = L D L^T with no fill-in. Solving H [x; y] = [0; r] yields
// y = -(J M^-1 J^T)^-1 r, the exact impulse for the row residual r = J v + bias.
// The soft step's coefficients then apply to the whole block:
//     biased pass:  d_lambda = massScale * y - impulseScale * lambda,  r = J v + biasRate C
//     relax pass:   d_lambda = y,                                     r = J v
// which is Catto's soft constraint with the system's effective mass in place
// of each row's.
//
// Which joints: ball, hinge, cone-twist and fixed joints (their 3 point rows;
// their angular, limit, motor and friction rows stay Gauss-Seidel, solved
// before the block). A connected group of such joints between dynamic bodies
// is a tree when it has no loop: joints = bodies - 1 + (joints to static or
// kinematic ends), with at most one such end (two anchors to the static world
// close a loop through it). A group with loops (a ring, the ball grids) is
// split into a spanning forest (findTrees): its trees are solved exactly and
// the joints that close its loops stay Gauss-Seidel, solved before them.
// The factorization is made once per step, by the step's first pass, and
// reused by its later passes while no anchor of the tree turned more than
// kGuardTurn since (solve(), solveTree()); a tree whose guard trips factors
// again alone. Double precision: the elimination works with products of
// masses and lever arms over whole trees.
//
// Speed (docs/joints.md has the figures). A body with at most one child joint
// (every link of a chain; a ragdoll's head and limbs) is eliminated first,
// while its block is still its mass, whose inverse the solver body holds: its
// two joints then couple through a 3x3 block, so a chain is solved as the
// block-tridiagonal joint-space system K = J M^-1 J^T, and 6x6 body blocks
// remain only where a body branches (a ragdoll's torso and pelvis) or roots a
// free tree. Each factored block is stored inverted, so the later passes are
// dense mat-vecs rather than dependent triangular solves. A tree that is a
// chain of joints (solveChain) is swept once per pass over packed links
// instead of four times over the generic storage, prefetching the scattered
// constraints: the same bits, ~8 % of the chain benchmark's step by wall
// clock (docs/joints.md, sixth round).
#include <algorithm>
#include <cstdint>
#include <vector>

#include "solver/joints/joint_common.hpp"
#include "solver/joints/tree_lanes.hpp"

namespace fulcrum::detail {

class JointTreeSolver {
public:
    // Finds the trees among `joints` (marks their `direct` flag). Bodies are
    // the contact solver's solver bodies (entry 0: static).
    void build(std::vector<JointConstraint>& joints, const std::vector<SolverBody>& bodies);
    // The trees of the last build(), for a joint list of the same structure
    // (same joints in the same order between the same solver bodies, the same
    // of them dynamic and with invertible inertia: JointSolver::prepare checks
    // it): marks the same `direct` flags and skips the search.
    void reuse(std::vector<JointConstraint>& joints);
    // One exact pass over every tree's point rows (biased or relax, ctx.useBias).
    void solve(std::vector<JointConstraint>& joints, SolverBody* bodies, const JointContext& ctx);
    // The same pass in pieces, for the task system: beginPass() once, then
    // solveTrees() over disjoint ranges of [0, treeCount()) in any order or
    // concurrently (trees share no moving body; a static or kinematic end they
    // share is never written). Same results as solve().
    // beginPass() decides whether the pass factors (the reuse schedule below)
    // and whether it takes the folded warm start; returns the former.
    bool beginPass(bool useBias);
    void solveTrees(std::uint32_t firstTree, std::uint32_t endTree, std::vector<JointConstraint>& joints, SolverBody* bodies,
                    const JointContext& ctx, bool refactor);
    bool empty() const { return nodes_.empty(); }
    // The trees whose warm start may be folded into their first biased pass
    // of a sub-step: only frictionless ball joints, and no body of theirs in a
    // joint with Gauss-Seidel rows (`bodyHasRows`, per solver body), which
    // would be solved before the tree and see the velocities without the
    // tree's warm start. Marks those joints' `warmStartInTree`.
    void markWarmStartFree(std::vector<JointConstraint>& joints, const std::vector<std::uint8_t>& bodyHasRows);
    // Whether the next biased pass solves with an exact factorization (its
    // anchors': solve()).
    bool nextBiasedPassExact() const { return !factored_ || factorAge_ == 0 || factorAge_ >= maxFactorAge_; }
    // A new sub-step's warm start. `foldWarmStart`: the caller skipped the
    // warm start of the joints marked warmStartInTree (it may when
    // nextBiasedPassExact()); the sub-step's first biased pass then applies
    // it with its impulses (solveTree). The factorization's age is counted in
    // position updates, by the relax passes (solve()).
    void newSubstep(bool foldWarmStart) {
        foldWarmStart_ = foldWarmStart;
        firstBiasedPass_ = true;
    }
    std::size_t treeCount() const { return trees_; }
    // Four trees of one shape in SIMD lanes of doubles on a kept
    // factorization (tree_lanes.hpp; the same bits as one by one): 0 none
    // (every tree scalar), 1 the baseline kernel, 2 the AVX2 one (only if
    // compiled and the CPU has it; else 1). Takes effect at the next pass that
    // factors every tree (the next step). JointSolver::setSimdPath sets it:
    // SimdPath::Scalar is 0.
    void setLanes(int mode);
    int lanes() const { return lanesWanted_; }
    // A group's residuals and impulses (around the lanes' kernel) four trees
    // at a time in SSE float lanes, each tree's scalar operations in the
    // scalar order (the same bits; only where the build has SSE2 floats:
    // elsewhere, and when off, tree by tree). On by default; off for tests.
    void setWideEnds(bool on) { wideEnds_ = on; }
    bool wideEnds() const { return wideEnds_; }
    // Passes solved in lanes, counted per group since the last build (tests).
    std::uint64_t lanePasses() const {
        std::uint64_t n = 0;
        for (const std::uint64_t k : lanePassesOf_) n += k;
        return n;
    }
    // The passes that factor also factor each such group in its lanes
    // (factorTreeLanes: the eliminations and the back-substitution, four
    // trees at once, the same bits). On by default; off for tests.
    void setLaneFactor(bool on) { laneFactor_ = on; }
    bool laneFactor() const { return laneFactor_; }
    // Tests: after each factorization in lanes, factor the four trees again
    // tree by tree (solveTree's scalar eliminations and back-substitution,
    // from blocks built again from the same state) and compare D^-1, Hp, X
    // and y with the lanes' bit for bit; laneFactorMismatches() counts the
    // trees that differ, laneFactorChecks() those compared. Off by default.
    void setLaneFactorCheck(bool on) { laneFactorCheck_ = on; }
    std::uint64_t laneFactorChecks() const {
        std::uint64_t n = 0;
        for (const std::uint64_t k : laneFactorChecksOf_) n += k;
        return n;
    }
    std::uint64_t laneFactorMismatches() const {
        std::uint64_t n = 0;
        for (const std::uint64_t k : laneFactorMismatchesOf_) n += k;
        return n;
    }
    // Groups factored in lanes since the last build (tests).
    std::uint64_t laneFactorPasses() const {
        std::uint64_t n = 0;
        for (const std::uint64_t k : laneFactorPassesOf_) n += k;
        return n;
    }
    // Tests: the lanes in `mask` of every refactorTrippedInLanes count as
    // failed (an elimination not definite), so their trees take the
    // fallback (factor alone at once). 0 by default.
    void setTrippedLaneFailures(unsigned mask) { trippedLaneFailures_ = mask & 15u; }
    // Trees of a group whose guard tripped on a kept-factor pass and that
    // factored again in their group's lanes (refactorTrippedInLanes) since
    // the last build (tests).
    std::uint64_t trippedLaneFactors() const {
        std::uint64_t n = 0;
        for (const std::uint64_t k : trippedLaneFactorsOf_) n += k;
        return n;
    }
    // Whether every group's stored blocks in the lanes (D^-1, Hp and X, the
    // factorizations the kept-factor passes use) equal `other`'s bit for
    // bit, for the same trees and groups (tests: the double values, which
    // the float results could hide).
    bool sameLaneBlocks(const JointTreeSolver& other) const;
    // Trees in groups of four of one shape (tests).
    std::size_t groupedTreeCount() const {
        std::size_t n = 0;
        for (const std::uint32_t g : groupOf_) n += g != kNone;
        return n;
    }
    // Trees solved as chains (solveChain), for tests.
    std::size_t chainCount() const {
        std::size_t n = 0;
        for (const std::uint8_t c : chain_) n += c;
        return n;
    }
    // Joints whose point rows a tree solves (their `direct` flag), for tests.
    std::size_t directJointCount() const {
        std::size_t n = 0;
        for (const std::uint8_t d : direct_) n += d;
        return n;
    }
    // Factorization reuse (solve()): a pass factors again once the anchors
    // it would reuse are `age` position updates old (1: every pass after a
    // position update factors, so every pass is exact; 2: at most one
    // position update old, the schedule before issue 21) or any anchor of
    // the tree turned by more than kGuardTurn since. The default,
    // kOncePerStep (no limit by age), factors once a step (prepare starts
    // every step unfactored) and lets the guard decide the rest, tree by
    // tree.
    void setMaxFactorAge(int age) { maxFactorAge_ = age < 1 ? 1 : age; }
    static constexpr int kOncePerStep = 1 << 30;
    static constexpr int kDefaultMaxFactorAge = kOncePerStep;
    // The guard: one angle, whatever the factorization's age. A stale
    // factorization's error scales with the turn times the tree's
    // conditioning, not with its age: the six-DOF chain under a 100:1 load
    // (tests/joints/six_dof_test.cpp) opened to 45 mm at worst over its run
    // when a factorization one position update old was kept up to 0.1 rad
    // (the old schedule, age 2), 11 mm up to 0.02 rad, 1.23 mm (as with
    // every pass factored) up to 0.005 rad (docs/joints.md, "Factorization
    // once per step").
    static constexpr double kGuardTurn = 0.005;  // rad (relative anchor change)
    // Counters (tests, benchmarks): trees factored, and guard trips among them.
    std::uint64_t factorizations() const { return factorizations_ + guardTrips(); }
    std::uint64_t guardTrips() const {
        std::uint64_t n = guardTripsPast_;
        for (const std::uint64_t k : guardTripsOf_) n += k;
        return n;
    }

private:
    static constexpr std::uint32_t kNone = UINT32_MAX;
    struct Node {
        std::uint32_t parent = kNone;  // node index of the parent (kNone: the root of its tree)
        std::uint32_t ref = 0;         // joint: index in the joint list; body: solver body index
        // Joint nodes whose parent is a joint (through a contracted body, below):
        // that body's solver index, and whether it is this joint's / the parent joint's body A.
        std::uint32_t via = kNone;
        bool viaIsA = false, viaIsParentA = false;
        bool joint = false;
        bool bodyIsA = false;          // body nodes: is it its parent joint's body A? joints: is the parent body its A?
        bool ownA = false, ownB = false;  // joint nodes: ends that are contracted bodies (their M^-1 goes into D directly)
    };
    struct Factor {
        double D[6][6];        // D (lower triangle), then D^-1 after elimination (full, symmetric)
        double Hp[6][6];       // H(parent, this): dim(parent) x dim(this)
        double X[6][6];        // D^-1 Hp^T, stored as X[c][k] = (D^-1 (row c of Hp)^T)_k: back-substitution
        double z[6];           // right-hand side, then D^-1 z after forward substitution
        double y[6];           // solution
        Vec3 rA, rB;           // joint nodes: anchors of this pass
        Vec3 factorA, factorB; // joint nodes: anchors of the factorization (the reuse guard)
    };
    // A chain tree's node (every node a joint below the next through a
    // contracted body; chain_): what its one fused children-first sweep
    // and its back-substitution read, packed (~300 bytes instead of the
    // generic Factor's ~1 kB, so the benchmark's 100 links stay in L1).
    // Indexed like nodes_ (unused for other trees). solveChain().
    struct ChainLink {
        double D[6];           // D^-1 after elimination: i00, i11, i22, i10, i20, i21 (symmetric)
        double Hp[3][3];       // H(parent, this) = -J_p M^-1 J^T through the body between them
        double z[3];           // right-hand side, then D^-1 z after forward substitution
        double X[3][3];        // D^-1 Hp^T, X[c][k] as in Factor
        double y[3];           // solution
        Vec3 rA, rB;           // anchors of this pass
        Vec3 factorA, factorB; // anchors of the factorization (the reuse guard)
        std::uint32_t via = kNone;  // the contracted body between this joint and its parent (kNone: the root)
        bool viaIsA = false, viaIsParentA = false, ownA = false, ownB = false;
    };
    struct Pending {
        std::uint32_t ref, parentPos;
        bool joint, bodyIsA;
    };
    template <int dim, int pdim>
    bool eliminate(std::uint32_t node);
    template <int dim, int pdim>
    void backSubstitute(std::uint32_t node);
    template <int dim, int pdim>
    void forward(std::uint32_t node);
    // eliminate / forward / backSubstitute<3, 3> written out (same bits).
    bool eliminateChainJoint(std::uint32_t node);
    void forwardChainJoint(std::uint32_t node);
    void backSubstituteChainJoint(std::uint32_t node);
    // The eliminations and the back-substitution over a tree's nodes
    // [begin, end), each node by its kind (solveTree, laneFactorMatchesScalar).
    bool eliminateNodes(std::uint32_t begin, std::uint32_t end);
    void backSubstituteNodes(std::uint32_t begin, std::uint32_t end);
    void findTrees(std::vector<JointConstraint>& joints, const std::vector<SolverBody>& bodies);
    // solveTree for a chain: the block build, the guard, the elimination or
    // forward substitution and the residual in one children-first sweep, the
    // same operations in the same order per value (same bits).
    bool solveChain(std::uint32_t tree, std::vector<JointConstraint>& joints, SolverBody* bodies, const JointContext& ctx,
                    bool refactor, bool foldedWarmStart);
    bool solveTree(std::uint32_t tree, std::vector<JointConstraint>& joints, SolverBody* bodies, const JointContext& ctx,
                   bool refactor, bool foldedWarmStart);
    // solveTree's pass on the kept factorization (no refactor), the same
    // operations in the same order per value (same bits), with the node
    // kinds looked up once (kind_) and the 3-vector work written out per
    // component as solveChain's. False if the guard trips (nothing applied):
    // the caller factors the tree again.
    bool solveTreeReused(std::uint32_t tree, std::vector<JointConstraint>& joints, SolverBody* bodies, const JointContext& ctx,
                         bool foldedWarmStart);
    // solveTreeReused's residuals (and its guard), into zAt(node, k).
    template <class ZAt>
    bool reusedResiduals(std::uint32_t tree, std::vector<JointConstraint>& joints, const SolverBody* bodies,
                         const JointContext& ctx, ZAt zAt);
    // solveTrees' work for one tree: solveTree, else (singular) Gauss-Seidel blocks.
    void solveOneTree(std::uint32_t t, std::vector<JointConstraint>& joints, SolverBody* bodies, const JointContext& ctx,
                      bool refactor);
    // The four trees of group `first` on their kept factorizations in lanes
    // (tree_lanes.hpp); a tree whose guard trips goes on to solveOneTree.
    void solveGroupInLanes(std::uint32_t first, std::vector<JointConstraint>& joints, SolverBody* bodies,
                           const JointContext& ctx);
    // solveGroupInLanes' residuals (guard included: returns the tripped
    // lanes' bits) and impulses, the four trees at once (setWideEnds). The
    // impulses only for a group with no tripped lane and one `folded` for all.
    // Each twice: the build's baseline instructions, and (the AVX2 path,
    // lanes_ == 2) the same code VEX-encoded (GCC and Clang: three-operand
    // forms, fewer register copies; no FMA, the same bits).
    unsigned wideResiduals(std::uint32_t first, std::vector<JointConstraint>& joints, const SolverBody* bodies,
                           const JointContext& ctx);
    void wideImpulses(std::uint32_t first, std::vector<JointConstraint>& joints, SolverBody* bodies,
                      const JointContext& ctx, bool folded);
    unsigned wideResidualsAvx2(std::uint32_t first, std::vector<JointConstraint>& joints, const SolverBody* bodies,
                               const JointContext& ctx);
    void wideImpulsesAvx2(std::uint32_t first, std::vector<JointConstraint>& joints, SolverBody* bodies,
                          const JointContext& ctx, bool folded);
    unsigned wideResidualsBody(std::uint32_t first, std::vector<JointConstraint>& joints, const SolverBody* bodies,
                               const JointContext& ctx);
    void wideImpulsesBody(std::uint32_t first, std::vector<JointConstraint>& joints, SolverBody* bodies,
                          const JointContext& ctx, bool folded);
    // A grouped tree's new factorization into its lane (D^-1, Hp, X).
    void copyFactorToLanes(std::uint32_t tree);
    // The reverse, for a scalar pass on a factorization made in the lanes (laneOnly_).
    void copyFactorFromLanes(std::uint32_t tree);
    // A tree's blocks built by buildBlocks into its lane, before the elimination.
    void gatherBlocksToLane(std::uint32_t tree);
    // The same into lane `lane` of a group block at `data`, whose nodes are
    // `lanes` (offsets into `data`; the tree's group's shape).
    void gatherBlocks(std::uint32_t tree, const TreeLaneNode* lanes, TreeLane4* data, int lane);
    // The lanes `tripped` of group `first` (a kept-factor pass whose guard
    // tripped there; nothing of theirs applied yet) factored again in a
    // scratch copy of the group's block by the lanes' factor kernel, as
    // solveTree would factor each alone (the same bits), and moved into
    // their lanes (in place when all four tripped); returns the lanes whose
    // elimination failed (they factor alone at once: solveOneTree). The
    // other lanes are left as they were.
    unsigned refactorTrippedInLanes(std::uint32_t first, std::vector<JointConstraint>& joints, const SolverBody* bodies,
                                    const JointContext& ctx, unsigned tripped);
    // solveTree's initial blocks, right-hand sides and anchors (factors_).
    void buildBlocks(std::uint32_t tree, std::vector<JointConstraint>& joints, const SolverBody* bodies,
                     const JointContext& ctx);
    // A pass that factors, for the four trees of group `first` (setLaneFactor).
    void factorGroupInLanes(std::uint32_t first, std::vector<JointConstraint>& joints, SolverBody* bodies,
                            const JointContext& ctx);
    // The group's impulses from its lanes' y (tripped lanes: solveOneTree).
    void groupImpulses(std::uint32_t first, std::vector<JointConstraint>& joints, SolverBody* bodies,
                       const JointContext& ctx, unsigned tripped, bool wide);
    // findTrees' grouping: four consecutive trees of one shape (not chains).
    void groupTrees();

    std::vector<Node> nodes_;       // elimination order: every tree's children before its parents
    std::vector<Factor> factors_;
    std::vector<std::uint32_t> treeStart_;  // nodes_ of tree t: [treeStart_[t], treeStart_[t + 1])
    std::size_t trees_ = 0;
    std::vector<std::uint8_t> valid_;  // per tree: its factorization of this sub-step succeeded
    std::vector<std::uint8_t> warmFree_;  // per tree: markWarmStartFree
    std::vector<std::uint8_t> chain_;     // per tree: a chain of joints (solveChain)
    // Per node (build()): kBodyNode, kJointBelowJoint (through a contracted
    // body), kJointBelowBody (or a root joint): which block sizes its
    // forward and back-substitution take (solveTreeReused).
    static constexpr std::uint8_t kBodyNode = 0, kJointBelowJoint = 1, kJointBelowBody = 2;
    std::vector<std::uint8_t> kind_;
    std::vector<ChainLink> links_;        // per node of a chain tree
    // Lanes (setLanes): per tree, the first tree of its group of four (kNone:
    // not grouped; a group is trees [g, g + 4)); per node of a group's first
    // tree, its lanes in laneData_ (a tree of the group reads its node i at
    // the first tree's node at the same place); lanes_ the mode in use,
    // lanesWanted_ the one set (taken when a pass factors every tree).
    std::vector<std::uint32_t> groupOf_;
    std::vector<TreeLaneNode> laneNodes_;
    // Per node of a group's first tree: its TreeLaneNode with the offsets
    // from the group block's start, and per group's first tree the block's
    // size (refactorTrippedInLanes' scratch copy).
    std::vector<TreeLaneNode> laneNodesLocal_;
    std::vector<std::uint32_t> laneBlockSize_;
    std::vector<TreeLane4> laneData_;
    std::vector<std::uint64_t> lanePassesOf_;  // per group's first tree (only its solver writes it)
    std::vector<std::uint64_t> laneFactorPassesOf_;  // the same, for factorGroupInLanes
    std::vector<std::uint64_t> trippedLaneFactorsOf_;  // the same, trees for refactorTrippedInLanes
    unsigned trippedLaneFailures_ = 0;  // setTrippedLaneFailures
    // Per tree: its factorization is in its group's lanes only (factors_'
    // D, Hp and X stale until copyFactorFromLanes).
    std::vector<std::uint8_t> laneOnly_;
    bool laneFactor_ = true, laneFactorCheck_ = false;
    std::vector<std::uint64_t> laneFactorChecksOf_, laneFactorMismatchesOf_;  // per group's first tree (setLaneFactorCheck)
    // setLaneFactorCheck's comparison for one tree of a group just factored in lanes.
    bool laneFactorMatchesScalar(std::uint32_t tree, std::vector<JointConstraint>& joints, const SolverBody* bodies,
                                 const JointContext& ctx);
    int lanes_ = 0, lanesWanted_ = 0;
    bool wideEnds_ = true;
    bool foldWarmStart_ = false, firstBiasedPass_ = false;
    bool foldThisPass_ = false;  // beginPass(): this pass takes the folded warm start
    Real guardTurn2_ = static_cast<Real>(kGuardTurn * kGuardTurn);  // the guard's angle, squared
    std::vector<std::uint8_t> direct_;  // per joint of the last build(): its `direct` flag (reuse())
    bool factored_ = false;
    // Position updates since the step's factorization (each relax pass
    // follows one): solve() factors again when the next pass would see
    // anchors maxFactorAge_ position updates old.
    int factorAge_ = 0;
    int maxFactorAge_ = kDefaultMaxFactorAge;
    // Factorizations by the schedule; guard trips per tree (trees may be
    // solved on several threads: each writes only its own), and those of
    // earlier builds.
    std::uint64_t factorizations_ = 0, guardTripsPast_ = 0;
    std::vector<std::uint64_t> guardTripsOf_;
    // build() scratch
    static constexpr std::uint32_t kBodyRoot = 0x80000000u;  // rootOf_: a tree rooted at a body, not a world joint
    std::vector<std::uint32_t> parentOf_, adjStart_, adj_, order_, rootOf_, frontier_;
    std::vector<std::uint8_t> visited_, contracted_, singular_, treeEdge_;
    std::vector<std::uint32_t> children_, nodeOf_;
    std::vector<Pending> queue_;
};

}  // namespace fulcrum::detail
