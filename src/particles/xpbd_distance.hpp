#pragma once
// XPBD distance constraints (Macklin, Müller, Chentanez 2016, "XPBD:
// Position-Based Simulation of Compliant Constrained Dynamics").
//
// For C = |x_a - x_b| - L with compliance alpha (m/N) and sub-step h, one
// Gauss-Seidel update is
//     alphaTilde = alpha / h^2
//     dLambda    = (-C - alphaTilde * lambda) / (w_a + w_b + alphaTilde)
//     x_a += w_a dLambda n,   x_b -= w_b dLambda n,   n = (x_a - x_b) / |x_a - x_b|
// lambda accumulates over the iterations of one sub-step and is reset at its
// start. lambda / h^2 is the constraint force, so at convergence C = -alpha * F:
// a constraint behaves as a spring of stiffness 1/alpha whatever the iteration
// count or time step (plain PBD's stiffness in [0, 1] is per iteration, so its
// effective stiffness changes with both). alpha = 0 is a rigid constraint.
//
// ---- Colours and SIMD (DistanceBatches)
// Solved one after another in the group's order, each constraint waits for the
// previous one's result (they share a particle): measured ~10 ns per constraint,
// latency-bound. Instead the constraints are split into colours - sets that
// share no particle - and a colour is solved 8 (AVX2, chosen at run time) or
// 4 (SSE2) constraints at a time in SIMD lanes (the graph colouring of
// docs/solver.md; constraints within a colour are independent, so the result
// is the same whatever the lane count: tested in Cloth.SimulationIsDeterministic).
//
// The colouring uses the structure every rope and cloth has: constraints
// (a, a + d) with the same index offset d (1 along a rope or a cloth row,
// the row length across rows, row length +- 1 on the diagonals, 2 and twice
// the row length for bend). Two constraints of one offset class share a
// particle only if their a's differ by exactly d, so class d splits into two
// colours by the parity of floor(a / d). For d >= 4 a colour then holds runs
// of consecutive a's whose b's are consecutive too: 4 lanes load with one
// unaligned SIMD load per coordinate and end instead of 8 scalar loads. For
// d = 1 and 2 (along rows) the 4 lanes' 8 particles fill one window of 8
// consecutive particles, split into a and b lanes with one shuffle (8 lanes:
// a window of 16, two in-half shuffles; the slots are stored in the order the
// shuffles produce, so no cross-half permute is needed). Any
// constraint that would still share a particle within its colour (duplicates,
// a == b) goes to a final sequential list. Each class's colours are solved in
// increasing offset order, so a cloth's stretch group sweeps along its rows,
// then across them.
//
// Measured on the 64 x 64 cloth (bench/cloth.cpp, 16 sub-steps): see
// docs/particles.md, "Performance".
//
// ---- Chains are solved in order (DistanceOrder)
// Colouring is a red-black (Jacobi-like) order: along a chain a correction
// travels one link per colour pass, so the load of a body hanging from a rope
// reaches the pin only after many sub-steps. Swept one by one from the held
// end, Gauss-Seidel carries it down the whole chain in one sweep. Measured on
// tests/particles_world's RopeHoldsAnAttachedBody (1 m, 10 segments, 2 kg
// body, 16 sub-steps): max stretch 1.098 % coloured, 0.596 % in order from the
// pinned end, 0.691 % from the body's end, 10.6 % alternating the direction
// every sub-step (it rings). Ropes are short, so the order costs nothing
// measurable; cloths keep the colours (their rows are swept in order within
// a colour anyway).
#include <cstdint>
#include <vector>

#include "particles/particle_soa.hpp"
#include "threads/staged_parallel.hpp"
#include "particles/particle_system.hpp"

namespace fulcrum::detail {

// How a group's constraints are ordered within a sweep.
enum class DistanceOrder : std::uint8_t {
    Coloured,  // colour by colour, several at a time in SIMD lanes (cloth)
    Forward,   // one by one in the group's order (a rope held at its start)
    Backward,  // one by one, last to first (a rope held at its end)
};

class DistanceBatches {
public:
    // Brings the batches up to date with `group` (re-colours only if its
    // constraints' particle pairs or the order changed; refreshes rest lengths
    // otherwise) and precomputes 1 / (w_a + w_b + alpha / h^2) for sub-step h.
    void prepare(const DistanceConstraintGroup& group, const std::vector<Real>& inverseMass, Real substep,
                 DistanceOrder order = DistanceOrder::Coloured);
    // One Gauss-Seidel sweep over the colours. The first iteration of a
    // sub-step starts the multipliers from 0 (no separate reset); the last
    // does not store them (nothing reads them after it).
    void solve(ParticleSoA& particles, bool firstIteration, bool lastIteration);
    // The same sweep as stages of a StagedParallel run (docs/particles.md,
    // "Threads"): addSweepStages appends one stage per colour (a colour of
    // kParallelSlots or more in units of whole SIMD chunks, counted from the
    // colour's start; a smaller one as a single unit) and one for the
    // sequential list; runSweepStage runs units [first, last) of the stage
    // whose arg it is given. A chunk reads and writes only its own
    // constraints' particles and no two constraints of a colour share one,
    // so the units of a stage may run in any order on any thread: the bits
    // of solve().
    void addSweepStages(StagedParallel& stages, std::uint32_t kind) const;
    void runSweepStage(ParticleSoA& particles, bool firstIteration, bool lastIteration, std::uint32_t arg,
                       std::uint32_t first, std::uint32_t last);
    // A colour at least this large is split: ~4 us of work with 8 lanes (a
    // 64 x 64 cloth's colours hold ~2,000 constraints).
    static constexpr std::size_t kParallelSlots = 1024;
    // SIMD chunks per unit of a split colour (256 constraints with 8 lanes, ~0.5 us).
    static constexpr std::uint32_t kChunksPerUnit = 32;
    std::size_t colourCount() const { return colourStart_.empty() ? 0 : colourStart_.size() - 1; }

private:
    void rebuild(const DistanceConstraintGroup& group, DistanceOrder order);
    template <bool First, bool Keep>
    void sweep(ParticleSoA& p);
    template <bool First, bool Keep>
    void solveColourRange(ParticleSoA& p, std::size_t begin, std::size_t end);
    template <bool First, bool Keep>
    void runStage(ParticleSoA& p, std::uint32_t arg, std::uint32_t first, std::uint32_t last);
    template <bool First, bool Keep>
    void solveRange(ParticleSoA& p, std::size_t begin, std::size_t end);

    std::vector<DistanceConstraint> source_;  // the group's constraints when coloured (change detection)
    std::vector<std::uint32_t> sourceIndex_;  // batch slot -> index in the group
    // Batch slots, colour by colour (structure of arrays).
    std::vector<std::uint32_t> a_, b_;
    std::vector<Real> rest_, inverseDenominator_, lambda_;
    std::vector<std::uint8_t> layout_;        // per chunk start k: where lanes k..k+3 find their particles
    std::vector<std::size_t> colourStart_;    // colour c is [colourStart_[c], colourStart_[c + 1])
    std::size_t sequentialBegin_ = 0;         // slots from here are solved one by one, in order
    Real alphaTilde_ = 0;
    bool unilateral_ = false;
    DistanceOrder order_ = DistanceOrder::Coloured;
    std::uint8_t lanes_ = 0;                  // SIMD lanes the layouts were made for
};

// Lanes of the coloured sweep on this machine: 8 with AVX2 (chosen at run
// time, also in the portable default build), 4 with SSE2, else 1. Every
// width gives bit-identical results (the lanes are independent constraints,
// each computing the scalar formula).
int distanceSimdLanes();
// Forces a narrower width (4 or 1; 0 restores the detected one): for tests
// and benchmarks comparing the kernels. Not thread-safe; call between steps.
void setDistanceSimdLanes(int lanes);

}  // namespace fulcrum::detail
