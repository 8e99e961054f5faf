#pragma once
// Per-system figures for the `--json` report (docs/cli.md, `--json`: "particle_systems")
// and for tests: stretch, centroid, penetration into rigid shapes, energy.
#include <string>

#include "fulcrum/particles.hpp"
#include "particles/particle_system.hpp"
#include "particles/rigid_collider.hpp"

namespace fulcrum {

struct StretchStats {
    Real max = 0;   // max over structural constraints of (|x_a - x_b| - L) / L
    Real mean = 0;  // mean of the same (signed: compression counts negative)
};

Vec3 centroid(const ParticleSystem& system);
StretchStats structuralStretch(const ParticleSystem& system);
// Deepest overlap r - d over every particle and every rigid shape near the
// system, except the bodies the system is attached to.
Real maxPenetration(const ParticleSystem& system, const RigidCollider& collider);
// The figures World::particleReport returns (no collider: no penetration).
ParticleReport report(const ParticleSystem& system, const RigidCollider* collider);

// Energy: kinetic from the last sub-step's velocity (x - x_prev) / h,
// gravitational potential at x (relative to the origin along -gravity) and the
// elastic energy C^2 / (2 alpha) of the compliant distance constraints. This
// is the energy that a converged XPBD step (implicit Euler on the constraint
// potential) cannot increase: M (v' - v) / h = -grad U(x') gives
// E' - E <= -1/2 |v' - v|^2_M for convex U.
struct ParticleEnergy {
    double kinetic = 0;
    double potential = 0;
    double elastic = 0;
    double total() const { return kinetic + potential + elastic; }
};
ParticleEnergy energy(const ParticleSystem& system, const Vec3& gravity);
// Total linear momentum (kg m/s) from the last sub-step's velocities.
Vec3 linearMomentum(const ParticleSystem& system);

}  // namespace fulcrum
