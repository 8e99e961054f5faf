// Manifold reduction to four points (Gregorius, GDC 2015): the deepest point
// first, so the solver always sees the worst penetration; then the point
// farthest from it; then the point giving the largest triangle; then the point
// that adds the most area outside that triangle. Four well-spread points
// support a resting body as well as the whole polygon would.
#include "collision/manifold.hpp"

#include <algorithm>
#include <cmath>

namespace fulcrum::detail {

void reduceContacts(std::span<const ContactCandidate> candidates, Real margin, Manifold& out) {
    out.pointCount = 0;
    const std::size_t n = candidates.size();
    if (n == 0) return;
    auto usable = [&](std::size_t i) { return candidates[i].depth >= -margin; };

    // 1. deepest
    std::size_t i0 = n;
    for (std::size_t i = 0; i < n; ++i) {
        if (usable(i) && (i0 == n || candidates[i].depth > candidates[i0].depth)) i0 = i;
    }
    if (i0 == n) return;
    auto emit = [&](std::size_t i) {
        ContactPoint& p = out.points[out.pointCount++];
        p.position = candidates[i].position;
        p.depth = candidates[i].depth;
        p.featureId = candidates[i].featureId;
    };
    emit(i0);
    const Vec3 a = candidates[i0].position;

    // 2. farthest from the deepest
    std::size_t i1 = n;
    Real best = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!usable(i)) continue;
        const Real d2 = lengthSquared(candidates[i].position - a);
        if (d2 > best) { best = d2; i1 = i; }
    }
    // Points closer than this are duplicates (the same corner found twice).
    const Real dupTol2 = best * Real(1e-6) + Real(1e-12);
    if (i1 == n || best <= dupTol2) return;
    emit(i1);
    const Vec3 b = candidates[i1].position;
    const Vec3 nrm = out.normal;

    // 3. largest triangle area (signed about the normal; keep its sign for winding)
    std::size_t i2 = n;
    Real bestArea = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!usable(i)) continue;
        const Real area = dot(cross(b - a, candidates[i].position - a), nrm);
        if (std::fabs(area) > std::fabs(bestArea)) { bestArea = area; i2 = i; }
    }
    if (i2 == n || bestArea * bestArea <= dupTol2 * best) return;
    emit(i2);
    // Orient the triangle counter-clockwise about the normal.
    Vec3 t0 = a, t1 = b, t2 = candidates[i2].position;
    if (bestArea < 0) { const Vec3 tmp = t1; t1 = t2; t2 = tmp; }

    // 4. the point adding the most area: most negative signed area against an edge
    std::size_t i3 = n;
    Real bestAdded = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (!usable(i)) continue;
        const Vec3 q = candidates[i].position;
        const Real a01 = dot(cross(t1 - t0, q - t0), nrm);
        const Real a12 = dot(cross(t2 - t1, q - t1), nrm);
        const Real a20 = dot(cross(t0 - t2, q - t2), nrm);
        const Real added = -std::min(a01, std::min(a12, a20));
        if (added > bestAdded) { bestAdded = added; i3 = i; }
    }
    if (i3 != n && bestAdded * bestAdded > dupTol2 * best) emit(i3);
}

}  // namespace fulcrum::detail
