#pragma once
// XPBD distance constraints (Macklin, Müller, Chentanez 2016, "XPBD:
// Position-Based Simulation of Compliant Constrained Dynamics").
//
// For C = |x_a - x_b| - L with compliance alpha (m/N) and sub-step h, one
// Gauss-Seidel update is
//     alphaTilde = alpha / h^2
//     dLambda    = (-C - alphaTilde * lambda) / (w_a + w_b + alphaTilde)
//     x_a += w_a dLambda n,   x_b -= w_b dLambda n,   n = (x_a - x_b) / |x_a - x_b|
// lambda accumulates over the iterations of one sub-step and is reset at its
// start. lambda / h^2 is the constraint force, so at convergence C = -alpha * F:
// a constraint behaves as a spring of stiffness 1/alpha whatever the iteration
// count or time step (plain PBD's stiffness in [0, 1] is per iteration, so its
// effective stiffness changes with both). alpha = 0 is a rigid constraint.
#include "particles/particle_system.hpp"

namespace fulcrum::detail {

void resetMultipliers(DistanceConstraintGroup& group);
void solveDistanceGroup(ParticleSystem& system, DistanceConstraintGroup& group, Real substep);

}  // namespace fulcrum::detail
