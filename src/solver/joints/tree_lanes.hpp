#pragma once
// Four joint trees of one shape in SIMD lanes of doubles (issue 21, branch
// `rainlanes`): the forward and back-substitution of JointTreeSolver's pass on
// a kept factorization (solveTreeReused) for four trees at once, lane k the
// k-th tree. Every lane gets exactly the scalar operations in the scalar order
// (forward<dim, pdim>, forwardChainJoint, backSubstitute<dim, pdim>, with their
// `0 +` starts), so each tree keeps its own bits: IEEE add, subtract and
// multiply are correctly rounded in a lane as in a scalar register, and the
// build never contracts them into FMAs (-ffp-contract=off, no -mfma). The
// residuals before and the impulses after stay the scalar code, per lane
// (tree_solver.cpp); only the double mat-vecs on the stored blocks, about 600
// multiply-adds per ragdoll and pass, run here.
//
// Two builds of one kernel (tree_lanes_kernels.hpp): tree_lanes.cpp with the
// target's baseline (two SSE2 registers of two doubles on x86-64, WebAssembly
// SIMD128 or plain scalar code elsewhere) and tree_lanes_avx2.cpp with -mavx2
// (one register of four), taken only where the CPU has AVX2, as the contact
// and joint lanes (solver/contact_wide.hpp). Which one, or none (every tree
// scalar), follows the solver's SimdPath (FULCRUM_SIMD): JointTreeSolver::setLanes.
#include <cstdint>

namespace fulcrum::detail {

// Four doubles, lane k of tree k of a group.
struct alignas(32) TreeLane4 {
    double v[4];
};

// One node of a group's shape and where its lanes live in the group's block:
// at off, z[dim], y[dim], D^-1[dim][dim], Hp[pdim][dim], X[pdim][dim] (row
// major, the scalar Factor's entries that the passes read). parentOff: the
// parent node's off (kNoParent: a root, pdim 0).
struct TreeLaneNode {
    static constexpr std::uint32_t kNoParent = UINT32_MAX;
    std::uint32_t off = 0, parentOff = kNoParent;
    std::uint8_t kind = 0;  // JointTreeSolver's kBodyNode, kJointBelowJoint, kJointBelowBody
    std::uint8_t dim = 0, pdim = 0;
};

// The pass on the kept factorization for one group: forward substitution
// children first (nodes in the trees' elimination order), then the
// back-substitution parents first. z in, y out, in `data`.
void solveTreeLanes(const TreeLaneNode* nodes, std::uint32_t count, TreeLane4* data);
void solveTreeLanesAvx2(const TreeLaneNode* nodes, std::uint32_t count, TreeLane4* data);
// The factorization of a pass that factors (issue 21, branch `rain8`), for
// one group: JointTreeSolver::eliminate<dim, pdim> and eliminateChainJoint,
// children first, then the back-substitution, each lane the scalar
// operations in the scalar order. In `data`: z the right-hand side, D's
// slot D's lower triangle (row major), Hp H(parent, this); out: D^-1 (full),
// X, z forward-substituted and y, as the kept-factor passes read them.
// Returns the lanes (bit k: tree k) whose elimination failed (a block not
// definite: the scalar code's `false`); their values are not to be used.
unsigned factorTreeLanes(const TreeLaneNode* nodes, std::uint32_t count, TreeLane4* data);
unsigned factorTreeLanesAvx2(const TreeLaneNode* nodes, std::uint32_t count, TreeLane4* data);
// Whether tree_lanes_avx2.cpp was compiled with AVX2 (else solveTreeLanesAvx2 is the baseline one).
bool treeLanesAvx2Compiled();

}  // namespace fulcrum::detail
