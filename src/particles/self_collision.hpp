#pragma once
// Particle-particle self-collision of one system, so a folded cloth does not
// pass through itself.
//
// Once per step a dense spatial hash (Teschner et al. 2003, "Optimized Spatial
// Hashing for Collision Detection of Deformable Objects"; the counting-sort
// layout of Müller's "Ten Minute Physics" cloth self-collision) finds the pairs
// within 2r plus the distance particles can travel this step. Pairs that are
// neighbours in the rest mesh (rest distance below
// ParticleSystem::selfCollisionExclusion) are skipped: the distance
// constraints already hold them, and a contact between them would fight those
// constraints. Every iteration then pushes overlapping pairs apart to r_a + r_b,
// sharing the correction by inverse mass (momentum conserving).
//
// All buffers keep their capacity between steps.
#include <array>
#include <cstdint>
#include <vector>

#include "particles/particle_system.hpp"

namespace fulcrum::detail {

class SelfCollision {
public:
    // `travel`: how far any particle may move during this step (m).
    void findPairs(const ParticleSystem& system, Real travel);
    void solve(ParticleSystem& system) const;
    std::size_t pairCount() const { return pairs_.size(); }

private:
    struct Pair {
        std::uint32_t a = 0, b = 0;
        Real minDistance = 0;
    };
    std::uint32_t bucketOf(std::int64_t ix, std::int64_t iy, std::int64_t iz) const;

    std::vector<std::uint32_t> cellStart_;   // prefix sums of bucket counts (tableSize + 1)
    std::vector<std::uint32_t> cellEntries_; // particle indices sorted by bucket
    std::vector<std::uint32_t> bucket_;      // bucket of each particle
    std::vector<std::array<std::int64_t, 3>> cell_;  // integer cell of each particle
    std::vector<Pair> pairs_;
    Real cellSize_ = 1;
};

}  // namespace fulcrum::detail
