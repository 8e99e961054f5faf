#include "particles/particle_integration.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE  // float lanes: the double build runs the scalar loop
#include <emmintrin.h>
#endif

namespace fulcrum::detail {

bool hasExtraForces(const ParticleSystem& system, const AirSettings& air) {
    if (system.linearDrag > 0 || !system.springs.empty()) return true;
    if (!system.triangles.empty() && air.density > 0 && (system.dragCoefficient > 0 || system.liftCoefficient != 0)) {
        return true;
    }
    return std::any_of(system.force.begin(), system.force.end(), [](const Vec3& f) { return f != Vec3::zero(); });
}

namespace {

// Flat-plate aerodynamics of one triangle (the model of Keckeisen et al. 2004
// and of most cloth simulators): with u = wind - v_triangle the air's velocity
// relative to the cloth, n the unit normal, A the area and cos = n . u / |u|,
//   drag = 1/2 rho C_D A |cos| |u|^2 along u          (pushes the cloth downwind)
//   lift = 1/2 rho C_L A |cos| |u|^2 * (p - (p . u^) u^),  p = sign(n . u) n
// i.e. lift is the part of the pressure direction p across the flow; it
// vanishes for a triangle edge-on (cos = 0) or face-on (p parallel to u) and
// peaks at 45 degrees, like a flat plate's. Each vertex takes a third.
void addAerodynamics(const ParticleSystem& s, const AirSettings& air, Real substep, std::vector<Vec3>& accel) {
    const Real halfRho = Real(0.5) * air.density;
    const Real invH = substep > 0 && s.previousSubstep > 0 ? 1 / s.previousSubstep : 0;
    for (const ParticleTriangle& t : s.triangles) {
        const Vec3 va = s.displacement[t.a] * invH;
        const Vec3 vb = s.displacement[t.b] * invH;
        const Vec3 vc = s.displacement[t.c] * invH;
        const Vec3 u = air.wind - (va + vb + vc) * (Real(1) / 3);
        const Real speed2 = lengthSquared(u);
        if (speed2 < Real(1e-12)) continue;
        const Vec3 areaNormal = cross(s.position[t.b] - s.position[t.a], s.position[t.c] - s.position[t.a]);
        const Real twiceArea = length(areaNormal);
        if (twiceArea < Real(1e-12)) continue;
        const Vec3 n = areaNormal / twiceArea;
        const Real area = Real(0.5) * twiceArea;
        const Real speed = std::sqrt(speed2);
        const Vec3 uHat = u / speed;
        const Real cosine = dot(n, uHat);
        const Real scale = halfRho * area * std::fabs(cosine) * speed2;
        Vec3 f = uHat * (scale * s.dragCoefficient);
        if (s.liftCoefficient != 0) {
            const Vec3 p = cosine >= 0 ? n : -n;
            f += (p - uHat * dot(p, uHat)) * (scale * s.liftCoefficient);
        }
        const Vec3 third = f * (Real(1) / 3);
        accel[t.a] += third * s.inverseMass[t.a];
        accel[t.b] += third * s.inverseMass[t.b];
        accel[t.c] += third * s.inverseMass[t.c];
    }
}

}  // namespace

void computeForceAccelerations(const ParticleSystem& s, const AirSettings& air, Real substep, std::vector<Vec3>& accel) {
    const std::size_t n = s.particleCount();
    accel.resize(n);  // no-op after the first step
    const Real invH = s.previousSubstep > 0 ? 1 / s.previousSubstep : 0;
    for (std::size_t i = 0; i < n; ++i) {
        Vec3 f = s.force[i];
        if (s.linearDrag > 0) f -= s.displacement[i] * (invH * s.linearDrag);
        accel[i] = f * s.inverseMass[i];
    }
    for (const ParticleSpring& sp : s.springs) {
        const Vec3 d = s.position[sp.b] - s.position[sp.a];
        const Real len = length(d);
        if (len < Real(1e-12)) continue;
        const Vec3 dir = d / len;
        const Vec3 vRel = (s.displacement[sp.b] - s.displacement[sp.a]) * invH;
        // Force on b; a receives the opposite.
        const Vec3 fb = dir * (-sp.stiffness * (len - sp.restLength) - sp.damping * dot(vRel, dir));
        accel[sp.b] += fb * s.inverseMass[sp.b];
        accel[sp.a] -= fb * s.inverseMass[sp.a];
    }
    if (!s.triangles.empty() && air.density > 0 && (s.dragCoefficient > 0 || s.liftCoefficient != 0)) {
        addAerodynamics(s, air, substep, accel);
    }
}

namespace {

// One coordinate of the prediction (particle_integration.hpp):
//     moved = (d + (x - q)) * keep,   d' = moved + (g + a) h^2 (free) or moved (pinned),
//     x' = q' = x + d'
// and, if `reference` is given, the range of x' - reference. `accelOf(i)` is
// particle i's extra acceleration on this axis.
template <class AccelOf>
void predictAxisScalar(std::size_t begin, std::size_t n, Real* x, Real* q, Real* d, const Real* w, Real g, Real keep,
                       Real h2, AccelOf accelOf, const Real* reference, Real& lo, Real& hi) {
    for (std::size_t i = begin; i < n; ++i) {
        const Real xi = x[i];
        const Real moved = (d[i] + (xi - q[i])) * keep;
        const Real next = w[i] > 0 ? moved + (g + accelOf(i)) * h2 : moved;
        d[i] = next;
        x[i] = q[i] = xi + next;
        if (reference) {
            const Real e = x[i] - reference[i];
            lo = e < lo ? e : lo;
            hi = e > hi ? e : hi;
        }
    }
}

// Gravity only: the same operations 4 at a time (SSE2), bit-identical to the
// scalar loop; folding the drift range into this pass saved the separate
// pass over the positions that the neighbour-list check was (7 % of the
// cloth benchmark's step).
void predictAxisGravity(std::size_t n, Real* x, Real* q, Real* d, const Real* w, Real g, Real keep, Real h2,
                        const Real* reference, Real& lo, Real& hi) {
    const auto none = [](std::size_t) { return Real(0); };
    std::size_t i = 0;
#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE  // float lanes: the double build runs the scalar loop
    const Real gh2 = (g + Real(0)) * h2;  // the scalar loop's (g + a) h^2 with a = 0
    const __m128 vKeep = _mm_set1_ps(keep), vGh2 = _mm_set1_ps(gh2), zero = _mm_setzero_ps();
    __m128 vLo = _mm_set1_ps(lo), vHi = _mm_set1_ps(hi);
    for (; i + 4 <= n; i += 4) {
        const __m128 xi = _mm_loadu_ps(x + i);
        const __m128 moved = _mm_mul_ps(_mm_add_ps(_mm_loadu_ps(d + i), _mm_sub_ps(xi, _mm_loadu_ps(q + i))), vKeep);
        const __m128 free = _mm_cmpgt_ps(_mm_loadu_ps(w + i), zero);
        const __m128 next = _mm_or_ps(_mm_and_ps(free, _mm_add_ps(moved, vGh2)), _mm_andnot_ps(free, moved));
        const __m128 nx = _mm_add_ps(xi, next);
        _mm_storeu_ps(d + i, next);
        _mm_storeu_ps(x + i, nx);
        _mm_storeu_ps(q + i, nx);
        if (reference) {
            const __m128 e = _mm_sub_ps(nx, _mm_loadu_ps(reference + i));
            vLo = _mm_min_ps(vLo, e);
            vHi = _mm_max_ps(vHi, e);
        }
    }
    alignas(16) float l[4], h[4];
    _mm_store_ps(l, vLo);
    _mm_store_ps(h, vHi);
    for (int k = 0; k < 4; ++k) {
        lo = l[k] < lo ? l[k] : lo;
        hi = h[k] > hi ? h[k] : hi;
    }
#endif
    predictAxisScalar(i, n, x, q, d, w, g, keep, h2, none, reference, lo, hi);
}

}  // namespace

void predictPositions(ParticleSystem& s, ParticleSoA& p, const Vec3& gravity, const std::vector<Vec3>& accel,
                      Real substep, DriftRange* drift) {
    const std::size_t n = p.size();
    const bool started = s.previousSubstep > 0;
    const Real ratio = started ? substep / s.previousSubstep : 0;
    const Real keep = ratio / (1 + substep * s.damping);
    // The first sub-step starts from rest: x_1 = x_0 + a h^2 / 2 (Taylor).
    // Taking x_{-1} = x_0 instead (a h^2) would give a released particle an
    // extra a h / 2 of speed: g t^2 / 2 (1 + 1 / n) after n sub-steps.
    const Real h2 = started ? substep * substep : Real(0.5) * substep * substep;
    const Real* w = p.w.data();
    Real* xs[3] = {p.x.data(), p.y.data(), p.z.data()};
    Real* qs[3] = {p.qx.data(), p.qy.data(), p.qz.data()};
    Real* ds[3] = {p.dx.data(), p.dy.data(), p.dz.data()};
    const Real g[3] = {gravity.x, gravity.y, gravity.z};
    const bool measure = drift != nullptr && drift->reference[0] != nullptr;
    for (int axis = 0; axis < 3; ++axis) {
        Real lo = std::numeric_limits<Real>::max(), hi = -std::numeric_limits<Real>::max();
        const Real* reference = measure ? drift->reference[axis] : nullptr;
        // One coordinate at a time: d + (x - q) is the last sub-step's
        // displacement including its constraint corrections (particle_soa.hpp).
        if (accel.empty()) {
            predictAxisGravity(n, xs[axis], qs[axis], ds[axis], w, g[axis], keep, h2, reference, lo, hi);
        } else {
            const Vec3* a = accel.data();
            const auto accelOf = [a, axis](std::size_t i) { return a[i][static_cast<std::size_t>(axis)]; };
            predictAxisScalar(0, n, xs[axis], qs[axis], ds[axis], w, g[axis], keep, h2, accelOf, reference, lo, hi);
        }
        if (measure) {
            drift->lo[axis] = lo;
            drift->hi[axis] = hi;
        }
    }
    // A pin places its particle; the jump from the prediction counts as the
    // particle's displacement (a moved pin carries its velocity).
    for (const ParticlePin& pin : s.pins) {
        p.setPosition(pin.particle, pin.target);
        if (!measure) continue;
        for (int axis = 0; axis < 3; ++axis) {
            const Real e = xs[axis][pin.particle] - drift->reference[axis][pin.particle];
            drift->lo[axis] = std::min(drift->lo[axis], e);
            drift->hi[axis] = std::max(drift->hi[axis], e);
        }
    }
    s.previousSubstep = substep;
}

}  // namespace fulcrum::detail
