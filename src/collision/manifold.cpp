// Manifold reduction to four points (Gregorius, GDC 2015): the deepest point
// first, so the solver always sees the worst penetration; then the point
// farthest from it; then the point giving the largest triangle; then the point
// that adds the most area outside that triangle. Four well-spread points
// support a resting body as well as the whole polygon would.
#include "collision/manifold.hpp"

#include <algorithm>
#include <cmath>

namespace fulcrum::detail {

namespace {

// Ties are common (the corners of a resting box all share one depth, the rim
// points of a cylinder cap give several equal-area quads), and breaking them
// by float noise makes the chosen points jump between frames and between
// rigidly moved copies of the same configuration. So each stage takes the
// *first* candidate within a small tolerance of the best value: the choice
// then follows the candidates' order, which comes from the shapes' own features.
constexpr Real kDepthTie = Real(1e-4);  // metres
constexpr Real kRelTie = Real(1e-3);

// Each candidate's value is computed once into a small array when there are
// few candidates (a face clipped against a face gives at most 8 for boxes, a
// few dozen for hulls), instead of once for the best and again for the first
// near it: the same values, so the same choice bit for bit.
constexpr std::size_t kCachedValues = 80;

template <class Value>
std::size_t firstNearBest(std::size_t n, Value&& value, Real absTie, Real relTie, Real& best) {
    best = -1e30f;
    if (n <= kCachedValues) {
        Real v[kCachedValues];
        for (std::size_t i = 0; i < n; ++i) {
            v[i] = value(i);
            best = std::max(best, v[i]);
        }
        if (best <= -1e29f) return n;
        const Real threshold = best - absTie - relTie * std::fabs(best);
        for (std::size_t i = 0; i < n; ++i) {
            if (v[i] >= threshold) return i;
        }
        return n;
    }
    for (std::size_t i = 0; i < n; ++i) best = std::max(best, value(i));
    if (best <= -1e29f) return n;
    const Real threshold = best - absTie - relTie * std::fabs(best);
    for (std::size_t i = 0; i < n; ++i) {
        if (value(i) >= threshold) return i;
    }
    return n;
}

}  // namespace

std::uint32_t compactCandidates(ContactCandidate* candidates, std::uint32_t count, const Vec3& normal, Real margin) {
    Manifold kept;
    kept.normal = normal;
    reduceContacts({candidates, count}, margin, kept);
    for (std::uint32_t k = 0; k < kept.pointCount; ++k) {
        candidates[k] = {kept.points[k].position, kept.points[k].depth, kept.points[k].featureId};
    }
    return kept.pointCount;
}

void reduceContacts(std::span<const ContactCandidate> candidates, Real margin, Manifold& out) {
    out.pointCount = 0;
    const std::size_t n = candidates.size();
    if (n == 0) return;
    constexpr Real kNone = -1e30f;
    auto usable = [&](std::size_t i) { return candidates[i].depth >= -margin; };
    auto emit = [&](std::size_t i) {
        ContactPoint& p = out.points[out.pointCount++];
        p.position = candidates[i].position;
        p.depth = candidates[i].depth;
        p.featureId = candidates[i].featureId;
    };

    // 1. deepest
    Real best;
    const std::size_t i0 = firstNearBest(n, [&](std::size_t i) { return usable(i) ? candidates[i].depth : kNone; }, kDepthTie, 0, best);
    if (i0 == n) return;
    emit(i0);
    const Vec3 a = candidates[i0].position;

    // 2. farthest from the deepest
    Real far2;
    const std::size_t i1 = firstNearBest(
        n, [&](std::size_t i) { return usable(i) ? lengthSquared(candidates[i].position - a) : kNone; }, 0, 2 * kRelTie, far2);
    // Points closer than this are duplicates (the same corner found twice).
    const Real dupTol2 = far2 * Real(1e-6) + Real(1e-12);
    if (i1 == n || far2 <= dupTol2) return;
    emit(i1);
    const Vec3 b = candidates[i1].position;
    const Vec3 nrm = out.normal;

    // 3. largest triangle (area about the normal; its sign gives the winding)
    auto area = [&](std::size_t i) { return dot(cross(b - a, candidates[i].position - a), nrm); };
    Real bestArea;
    const std::size_t i2 = firstNearBest(n, [&](std::size_t i) { return usable(i) ? std::fabs(area(i)) : kNone; }, 0, kRelTie, bestArea);
    if (i2 == n || bestArea * bestArea <= dupTol2 * far2) return;
    emit(i2);
    // Orient the triangle counter-clockwise about the normal.
    Vec3 t0 = a, t1 = b, t2 = candidates[i2].position;
    if (area(i2) < 0) std::swap(t1, t2);

    // 4. the point adding the most area outside the triangle
    auto added = [&](std::size_t i) {
        if (!usable(i)) return kNone;
        const Vec3 q = candidates[i].position;
        const Real a01 = dot(cross(t1 - t0, q - t0), nrm);
        const Real a12 = dot(cross(t2 - t1, q - t1), nrm);
        const Real a20 = dot(cross(t0 - t2, q - t2), nrm);
        return -std::min(a01, std::min(a12, a20));
    };
    Real bestAdded;
    const std::size_t i3 = firstNearBest(n, added, 0, kRelTie, bestAdded);
    if (i3 != n && bestAdded > 0 && bestAdded * bestAdded > dupTol2 * far2) emit(i3);
}

}  // namespace fulcrum::detail
