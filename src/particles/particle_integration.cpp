#include "particles/particle_integration.hpp"

#include <algorithm>
#include <cmath>

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

void predictPositions(ParticleSystem& s, ParticleSoA& p, const Vec3& gravity, const std::vector<Vec3>& accel,
                      Real substep) {
    const std::size_t n = p.size();
    const bool started = s.previousSubstep > 0;
    const Real ratio = started ? substep / s.previousSubstep : 0;
    const Real keep = ratio / (1 + substep * s.damping);
    // The first sub-step starts from rest: x_1 = x_0 + a h^2 / 2 (Taylor).
    // Taking x_{-1} = x_0 instead (a h^2) would give a released particle an
    // extra a h / 2 of speed: g t^2 / 2 (1 + 1 / n) after n sub-steps.
    const Real h2 = started ? substep * substep : Real(0.5) * substep * substep;
    const Real* w = p.w.data();
    // One coordinate at a time: three simple loops the compiler vectorises.
    // d + (x - q) is the last sub-step's displacement including its
    // constraint corrections (particle_soa.hpp).
    const auto axis = [&](Real* x, Real* q, Real* d, Real g, auto accelOf) {
        for (std::size_t i = 0; i < n; ++i) {
            const Real xi = x[i];
            const Real moved = (d[i] + (xi - q[i])) * keep;
            const Real next = w[i] > 0 ? moved + (g + accelOf(i)) * h2 : moved;
            d[i] = next;
            x[i] = q[i] = xi + next;
        }
    };
    if (accel.empty()) {
        const auto none = [](std::size_t) { return Real(0); };
        axis(p.x.data(), p.qx.data(), p.dx.data(), gravity.x, none);
        axis(p.y.data(), p.qy.data(), p.dy.data(), gravity.y, none);
        axis(p.z.data(), p.qz.data(), p.dz.data(), gravity.z, none);
    } else {
        const Vec3* a = accel.data();
        axis(p.x.data(), p.qx.data(), p.dx.data(), gravity.x, [a](std::size_t i) { return a[i].x; });
        axis(p.y.data(), p.qy.data(), p.dy.data(), gravity.y, [a](std::size_t i) { return a[i].y; });
        axis(p.z.data(), p.qz.data(), p.dz.data(), gravity.z, [a](std::size_t i) { return a[i].z; });
    }
    // A pin places its particle; the jump from the prediction counts as the
    // particle's displacement (a moved pin carries its velocity).
    for (const ParticlePin& pin : s.pins) p.setPosition(pin.particle, pin.target);
    s.previousSubstep = substep;
}

}  // namespace fulcrum::detail
