#include "particles/xpbd_distance.hpp"

#include <algorithm>

namespace fulcrum::detail {

void resetMultipliers(DistanceConstraintGroup& group) { std::fill(group.lambda.begin(), group.lambda.end(), Real(0)); }

void solveDistanceGroup(ParticleSystem& system, DistanceConstraintGroup& group, Real substep) {
    Vec3* x = system.position.data();
    const Real* w = system.inverseMass.data();
    Real* lambda = group.lambda.data();
    const Real alphaTilde = group.compliance / (substep * substep);
    const bool unilateral = group.unilateral;
    const std::size_t count = group.constraints.size();
    for (std::size_t k = 0; k < count; ++k) {
        const DistanceConstraint c = group.constraints[k];
        const Vec3 d = x[c.a] - x[c.b];
        const Real len2 = lengthSquared(d);
        if (len2 < Real(1e-24)) continue;  // coincident: no direction to push along
        const Real len = std::sqrt(len2);
        const Real C = len - c.restLength;
        if (unilateral && C <= 0) continue;  // a slack tether does nothing
        const Real denominator = w[c.a] + w[c.b] + alphaTilde;
        if (denominator <= 0) continue;      // both ends immovable
        const Real dLambda = (-C - alphaTilde * lambda[k]) / denominator;
        lambda[k] += dLambda;
        const Vec3 n = d * (dLambda / len);
        x[c.a] += n * w[c.a];
        x[c.b] -= n * w[c.b];
    }
}

}  // namespace fulcrum::detail
