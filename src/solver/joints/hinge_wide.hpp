// Hinge joints in SIMD lanes: the twins of HingeJoint::warmStart and HingeJoint::solve
// (hinge.cpp, coupled_row.cpp, joint_common.hpp), a part of the wide kernels
// (joint_wide_kernels.hpp includes it once per width, inside its namespace,
// after the shared pieces). Every hinge of a regular colour is wide, in a
// joint tree or not (a tree's joint leaves its point block to the tree
// solver, whose impulse lives in the constraint record).
//
// Same bits as the scalar kernels, and why:
// - what the scalar code derives from the frame alone in every pass (the two
//   axes, the basis (p1, p2) of the alignment rows, their 2x2 block, the
//   alignment error, the hinge angle with its arctangent) is computed once
//   per rotation refresh and kept: the same inputs give the same bits;
// - the free axis's coupling (coupleHingeRow: a 5x5 Cholesky in double, once
//   per sub-step) runs the scalar function's operations in lanes of doubles
//   (coupledInverseMassLanes; lane by lane through the scalar function itself
//   where there are no double lanes), on the lane's bodies and frame: the
//   block keeps its result (the `apply` row and the effective mass) for the
//   sub-step's passes, as the scalar record does;
// - each row does its scalar twin's operations in order; the motor's clamp
//   `next > max ? max : (next < -max ? -max : next)` is two selects in that
//   order; copysign(1, n.z) in orthonormalBasis reads the sign bit (n.z < 0
//   or 1 / n.z < 0, which also catches -0);
// - a branch is a mask (spring, motor, limit per lane; a row's positive
//   effective mass; the alignment block's positive determinant; the point
//   block where the tree solver does not have it and its K is invertible).
#ifndef FULCRUM_JOINT_WIDE_NS
#error "included by joint_wide_kernels.hpp only"
#endif

#include "solver/joints/coupled_row.hpp"

namespace fulcrum::detail::FULCRUM_JOINT_WIDE_NS {
namespace {

struct HingeBlock : FramedLanes {
    bool anyDirect = false, anySpring = false, anyMotor = false, anyLimit = false;
    bool allDirect = true;  // every used lane's point rows are the tree solver's: no point block here
    // The joint's constants.
    FloatW direct;                      // 1 where the tree solver has the point rows
    FloatW spring, motor, limit;        // 1 where the row is on
    FloatW springTarget, springBias, springGamma, maxSpringImpulse, motorSpeed, maxMotorImpulse, lower, upper;
    // Per rotation refresh: the frame, the axes, the alignment rows' basis,
    // block and error, the angle.
    Vec3W rA, rB, d;
    Vec3W axisA, p1, p2;
    FloatW k11, k12, k22, alignmentValid;  // K of the alignment rows; 1 where det > 0
    FloatW c1, c2;                         // p1 . (axisA x axisB), p2 . (axisA x axisB)
    FloatW angle;
    // Per sub-step (the warm start).
    Mat3W pointMass;
    FloatW pointMassValid;
    RowW apply;             // CoupledRow::apply
    FloatW axialInvMass;    // CoupledRow::invMass
    std::uint8_t axialCoupled[kLanes] = {};  // JointConstraint::axialCoupled (AxialCoupling: the coupling's guard)
    // Accumulated impulses (linear: the lanes not in a tree).
    Vec3W linear, angular;
    FloatW springImpulse, motorImpulse, lowerImpulse, upperImpulse;
};

void buildHingeBlock(HingeBlock& k, const JointConstraint* constraints, const std::uint32_t* indices, int laneCount,
                     const SolverBody* bodies) {
    k = HingeBlock{};
    k.laneCount = static_cast<std::uint32_t>(laneCount);
    const auto flag = [](FloatW& f, int l, bool on) { setLane(f, l, on ? 1.0f : 0.0f); };
    for (int l = 0; l < kLanes; ++l) {
        if (l >= laneCount) {
            setEmptyBodyLane(k, l);
            setEmptyRestPoseLane(k, l);
            setInertiaLane(k, l, bodies);
            continue;
        }
        const JointConstraint& j = constraints[indices[l]];
        setBodyLane(k, l, j, indices[l], bodies);
        setRestPoseLane(k, l, j);
        setInertiaLane(k, l, bodies);
        flag(k.direct, l, j.direct);
        flag(k.spring, l, j.spring);
        flag(k.motor, l, j.motor);
        flag(k.limit, l, j.limit);
        k.anyDirect = k.anyDirect || j.direct;
        k.allDirect = k.allDirect && j.direct;
        k.anySpring = k.anySpring || j.spring;
        k.anyMotor = k.anyMotor || j.motor;
        k.anyLimit = k.anyLimit || j.limit;
        setLane(k.springTarget, l, j.springTarget);
        setLane(k.springBias, l, j.springBias);
        setLane(k.springGamma, l, j.springGamma);
        setLane(k.maxSpringImpulse, l, j.maxSpringImpulse);
        setLane(k.motorSpeed, l, j.motorSpeed);
        setLane(k.maxMotorImpulse, l, j.maxMotorImpulse);
        setLane(k.lower, l, j.lower);
        setLane(k.upper, l, j.upper);
        setLane(k.linear, l, j.impulse.linear);
        setLane(k.angular, l, j.impulse.angular);
        setLane(k.springImpulse, l, j.impulse.spring);
        setLane(k.motorImpulse, l, j.impulse.motor);
        setLane(k.lowerImpulse, l, j.impulse.lower);
        setLane(k.upperImpulse, l, j.impulse.upper);
    }
}

// orthonormalBasis(n, t1, t2) (vec3.hpp), with sign = copysign(1, n.z).
FULCRUM_JOINT_WIDE_INLINE void orthonormalBasis(const Vec3W& n, Vec3W& t1, Vec3W& t2) {
    const FloatW zero = 0.0f, one = 1.0f;
    const MaskW negative = (n.z < zero) | (one / n.z < zero);
    const FloatW sign = select(negative, FloatW(-1.0f), one);
    const FloatW a = FloatW(-1.0f) / (sign + n.z);
    const FloatW b = n.x * n.y * a;
    t1 = {one + sign * n.x * n.x * a, sign * b, -sign * n.x};
    t2 = {b, sign + n.y * n.y * a, -n.y};
}

// updateFrame (orientations included), and what the passes derive from it alone.
FULCRUM_JOINT_WIDE_INLINE void updateHingeFrame(HingeBlock& k, const Ends& e, JointConstraint* constraints,
                                                const Quat* rotations, std::uint64_t generation) {
    const FloatW zero = 0.0f;
    const QuatW dqA = gatherRotation(rotations, k.bodyA), dqB = gatherRotation(rotations, k.bodyB);
    k.rA = rotate(dqA, k.rA0);
    k.rB = rotate(dqB, k.rB0);
    k.d = k.centreDelta + (e.b.dp() - e.a.dp()) + k.rB - k.rA;
    const QuatW qA = dqA * k.qA0, qB = dqB * k.qB0;
    k.axisA = rotate(qA, k.localAxisA);
    const Vec3W axisB = rotate(qB, k.localAxisB);
    // solveAlignment's basis, block and error.
    orthonormalBasis(k.axisA, k.p1, k.p2);
    const Mat3W I = e.invIA + e.invIB;
    const Vec3W Ip1 = I * k.p1, Ip2 = I * k.p2;
    k.k11 = dot(k.p1, Ip1);
    k.k12 = dot(k.p1, Ip2);
    k.k22 = dot(k.p2, Ip2);
    const FloatW det = k.k11 * k.k22 - k.k12 * k.k12;
    k.alignmentValid = select(det > zero, FloatW(1.0f), zero);
    const Vec3W C = cross(k.axisA, axisB);
    k.c1 = dot(k.p1, C);
    k.c2 = dot(k.p2, C);
    if (k.anySpring || k.anyLimit) k.angle = twistAngle(k.relative0Conjugate, qA, qB, k.localAxisA, k.laneCount);
    k.frameAt = generation;
    if (k.anyDirect) writeTreeFrames(constraints, k.constraint, k.laneCount, k.direct, k.rA, k.rB, k.d, qA, qB, generation);
}

FULCRUM_JOINT_WIDE_INLINE Vec3W hingePointImpulse(const HingeBlock& k, const JointConstraint* constraints) {
    if (!k.anyDirect) return k.linear;
    Vec3W P = k.linear;
    for (std::uint32_t lane = 0; lane < k.laneCount; ++lane) {
        const int l = static_cast<int>(lane);
        if (getLane(k.direct, l) > 0) setLane(P, l, constraints[k.constraint[lane]].impulse.linear);
    }
    return P;
}

// coupleHingeRow (coupled_row.cpp): the free axis's row with the point rows
// (unit x, y, z through rA, rB) and the alignment rows (p1, p2) held. The
// couplings K_ij (float, as `coupling` computes them, each body's M^-1 J_j
// once per row) in lanes; the 5x5 solve in double, in lanes of doubles
// (coupledInverseMassLanes: the bits of the scalar coupledInverseMass, which
// the targets without them call per lane); `apply` = measure + sum held_i c_i in
// lanes. Lanes whose solve fails get the plain row, as coupleRow returns it.
// Only the lanes in `redo` are coupled; the others keep theirs.
FULCRUM_JOINT_WIDE_INLINE void coupleHingeRow(HingeBlock& k, const Ends& e, const MaskW& redo) {
    const FloatW zero = 0.0f, one = 1.0f;
    const Vec3W units[3] = {{one, zero, zero}, {zero, one, zero}, {zero, zero, one}};
    constexpr int kRows = 6;  // 5 held, then the measured row
    RowW rows[kRows];
    for (int i = 0; i < 3; ++i) rows[i] = {units[i], cross(k.rA, units[i]), cross(k.rB, units[i])};  // linearRow
    rows[3] = angularRow(k.p1);
    rows[4] = angularRow(k.p2);
    rows[5] = angularRow(k.axisA);
    Vec3W massA[kRows], massB[kRows];  // IA^-1 s.angularA, IB^-1 s.angularB
    for (int i = 0; i < kRows; ++i) {
        massA[i] = e.invIA * rows[i].angularA;
        massB[i] = e.invIB * rows[i].angularB;
    }
    const FloatW m = e.mA + e.mB;
    const auto coupling = [&](int r, int s) {
        return m * dot(rows[r].linear, rows[s].linear) + dot(rows[r].angularA, massA[s]) + dot(rows[r].angularB, massB[s]);
    };
    alignas(32) Real K[5][5][kLanes];  // K_oo's lower triangle
    for (int i = 0; i < 5; ++i) {
        for (int j = 0; j <= i; ++j) coupling(i, j).store(K[i][j]);
    }
    alignas(32) Real rowMass[kLanes];
    coupling(5, 5).store(rowMass);  // rowInverseMass(measure) = K_aa in float
    // rhs_i = -K_ia, with K_ia = coupling(held_i, measure): its own products.
    alignas(32) Real Kia[5][kLanes];
    for (int i = 0; i < 5; ++i) coupling(i, 5).store(Kia[i]);
    alignas(32) Real c[5][kLanes] = {}, invMass[kLanes], coupled[kLanes] = {};
#ifdef FULCRUM_JOINT_WIDE_DOUBLE_LANES
    // The lanes' solves in lanes of doubles (coupledInverseMassLanes: the
    // scalar function's bits), kDoubleLanes at a time where one needs it.
    for (int first = 0; first < static_cast<int>(k.laneCount); first += kDoubleLanes) {
        bool any = false;
        for (int l = first; l < first + kDoubleLanes; ++l) any = any || (l < static_cast<int>(k.laneCount) && redo.lane(l));
        if (!any) continue;
        LanesD L[5][5], rhs[5], solved[5], kk;
        for (int i = 0; i < 5; ++i) {
            for (int j = 0; j <= i; ++j) L[i][j] = doubleLanesOf(&K[i][j][first]);
            for (int j = i + 1; j < 5; ++j) L[i][j] = splatD(0.0);
            rhs[i] = -doubleLanesOf(&Kia[i][first]);
        }
        LanesM ok;
        coupledInverseMassLanes(L, rhs, doubleLanesOf(&rowMass[first]), solved, kk, ok);
        alignas(32) Real cs[5][kDoubleLanes], ks[kDoubleLanes];
        for (int i = 0; i < 5; ++i) storeFloatLanes(cs[i], solved[i]);
        storeFloatLanes(ks, kk);
        for (int w = 0; w < kDoubleLanes; ++w) {
            const int l = first + w;
            if (l >= static_cast<int>(k.laneCount) || !redo.lane(l) || ok[w] == 0) continue;
            for (int i = 0; i < 5; ++i) c[i][l] = cs[i][w];
            invMass[l] = ks[w];
            coupled[l] = 1.0f;
        }
    }
    for (std::uint32_t lane = 0; lane < k.laneCount; ++lane) {
        const int l = static_cast<int>(lane);
        if (!redo.lane(l)) {
            invMass[lane] = getLane(k.axialInvMass, l);
        } else if (coupled[lane] == 0.0f) {
            invMass[lane] = rowMass[lane];
        }
    }
#else
    for (std::uint32_t lane = 0; lane < k.laneCount; ++lane) {
        const int l = static_cast<int>(lane);
        if (!redo.lane(l)) {
            invMass[lane] = getLane(k.axialInvMass, l);
            continue;
        }
        invMass[lane] = rowMass[lane];
        double L[kMaxHeldRows][kMaxHeldRows] = {};
        double rhs[kMaxHeldRows] = {};
        for (int i = 0; i < 5; ++i) {
            for (int j = 0; j <= i; ++j) L[i][j] = static_cast<double>(K[i][j][lane]);
            rhs[i] = -static_cast<double>(Kia[i][lane]);
        }
        double solved[kMaxHeldRows];
        double kk = 0;
        if (!coupledInverseMass(L, rhs, 5, static_cast<double>(rowMass[lane]), solved, kk)) continue;
        for (int i = 0; i < 5; ++i) c[i][lane] = static_cast<Real>(solved[i]);
        invMass[lane] = static_cast<Real>(kk);
        coupled[lane] = 1.0f;
    }
#endif
    for (std::uint32_t lane = k.laneCount; lane < static_cast<std::uint32_t>(kLanes); ++lane) invMass[lane] = 0.0f;
    RowW apply = rows[5];
    for (int i = 0; i < 5; ++i) {
        const FloatW ci = FloatW::load(c[i]);
        apply.linear = apply.linear + rows[i].linear * ci;
        apply.angularA = apply.angularA + rows[i].angularA * ci;
        apply.angularB = apply.angularB + rows[i].angularB * ci;
    }
    const MaskW ok = FloatW::load(coupled) > zero;
    const RowW fresh = {select(ok, apply.linear, rows[5].linear), select(ok, apply.angularA, rows[5].angularA),
                        select(ok, apply.angularB, rows[5].angularB)};
    k.apply = {select(redo, fresh.linear, k.apply.linear), select(redo, fresh.angularA, k.apply.angularA),
               select(redo, fresh.angularB, k.apply.angularB)};
    k.axialInvMass = FloatW::load(invMass);
}

// HingeJoint's guard (couplingStale, coupled_row.hpp), lane by lane: the
// lanes of `axial` whose row is stale for this pass (`relax`: a relax pass,
// new positions) are coupled again, the others keep theirs.
FULCRUM_JOINT_WIDE_INLINE void recoupleHingeLanes(HingeBlock& k, const Ends& e, const MaskW& axial,
                                                  const JointContext& ctx, bool relax) {
    alignas(32) Real redo[kLanes] = {};
    bool anyRedo = false;
    for (std::uint32_t lane = 0; lane < k.laneCount; ++lane) {
        if (!axial.lane(static_cast<int>(lane))) continue;
        const std::uint8_t state = k.axialCoupled[lane];
        if (!couplingStale(state, relax, ctx.rotations[k.bodyA[lane]], ctx.rotations[k.bodyB[lane]])) continue;
        k.axialCoupled[lane] = relax || state != kAxialNotCoupled ? kAxialMoved : kAxialAtStart;
        redo[lane] = 1.0f;
        anyRedo = true;
    }
    if (anyRedo) coupleHingeRow(k, e, FloatW::load(redo) > FloatW(0.0f));
}

// HingeJoint::warmStart: cachePointMass (the lanes not in a tree), the alignment
// impulse's perpendicular part, the point and alignment impulses applied,
// then the free axis coupled (lane by lane) and its impulse applied.
void warmStartHingeBlocks(HingeBlock* blocks, std::size_t count, SolverBody* bodies, JointConstraint* constraints,
                          const JointContext& ctx) {
    const FloatW zero = 0.0f;
    const MaskW all = zero == zero;
    for (std::size_t bi = 0; bi < count; ++bi) {
        HingeBlock& k = blocks[bi];
        const bool stale = k.frameAt != ctx.generation;
        Ends e = stale ? gatherEnds<true>(bodies, k) : gatherEnds<false>(bodies, k);
        if (stale) updateHingeFrame(k, e, constraints, ctx.rotations, ctx.generation);
        if (k.allDirect) {
            // cachePointMass serves only the point block, which the tree
            // solver has in every lane: the passes solve none here.
            k.pointMassValid = zero;
        } else {
            MaskW pointValid;
            k.pointMass = inverseWherePositive(pointInverseMass(e, k.rA, k.rB), pointValid, Mat3W{});
            k.pointMassValid = select(pointValid, FloatW(1.0f), zero);
        }
        const Vec3W& axis = k.axisA;
        k.angular = k.angular - axis * dot(axis, k.angular);
        applyPoint(e, k.rA, k.rB, hingePointImpulse(k, constraints), all);
        e.wA = e.wA - e.invIA * k.angular;
        e.wB = e.wB + e.invIB * k.angular;
        if (k.anySpring || k.anyMotor || k.anyLimit) {
            const MaskW axial = (k.spring > zero) | (k.motor > zero) | (k.limit > zero);
            // HingeJoint::warmStart: couple the lanes not yet coupled this step.
            recoupleHingeLanes(k, e, axial, ctx, false);
            // axialImpulse: spring + motor + lower - upper.
            const FloatW impulse = k.springImpulse + k.motorImpulse + k.lowerImpulse - k.upperImpulse;
            applyRow(k.apply, e, impulse, axial);
        }
        scatterEnds(bodies, k.writeA, k.writeB, e);
    }
}

// HingeJoint::solve: spring, motor, lower and upper limits on the free axis (the
// coupled rows), the alignment rows, the point block (the lanes not in a tree).
void solveHingeBlocks(HingeBlock* blocks, std::size_t count, SolverBody* bodies, JointConstraint* constraints,
                   const JointContext& ctx) {
    const FloatW zero = 0.0f;
    const PassW pass(ctx);
    for (std::size_t bi = 0; bi < count; ++bi) {
        HingeBlock& k = blocks[bi];
        const bool stale = k.frameAt != ctx.generation;
        Ends e = stale ? gatherEnds<true>(bodies, k) : gatherEnds<false>(bodies, k);
        if (stale) updateHingeFrame(k, e, constraints, ctx.rotations, ctx.generation);
        if (!pass.useBias && (k.anySpring || k.anyMotor || k.anyLimit)) {
            // A relax pass has new positions: HingeJoint::solve's guard.
            const MaskW axial = (k.spring > zero) | (k.motor > zero) | (k.limit > zero);
            recoupleHingeLanes(k, e, axial, ctx, true);
        }
        const RowW measure = angularRow(k.axisA);
        const FloatW kAxial = k.axialInvMass;
        if (k.anySpring) {
            // solveCoupledSpring: d = -(v + bias C + gamma lambda) / (k + gamma),
            // the sum clamped to +-max; d recomputed only where it saturates.
            const FloatW kg = kAxial + k.springGamma;
            const MaskW on = (k.spring > zero) & (kg > zero);
            const FloatW C = k.angle - k.springTarget;
            FloatW d = -(rowVelocity(measure, e) + k.springBias * C + k.springGamma * k.springImpulse) / kg;
            FloatW next = k.springImpulse + d;
            const FloatW max = k.maxSpringImpulse, negMax = -k.maxSpringImpulse;
            const MaskW over = next > max, under = next < negMax;
            const MaskW saturated = (over | under) & on;
            if (saturated.any()) {
                next = select(over, max, select(under, negMax, next));
                d = select(saturated, next - k.springImpulse, d);
            }
            k.springImpulse = select(on, next, k.springImpulse);
            applyRow(k.apply, e, d, on);
        }
        if (k.anyMotor) {
            // solveCoupledMotor: the impulse clamped to +-max.
            const MaskW on = (k.motor > zero) & (kAxial > zero);
            const FloatW d = -(rowVelocity(measure, e) - k.motorSpeed) / kAxial;
            FloatW next = k.motorImpulse + d;
            const FloatW max = k.maxMotorImpulse, negMax = -k.maxMotorImpulse;
            next = select(next > max, max, select(next < negMax, negMax, next));
            applyRow(k.apply, e, next - k.motorImpulse, on);
            k.motorImpulse = select(on, next, k.motorImpulse);
        }
        if (k.anyLimit) {
            // solveCoupledLimit, sign +1 (lower) then -1 (upper).
            const MaskW on = (k.limit > zero) & (kAxial > zero);
            {
                const FloatW next = nextLimitImpulse(rowVelocity(measure, e), k.angle - k.lower, kAxial, k.lowerImpulse, pass);
                applyRow(k.apply, e, next - k.lowerImpulse, on);
                k.lowerImpulse = select(on, next, k.lowerImpulse);
            }
            {
                const FloatW next =
                    nextLimitImpulse(-rowVelocity(measure, e), k.upper - k.angle, kAxial, k.upperImpulse, pass);
                applyRow(k.apply, e, -(next - k.upperImpulse), on);
                k.upperImpulse = select(on, next, k.upperImpulse);
            }
        }
        // solveAlignment.
        {
            const MaskW on = k.alignmentValid > zero;
            const Vec3W dw = e.wB - e.wA;
            FloatW r1 = dot(k.p1, dw), r2 = dot(k.p2, dw);
            FloatW massScale = 1.0f, impulseScale = 0.0f;
            if (pass.useBias) {
                r1 = r1 + pass.soft[0] * k.c1;
                r2 = r2 + pass.soft[0] * k.c2;
                massScale = pass.soft[1];
                impulseScale = pass.soft[2];
            }
            const FloatW inv = FloatW(1.0f) / (k.k11 * k.k22 - k.k12 * k.k12);
            const FloatW d1 = -massScale * inv * (k.k22 * r1 - k.k12 * r2) - impulseScale * dot(k.p1, k.angular);
            const FloatW d2 = -massScale * inv * (k.k11 * r2 - k.k12 * r1) - impulseScale * dot(k.p2, k.angular);
            const Vec3W T = k.p1 * d1 + k.p2 * d2;
            k.angular = select(on, k.angular + T, k.angular);
            e.wA = select(on, e.wA - e.invIA * T, e.wA);
            e.wB = select(on, e.wB + e.invIB * T, e.wB);
        }
        const MaskW point = (k.direct <= zero) & (k.pointMassValid > zero);
        if (point.any()) solvePointBlock(e, k.rA, k.rB, k.d, k.linear, k.pointMass, point, pass);
        scatterEnds(bodies, k.writeA, k.writeB, e);
    }
}

// The impulses back into the records, and the free axis's rows (jointReaction reads `apply`).
void storeHingeBlock(const HingeBlock& k, JointConstraint* constraints) {
    for (std::uint32_t lane = 0; lane < k.laneCount; ++lane) {
        const int l = static_cast<int>(lane);
        JointConstraint& j = constraints[k.constraint[lane]];
        if (!(getLane(k.direct, l) > 0)) j.impulse.linear = k.linear.lane(l);
        j.impulse.angular = k.angular.lane(l);
        j.impulse.spring = getLane(k.springImpulse, l);
        j.impulse.motor = getLane(k.motorImpulse, l);
        j.impulse.lower = getLane(k.lowerImpulse, l);
        j.impulse.upper = getLane(k.upperImpulse, l);
        if (j.spring || j.motor || j.limit) {
            j.axial.apply = {k.apply.linear.lane(l), k.apply.angularA.lane(l), k.apply.angularB.lane(l)};
            j.axial.invMass = getLane(k.axialInvMass, l);
        }
    }
}

}  // namespace
}  // namespace fulcrum::detail::FULCRUM_JOINT_WIDE_NS
