#pragma once
// The position stage's per-body rotation work four bodies at a time, one per
// SIMD lane (GCC and Clang vector types on SSE2, the x86-64 baseline; one
// body at a time elsewhere): the rotation of an isotropic body by its
// angular velocity (integrateRotation) and the pose change since the step's
// start that the contact kernels read (BodyStore::updateDeltas). Each lane
// runs exactly the scalar function's operations in the same order (no FMA:
// -ffp-contract=off), so a body's bits do not depend on whether, or with
// which bodies, it went through the lanes: the world's results stay the same
// for any body order, thread ranges or lane grouping. A lane whose input
// leaves the range the lanes cover (a rotation under 1e-9 rad or a half
// angle above 0.75 rad, a turn too large for the rotation vector's series,
// anything not finite) takes the scalar function instead.
#include "fulcrum/math/quat.hpp"

namespace fulcrum::detail {

// For tests: false sends every body through the scalar functions (the
// reference the lanes must match bit for bit). Default true.
bool poseLanesEnabled();
void setPoseLanesEnabled(bool enabled);

// q[k] = integrateRotation(*q[k], *w[k], h) for k < n (1 <= n <= 4).
void integrateRotations(Quat* const* q, const Vec3* const* w, int n, Real h);

// *out[k] = stepRotationVector(*q[k] * conjugate(*start[k])) for k < n
// (1 <= n <= 4; body_store.hpp).
void stepRotationVectors(const Quat* const* q, const Quat* const* start, Vec3* const* out, int n);

}  // namespace fulcrum::detail
