#include "particles/self_collision.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace fulcrum::detail {

std::uint32_t SelfCollision::bucketOf(std::int64_t ix, std::int64_t iy, std::int64_t iz) const {
    // Teschner's hash with unsigned arithmetic (wrap-around is defined).
    const auto ux = static_cast<std::uint32_t>(ix), uy = static_cast<std::uint32_t>(iy), uz = static_cast<std::uint32_t>(iz);
    const std::uint32_t h = (ux * 92837111u) ^ (uy * 689287499u) ^ (uz * 283923481u);
    return h % static_cast<std::uint32_t>(cellStart_.size() - 1);
}

void SelfCollision::findPairs(const ParticleSystem& s, Real travel) {
    pairs_.clear();
    const std::size_t n = s.particleCount();
    if (!s.selfCollision || n < 2) return;
    Real maxRadius = 0;
    for (Real r : s.radius) maxRadius = std::max(maxRadius, r);
    const Real reach = 2 * maxRadius + travel;  // farthest pair that can touch during the step
    cellSize_ = reach;
    const std::size_t tableSize = 2 * n;
    cellStart_.assign(tableSize + 1, 0);  // same size every step: no reallocation
    cellEntries_.resize(n);
    bucket_.resize(n);
    cell_.resize(n);
    const Real inv = 1 / cellSize_;
    const auto cellCoord = [inv](Real v) { return static_cast<std::int64_t>(std::floor(v * inv)); };
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3& p = s.position[i];
        cell_[i] = {cellCoord(p.x), cellCoord(p.y), cellCoord(p.z)};
        bucket_[i] = bucketOf(cell_[i][0], cell_[i][1], cell_[i][2]);
        ++cellStart_[bucket_[i]];
    }
    // Inclusive prefix sums: cellStart_[b] = end of bucket b; then fill
    // backwards, decrementing, so cellStart_[b] ends at the start of bucket b
    // and each bucket lists its particles in ascending order (determinism).
    for (std::size_t b = 1; b < tableSize; ++b) cellStart_[b] += cellStart_[b - 1];
    cellStart_[tableSize] = static_cast<std::uint32_t>(n);
    for (std::size_t i = n; i-- > 0;) cellEntries_[--cellStart_[bucket_[i]]] = static_cast<std::uint32_t>(i);

    const Real exclusion2 = s.selfCollisionExclusion * s.selfCollisionExclusion;
    const Real reach2 = reach * reach;
    for (std::size_t a = 0; a < n; ++a) {
        const Vec3& pa = s.position[a];
        const std::int64_t cx = cell_[a][0], cy = cell_[a][1], cz = cell_[a][2];
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
            for (std::int64_t dy = -1; dy <= 1; ++dy) {
                for (std::int64_t dx = -1; dx <= 1; ++dx) {
                    const std::array<std::int64_t, 3> cell{cx + dx, cy + dy, cz + dz};
                    const std::uint32_t bucket = bucketOf(cell[0], cell[1], cell[2]);
                    for (std::uint32_t e = cellStart_[bucket]; e < cellStart_[bucket + 1]; ++e) {
                        const std::uint32_t b = cellEntries_[e];
                        if (b <= a) continue;  // each pair once, owned by its lower index
                        // Several cells share a bucket: take b only from its own cell, so
                        // it is seen once (cheaper than de-duplicating buckets or pairs).
                        if (cell_[b] != cell) continue;
                        if (s.inverseMass[a] == 0 && s.inverseMass[b] == 0) continue;
                        if (lengthSquared(s.position[b] - pa) > reach2) continue;
                        if (lengthSquared(s.restPosition[b] - s.restPosition[a]) < exclusion2) continue;
                        pairs_.push_back({static_cast<std::uint32_t>(a), b, s.radius[a] + s.radius[b]});
                    }
                }
            }
        }
    }
}

void SelfCollision::solve(ParticleSystem& s) const {
    Vec3* x = s.position.data();
    const Real* w = s.inverseMass.data();
    for (const Pair& p : pairs_) {
        const Vec3 d = x[p.a] - x[p.b];
        const Real dist2 = lengthSquared(d);
        if (dist2 >= p.minDistance * p.minDistance || dist2 < Real(1e-24)) continue;
        const Real dist = std::sqrt(dist2);
        const Real C = dist - p.minDistance;  // < 0
        const Real dLambda = -C / (w[p.a] + w[p.b]);
        const Vec3 n = d * (dLambda / dist);
        x[p.a] += n * w[p.a];
        x[p.b] -= n * w[p.b];
    }
}

}  // namespace fulcrum::detail
