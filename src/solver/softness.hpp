#pragma once
// Soft constraints: an implicit spring-damper folded into a rigid row (the
// soft step of Box2D v3 / Catto's "Solver2D"). Contacts and joints share it.
#include <numbers>

#include "fulcrum/math.hpp"

namespace fulcrum::detail {

// Per-row coefficients: bias velocity = biasRate * C, impulse =
// -massScale * m_eff * (Cdot + bias) - impulseScale * accumulated.
struct Softness {
    Real biasRate = 0, massScale = 1, impulseScale = 0;
};

// A spring-damper at `hertz` and damping ratio `zeta` on sub-step h (0 Hz: rigid).
inline Softness makeSoftness(Real hertz, Real zeta, Real h) {
    if (hertz == 0) return {0, 1, 0};
    const Real omega = 2 * std::numbers::pi_v<Real> * hertz;
    const Real a1 = 2 * zeta + h * omega;
    const Real a2 = h * omega * a1;
    const Real a3 = 1 / (1 + a2);
    return {omega / a1, a2 * a3, a3};
}

}  // namespace fulcrum::detail
