#include "particles/self_collision.hpp"

#include <algorithm>
#include <cmath>

namespace fulcrum::detail {


void SelfCollision::requestDrift(const ParticleSoA& p, DriftRange& drift) const {
    const bool usable = valid_ && builtX_.size() == p.size();
    drift.reference[0] = usable ? builtX_.data() : nullptr;
    drift.reference[1] = usable ? builtY_.data() : nullptr;
    drift.reference[2] = usable ? builtZ_.data() : nullptr;
}

bool SelfCollision::listStillComplete(const ParticleSoA& p, const DriftRange& drift) const {
    if (builtX_.size() != p.size() || drift.reference[0] != builtX_.data()) return false;
    // Complete while the half-diagonal of the displacements' box is below
    // skin / 2; 0.4 leaves a fifth of the skin for the corrections of the
    // sub-step about to be solved.
    Real half2 = 0;
    for (int axis = 0; axis < 3; ++axis) {
        const Real half = Real(0.5) * (drift.hi[axis] - drift.lo[axis]);
        half2 += half * half;
    }
    const Real limit = Real(0.4) * skin_;
    return half2 < limit * limit;
}

void SelfCollision::update(const ParticleSystem& s, const ParticleSoA& p, const DriftRange& drift, TaskSystem* tasks) {
    if (!s.selfCollision || p.size() < 2) {
        pairs_.clear();
        valid_ = false;
        return;
    }
    if (valid_ && listStillComplete(p, drift)) return;
    findPairs(s, p, tasks);
}

void SelfCollision::findPairs(const ParticleSystem& s, const ParticleSoA& p, TaskSystem* tasks) {
    ++searches_;
    valid_ = true;
    pairs_.clear();
    const std::size_t n = p.size();
    Real maxRadius = 0;
    for (Real r : s.radius) maxRadius = std::max(maxRadius, r);
    // The skin trades searches for list length: 2r (one particle diameter)
    // is searched ~once per step while the 64 x 64 cloth slides off the
    // sphere, and rarely once it rests. (Search cost grows with the cell
    // area, (2r + skin)^2, the search rate falls as 1/skin: 2r is the optimum.)
    skin_ = 2 * maxRadius;
    const Real reach = 2 * maxRadius + skin_;  // farthest pair that can touch before the next search
    builtX_.assign(p.x.begin(), p.x.end());
    builtY_.assign(p.y.begin(), p.y.end());
    builtZ_.assign(p.z.begin(), p.z.end());

    // A dense grid over the system's bounding box, one empty cell of padding
    // on every side (so neighbour cells need no bounds checks). Cells of
    // size >= reach: touching pairs are in the same or adjacent cells. A
    // scattered system gets coarser cells rather than a huge table.
    Vec3 lo = p.position(0), hi = lo;
    bool finite = true;
    for (std::size_t i = 0; i < n; ++i) {
        const Vec3 x = p.position(i);
        finite = finite && std::isfinite(x.x) && std::isfinite(x.y) && std::isfinite(x.z);
        lo = min(lo, x);
        hi = max(hi, x);
    }
    // A system gone non-finite (a loaded snapshot that blows up in its first
    // sub-step; found by fuzz/snapshot_fuzz.cpp) has no grid: min/max skip
    // NaNs, so its cell coordinates would fall outside the table. No pairs;
    // the step's check after the sub-steps reports the NaN.
    if (!finite) {
        valid_ = false;
        return;
    }
    Real cell = reach;
    std::size_t gx = 0, gy = 0, gz = 0;
    const double cellLimit = 16.0 * static_cast<double>(n) + 4096.0;
    for (;;) {
        const auto dim = [cell](Real extent) { return static_cast<double>(std::floor(extent / cell)) + 3.0; };
        const double cells = dim(hi.x - lo.x) * dim(hi.y - lo.y) * dim(hi.z - lo.z);
        if (cells <= cellLimit) {
            gx = static_cast<std::size_t>(dim(hi.x - lo.x));
            gy = static_cast<std::size_t>(dim(hi.y - lo.y));
            gz = static_cast<std::size_t>(dim(hi.z - lo.z));
            break;
        }
        cell *= 2;
    }
    const std::size_t cells = gx * gy * gz;
    const Real inv = 1 / cell;
    cellStart_.assign(cells + 1, 0);
    cellOf_.resize(n);
    sortedIndex_.resize(n);
    sortedX_.resize(n); sortedY_.resize(n); sortedZ_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
        const auto ix = static_cast<std::size_t>((p.x[i] - lo.x) * inv) + 1;
        const auto iy = static_cast<std::size_t>((p.y[i] - lo.y) * inv) + 1;
        const auto iz = static_cast<std::size_t>((p.z[i] - lo.z) * inv) + 1;
        cellOf_[i] = static_cast<std::uint32_t>(ix + gx * (iy + gy * iz));
        ++cellStart_[cellOf_[i]];
    }
    // Counting sort (exclusive prefix sums, then fill in index order: each
    // cell lists its particles in ascending order - deterministic).
    std::uint32_t running = 0;
    for (std::size_t c = 0; c <= cells; ++c) {
        const std::uint32_t count = cellStart_[c];
        cellStart_[c] = running;
        running += count;
    }
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t k = cellStart_[cellOf_[i]]++;
        sortedIndex_[k] = static_cast<std::uint32_t>(i);
        sortedX_[k] = p.x[i]; sortedY_[k] = p.y[i]; sortedZ_[k] = p.z[i];
    }
    for (std::size_t c = cells; c-- > 0;) cellStart_[c + 1] = cellStart_[c];
    cellStart_[0] = 0;

    // Each pair once: a particle looks at the rest of its own row of three
    // cells (x - 1 .. x + 1) after itself in sorted order, and at four of
    // the eight neighbouring rows (the "forward" half); the other half sees
    // it from the other side. Rows are contiguous in the sorted arrays.
    const std::size_t rowY = gx, rowZ = gx * gy;
    const std::size_t forwardRows[4] = {rowY, rowZ - rowY, rowZ, rowZ + rowY};
    const Real exclusion2 = s.selfCollisionExclusion * s.selfCollisionExclusion;
    const Real reach2 = reach * reach;
    const Real* w = p.w.data();
    // Sorted particles [first, last) into `out`, in sorted order.
    const auto search = [&](std::size_t first, std::size_t last, std::vector<Pair>& out) {
        const auto consider = [&](std::uint32_t a, std::size_t k, Real ax, Real ay, Real az) {
            const Real ex = sortedX_[k] - ax, ey = sortedY_[k] - ay, ez = sortedZ_[k] - az;
            if (ex * ex + ey * ey + ez * ez > reach2) return;
            const std::uint32_t b = sortedIndex_[k];
            if (w[a] == 0 && w[b] == 0) return;
            if (lengthSquared(s.restPosition[b] - s.restPosition[a]) < exclusion2) return;
            out.push_back({std::min(a, b), std::max(a, b), s.radius[a] + s.radius[b]});
        };
        for (std::size_t k = first; k < last; ++k) {
            const std::uint32_t a = sortedIndex_[k];
            const Real ax = sortedX_[k], ay = sortedY_[k], az = sortedZ_[k];
            const std::size_t c = cellOf_[a];
            for (std::size_t e = k + 1; e < cellStart_[c + 2]; ++e) consider(a, e, ax, ay, az);
            for (const std::size_t offset : forwardRows) {
                const std::size_t r = c + offset;
                for (std::size_t e = cellStart_[r - 1]; e < cellStart_[r + 2]; ++e) consider(a, e, ax, ay, az);
            }
        }
    };
    const auto blocks = static_cast<std::uint32_t>((n + kSearchBlock - 1) / kSearchBlock);
    if (tasks == nullptr || tasks->workerCount() <= 1 || blocks < 2) {
        search(0, n, pairs_);
        return;
    }
    // Fixed blocks, each its own list (kept between searches: no allocation
    // once they have grown), joined in block order: the serial list.
    if (blockPairs_.size() < blocks) blockPairs_.resize(blocks);
    tasks->parallelFor(blocks, 1, [&](std::uint32_t begin, std::uint32_t end, std::uint32_t) {
        for (std::uint32_t block = begin; block < end; ++block) {
            std::vector<Pair>& out = blockPairs_[block];
            out.clear();
            const std::size_t first = std::size_t{block} * kSearchBlock;
            search(first, std::min(n, first + kSearchBlock), out);
        }
    });
    for (std::uint32_t block = 0; block < blocks; ++block) {
        pairs_.insert(pairs_.end(), blockPairs_[block].begin(), blockPairs_[block].end());
    }
}

void SelfCollision::solve(ParticleSoA& p) const {
    Real* x = p.x.data();
    Real* y = p.y.data();
    Real* z = p.z.data();
    const Real* w = p.w.data();
    for (const Pair& pair : pairs_) {
        const std::uint32_t a = pair.a, b = pair.b;
        const Real dx = x[a] - x[b], dy = y[a] - y[b], dz = z[a] - z[b];
        const Real dist2 = dx * dx + dy * dy + dz * dz;
        if (dist2 >= pair.minDistance * pair.minDistance || dist2 < Real(1e-24)) continue;
        const Real dist = std::sqrt(dist2);
        const Real C = dist - pair.minDistance;  // < 0
        const Real s = (-C / (w[a] + w[b])) / dist;
        x[a] += dx * s * w[a]; y[a] += dy * s * w[a]; z[a] += dz * s * w[a];
        x[b] -= dx * s * w[b]; y[b] -= dy * s * w[b]; z[b] -= dz * s * w[b];
    }
}

}  // namespace fulcrum::detail
