#pragma once
// A joint's free-axis row (hinge angle, slider translation) solved together
// with the rows that hold the joint's other directions.
//
// Why: a hinge's friction, motor, spring and limit rows turn B about the axis,
// but the point rows, solved after them, turn a lever about its anchor, not
// about its centre. With the row's free-body effective mass 1 / (a . (IA^-1 +
// IB^-1) a) each pass only moves the lever by I_cm / (I_cm + m r^2) of what it
// should: a 5 cm sphere 0.5 m from its hinge got 0.4 % per pass, so 6 N m of
// friction let a 4.9 N m load fall (measured: the lever fell 0.6 rad in 1 s)
// and a motor never reached its speed under load. A slider's motor row
// through an anchor beside the centre has the opposite error (its free-body
// mass counts a rotation the angular lock forbids).
//
// The fix is the block solve of [held rows; free row] with the free row's
// impulse clamped: for a free-row impulse t the held rows take c t, where
//     K_oo c = -K_oa      (K = J M^-1 J^T over the two bodies),
// so the held rows' velocities don't change, and the free row's effective
// mass is the Schur complement 1 / (K_aa + K_ao c): the inertia about the
// joint, I_cm + m r^2 for a lever on a static hinge. This is the articulated
// effective mass of the joint's own two bodies (the rest of a tree is not
// included). The held rows' share is applied with the free row (`apply`) but
// stays out of their accumulated impulses; reaction forces add it back.
#include <cmath>
#include <cstdint>

#include "solver/joints/joint_common.hpp"

namespace fulcrum::detail {

inline constexpr int kMaxHeldRows = 5;

// The free row `measure` coupled to `count` held rows: `apply` is the impulse
// direction of a unit free-row impulse with the held rows' share, `invMass` its
// effective inverse mass. Returns false (and the plain row) when the held rows'
// block is singular (a body with locked rotation).
bool coupleRow(const SolverBody& a, const SolverBody& b, const JointRow* held, int count, const JointRow& measure,
               JointRow& apply, Real& invMass);

// The block solve behind coupleRow, on its couplings K_ij = J_i M^-1 J_j^T
// (double): L holds K_oo's lower triangle (overwritten by its Cholesky
// factor), rhs = -K_oa, kaa = K_aa. Gives c = K_oo^-1 rhs and the Schur
// complement schur = K_aa + K_ao c; false where K_oo or the complement is (nearly) singular.
// Shared by coupleRow and the wide hinge kernels (hinge_wide.hpp),
// which compute the couplings in lanes: one code, so the same bits. Static:
// each translation unit has its own copy (the AVX2 one may not lend its copy
// to code that runs without AVX2), and a constant `count` unrolls it (the
// wide hinge's solves, ragdolls, callgrind: 69 M out of line).
static inline bool coupledInverseMass(double (&L)[kMaxHeldRows][kMaxHeldRows], const double* rhs, int count,
                                      double kaa, double* c, double& schur) {
    // Cholesky of K_oo (count x count, double: the lever's I_cm and m r^2 differ by orders of magnitude).
    double scale = 0;
    for (int i = 0; i < count; ++i) scale = std::fmax(scale, L[i][i]);
    for (int j = 0; j < count; ++j) {
        double s = L[j][j];
        for (int k = 0; k < j; ++k) s -= L[j][k] * L[j][k];
        if (!(s > 1e-9 * scale)) return false;
        const double d = std::sqrt(s);
        L[j][j] = d;
        for (int i = j + 1; i < count; ++i) {
            double t = L[i][j];
            for (int k = 0; k < j; ++k) t -= L[i][k] * L[j][k];
            L[i][j] = t / d;
        }
    }
    for (int i = 0; i < count; ++i) {
        double t = rhs[i];
        for (int k = 0; k < i; ++k) t -= L[i][k] * c[k];
        c[i] = t / L[i][i];
    }
    for (int i = count; i-- > 0;) {
        double t = c[i];
        for (int k = i + 1; k < count; ++k) t -= L[k][i] * c[k];
        c[i] = t / L[i][i];
    }
    // Schur complement K_aa - K_ao K_oo^-1 K_oa = K_aa + K_ao c.
    schur = kaa;
    for (int i = 0; i < count; ++i) schur -= rhs[i] * c[i];
    return schur > 1e-12 * kaa;
}

// A hinge's coupled free-axis row (friction, motor, spring, limits) is
// coupled once per step and kept while neither body has turned more than
// kCouplingGuardTurn since the step's start; past it, the row is coupled
// again at every position update.
// Why: the coupling (a 5x5 solve in double per joint) depends only on the
// anchors, the axis and the inverse inertias, which turn with the bodies; a
// joint whose bodies barely turn within a step needn't redo it every
// sub-step (the hinges' warm start cost twice their passes in Box3D's rain).
// Why one guard, checked where the positions change: a kept row's error
// follows the largest turn any pass reuses it across, whatever its age (the
// lesson of the joint trees' factorization, docs/joints.md, "Factorization
// once per step"). The positions change only between a sub-step's biased
// passes and its relax pass; the next warm start and biased passes see the
// relax pass's positions. So the relax pass checks the guard (from the
// step's start, the rotations JointContext::rotations hold) and couples
// again where it trips, and every pass solves with a row coupled either at
// the step's start within the guard or at its own positions. A row once
// coupled away from the step's start is coupled at every later relax pass
// (Moved): measured from the step's start, its own pose is not known
// without keeping the rotations (32 bytes more per constraint record, the
// ball grid's memory traffic: +0.9 % instructions).
// Scalar and wide kernels take the decision with these functions, lane by
// lane (the same bits on every path).
enum AxialCoupling : std::uint8_t {
    kAxialNotCoupled = 0,  // not yet this step
    kAxialAtStart = 1,     // at the step's first warm start (the step's start pose)
    kAxialMoved = 2,       // at a relax pass, with that pass's positions
};
inline constexpr double kCouplingGuardTurn = 0.005;  // rad, the joint trees' guard (JointTreeSolver::kGuardTurn)
// Whether a body has turned by more than kCouplingGuardTurn since the step's
// start (rotA, rotB: JointContext::rotations; |q - 1| is half the angle, to first order).
inline bool couplingTurned(const Quat& rotA, const Quat& rotB) {
    constexpr Real kHalfTurn2 = static_cast<Real>(0.25 * kCouplingGuardTurn * kCouplingGuardTurn);
    const auto moved = [](const Quat& q) {
        const Real dw = q.w - 1;
        return ((dw * dw + q.x * q.x) + q.y * q.y) + q.z * q.z > kHalfTurn2;
    };
    return moved(rotA) || moved(rotB);
}
// Whether a pass (relax: !useBias) must couple the row again before solving:
// not coupled yet, or (at a relax pass, the positions new) coupled away from
// the step's start or a body turned past the guard.
inline bool couplingStale(std::uint8_t state, bool relax, const Quat& rotA, const Quat& rotB) {
    if (state == kAxialNotCoupled) return true;
    if (!relax) return false;
    return state == kAxialMoved || couplingTurned(rotA, rotB);
}

// The hinge's point rows (anchors rA, rB) and its two alignment rows (perpendicular to axisA).
void coupleHingeRow(const SolverBody& a, const SolverBody& b, const Vec3& rA, const Vec3& rB, const Vec3& axisA,
                    CoupledRow& out);
// The slider's angular lock and its two perpendicular rows (lever leverA on A, rB on B).
void coupleSliderRow(const SolverBody& a, const SolverBody& b, const Vec3& leverA, const Vec3& rB, const Vec3& axis,
                     CoupledRow& out);

// Rows on the free axis, solved with the coupled row: `r.measure` is the row
// of this pass (its velocity), `r.apply` / `r.invMass` of the sub-step's
// warm start. `sign` -1 turns the row around (upper limits).
void solveCoupledLimit(const CoupledRow& r, Real sign, SolverBody& a, SolverBody& b, Real C, Real& lambda,
                       const JointContext& ctx);
void solveCoupledMotor(const CoupledRow& r, SolverBody& a, SolverBody& b, Real speed, Real maxImpulse, Real& lambda);
// The spring's accumulated impulse is clamped to +-maxImpulse (h maxForce, the
// position drive's limit); unclamped, the update is the plain `lambda += d`
// (the same bits as before the limit existed).
void solveCoupledSpring(const CoupledRow& r, SolverBody& a, SolverBody& b, Real C, Real biasRate, Real gamma,
                        Real maxImpulse, Real& lambda);

// JointSolver::prepare for a hinge or slider: the free axis's limits, motor
// and spring from its definition's record (h: the sub-step).
inline void prepareFreeAxis(JointConstraint& j, const JointDef& def, Real h) {
    j.limit = def.hasLimits;
    j.lower = def.lowerLimit;
    j.upper = def.upperLimit;
    j.motor = def.motor.enabled;
    j.motorSpeed = def.motor.speed;
    j.maxMotorImpulse = h * def.motor.maxForce;
    j.spring = def.spring.enabled && (def.spring.stiffness > 0 || def.spring.damping > 0);
    j.springTarget = def.spring.target;
    springCoefficients(def.spring.stiffness, def.spring.damping, h, j.springBias, j.springGamma);
    j.maxSpringImpulse = h * def.spring.maxForce;
}

// The reaction of the free axis's rows with the held rows' share (not in
// those rows' accumulated impulses, so added here; torque about B's anchor).
inline void addFreeAxisReaction(const JointConstraint& j, Vec3& force, Vec3& torque) {
    if (!(j.spring || j.motor || j.limit)) return;
    const JointImpulses& i = j.impulse;
    const Real axial = i.spring + i.motor + i.lower - i.upper;
    const Vec3 P = j.axial.apply.linear * axial;
    force += P;
    torque += j.axial.apply.angularB * axial - cross(j.frame.rB, P);
}

}  // namespace fulcrum::detail
