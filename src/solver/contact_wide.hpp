#pragma once
// The wide (SIMD) contact solver: the constraints of one graph colour solved
// a block of 4 or 8 at a time, with the constraint data in structure-of-arrays
// blocks and the bodies gathered and scattered per lane.
//
// ---- Two widths, chosen at run time ---------------------------------------------
// The kernels (contact_wide_kernels.hpp) are written once over a simd.hpp
// policy and compiled twice: 4 lanes with SSE2 in contact_wide.cpp (every
// x86-64 CPU; PortablePolicy<4> elsewhere) and 8 lanes with AVX2 in
// contact_wide_avx2.cpp (only that file is compiled with -mavx2, and never
// with -mfma: see CMakeLists.txt and simd.hpp on contraction). Each ContactSolver
// picks one when it is made: AVX2 if the CPU has it (__builtin_cpu_supports),
// else SSE2; the environment variable FULCRUM_SIMD=scalar|sse2|avx2 and
// ContactSolver::setSimdPath override that (tests, benchmarks). The two
// widths and the scalar reference give the same bits (below), so the choice
// changes only the speed: measured in docs/solver.md ("8 lanes").
//
// Why it is correct: constraints of one colour share no dynamic body (the
// colouring in contact_solver.cpp), so the lanes of a block never write the
// same body and a block's result does not depend on the order of its lanes,
// nor on how a colour is cut into blocks (4 or 8 lanes).
// Static bodies are solver body 0 (all zeros) and kinematic bodies have
// infinite mass: they are gathered (a kinematic body has a velocity) but
// never scattered (writeA/writeB hold kEmptyLane), so lanes may share them.
//
// Why it is the scalar solver, bit for bit: every kernel does the same float
// operations in the same order as its scalar twin in contact_solver.cpp, and
// src/math/simd.hpp's operations are lane-wise the scalar ones. std::max(a, b)
// is (a < b) ? b : a, which is the wide max(b, a); std::min(a, b) is the wide
// min(b, a); std::clamp is two selects in its own order. The scalar branches
// become selects whose untaken side changes nothing; a lane beyond a
// manifold's point count has zero mass and zero impulse, so it adds exactly
// zero. The only freedom left is the sign of a zero (x - 0 vs x - (-0) when x
// is itself zero), which no later operation turns into a different non-zero
// value (there is no division by a velocity). tests/solver/simd_solver_test.cpp
// checks positions and velocities for equality over a pile's whole fall, for
// the scalar path, 4 lanes and 8 lanes.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "fulcrum/math.hpp"

namespace fulcrum::detail {

struct SolverBody;
struct Contact;

// What ContactSolver::buildConstraint reads for one constraint, copied out of
// its contact and manifold (prepare stages these in colour order, so the block
// build reads them sequentially instead of chasing one manifold allocation
// per lane).
struct LaneSource {
    Vec3 normal;
    std::uint32_t pointCount = 0;
    Vec3 frictionImpulse;
    Real twistImpulse = 0;
    Vec3 rollingImpulse;
    std::uint32_t bodyA = 0, bodyB = 0, contact = 0, manifoldIndex = 0;
    Real friction = 0, restitution = 0, rollingResistance = 0;
    Real pushMax = 0;  // ContactSolver::pushLimit
    Real biasRate = 0, massScale = 1, impulseScale = 0;  // the lane's softness: ContactSolver::softnessOf
    struct Point {
        Vec3 position;
        Real depth = 0, normalImpulse = 0;
    } points[4];
};

// Which code solves the coloured contact constraints.
enum class SimdPath : std::uint8_t {
    Scalar,  // ContactConstraint one at a time: the reference
    Sse2,    // 4 lanes (SSE2 on x86-64, portable C++ elsewhere)
    Avx2,    // 8 lanes (AVX2, only where the CPU has it)
};
const char* simdPathName(SimdPath path);
// The 8-lane kernels are compiled in and this CPU runs them.
bool avx2Available();
// The fastest path this machine runs: Avx2 if avx2Available(), else Sse2.
SimdPath bestSimdPath();
// FULCRUM_SIMD (scalar, sse2 or avx2; avx2 falls back to sse2 where the CPU
// lacks it) if set, else bestSimdPath(). Read once per process. An unknown
// value throws fulcrum::Error naming the variable and the accepted values.
SimdPath initialSimdPath();
// The path a FULCRUM_SIMD value names (null or empty: bestSimdPath()); throws
// fulcrum::Error naming the variable and the accepted values for anything else.
SimdPath simdPathFromSetting(const char* text);

// The blocks of one step and the kernels over them, for one width: the part
// of the solver that depends on the lane count, behind one virtual call per
// colour (or per block for build and store).
class WideBlocks {
public:
    virtual ~WideBlocks() = default;
    virtual SimdPath path() const = 0;
    virtual int lanes() const = 0;
    virtual std::size_t size() const = 0;
    virtual void reserve(std::size_t blocks) = 0;
    // Blocks [0, blocks); their contents are undefined until built.
    virtual void resize(std::size_t blocks) = 0;
    // Block `block` from lanes [0, laneCount) of `lanes`, the rest empty. The
    // same operations in the same order as ContactSolver::buildConstraint (the
    // scalar reference), so the same bits. startCom: each solver body's centre
    // of mass at the step's start.
    virtual void build(std::size_t block, const LaneSource* lanes, int laneCount, const SolverBody* bodies,
                       const Vec3* startCom) = 0;
    // Twins of ContactSolver::warmStart, solve, applyRestitution and store, over
    // blocks [first, first + count).
    virtual void warmStart(std::size_t first, std::size_t count, SolverBody* bodies) = 0;
    virtual void solve(std::size_t first, std::size_t count, SolverBody* bodies, bool useBias, Real invH) = 0;
    virtual void restitution(SolverBody* bodies, Real threshold) = 0;
    // Where block `block` stores its lanes' results (for the store's prefetch).
    virtual void laneTargets(std::size_t block, const std::uint32_t*& contact, const std::uint32_t*& manifold,
                             std::uint32_t& laneCount) const = 0;
    virtual void store(std::size_t first, std::size_t count, const SolverBody* bodies, Contact* contacts) const = 0;
    // The sum over the blocks of their largest lane point count (tests).
    virtual std::size_t pointRuns() const = 0;
    // Blocks whose end A is the static world in every lane run kernels that
    // read none of A's rows (staticAKernels in contact_wide_kernels.hpp: the
    // same bits); off, every block runs the general kernel (the tests'
    // reference). Set before building. On by default.
    virtual void setStaticAKernels(bool on) = 0;
    // How many of the built blocks took those kernels (tests).
    virtual std::size_t staticABlocks() const = 0;
};

// The blocks for `path` (Sse2, or Avx2 when avx2Available(); nullptr otherwise).
std::unique_ptr<WideBlocks> makeWideBlocks(SimdPath path);
// From contact_wide_avx2.cpp, for makeWideBlocks: whether that file was
// compiled with AVX2 (not on non-x86 targets or other compilers), and its
// 8-lane blocks (nullptr where it was not).
bool avx2KernelsCompiled();
std::unique_ptr<WideBlocks> makeAvx2Blocks();

}  // namespace fulcrum::detail
