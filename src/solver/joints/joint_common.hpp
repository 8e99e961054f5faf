#pragma once
// Shared pieces of the joint solver: the per-step constraint record, the
// context of a pass, and the row kinds every joint is built from.
//
// Every joint is a set of rows J v + bias = 0 on two solver bodies (entry 0 of
// the contact solver's body array is the all-zero static stand-in, so a static
// end needs no branch). Rows come in five kinds (Catto, "Soft Step", 2024;
// Box2D v3's joint files are the model, written anew here for 3D):
//   equality  soft in the biased pass (implicit spring-damper coefficients,
//             Softness), rigid and bias-free in the relax pass;
//   limit     one-sided (lambda >= 0): speculative while the limit is not yet
//             reached (bias C / h lets the joint approach exactly to it), soft
//             once it is violated, bias-free in the relax pass;
//   motor     a velocity target, its impulse clamped to h * maxForce;
//   spring    a physical spring (stiffness k, damping c) in implicit form,
//             solved in both passes like any force;
//   block     the 3-row point-to-point (ball) and the 3-row angular lock are
//             solved as 3x3 blocks, which converges far better than three
//             scalar rows on long chains.
// Anchors and axes rotate with each sub-step's rotation delta (dq), as the
// soft step requires for joints (docs/joints.md; contacts keep the step's anchors).
#include <cmath>
#include <cstdint>
#include <limits>

#include "fulcrum/joint.hpp"
#include "solver/contact_solver.hpp"

namespace fulcrum::detail {

// Accumulated sub-step impulses of a joint, kept between steps for warm starting.
// Linear and angular block impulses are world vectors on body B.
struct JointImpulses {
    Vec3 linear;    // point rows, or the slider's two perpendicular rows
    Vec3 angular;   // angular lock rows (fixed, slider), the hinge's two alignment rows
    Real axial = 0;                 // rod / rigid distance row
    Real spring = 0, motor = 0;     // along the free axis (hinge, slider) or the distance
    Real lower = 0, upper = 0;      // limits (hinge, slider, distance min/max, cone-twist twist)
    Real swing = 0;                 // cone-twist swing cone
    Vec3 friction;                  // ball / cone-twist joint friction (angular, world, on B)
    // Six-DOF (six_dof.hpp): each axis's motor and spring, components along
    // the joint's axes (x, y, z). Its locks and limits use `linear` and
    // `angular`: world vectors when all three axes of the kind are locked (the
    // point block, the angular block), else per-axis components, signed
    // (lower limit +, upper -).
    Vec3 axisMotorLinear, axisMotorAngular, axisSpringLinear, axisSpringAngular;
    Vec3 drive;                     // cone-twist drive (angular, world, on B)
};

// A scalar row: +linear and +angularB act on B, -linear and -angularA on A.
struct JointRow {
    Vec3 linear, angularA, angularB;
};

// The free-axis row of a hinge or slider solved with the joint's held rows
// (coupled_row.hpp): `apply` is a unit impulse with the held rows' share,
// `invMass` its effective inverse mass, both from the sub-step's warm start.
struct CoupledRow {
    JointRow measure;  // the free row itself (its velocity)
    JointRow apply;
    Real invMass = 0;
};

// The geometry of a joint now, from its bodies' deltas since the step's start.
struct JointFrame {
    Vec3 rA, rB;   // anchors from each centre of mass, world, now
    Vec3 d;        // pB - pA
    Quat qA, qB;   // orientations now (kept only where the type reads them: updateFrame)
};

// One joint prepared for this step.
struct JointConstraint {
    std::uint32_t slot = 0;           // WorldImpl::joints index
    std::uint32_t bodyA = 0, bodyB = 0;  // solver body indices (0: static)
    std::uint32_t denseA = 0, denseB = 0;  // dense body indices (kNoIndex: the world)
    Vec3 localAnchorA, localAnchorB;  // from each centre of mass, body axes (world point for the world)
    JointType type = JointType::Ball;
    bool limit = false, motor = false, spring = false;
    Vec3 rA0, rB0;                    // anchors from each centre of mass, world, step start
    Vec3 centreDelta;                 // comB - comA at the step's start (world end: its com is the origin)
    Quat qA0, qB0;                    // orientations at the step's start (world: identity)
    Quat relative0;                   // conj(qA) qB at creation: the joint's rest pose
    Vec3 localAxisA, localAxisB;      // hinge / slider / cone-twist axis in each body's frame
    Real lower = 0, upper = 0;        // limits: rad (hinge, twist) or m (slider, distance min/max)
    Real swingLimit = 0;              // cone-twist, rad
    Real motorSpeed = 0, maxMotorImpulse = 0;
    Real springTarget = 0, springBias = 0, springGamma = 0;  // implicit spring row (see springCoefficients)
    Real maxSpringImpulse = std::numeric_limits<Real>::infinity();  // h * spring.maxForce (hinge, slider)
    Real restLength = 0;              // distance joints
    bool rigidDistance = false;       // rod: min == max and no spring
    bool direct = false;              // point rows solved by the tree solver (tree_solver.hpp), not here
    bool warmStartInTree = false;     // its tree may fold the warm start into its solve (JointTreeSolver::markWarmStartFree)
    bool pointMassValid = false;      // pointMass holds the inverse of the 3x3 point block's K
    std::uint8_t axialCoupled = 0;    // hinge: where `axial` was coupled this step (AxialCoupling, coupled_row.hpp)
    Mat3 pointMass = Mat3::zero();    // K^-1 at the sub-step's start (warm start), reused by its passes
    bool frictionValid = false;       // friction (ball, cone-twist): see cacheFriction
    Mat3 frictionMass = Mat3::zero(), frictionCoupling = Mat3::zero();
    Real maxFrictionImpulse = 0;      // h * frictionTorque (ball, cone-twist)
    CoupledRow axial;                 // hinge, slider: the free axis's rows (spring, motor, friction, limits)
    Quat localFrameA;                 // six-DOF: the joint frame in A's body axes
    const JointDef* record = nullptr; // the joint's definition (six-DOF axes, cone-twist drive): the world's record, alive through the step
    bool pointLocked = false, rotationLocked = false;  // six-DOF: all linear / all angular axes locked
    JointImpulses impulse;
    // The geometry for the current deltas (dp, dtheta) of its bodies, and the
    // rotation refresh at which it was computed (currentFrame): the deltas
    // change only when the positions do (ContactSolver::updateDeltas), so one
    // frame serves the warm start and every biased pass of a sub-step, and
    // the relax pass and the next sub-step's warm start (the same deltas).
    JointFrame frame;
    std::uint64_t frameAt = 0;
};

struct JointContext {
    Real h = 0, invH = 0;
    // Per solver body (JointSolver::refreshRotations): exp(dtheta), and the
    // refresh at which its deltas last changed; `generation`: the latest refresh.
    const Quat* rotations = nullptr;
    const std::uint64_t* changedAt = nullptr;
    std::uint64_t generation = 0;
    Softness soft;          // joints' equality rows (biased pass)
    Softness limitSoft;     // violated limits (biased pass)
    bool useBias = true;
};

inline Real rowVelocity(const JointRow& r, const SolverBody& a, const SolverBody& b) {
    return dot(r.linear, b.v - a.v) + dot(r.angularB, b.w) - dot(r.angularA, a.w);
}

inline Real rowInverseMass(const JointRow& r, const SolverBody& a, const SolverBody& b) {
    return (a.invMass + b.invMass) * lengthSquared(r.linear) + dot(r.angularA, a.invI * r.angularA) +
           dot(r.angularB, b.invI * r.angularB);
}

inline void applyRow(const JointRow& r, SolverBody& a, SolverBody& b, Real impulse) {
    a.v -= r.linear * (a.invMass * impulse);
    a.w -= a.invI * (r.angularA * impulse);
    b.v += r.linear * (b.invMass * impulse);
    b.w += b.invI * (r.angularB * impulse);
}

// Angular row about a world axis.
inline JointRow angularRow(const Vec3& axis) { return {Vec3{}, axis, axis}; }
// Linear row along d through anchors rA (lever arm on A) and rB.
inline JointRow linearRow(const Vec3& d, const Vec3& rA, const Vec3& rB) { return {d, cross(rA, d), cross(rB, d)}; }

// Equality row: C = 0, soft in the biased pass.
inline void solveEqualityRow(const JointRow& r, SolverBody& a, SolverBody& b, Real C, Real& lambda, const JointContext& ctx) {
    const Real k = rowInverseMass(r, a, b);
    if (k <= 0) return;
    Real bias = 0, massScale = 1, impulseScale = 0;
    if (ctx.useBias) {
        bias = ctx.soft.biasRate * C;
        massScale = ctx.soft.massScale;
        impulseScale = ctx.soft.impulseScale;
    }
    const Real d = -massScale * (rowVelocity(r, a, b) + bias) / k - impulseScale * lambda;
    lambda += d;
    applyRow(r, a, b, d);
}

// The next accumulated impulse (>= 0) of a one-sided limit row with inverse
// effective mass k > 0, row velocity `velocity` and position error C: rigid and
// speculative while C > 0 (the gap may close in one sub-step, no further), soft
// once violated. Shared by the plain rows and the coupled free-axis rows.
inline Real nextLimitImpulse(Real velocity, Real C, Real k, Real lambda, const JointContext& ctx) {
    Real bias = 0, massScale = 1, impulseScale = 0;
    if (C > 0) {
        bias = C * ctx.invH;
    } else if (ctx.useBias) {
        bias = ctx.limitSoft.biasRate * C;
        massScale = ctx.limitSoft.massScale;
        impulseScale = ctx.limitSoft.impulseScale;
    }
    const Real d = -massScale * (velocity + bias) / k - impulseScale * lambda;
    return lambda + d > 0 ? lambda + d : Real(0);
}

// One-sided limit row: keeps C >= 0 with lambda >= 0 (speculative while C > 0).
inline void solveLimitRow(const JointRow& r, SolverBody& a, SolverBody& b, Real C, Real& lambda, const JointContext& ctx) {
    const Real k = rowInverseMass(r, a, b);
    if (k <= 0) return;
    const Real next = nextLimitImpulse(rowVelocity(r, a, b), C, k, lambda, ctx);
    applyRow(r, a, b, next - lambda);
    lambda = next;
}

// Motor row: drives the row velocity to `speed` with |impulse| <= maxImpulse.
inline void solveMotorRow(const JointRow& r, SolverBody& a, SolverBody& b, Real speed, Real maxImpulse, Real& lambda) {
    const Real k = rowInverseMass(r, a, b);
    if (k <= 0) return;
    const Real d = -(rowVelocity(r, a, b) - speed) / k;
    Real next = lambda + d;
    next = next > maxImpulse ? maxImpulse : (next < -maxImpulse ? -maxImpulse : next);
    applyRow(r, a, b, next - lambda);
    lambda = next;
}

// Implicit spring-damper on a row (Catto, "Soft Constraints", GDC 2011): the
// sub-step impulse solves Cdot' + (k / (c + h k)) C + gamma lambda = 0 with
// gamma = 1 / (h (c + h k)); stable for any stiffness.
inline void springCoefficients(Real stiffness, Real damping, Real h, Real& bias, Real& gamma) {
    const Real s = damping + h * stiffness;
    if (s <= 0) {
        bias = 0;
        gamma = 0;
        return;
    }
    bias = stiffness / s;
    gamma = 1 / (h * s);
}

inline void solveSpringRow(const JointRow& r, SolverBody& a, SolverBody& b, Real C, Real biasRate, Real gamma, Real& lambda) {
    const Real k = rowInverseMass(r, a, b);
    if (k + gamma <= 0) return;
    const Real d = -(rowVelocity(r, a, b) + biasRate * C + gamma * lambda) / (k + gamma);
    lambda += d;
    applyRow(r, a, b, d);
}

// ---- blocks

// 3x3 effective mass inverse of the point-to-point constraint at anchors rA, rB.
inline Mat3 pointInverseMass(const SolverBody& a, const SolverBody& b, const Vec3& rA, const Vec3& rB) {
    const Mat3 sa = Mat3::skew(rA), sb = Mat3::skew(rB);
    return Mat3::diagonal(a.invMass + b.invMass) - sa * a.invI * sa - sb * b.invI * sb;
}

inline void applyPoint(SolverBody& a, SolverBody& b, const Vec3& rA, const Vec3& rB, const Vec3& P) {
    a.v -= P * a.invMass;
    a.w -= a.invI * cross(rA, P);
    b.v += P * b.invMass;
    b.w += b.invI * cross(rB, P);
}

// The impulse of a soft 3-row block with effective mass `invK`, velocity
// error `cdot` and position error C (biased pass) on top of the accumulated
// `lambda`: rigid in the relax pass, soft in the biased one. One place for
// the point block, the angular lock and the cone-twist's rigid drive.
inline Vec3 softBlockImpulse(const Mat3& invK, const Vec3& cdot, const Vec3& C, const Vec3& lambda, const JointContext& ctx) {
    Vec3 bias;
    Real massScale = 1, impulseScale = 0;
    if (ctx.useBias) {
        bias = C * ctx.soft.biasRate;
        massScale = ctx.soft.massScale;
        impulseScale = ctx.soft.impulseScale;
    }
    return -(invK * (cdot + bias)) * massScale - lambda * impulseScale;
}

// Point-to-point: pB - pA = C -> 0 (3 rows as one block). `invK` is the
// block's effective mass, computed once per sub-step (cachePointMass): the
// anchors turn little within a sub-step, and recomputing the 3x3 inverse in
// every pass cost the ball-joint grid a third of its time.
inline void solvePointBlock(SolverBody& a, SolverBody& b, const Vec3& rA, const Vec3& rB, const Vec3& C, Vec3& lambda,
                            const JointContext& ctx, const Mat3& invK) {
    const Vec3 cdot = b.v + cross(b.w, rB) - a.v - cross(a.w, rA);
    const Vec3 d = softBlockImpulse(invK, cdot, C, lambda, ctx);
    lambda += d;
    applyPoint(a, b, rA, rB, d);
}

inline void cachePointMass(JointConstraint& j, const SolverBody& a, const SolverBody& b, const Vec3& rA, const Vec3& rB) {
    const Mat3 K = pointInverseMass(a, b, rA, rB);
    j.pointMassValid = determinant(K) > 0;
    j.pointMass = j.pointMassValid ? inverse(K) : Mat3::zero();
}

// Angular lock: the rotation vector C of B from its rest pose relative to A -> 0.
inline void solveAngularBlock(SolverBody& a, SolverBody& b, const Vec3& C, Vec3& lambda, const JointContext& ctx) {
    const Mat3 K = a.invI + b.invI;
    const Real det = determinant(K);
    if (!(det > 0)) return;
    const Vec3 d = softBlockImpulse(inverse(K), b.w - a.w, C, lambda, ctx);
    lambda += d;
    a.w -= a.invI * d;
    b.w += b.invI * d;
}

// Joint friction (ball, cone-twist): the relative spin wB - wA -> 0 with the
// angular impulse's magnitude clamped to h * frictionTorque (dry friction).
//
// The friction torque T comes with the point impulse P = coupling * T that
// keeps the anchors' relative velocity unchanged, and its effective mass is
// the Schur complement of the point block,
//     K = K_ww - K_wp K_pp^-1 K_pw,   K_ww = IA^-1 + IB^-1,  K_wp = IB^-1 [rB]x + IA^-1 [rA]x,
// i.e. the spin as the joint allows it (a lever turning about its anchor),
// not the free body's. With the free body's mass alone, a light body far from
// its anchor (a 1 cm ball on a 1 m lever, inertia 4e-5 vs 1 kg m^2 about the
// anchor) was not slowed at all, and the warm-started impulse spun it up by
// 2,000 rad/s per sub-step until it blew up. Both are computed at the sub-step's
// warm start (cacheFriction).
// `always`: computed also without friction (the cone-twist drive's rows use
// the same Schur complement and coupling: cone_twist.cpp).
inline void cacheFriction(JointConstraint& j, const SolverBody& a, const SolverBody& b, const Vec3& rA, const Vec3& rB,
                          bool always = false) {
    j.frictionValid = false;
    if (j.maxFrictionImpulse <= 0 && !always) return;
    const Mat3 Kww = a.invI + b.invI;
    const Mat3 Kpp = pointInverseMass(a, b, rA, rB);
    if (!(determinant(Kpp) > 0)) return;
    const Mat3 Kwp = b.invI * Mat3::skew(rB) + a.invI * Mat3::skew(rA);
    const Mat3 KppInv = inverse(Kpp);
    const Mat3 Kpw = transpose(Kwp);
    const Mat3 K = Kww - Kwp * KppInv * Kpw;
    if (!(determinant(K) > 0)) return;
    j.frictionMass = inverse(K);
    j.frictionCoupling = Mat3::zero() - KppInv * Kpw;
    j.frictionValid = true;
}

inline void applyFriction(const JointConstraint& j, SolverBody& a, SolverBody& b, const Vec3& rA, const Vec3& rB, const Vec3& T) {
    const Vec3 P = j.frictionCoupling * T;
    a.v -= P * a.invMass;
    a.w -= a.invI * (T + cross(rA, P));
    b.v += P * b.invMass;
    b.w += b.invI * (T + cross(rB, P));
}

inline void solveFrictionBlock(JointConstraint& j, SolverBody& a, SolverBody& b, const Vec3& rA, const Vec3& rB) {
    if (!j.frictionValid) return;
    Vec3& lambda = j.impulse.friction;
    const Vec3 old = lambda;
    lambda -= j.frictionMass * (b.w - a.w);
    const Real len = length(lambda);
    if (len > j.maxFrictionImpulse) lambda *= j.maxFrictionImpulse / len;
    applyFriction(j, a, b, rA, rB, lambda - old);
}

// ---- current geometry of a joint from the bodies' deltas

// Rotation since the step's start. The solver keeps it as a rotation vector
// (the contact rows only need it to first order); joints need the exact
// rotation, which is its exponential map.
//
// The half-angle's sin and cos by their Taylor series up to 0.5 rad (a body
// turned under ~57 degrees since the step's start, nearly always): the first
// omitted terms, x^11 / 11! and x^12 / 12!, are below 1.3e-11, far under float
// rounding, and the series in double rounded once to float is as close as
// the library's sinf/cosf (within an ulp). The two library calls were most
// of refreshRotations (chain benchmark, callgrind 600 steps: 29.0 M -> see
// docs/joints.md, fifth round). sin(x) / angle is taken as one factor, so
// the axis needs no division.
inline Quat deltaRotation(const SolverBody& b) {
    const Real angle = length(b.dtheta);
    if (!(angle > Real(0))) return Quat::identity();
    const Real half = Real(0.5) * angle;
    if (!(half <= Real(0.5))) {
        const Vec3 n = b.dtheta / angle;
        Real s = 0, c = 1;
        dmath::sinCos(half, s, c);
        return {c, n.x * s, n.y * s, n.z * s};
    }
    const double x = static_cast<double>(half), z = x * x;
    // sin(x) / (2 x) = sin(half) / angle, and cos(x).
    const double sinOverAngle =
        0.5 * (1 + z * (-1.0 / 6 + z * (1.0 / 120 + z * (-1.0 / 5040 + z * (1.0 / 362880)))));
    const double c = 1 + z * (-0.5 + z * (1.0 / 24 + z * (-1.0 / 720 + z * (1.0 / 40320 + z * (-1.0 / 3628800)))));
    const Real k = static_cast<Real>(sinOverAngle);
    return {static_cast<Real>(c), b.dtheta.x * k, b.dtheta.y * k, b.dtheta.z * k};
}

// Ball and distance joints read only the anchors and their separation (each
// type's kReadsOrientations says the same: joint_types.hpp checks it). A
// test of the type here, not a flag in the record: the tree solver's chain
// pass (currentFrame, inline there) took 0.2 % more instructions with a flag.
constexpr bool frameNeedsOrientations(JointType t) { return t != JointType::Ball && t != JointType::Distance; }

// f <- the joint's geometry for rotations dqA, dqB since the step's start
// (orientations only where the joint type reads them).
inline void updateFrame(JointFrame& f, const JointConstraint& j, const SolverBody& a, const SolverBody& b, const Quat& dqA,
                        const Quat& dqB) {
    f.rA = rotate(dqA, j.rA0);
    f.rB = rotate(dqB, j.rB0);
    f.d = j.centreDelta + (b.dp - a.dp) + f.rB - f.rA;
    if (frameNeedsOrientations(j.type)) {
        f.qA = dqA * j.qA0;
        f.qB = dqB * j.qB0;
    }
}

// The joint's geometry inside a pass: its kept frame, recomputed first if
// one of its bodies' deltas changed since it was computed (the same bits as
// computing it every time: the inputs are the same).
inline const JointFrame& currentFrame(JointConstraint& j, const SolverBody& a, const SolverBody& b, const JointContext& ctx) {
    if (j.frameAt < ctx.changedAt[j.bodyA] || j.frameAt < ctx.changedAt[j.bodyB]) {
        updateFrame(j.frame, j, a, b, ctx.rotations[j.bodyA], ctx.rotations[j.bodyB]);
        j.frameAt = ctx.generation;
    }
    return j.frame;
}

// Rotation of B away from its rest pose relative to A, as a world rotation vector.
inline Vec3 angularError(const JointConstraint& j, const Quat& qA, const Quat& qB) {
    return toRotationVector(qB * conjugate(qA * j.relative0));
}

// Angle of B relative to A about A's axis `localAxis`, from the rest pose, in (-pi, pi]:
// the twist part of the swing-twist decomposition of the relative rotation.
inline Real twistAngle(const Quat& relative0, const Quat& qA, const Quat& qB, const Vec3& localAxis) {
    Quat r = conjugate(qA) * qB * conjugate(relative0);
    if (r.w < 0) r = -r;
    return 2 * dmath::atan2(dot(r.vec(), localAxis), r.w);
}

// ---- prepare (JointSolver::prepare): rows a joint does not use this step start at zero

inline void dropLimitImpulsesIfOff(JointConstraint& j) {
    if (!j.limit) j.impulse.lower = j.impulse.upper = 0;
}
// Spin friction (ball, cone-twist) off: no friction row and no impulse.
inline void dropSpinFriction(JointConstraint& j) {
    j.maxFrictionImpulse = 0;
    j.impulse.friction = {};
}
inline void dropSpinFrictionIfOff(JointConstraint& j) {
    if (j.maxFrictionImpulse == 0) dropSpinFriction(j);
}

// Force (N) and torque (N m) the joint applied to body B over the last sub-step,
// from its accumulated impulses; `invH` = 1 / sub-step. Torque about B's anchor
// (j.frame: JointSolver::store brings it up to date first).
void jointReaction(const JointConstraint& j, const SolverBody& a, const SolverBody& b, Real invH, Vec3& force, Vec3& torque);

}  // namespace fulcrum::detail
