// Cone-twist joints in SIMD lanes: the twins of ConeTwistJoint::warmStart and
// ConeTwistJoint::solve (cone_twist.cpp, joint_common.hpp), a part of the wide
// kernels (joint_wide_kernels.hpp includes it once per width, inside its
// namespace, after the shared pieces). Every cone-twist of a regular colour
// is wide: with or without friction, in a joint tree or not (a tree's joint
// leaves its point block to the tree solver, whose impulse lives in the
// constraint record, read from there at each warm start). Ball joints with
// friction (BallJoint::warmStart and solve: a cone-twist without its limits) share
// these blocks, their lanes masked out of the limit rows (`cone` = 0).
//
// Same bits as the scalar kernels, and why:
// - the frame (anchors, separation, orientations) and everything the scalar
//   code derives from it alone in every pass (coneGeometry's axes, swing
//   angle and twist axis, twistAngle) are computed once per rotation refresh
//   and kept: the same inputs give the same bits, and the two arctangents per
//   joint and pass (~9 % of the ragdolls scene on the scalar path: atanf,
//   atan2f) run once per refresh, lane by lane through libm's atan2f;
// - each row does its scalar twin's operations in order, zero linear parts
//   of the angular rows included (0 * x keeps the sign of x's zero);
// - a branch is a mask: the swing row where the cone is limited and the axes
//   are apart, the friction block where it is valid, a limit row where its
//   effective mass is positive, the point block where the tree solver does
//   not have it and its K is invertible; the limit's three cases select
//   their constants.
#ifndef FULCRUM_JOINT_WIDE_NS
#error "included by joint_wide_kernels.hpp only"
#endif

namespace fulcrum::detail::FULCRUM_JOINT_WIDE_NS {
namespace {

struct ConeTwistBlock : FramedLanes {
    bool anyFriction = false, anyDirect = false, anySwingLimit = false, anyCone = false;
    // The joint's constants.
    FloatW lower, upper, swingLimit, maxFriction;
    FloatW swingLimited;  // 1 where swingLimit < pi
    FloatW direct;        // 1 where the tree solver has the point rows
    FloatW cone;          // 1 for a cone-twist, 0 for a ball joint with friction (no limit rows)
    // Per rotation refresh: JointFrame and ConeGeometry, and the twist angle.
    Vec3W rA, rB, d;
    Vec3W swingAxis, twistAxis;
    FloatW swing, hasSwing, twist;
    // Per sub-step (the warm start).
    Mat3W pointMass;
    FloatW pointMassValid;
    Mat3W frictionMass, frictionCoupling;
    FloatW frictionValid;
    // Accumulated impulses (linear: the lanes not in a tree).
    Vec3W linear, friction;
    FloatW lowerImpulse, upperImpulse, swingImpulse;
};

void buildConeTwistBlock(ConeTwistBlock& k, const JointConstraint* constraints, const std::uint32_t* indices, int laneCount,
                         const SolverBody* bodies) {
    k = ConeTwistBlock{};
    k.laneCount = static_cast<std::uint32_t>(laneCount);
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
        setLane(k.lower, l, j.lower);
        setLane(k.upper, l, j.upper);
        setLane(k.swingLimit, l, j.swingLimit);
        setLane(k.maxFriction, l, j.maxFrictionImpulse);
        const bool isCone = j.type == JointType::ConeTwist;
        const bool limited = isCone && j.swingLimit < std::numbers::pi_v<Real>;  // swingLimited (cone_twist.cpp)
        setLane(k.cone, l, isCone ? 1.0f : 0.0f);
        k.anyCone = k.anyCone || isCone;
        setLane(k.swingLimited, l, limited ? 1.0f : 0.0f);
        setLane(k.direct, l, j.direct ? 1.0f : 0.0f);
        k.anyFriction = k.anyFriction || j.maxFrictionImpulse > 0;
        k.anyDirect = k.anyDirect || j.direct;
        k.anySwingLimit = k.anySwingLimit || limited;
        setLane(k.linear, l, j.impulse.linear);
        setLane(k.friction, l, j.impulse.friction);
        setLane(k.lowerImpulse, l, j.impulse.lower);
        setLane(k.upperImpulse, l, j.impulse.upper);
        setLane(k.swingImpulse, l, j.impulse.swing);
    }
}

// updateFrame (orientations included) and coneGeometry, and twistAngle.
FULCRUM_JOINT_WIDE_INLINE void updateConeTwistFrame(ConeTwistBlock& k, const Ends& e, JointConstraint* constraints,
                                                    const Quat* rotations, std::uint64_t generation) {
    const FloatW zero = 0.0f, one = 1.0f, tiny = Real(1e-6);
    const QuatW dqA = gatherRotation(rotations, k.bodyA), dqB = gatherRotation(rotations, k.bodyB);
    k.rA = rotate(dqA, k.rA0);
    k.rB = rotate(dqB, k.rB0);
    k.d = k.centreDelta + (e.b.dp() - e.a.dp()) + k.rB - k.rA;
    const QuatW qA = dqA * k.qA0, qB = dqB * k.qB0;
    // coneGeometry.
    const Vec3W axisA = rotate(qA, k.localAxisA);
    const Vec3W axisB = rotate(qB, k.localAxisB);
    const Vec3W c = cross(axisA, axisB);
    const FloatW s = length(c);
    k.swing = atan2Lanes(s, dot(axisA, axisB), k.laneCount);
    const MaskW hasSwing = s > tiny;
    k.hasSwing = select(hasSwing, one, zero);
    k.swingAxis = select(hasSwing, c * (one / s), Vec3W{});
    const Vec3W mid = axisA + axisB;
    const FloatW m = length(mid);
    k.twistAxis = select(m > tiny, mid * (one / m), axisA);
    k.twist = twistAngle(k.relative0Conjugate, qA, qB, k.localAxisA, k.laneCount);
    k.frameAt = generation;
    if (k.anyDirect) writeTreeFrames(constraints, k.constraint, k.laneCount, k.direct, k.rA, k.rB, k.d, qA, qB, generation);
}

// The tree lanes' point impulse from their records (the tree solver's), the
// others' from the block.
FULCRUM_JOINT_WIDE_INLINE Vec3W pointImpulse(const ConeTwistBlock& k, const JointConstraint* constraints) {
    if (!k.anyDirect) return k.linear;
    Vec3W P = k.linear;
    for (std::uint32_t lane = 0; lane < k.laneCount; ++lane) {
        const int l = static_cast<int>(lane);
        if (getLane(k.direct, l) > 0) setLane(P, l, constraints[k.constraint[lane]].impulse.linear);
    }
    return P;
}

// applyFriction where `on`: P = coupling T; vA -= P mA, wA -= IA^-1 (T + rA x P), and + on B.
FULCRUM_JOINT_WIDE_INLINE void applyFriction(const ConeTwistBlock& k, Ends& e, const Vec3W& T, const MaskW& on) {
    const Vec3W P = k.frictionCoupling * T;
    e.vA = select(on, e.vA - P * e.mA, e.vA);
    e.wA = select(on, e.wA - e.invIA * (T + cross(k.rA, P)), e.wA);
    e.vB = select(on, e.vB + P * e.mB, e.vB);
    e.wB = select(on, e.wB + e.invIB * (T + cross(k.rB, P)), e.wB);
}

// ConeTwistJoint::warmStart: cachePointMass (the lanes not in a tree), the twist and
// swing impulses and the point impulse applied, cacheFriction and its impulse.
void warmStartConeTwistBlocks(ConeTwistBlock* blocks, std::size_t count, SolverBody* bodies,
                              JointConstraint* constraints, const JointContext& ctx) {
    const FloatW zero = 0.0f;
    const MaskW all = zero == zero;
    for (std::size_t bi = 0; bi < count; ++bi) {
        ConeTwistBlock& k = blocks[bi];
        const bool stale = k.frameAt != ctx.generation;
        Ends e = stale ? gatherEnds<true>(bodies, k) : gatherEnds<false>(bodies, k);
        if (stale) updateConeTwistFrame(k, e, constraints, ctx.rotations, ctx.generation);
        // cachePointMass; the same K and inverse serve cacheFriction's K_pp.
        const Mat3W Kpp = pointInverseMass(e, k.rA, k.rB);
        MaskW pointValid;
        const Mat3W KppInv = inverseWherePositive(Kpp, pointValid, Mat3W{});
        k.pointMass = KppInv;
        k.pointMassValid = select(pointValid, FloatW(1.0f), zero);
        applyPoint(e, k.rA, k.rB, pointImpulse(k, constraints), all);
        if (k.anyCone) {
            // The limits' impulse (a ball joint's lanes: none).
            const MaskW cone = k.cone > zero;
            Vec3W T = k.twistAxis * (k.lowerImpulse - k.upperImpulse);
            T = select(k.hasSwing > zero, T - k.swingAxis * k.swingImpulse, T);
            e.wA = select(cone, e.wA - e.invIA * T, e.wA);
            e.wB = select(cone, e.wB + e.invIB * T, e.wB);
        }
        // cacheFriction: the Schur complement of the point block (joint_common.hpp).
        k.frictionValid = zero;
        if (k.anyFriction) {
            const Mat3W Kww = e.invIA + e.invIB;
            const Mat3W Kwp = e.invIB * skew(k.rB) + e.invIA * skew(k.rA);
            const Mat3W Kpw = transpose(Kwp);
            const Mat3W K = Kww - Kwp * KppInv * Kpw;
            MaskW massValid;
            const Mat3W mass = inverseWherePositive(K, massValid, k.frictionMass);
            const MaskW valid = (k.maxFriction > zero) & pointValid & massValid;
            k.frictionMass = mass;
            k.frictionCoupling = select(valid, Mat3W{} - KppInv * Kpw, k.frictionCoupling);
            k.frictionValid = select(valid, FloatW(1.0f), zero);
            applyFriction(k, e, k.friction, valid);
            k.friction = select(valid, k.friction, Vec3W{});
        } else {
            k.friction = Vec3W{};
        }
        scatterEnds(bodies, k.writeA, k.writeB, e);
    }
}

// ConeTwistJoint::solve: the friction block, the swing limit, the twist limits, the
// point block (the lanes not in a tree), in that order.
void solveConeTwistBlocks(ConeTwistBlock* blocks, std::size_t count, SolverBody* bodies, JointConstraint* constraints,
                   const JointContext& ctx) {
    const FloatW zero = 0.0f;
    const PassW pass(ctx);
    for (std::size_t bi = 0; bi < count; ++bi) {
        ConeTwistBlock& k = blocks[bi];
        const bool stale = k.frameAt != ctx.generation;
        Ends e = stale ? gatherEnds<true>(bodies, k) : gatherEnds<false>(bodies, k);
        if (stale) updateConeTwistFrame(k, e, constraints, ctx.rotations, ctx.generation);
        // solveFrictionBlock: lambda -= M (wB - wA), scaled back to the
        // largest impulse when longer (lambda *= max / len).
        if (k.anyFriction) {
            const MaskW valid = k.frictionValid > zero;
            const Vec3W old = k.friction;
            Vec3W lambda = old - k.frictionMass * (e.wB - e.wA);
            const FloatW len = length(lambda);
            lambda = select(len > k.maxFriction, lambda * (k.maxFriction / len), lambda);
            applyFriction(k, e, lambda - old, valid);
            k.friction = select(valid, lambda, old);
        }
        if (k.anySwingLimit) {
            const MaskW on = (k.swingLimited > zero) & (k.hasSwing > zero);
            const Vec3W inward = -k.swingAxis;
            solveLimitRow(RowW{Vec3W{}, inward, inward}, e, k.swingLimit - k.swing, k.swingImpulse, on, pass);
        }
        if (k.anyCone) {
            const MaskW cone = k.cone > zero;
            solveLimitRow(angularRow(k.twistAxis), e, k.twist - k.lower, k.lowerImpulse, cone, pass);
            const Vec3W back = -k.twistAxis;
            solveLimitRow(RowW{Vec3W{}, back, back}, e, k.upper - k.twist, k.upperImpulse, cone, pass);
        }
        const MaskW point = (k.direct <= zero) & (k.pointMassValid > zero);
        if (point.any()) solvePointBlock(e, k.rA, k.rB, k.d, k.linear, k.pointMass, point, pass);
        scatterEnds(bodies, k.writeA, k.writeB, e);
    }
}

// The impulses back into the records, and what jointReaction reads of the
// step: the friction coupling where friction was valid.
void storeConeTwistBlock(const ConeTwistBlock& k, JointConstraint* constraints) {
    for (std::uint32_t lane = 0; lane < k.laneCount; ++lane) {
        const int l = static_cast<int>(lane);
        JointConstraint& j = constraints[k.constraint[lane]];
        if (!(getLane(k.direct, l) > 0)) {
            j.impulse.linear = {getLane(k.linear.x, l), getLane(k.linear.y, l), getLane(k.linear.z, l)};
        }
        j.impulse.friction = {getLane(k.friction.x, l), getLane(k.friction.y, l), getLane(k.friction.z, l)};
        j.impulse.lower = getLane(k.lowerImpulse, l);
        j.impulse.upper = getLane(k.upperImpulse, l);
        j.impulse.swing = getLane(k.swingImpulse, l);
        j.frictionValid = getLane(k.frictionValid, l) > 0;
        if (j.frictionValid) {
            const auto column = [&](const Vec3W& c) { return Vec3{getLane(c.x, l), getLane(c.y, l), getLane(c.z, l)}; };
            j.frictionCoupling = {column(k.frictionCoupling.c0), column(k.frictionCoupling.c1), column(k.frictionCoupling.c2)};
        }
    }
}

}  // namespace
}  // namespace fulcrum::detail::FULCRUM_JOINT_WIDE_NS
