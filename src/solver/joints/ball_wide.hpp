// Ball joints in SIMD lanes: the twins of BallJoint::warmStart and
// BallJoint::solve (ball.cpp, joint_common.hpp) for the frictionless
// Gauss-Seidel ball joints (joint_wide.hpp describes the layout and why the
// bits are the scalar ones), a part of the wide kernels
// (joint_wide_kernels.hpp includes it once per width, inside its namespace,
// after the shared pieces). Ball joints with friction run in the cone-twist
// blocks (cone_twist_wide.hpp).
#ifndef FULCRUM_JOINT_WIDE_NS
#error "included by joint_wide_kernels.hpp only"
#endif

namespace fulcrum::detail::FULCRUM_JOINT_WIDE_NS {
namespace {

// kLanes ball joints of one colour. Lanes past laneCount are empty: solver
// body 0 (the all-zero static stand-in) on both ends, never written back.
struct BallBlock {
    std::uint32_t bodyA[kLanes], bodyB[kLanes];    // gather: solver body (0: static)
    std::uint32_t writeA[kLanes], writeB[kLanes];  // scatter: the body if dynamic, else kEmptyLane
    std::uint32_t constraint[kLanes];              // where store() puts each lane's impulse
    std::uint32_t laneCount = 0;
    std::uint64_t frameAt = 0;                     // the rotation refresh the frame was computed at (0: none)
    Vec3W rA0, rB0, centreDelta;                   // JointConstraint's, the step's start
    Vec3W rA, rB, d;                               // JointFrame: anchors and pB - pA now
    Mat3W pointMass;                               // K^-1 of the sub-step (cachePointMass); zero if invalid
    FloatW pointMassValid;                         // 1 where determinant(K) > 0, else 0
    Vec3W impulse;                                 // JointImpulses::linear
};

// rotate(q, v) = (v + t q.w) + u x t with t = (u x v) 2 (quat.hpp).
FULCRUM_JOINT_WIDE_INLINE Vec3W rotate(const std::array<FloatW, 4>& q, const Vec3W& v) {
    const Vec3W u{q[1], q[2], q[3]};
    const Vec3W t = cross(u, v) * FloatW(2.0f);
    return (v + t * q[0]) + cross(u, t);
}

// updateFrame for a ball joint: the anchors rotated by the bodies' rotations
// since the step's start, and d = ((centreDelta + (dpB - dpA)) + rB) - rA.
FULCRUM_JOINT_WIDE_INLINE void updateFrame(BallBlock& k, const BodyW& a, const BodyW& b, const Quat* rotations,
                                           std::uint64_t generation) {
    const std::array<FloatW, 4> qA = FloatW::gatherTransposed<4>(rotations, k.bodyA);
    const std::array<FloatW, 4> qB = FloatW::gatherTransposed<4>(rotations, k.bodyB);
    k.rA = rotate(qA, k.rA0);
    k.rB = rotate(qB, k.rB0);
    k.d = k.centreDelta + (b.dp() - a.dp()) + k.rB - k.rA;
    k.frameAt = generation;
}

// cachePointMass: K = diag(mA + mB) - [rA] IA^-1 [rA] - [rB] IB^-1 [rB]
// (pointInverseMass, products in Mat3's order), its inverse by the adjugate
// where determinant(K) > 0, else zero.
FULCRUM_JOINT_WIDE_INLINE void cachePointMass(BallBlock& k, const BodyW& a, const BodyW& b) {
    const FloatW zero = 0.0f;
    const Mat3W sa = skew(k.rA), sb = skew(k.rB);
    const Mat3W ta = sa * a.invI() * sa;
    const Mat3W tb = sb * b.invI() * sb;
    const FloatW m = a.invMass() + b.invMass();
    const Mat3W diagonal{{m, zero, zero}, {zero, m, zero}, {zero, zero, m}};
    const Mat3W K{diagonal.c0 - ta.c0 - tb.c0, diagonal.c1 - ta.c1 - tb.c1, diagonal.c2 - ta.c2 - tb.c2};
    // inverse(): rows r0 = c1 x c2, r1 = c2 x c0, r2 = c0 x c1; det = c0 . r0.
    const Vec3W r0 = cross(K.c1, K.c2), r1 = cross(K.c2, K.c0), r2 = cross(K.c0, K.c1);
    const FloatW det = dot(K.c0, r0);
    const MaskW valid = det > zero;
    const FloatW inv = FloatW(1.0f) / det;
    const auto keep = [&](const FloatW& x) { return select(valid, x, zero); };
    // Mat3::fromRows(r0, r1, r2) * inv: column j holds component j of each row.
    k.pointMass = {{keep(r0.x * inv), keep(r1.x * inv), keep(r2.x * inv)},
                   {keep(r0.y * inv), keep(r1.y * inv), keep(r2.y * inv)},
                   {keep(r0.z * inv), keep(r1.z * inv), keep(r2.z * inv)}};
    k.pointMassValid = select(valid, FloatW(1.0f), zero);
}

// Block `k` from its lanes' constraints (JointSolver::prepare, once per step).
void buildBlock(BallBlock& k, const JointConstraint* constraints, const std::uint32_t* indices, int laneCount,
                const SolverBody* bodies) {
    k.laneCount = static_cast<std::uint32_t>(laneCount);
    k.frameAt = 0;
    k.rA0 = k.rB0 = k.centreDelta = k.impulse = Vec3W{};
    for (int l = 0; l < kLanes; ++l) {
        if (l >= laneCount) {
            setEmptyBodyLane(k, l);
            continue;
        }
        const JointConstraint& j = constraints[indices[l]];
        setBodyLane(k, l, j, indices[l], bodies);
        setLane(k.impulse, l, j.impulse.linear);
    }
    k.pointMass = Mat3W{};
    k.pointMassValid = 0.0f;
}

// The twin of BallJoint::warmStart for a frictionless Gauss-Seidel ball joint: the
// frame, the point block's mass for this sub-step, and the stored impulse
// applied (applyPoint: v -= P mA, w -= IA^-1 (rA x P), and + on B).
void warmStartBlocks(BallBlock* blocks, std::size_t count, SolverBody* bodies, const Quat* rotations,
                     std::uint64_t generation) {
    for (std::size_t bi = 0; bi < count; ++bi) {
        BallBlock& k = blocks[bi];
        const bool stale = k.frameAt != generation;  // the first warm start of a step (later: the relax pass's frame)
        const BodyW a = stale ? gatherBody<true>(bodies, k.bodyA) : gatherBody<false>(bodies, k.bodyA);
        const BodyW b = stale ? gatherBody<true>(bodies, k.bodyB) : gatherBody<false>(bodies, k.bodyB);
        if (stale) updateFrame(k, a, b, rotations, generation);
        cachePointMass(k, a, b);
        const Vec3W& P = k.impulse;
        const Vec3W vA = a.v() - P * a.invMass();
        const Vec3W wA = a.w() - a.invI() * cross(k.rA, P);
        const Vec3W vB = b.v() + P * b.invMass();
        const Vec3W wB = b.w() + b.invI() * cross(k.rB, P);
        scatterVelocity(bodies, k.writeA, a, vA, wA);
        scatterVelocity(bodies, k.writeB, b, vB, wB);
    }
}

// The twin of BallJoint::solve (solvePointBlock) for a frictionless Gauss-Seidel
// ball joint: d = -(K^-1 (cdot + bias)) massScale - lambda impulseScale with
// cdot = ((vB + wB x rB) - vA) - wA x rA; lanes without an invertible block
// keep their velocities and impulse (the scalar code skips them).
template <bool useBias>
void solveBlocks(BallBlock* blocks, std::size_t count, SolverBody* bodies, const Quat* rotations, std::uint64_t generation,
                 const Softness& soft) {
    // The relax pass's constants are the scalar ones (bias 0, massScale 1,
    // impulseScale 0), operated with as the scalar code does.
    const FloatW biasRate = useBias ? soft.biasRate : 0.0f;
    const FloatW massScale = useBias ? soft.massScale : 1.0f;
    const FloatW impulseScale = useBias ? soft.impulseScale : 0.0f;
    const FloatW zero = 0.0f;
    for (std::size_t bi = 0; bi < count; ++bi) {
        BallBlock& k = blocks[bi];
        // The relax pass follows a position update (a new frame); the biased
        // pass follows the warm start (the same frame).
        const bool stale = k.frameAt != generation;
        const BodyW a = stale ? gatherBody<true>(bodies, k.bodyA) : gatherBody<false>(bodies, k.bodyA);
        const BodyW b = stale ? gatherBody<true>(bodies, k.bodyB) : gatherBody<false>(bodies, k.bodyB);
        if (stale) updateFrame(k, a, b, rotations, generation);
        const Vec3W vA0 = a.v(), wA0 = a.w(), vB0 = b.v(), wB0 = b.w();
        const Vec3W cdot = vB0 + cross(wB0, k.rB) - vA0 - cross(wA0, k.rA);
        const Vec3W bias = useBias ? k.d * biasRate : Vec3W{};  // the relax pass: Vec3{}, +0
        const Vec3W d = -(k.pointMass * (cdot + bias)) * massScale - k.impulse * impulseScale;
        const MaskW valid = k.pointMassValid > zero;
        k.impulse = select(valid, k.impulse + d, k.impulse);
        const Vec3W vA = select(valid, vA0 - d * a.invMass(), vA0);
        const Vec3W wA = select(valid, wA0 - a.invI() * cross(k.rA, d), wA0);
        const Vec3W vB = select(valid, vB0 + d * b.invMass(), vB0);
        const Vec3W wB = select(valid, wB0 + b.invI() * cross(k.rB, d), wB0);
        scatterVelocity(bodies, k.writeA, a, vA, wA);
        scatterVelocity(bodies, k.writeB, b, vB, wB);
    }
}

}  // namespace
}  // namespace fulcrum::detail::FULCRUM_JOINT_WIDE_NS
