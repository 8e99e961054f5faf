// The free-axis row of hinges and sliders solved with the joint's held rows: see coupled_row.hpp.
#include "solver/joints/coupled_row.hpp"

#include <cmath>

namespace fulcrum::detail {

namespace {

// K_ij = J_i M^-1 J_j^T for two rows on bodies a, b (JointRow sign conventions).
double coupling(const SolverBody& a, const SolverBody& b, const JointRow& r, const JointRow& s) {
    return static_cast<double>((a.invMass + b.invMass) * dot(r.linear, s.linear) + dot(r.angularA, a.invI * s.angularA) +
                               dot(r.angularB, b.invI * s.angularB));
}

}  // namespace

bool coupleRow(const SolverBody& a, const SolverBody& b, const JointRow* held, int count, const JointRow& measure,
               JointRow& apply, Real& invMass) {
    apply = measure;
    invMass = rowInverseMass(measure, a, b);
    double L[kMaxHeldRows][kMaxHeldRows] = {};
    double rhs[kMaxHeldRows] = {};
    for (int i = 0; i < count; ++i) {
        for (int k = 0; k <= i; ++k) L[i][k] = coupling(a, b, held[i], held[k]);
        rhs[i] = -coupling(a, b, held[i], measure);
    }
    double c[kMaxHeldRows];
    double k = 0;
    if (!coupledInverseMass(L, rhs, count, coupling(a, b, measure, measure), c, k)) return false;
    for (int i = 0; i < count; ++i) {
        const Real ci = static_cast<Real>(c[i]);
        apply.linear += held[i].linear * ci;
        apply.angularA += held[i].angularA * ci;
        apply.angularB += held[i].angularB * ci;
    }
    invMass = static_cast<Real>(k);
    return true;
}

void coupleHingeRow(const SolverBody& a, const SolverBody& b, const Vec3& rA, const Vec3& rB, const Vec3& axisA,
                    CoupledRow& out) {
    Vec3 p1, p2;
    orthonormalBasis(axisA, p1, p2);
    const JointRow held[5] = {linearRow({1, 0, 0}, rA, rB), linearRow({0, 1, 0}, rA, rB), linearRow({0, 0, 1}, rA, rB),
                              angularRow(p1), angularRow(p2)};
    out.measure = angularRow(axisA);
    coupleRow(a, b, held, 5, out.measure, out.apply, out.invMass);
}

void coupleSliderRow(const SolverBody& a, const SolverBody& b, const Vec3& leverA, const Vec3& rB, const Vec3& axis,
                     CoupledRow& out) {
    Vec3 p1, p2;
    orthonormalBasis(axis, p1, p2);
    const JointRow held[5] = {angularRow({1, 0, 0}), angularRow({0, 1, 0}), angularRow({0, 0, 1}),
                              linearRow(p1, leverA, rB), linearRow(p2, leverA, rB)};
    out.measure = linearRow(axis, leverA, rB);
    coupleRow(a, b, held, 5, out.measure, out.apply, out.invMass);
}

namespace {

void applyCoupled(const CoupledRow& r, Real sign, SolverBody& a, SolverBody& b, Real impulse) {
    applyRow(r.apply, a, b, sign * impulse);
}

}  // namespace

void solveCoupledLimit(const CoupledRow& r, Real sign, SolverBody& a, SolverBody& b, Real C, Real& lambda,
                       const JointContext& ctx) {
    const Real k = r.invMass;
    if (!(k > 0)) return;
    const Real next = nextLimitImpulse(sign * rowVelocity(r.measure, a, b), C, k, lambda, ctx);
    applyCoupled(r, sign, a, b, next - lambda);
    lambda = next;
}

void solveCoupledMotor(const CoupledRow& r, SolverBody& a, SolverBody& b, Real speed, Real maxImpulse, Real& lambda) {
    const Real k = r.invMass;
    if (!(k > 0)) return;
    const Real d = -(rowVelocity(r.measure, a, b) - speed) / k;
    Real next = lambda + d;
    next = next > maxImpulse ? maxImpulse : (next < -maxImpulse ? -maxImpulse : next);
    applyCoupled(r, 1, a, b, next - lambda);
    lambda = next;
}

void solveCoupledSpring(const CoupledRow& r, SolverBody& a, SolverBody& b, Real C, Real biasRate, Real gamma,
                        Real maxImpulse, Real& lambda) {
    const Real k = r.invMass;
    if (!(k + gamma > 0)) return;
    Real d = -(rowVelocity(r.measure, a, b) + biasRate * C + gamma * lambda) / (k + gamma);
    Real next = lambda + d;
    // Saturated: the drive's force limit. Only then is d recomputed, so an
    // unlimited (or unsaturated) spring keeps its bits.
    if (next > maxImpulse || next < -maxImpulse) {
        next = next > maxImpulse ? maxImpulse : -maxImpulse;
        d = next - lambda;
    }
    lambda = next;
    applyCoupled(r, 1, a, b, d);
}

}  // namespace fulcrum::detail
