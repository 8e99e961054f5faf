#pragma once
// Forces on particles and the position-Verlet prediction of one sub-step.
//
// Position Verlet with a variable step (h this sub-step, h' the previous one):
//     x_{n+1} = x_n + (x_n - x_{n-1}) * (h / h') * d + a h^2,   d = 1 / (1 + h c)
// With constant h and no damping this is the textbook x' = 2x - x_prev + a h^2.
// c (1/s) is the system's damping, the same law as the rigid bodies' linear
// damping. The constraint projection that follows moves x_{n+1}; the velocity
// (x_{n+1} - x_n) / h then includes the constraint forces, as in PBD.
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

// Verlet prediction; pinned particles jump to their pin targets.
// `accel` may be empty (gravity only).
void predictPositions(ParticleSystem& system, const Vec3& gravity, const std::vector<Vec3>& accel, Real substep);
// The same on the step's working copy (the solver's path; `system` gives pins and the Verlet ratio).
void predictPositions(ParticleSystem& system, ParticleSoA& particles, const Vec3& gravity, const std::vector<Vec3>& accel,
                      Real substep);

}  // namespace fulcrum::detail
