#pragma once
// Forces on particles and the position-Verlet prediction of one sub-step.
//
// Position Verlet with a variable step (h this sub-step, h' the previous one):
//     x_{n+1} = x_n + d_n * (h / h') * k + a h^2,   d_n = x_n - x_{n-1},   k = 1 / (1 + h c)
// With constant h and no damping this is the textbook x' = 2x - x_prev + a h^2,
// exact for a constant acceleration. c (1/s) is the system's damping, the
// same law as the rigid bodies' linear damping. The constraint projection that
// follows moves x_{n+1}; the displacement (x_{n+1} - x_n) then includes the
// constraint forces, as in PBD.
//
// The displacement d is kept in its own array rather than recomputed as
// x - x_prev: far from the origin a float position cannot hold the tiny
// per-sub-step change a h^2 (1.1e-5 m for g at 16 sub-steps of 1/60 s;
// the spacing of floats near 10 is 9.5e-7, near 1000 it is 6.1e-5), so
// 2x - x_prev + a h^2 rounded it away systematically. Measured, a particle
// falling from rest for 1 s: x_prev stored, at y = 10 it gained 98.55 % of
// g t; with d stored it falls g t^2 / 2 within 1e-4 at y = 10 and 1000
// (test FreeFallIsExactFarFromTheOrigin).
//
// Accelerations a = g + F / m come from gravity, user forces, linear drag
// (F = -b v), particle springs and, for cloth, aerodynamic forces on its
// triangles (see aerodynamics in particle_integration.cpp).
#include <vector>

#include "particles/particle_soa.hpp"
#include "particles/particle_system.hpp"

namespace fulcrum::detail {

struct AirSettings {
    Vec3 wind;            // m/s, world
    Real density = 0;     // kg/m^3
};

// True if the system needs per-particle accelerations beyond gravity this step.
bool hasExtraForces(const ParticleSystem& system, const AirSettings& air);

// accel[i] = F_i / m_i for user forces, drag, springs and aerodynamics (gravity not included).
void computeForceAccelerations(const ParticleSystem& system, const AirSettings& air, Real substep,
                               std::vector<Vec3>& accel);

// How far the particles have drifted from reference positions (self-
// collision's neighbour list: where it was built), measured in the
// prediction's own pass: per axis, the range [lo, hi] of x - reference over
// every particle after the prediction. Exact (min and max do not round), so
// the answer does not depend on the SIMD width or order.
struct DriftRange {
    const Real* reference[3] = {nullptr, nullptr, nullptr};  // null: not measured
    Real lo[3] = {0, 0, 0};
    Real hi[3] = {0, 0, 0};
};

// Verlet prediction on the step's working copy; pinned particles jump to
// their pin targets (`system` gives pins and the Verlet ratio). `accel` may be
// empty (gravity only). Fills `drift` if it has references.
void predictPositions(ParticleSystem& system, ParticleSoA& particles, const Vec3& gravity, const std::vector<Vec3>& accel,
                      Real substep, DriftRange* drift = nullptr);

}  // namespace fulcrum::detail
