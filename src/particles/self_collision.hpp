#pragma once
// Particle-particle self-collision of one system, so a folded cloth does not
// pass through itself.
//
// A uniform grid over the system's bounding box, filled by counting sort (the
// layout of Müller's "Ten Minute Physics" cloth self-collision; the spatial
// hash of Teschner et al. 2003 it replaces cost 1.5 ms per step here against
// 0.42: shared buckets need a cell check per entry, 27 cells per particle)
// finds the pairs within 2r plus a skin. Pairs that are neighbours in the rest
// mesh (rest distance below ParticleSystem::selfCollisionExclusion) are
// skipped: the distance
// constraints already hold them, and a contact between them would fight those
// constraints. Every iteration then pushes overlapping pairs apart to
// r_a + r_b, sharing the correction by inverse mass (momentum conserving).
//
// When to search: a Verlet neighbour list (as in molecular dynamics). The
// list holds every pair within 2r + skin when it was built; it stays complete
// while no particle has moved more than skin / 2 relative to some common
// motion m since then (two particles close in by at most |e_a - m| + |e_b - m|
// for their displacements e, and a uniform motion changes no distance). Each
// sub-step the prediction measures, in its own pass, the per-axis range of
// the displacements e; with m the range's centre, every |e - m| is at most
// the half-diagonal of that box, which must stay below 0.4 skin. (Measured
// on the cloth benchmark: 566 searches in 600 steps against 569 with the
// previous check, max |e - mean e|, which needed two extra passes: 7 % of the
// step.) The search happens only when needed. The previous scheme searched once per step with a margin of
// twice the largest relative travel of the whole step: once the 64 x 64 cloth
// hit the sphere, parts at rest and parts still falling at 6 m/s made that
// margin ~0.2 m, the hash cells held dozens of particles and the list tens of
// thousands of pairs, solved every sub-step (measured: 55 % of the step).
//
// All buffers keep their capacity between steps.
#include <cstdint>
#include <vector>

#include "fulcrum/task_system.hpp"
#include "particles/particle_integration.hpp"
#include "particles/particle_soa.hpp"
#include "particles/particle_system.hpp"

namespace fulcrum::detail {

class SelfCollision {
public:
    // Points `drift` at the positions the list was built at, so the
    // prediction measures how far the particles moved since (nothing when
    // there is no list to check).
    void requestDrift(const ParticleSoA& particles, DriftRange& drift) const;
    // Called every sub-step after the prediction with what it measured:
    // re-searches if the list may have become incomplete (or the system
    // changed), else does nothing.
    // `tasks` (may be null) runs the search's pair tests in fixed blocks of
    // sorted particles, each into its own list, joined in block order: the
    // list one thread makes, for any worker count.
    void update(const ParticleSystem& system, const ParticleSoA& particles, const DriftRange& drift,
                TaskSystem* tasks = nullptr);
    void solve(ParticleSoA& particles) const;
    std::size_t pairCount() const { return pairs_.size(); }
    std::size_t searchCount() const { return searches_; }
    // Forget the list (the system was edited between steps: a teleported particle).
    void invalidate() { valid_ = false; }

private:
    struct Pair {
        std::uint32_t a = 0, b = 0;
        Real minDistance = 0;
    };
    void findPairs(const ParticleSystem& system, const ParticleSoA& particles, TaskSystem* tasks);
    // Sorted particles per block of the pair tests (~5-10 us of work each on
    // the 64 x 64 cloth).
    static constexpr std::uint32_t kSearchBlock = 256;
    bool listStillComplete(const ParticleSoA& particles, const DriftRange& drift) const;

    std::vector<std::uint32_t> cellStart_;   // start of each grid cell in the sorted arrays (cells + 1)
    std::vector<std::uint32_t> cellOf_;      // grid cell of each particle
    std::vector<std::uint32_t> sortedIndex_; // particle indices sorted by cell
    std::vector<Real> sortedX_, sortedY_, sortedZ_;  // their positions, in the same order
    std::vector<Real> builtX_, builtY_, builtZ_;       // positions when the list was built
    std::vector<Pair> pairs_;
    std::vector<std::vector<Pair>> blockPairs_;  // per search block (threads); joined into pairs_
    Real skin_ = 0;
    bool valid_ = false;
    std::size_t searches_ = 0;
};

}  // namespace fulcrum::detail
