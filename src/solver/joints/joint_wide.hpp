#pragma once
// Joints in SIMD lanes: the Gauss-Seidel ball joints, hinges and cone-twists
// of one graph colour solved a block of 4 or 8 at a time (docs/joints.md,
// "Joint rows in SIMD lanes"), on the contact solver's pattern
// (solver/contact_wide.hpp). This essay describes the ball joints' blocks
// (ball_wide.hpp); hinges and cone-twists follow the same rules
// with what their rows add (hinge_wide.hpp, cone_twist_wide.hpp).
//
// Which joints (wideKind): ball joints whose point block the Gauss-Seidel
// passes solve (not a joint tree's: tree_solver.hpp has those rows) and that
// have no friction; ball joints with friction, cone-twists and hinges, in
// trees or not; in every colour but the overflow colour (whose joints may share a
// body and must run one after another). Everything else stays on the scalar
// kernels (joints/<type>.cpp), which remain the reference: FULCRUM_SIMD=scalar
// or JointSolver::setSimdPath(SimdPath::Scalar) runs every joint through them.
//
// Layout: per block, the lanes' solver-body indices (gathered by whole rows
// of the solver-body array, 4 floats per load, transposed in registers), the
// step's anchors (rA0, rB0, centre delta) and the accumulated impulse in
// structure-of-arrays form, plus what the passes derive from them: the frame
// (anchors and separation now) and the inverse of the 3x3 point block. Built
// once per step in JointSolver::prepare from the JointConstraint records; the
// impulses go back to the records in JointSolver::store.
//
// Why it is the scalar solver, bit for bit: each kernel is the twin of the
// scalar code it replaces (updateFrame, cachePointMass with pointInverseMass,
// applyPoint, solvePointBlock in joint_common.hpp) and does the same float
// operations in the same order, zero terms of the skew matrices included;
// simd.hpp's operations are lane-wise the scalar ones (no -mfma: see simd.hpp
// on contraction). A scalar branch (an invertible block or not, the biased
// pass or not) becomes a select between the two results, or, for the pass,
// a template argument. The frame is recomputed once per rotation refresh
// (JointSolver::refreshRotations) instead of where one of its bodies changed:
// an unchanged body has bit-identical deltas and rotation, so the recomputed
// frame has the bits of the kept one. Lanes of a block share no dynamic body
// (the colouring), so neither the order of the lanes nor the cut of a colour
// into blocks or task ranges changes a result; static and kinematic ends are
// gathered but never scattered (kEmptyLane), as the parallel scalar path
// works on copies of them. tests/joints/joint_simd_test.cpp checks positions
// and velocities for equality over whole runs on the scalar, 4- and 8-lane paths.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "fulcrum/math.hpp"
#include "solver/contact_wide.hpp"  // SimdPath, avx2Available, initialSimdPath: one switch for both solvers

namespace fulcrum::detail {

struct JointConstraint;
struct JointContext;
struct SolverBody;

// The blocks of one step's wide joints and the kernels over them, for one
// width (4 lanes: SSE2; 8: AVX2), behind one virtual call per range of blocks.
// A block holds joints of one kind (ball, cone-twist, hinge); a colour's
// blocks are consecutive, of any kinds.
class WideJoints {
public:
    virtual ~WideJoints() = default;
    virtual SimdPath path() const = 0;
    virtual int lanes() const = 0;
    virtual std::size_t size() const = 0;
    virtual void reserve(std::size_t blocks) = 0;
    // Forgets every block; build() then appends blocks 0, 1, 2...
    virtual void clear() = 0;
    // The next block from the constraints constraints[indices[0 .. laneCount)),
    // all of one type (wideKind), the rest of its lanes empty (no body, zero impulse).
    virtual void build(const JointConstraint* constraints, const std::uint32_t* indices, int laneCount,
                       const SolverBody* bodies) = 0;
    // Twins of the warm start and solve kernels (BallJoint::warmStart, BallJoint::solve,
    // ConeTwistJoint::warmStart...) over blocks [first, first + count). The context
    // gives the rotations of the latest refresh (ctx.rotations, number
    // ctx.generation: a block computes its frame once per refresh), the
    // softness and the pass; `constraints` the records (a tree joint's point
    // impulse lives there, the tree solver's; and the tree solver reads the
    // frame a block computes for a tree joint from there).
    virtual void warmStart(std::size_t first, std::size_t count, SolverBody* bodies, JointConstraint* constraints,
                           const JointContext& ctx) = 0;
    virtual void solve(std::size_t first, std::size_t count, SolverBody* bodies, JointConstraint* constraints,
                       const JointContext& ctx) = 0;
    // The accumulated impulses back into their constraints, and what the
    // reactions read of the step (friction coupling, the free axis's rows).
    virtual void store(JointConstraint* constraints) const = 0;
};

// Which blocks a joint goes into in a regular colour (NotWide: it stays on
// the scalar kernels): Ball, Gauss-Seidel frictionless ball joints;
// ConeTwist, cone-twists and ball joints with friction (in trees or not);
// Hinge, hinges (in trees or not). Sliders, fixed and distance joints, and a
// tree's frictionless ball joints (the tree solver has their only rows) are NotWide.
enum class WideKind : std::uint8_t { Ball, ConeTwist, Hinge, NotWide };
WideKind wideKind(const JointConstraint& j);

// The blocks for `path` (Sse2, or Avx2 when avx2Available(); nullptr for Scalar).
std::unique_ptr<WideJoints> makeWideJoints(SimdPath path);
// The blocks' atan2 (dmath::atan2 on Real, in the path's lanes) over n
// pairs, for tests: the same bits as dmath::atan2 one by one. False (nothing
// written) for a path whose joint kernels are not built or not runnable here.
bool wideAtan2(SimdPath path, const Real* y, const Real* x, Real* out, std::size_t n);
bool avx2JointAtan2(const Real* y, const Real* x, Real* out, std::size_t n);
// From joint_wide_avx2.cpp: whether it was compiled with AVX2, and its 8-lane blocks.
bool avx2JointKernelsCompiled();
std::unique_ptr<WideJoints> makeAvx2Joints();

}  // namespace fulcrum::detail
