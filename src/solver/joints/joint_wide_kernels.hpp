// The wide joint kernels (joint_wide.hpp): the lane math every kind shares,
// each kind's blocks from its own file (ball_wide.hpp, cone_twist_wide.hpp,
// hinge_wide.hpp, beside the type's scalar kernels) and the Blocks class that
// runs them, written once over a simd.hpp policy and compiled once per
// width, as the contact kernels are
// (contact_wide_kernels.hpp): a translation unit defines
//   FULCRUM_JOINT_WIDE_NS      the namespace of this copy (joint_sse2, joint_avx2)
//   FULCRUM_JOINT_WIDE_POLICY  the simd.hpp policy
// and includes this file once. Everything here is in an unnamed namespace, so
// the AVX2 copy is its translation unit's own; it calls no shared inline
// function of the scalar math (Mat3's inverse, rotate...) that the linker
// could pick an AVX2-compiled copy of for code running on a CPU without AVX2:
// the kernels spell the operations out on the wide types.
#ifndef FULCRUM_JOINT_WIDE_NS
#error "define FULCRUM_JOINT_WIDE_NS and FULCRUM_JOINT_WIDE_POLICY before including joint_wide_kernels.hpp"
#endif
// Run as each entry point returns (the AVX2 copy: _mm256_zeroupper(), for
// the reason contact_wide_kernels.hpp gives).
#ifndef FULCRUM_JOINT_WIDE_LEAVE
#define FULCRUM_JOINT_WIDE_LEAVE() ((void)0)
#endif

#include <array>
#include <cmath>
#include <cstring>
#include <numbers>
#include <type_traits>
#include <vector>

#include "math/simd.hpp"
#include "solver/contact_solver.hpp"
#include "solver/joints/joint_common.hpp"
#include "solver/joints/joint_wide.hpp"

namespace fulcrum::detail::FULCRUM_JOINT_WIDE_NS {
namespace {

using Policy = FULCRUM_JOINT_WIDE_POLICY;
using FloatW = simd::FloatWide<Policy>;
using MaskW = simd::MaskWide<Policy>;
using Vec3W = simd::Vec3Wide<Policy>;
using simd::kEmptyLane;
constexpr int kLanes = Policy::kLanes;

#define FULCRUM_JOINT_WIDE_INLINE inline __attribute__((always_inline))

static_assert(sizeof(SolverBody) == 24 * sizeof(Real) && std::is_trivially_copyable_v<SolverBody>,
              "the kernels read a solver body as 24 floats: v, invMass, w, dp, dtheta, invI, padding");
static_assert(sizeof(Quat) == 4 * sizeof(Real) && std::is_trivially_copyable_v<Quat>,
              "the kernels read a rotation as 4 floats: w, x, y, z");
static_assert(sizeof(FloatW) == kLanes * sizeof(Real) && std::is_trivially_copyable_v<FloatW>);

// Column-major like Mat3 (c0, c1, c2), so its products are Mat3's, term for term.
struct Mat3W {
    Vec3W c0, c1, c2;
};

// m v = c0 v.x + c1 v.y + c2 v.z (fulcrum's Mat3 * Vec3, term for term).
FULCRUM_JOINT_WIDE_INLINE Vec3W operator*(const Mat3W& m, const Vec3W& v) { return m.c0 * v.x + m.c1 * v.y + m.c2 * v.z; }
// a b, column by column (fulcrum's Mat3 * Mat3).
FULCRUM_JOINT_WIDE_INLINE Mat3W operator*(const Mat3W& a, const Mat3W& b) { return {a * b.c0, a * b.c1, a * b.c2}; }

// Mat3::skew(r): the matrix of v -> r x v, with its exact zeros.
FULCRUM_JOINT_WIDE_INLINE Mat3W skew(const Vec3W& r) {
    const FloatW zero = 0.0f;
    return {{zero, r.z, -r.y}, {-r.z, zero, r.x}, {r.y, -r.x, zero}};
}

FULCRUM_JOINT_WIDE_INLINE Mat3W operator+(const Mat3W& a, const Mat3W& b) { return {a.c0 + b.c0, a.c1 + b.c1, a.c2 + b.c2}; }
FULCRUM_JOINT_WIDE_INLINE Mat3W operator-(const Mat3W& a, const Mat3W& b) { return {a.c0 - b.c0, a.c1 - b.c1, a.c2 - b.c2}; }
// Mat3::fromRows and transpose.
FULCRUM_JOINT_WIDE_INLINE Mat3W fromRows(const Vec3W& r0, const Vec3W& r1, const Vec3W& r2) {
    return {{r0.x, r1.x, r2.x}, {r0.y, r1.y, r2.y}, {r0.z, r1.z, r2.z}};
}
FULCRUM_JOINT_WIDE_INLINE Mat3W transpose(const Mat3W& m) { return fromRows(m.c0, m.c1, m.c2); }
FULCRUM_JOINT_WIDE_INLINE Mat3W select(const MaskW& m, const Mat3W& a, const Mat3W& b) {
    return {select(m, a.c0, b.c0), select(m, a.c1, b.c1), select(m, a.c2, b.c2)};
}

// inverse(m) where determinant(m) = c0 . (c1 x c2) > 0 (`valid`), as Mat3's
// adjugate spells it (fromRows(r0, r1, r2) * (1 / det)); other lanes: `otherwise`.
FULCRUM_JOINT_WIDE_INLINE Mat3W inverseWherePositive(const Mat3W& m, MaskW& valid, const Mat3W& otherwise) {
    const Vec3W r0 = cross(m.c1, m.c2), r1 = cross(m.c2, m.c0), r2 = cross(m.c0, m.c1);
    const FloatW det = dot(m.c0, r0);
    valid = det > FloatW(0.0f);
    const FloatW inv = FloatW(1.0f) / det;
    const Mat3W adj = fromRows(r0, r1, r2);
    return select(valid, Mat3W{adj.c0 * inv, adj.c1 * inv, adj.c2 * inv}, otherwise);
}

// A quaternion per lane (w, x, y, z), Quat's products term for term.
struct QuatW {
    FloatW w, x, y, z;
};
FULCRUM_JOINT_WIDE_INLINE QuatW operator*(const QuatW& a, const QuatW& b) {
    return {a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
            a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
FULCRUM_JOINT_WIDE_INLINE QuatW conjugate(const QuatW& q) { return {q.w, -q.x, -q.y, -q.z}; }
FULCRUM_JOINT_WIDE_INLINE Vec3W rotate(const QuatW& q, const Vec3W& v) {
    const Vec3W u{q.x, q.y, q.z};
    const Vec3W t = cross(u, v) * FloatW(2.0f);
    return (v + t * q.w) + cross(u, t);
}
FULCRUM_JOINT_WIDE_INLINE QuatW gatherRotation(const Quat* rotations, const std::uint32_t* index) {
    const std::array<FloatW, 4> q = FloatW::gatherTransposed<4>(rotations, index);
    return {q[0], q[1], q[2], q[3]};
}

// atan2 per lane (lanes [0, laneCount); the rest 0): the lanes call the same
// function the scalar code does (dmath::atan2 on floats), so both paths
// round alike.
FULCRUM_JOINT_WIDE_INLINE FloatW atan2Lanes(const FloatW& y, const FloatW& x, std::uint32_t laneCount) {
    alignas(32) Real ys[kLanes], xs[kLanes], out[kLanes] = {};
    y.store(ys);
    x.store(xs);
    for (std::uint32_t l = 0; l < laneCount; ++l) out[l] = dmath::atan2(ys[l], xs[l]);
    return FloatW::load(out);
}

// twistAngle: r = (conj(qA) qB) conj(relative0), turned to r.w >= 0, and
// 2 atan2(r.vec . localAxis, r.w).
FULCRUM_JOINT_WIDE_INLINE FloatW twistAngle(const QuatW& relative0Conjugate, const QuatW& qA, const QuatW& qB,
                                            const Vec3W& localAxis, std::uint32_t laneCount) {
    QuatW r = (conjugate(qA) * qB) * relative0Conjugate;
    const MaskW flip = r.w < FloatW(0.0f);
    r = {select(flip, -r.w, r.w), select(flip, -r.x, r.x), select(flip, -r.y, r.y), select(flip, -r.z, r.z)};
    return FloatW(2.0f) * atan2Lanes(dot(Vec3W{r.x, r.y, r.z}, localAxis), r.w, laneCount);
}

// One lane of a wide value, in place (simd.hpp).
using simd::getLane;
using simd::setLane;

// A body's solver state, gathered by whole rows (simd.hpp's transposed
// gathers: a 16-byte load per lane and 4 floats, then a transpose in
// registers). Floats 8-11 (dp.y, dp.z, dtheta.x, dtheta.y) only where the
// frame is recomputed (`deltas`): the other passes skip that load.
struct BodyW {
    std::array<FloatW, 24> row;
    Vec3W v() const { return {row[0], row[1], row[2]}; }
    FloatW invMass() const { return row[3]; }
    Vec3W w() const { return {row[4], row[5], row[6]}; }
    Vec3W dp() const { return {row[7], row[8], row[9]}; }
    Mat3W invI() const { return {{row[13], row[14], row[15]}, {row[16], row[17], row[18]}, {row[19], row[20], row[21]}}; }
};

// Floats [first, first + 4) of every lane's row into b.row (a named function,
// not a lambda: a lambda would not be always-inline, and when the kernels
// grew GCC made it a call per group: the grid's ball joints +11 % of the
// instructions, callgrind, ninth session).
FULCRUM_JOINT_WIDE_INLINE void gatherGroup(const Real* const* rows, std::size_t first, BodyW& b) {
    typename Policy::Reg regs[4];
    const Real* shifted[kLanes];
    for (int i = 0; i < kLanes; ++i) shifted[i] = rows[i] + first;
    Policy::loadTransposed4(shifted, regs);
    for (std::size_t c = 0; c < 4; ++c) b.row[first + c] = FloatW(regs[c]);
}

// `index` holds a solver body in every lane (empty lanes: body 0, never kEmptyLane).
template <bool deltas>
FULCRUM_JOINT_WIDE_INLINE BodyW gatherBody(const SolverBody* bodies, const std::uint32_t* index) {
    const Real* rows[kLanes];
    for (int i = 0; i < kLanes; ++i) rows[i] = reinterpret_cast<const Real*>(bodies + index[i]);
    BodyW b;
    gatherGroup(rows, 0, b);
    gatherGroup(rows, 4, b);
    if constexpr (deltas) gatherGroup(rows, 8, b);
    gatherGroup(rows, 12, b);
    gatherGroup(rows, 16, b);
    gatherGroup(rows, 20, b);
    return b;
}

// Writes v and w back (floats 0-7 of each row; invMass and dp.x unchanged).
FULCRUM_JOINT_WIDE_INLINE void scatterVelocity(SolverBody* bodies, const std::uint32_t* index, const BodyW& body,
                                               const Vec3W& v, const Vec3W& w) {
    const std::array<FloatW, 8> row = {v.x, v.y, v.z, body.row[3], w.x, w.y, w.z, body.row[7]};
    FloatW::scatterTransposed<8>(bodies, index, row);
}

// A block's two ends while its rows run: the gathered rows and the
// velocities as the rows change them (the scalar kernels' a.v, a.w, b.v, b.w).
struct Ends {
    BodyW a, b;
    Vec3W vA, wA, vB, wB;
    Mat3W invIA, invIB;
    FloatW mA, mB;
};

template <bool deltas>
FULCRUM_JOINT_WIDE_INLINE Ends gatherEnds(const SolverBody* bodies, const std::uint32_t* indexA, const std::uint32_t* indexB) {
    Ends e;
    e.a = gatherBody<deltas>(bodies, indexA);
    e.b = gatherBody<deltas>(bodies, indexB);
    e.vA = e.a.v();
    e.wA = e.a.w();
    e.vB = e.b.v();
    e.wB = e.b.w();
    e.invIA = e.a.invI();
    e.invIB = e.b.invI();
    e.mA = e.a.invMass();
    e.mB = e.b.invMass();
    return e;
}

// A JointRow per lane (+linear and +angularB on B, -linear and -angularA on A).
struct RowW {
    Vec3W linear, angularA, angularB;
};
// angularRow(axis): a zero linear part, kept so the products are the scalar ones.
FULCRUM_JOINT_WIDE_INLINE RowW angularRow(const Vec3W& axis) { return {Vec3W{}, axis, axis}; }

// rowVelocity, rowInverseMass, applyRow (joint_common.hpp), term for term.
FULCRUM_JOINT_WIDE_INLINE FloatW rowVelocity(const RowW& r, const Ends& e) {
    return dot(r.linear, e.vB - e.vA) + dot(r.angularB, e.wB) - dot(r.angularA, e.wA);
}
FULCRUM_JOINT_WIDE_INLINE FloatW rowInverseMass(const RowW& r, const Ends& e) {
    return (e.mA + e.mB) * lengthSquared(r.linear) + dot(r.angularA, e.invIA * r.angularA) +
           dot(r.angularB, e.invIB * r.angularB);
}
// applyRow where `on`; other lanes keep their velocities.
FULCRUM_JOINT_WIDE_INLINE void applyRow(const RowW& r, Ends& e, const FloatW& impulse, const MaskW& on) {
    e.vA = select(on, e.vA - r.linear * (e.mA * impulse), e.vA);
    e.wA = select(on, e.wA - e.invIA * (r.angularA * impulse), e.wA);
    e.vB = select(on, e.vB + r.linear * (e.mB * impulse), e.vB);
    e.wB = select(on, e.wB + e.invIB * (r.angularB * impulse), e.wB);
}

// applyPoint where `on`.
FULCRUM_JOINT_WIDE_INLINE void applyPoint(Ends& e, const Vec3W& rA, const Vec3W& rB, const Vec3W& P, const MaskW& on) {
    e.vA = select(on, e.vA - P * e.mA, e.vA);
    e.wA = select(on, e.wA - e.invIA * cross(rA, P), e.wA);
    e.vB = select(on, e.vB + P * e.mB, e.vB);
    e.wB = select(on, e.wB + e.invIB * cross(rB, P), e.wB);
}

// pointInverseMass: diag(mA + mB) - [rA] IA^-1 [rA] - [rB] IB^-1 [rB].
FULCRUM_JOINT_WIDE_INLINE Mat3W pointInverseMass(const Ends& e, const Vec3W& rA, const Vec3W& rB) {
    const FloatW zero = 0.0f;
    const Mat3W sa = skew(rA), sb = skew(rB);
    const Mat3W ta = sa * e.invIA * sa;
    const Mat3W tb = sb * e.invIB * sb;
    const FloatW m = e.mA + e.mB;
    const Mat3W diagonal{{m, zero, zero}, {zero, m, zero}, {zero, zero, m}};
    return diagonal - ta - tb;
}

// A tree joint's frame into its record (JointFrame, and the refresh it is
// of), for the lanes with `direct` > 0: the tree solver's pass after the
// blocks then finds it current (currentFrame) instead of computing it again
// (ragdolls, callgrind: the tree solver 261 M -> 341 M without it). Same bits:
// the lanes computed what updateFrame computes.
FULCRUM_JOINT_WIDE_INLINE void writeTreeFrames(JointConstraint* constraints, const std::uint32_t* constraint,
                                               std::uint32_t laneCount, const FloatW& direct, const Vec3W& rA,
                                               const Vec3W& rB, const Vec3W& d, const QuatW& qA, const QuatW& qB,
                                               std::uint64_t generation) {
    const auto quat = [](const QuatW& q, int l) { return Quat{getLane(q.w, l), getLane(q.x, l), getLane(q.y, l), getLane(q.z, l)}; };
    const auto vec = [](const Vec3W& v, int l) { return Vec3{getLane(v.x, l), getLane(v.y, l), getLane(v.z, l)}; };
    for (std::uint32_t lane = 0; lane < laneCount; ++lane) {
        const int l = static_cast<int>(lane);
        if (!(getLane(direct, l) > 0)) continue;
        JointConstraint& j = constraints[constraint[lane]];
        j.frame.rA = vec(rA, l);
        j.frame.rB = vec(rB, l);
        j.frame.d = vec(d, l);
        j.frame.qA = quat(qA, l);
        j.frame.qB = quat(qB, l);
        j.frameAt = generation;
    }
}

// The constants of a pass (JointContext's): limits' softness and 1 / h.
struct PassW {
    FloatW invH;
    FloatW soft[3];       // ctx.soft: biasRate, massScale, impulseScale
    FloatW limitSoft[3];  // ctx.limitSoft
    bool useBias = true;
    explicit PassW(const JointContext& ctx)
        : invH(ctx.invH),
          soft{ctx.soft.biasRate, ctx.soft.massScale, ctx.soft.impulseScale},
          limitSoft{ctx.limitSoft.biasRate, ctx.limitSoft.massScale, ctx.limitSoft.impulseScale},
          useBias(ctx.useBias) {}
};

// nextLimitImpulse: speculative (bias C / h, rigid) where C > 0, soft in the
// biased pass elsewhere, rigid and bias-free in the relax pass; the sum
// clamped to >= 0 (`lambda + d > 0 ? lambda + d : 0`).
FULCRUM_JOINT_WIDE_INLINE FloatW nextLimitImpulse(const FloatW& velocity, const FloatW& C, const FloatW& k,
                                                  const FloatW& lambda, const PassW& pass) {
    const FloatW zero = 0.0f, one = 1.0f;
    const MaskW open = C > zero;
    const FloatW bias = select(open, C * pass.invH, pass.useBias ? pass.limitSoft[0] * C : zero);
    const FloatW massScale = select(open, one, pass.useBias ? pass.limitSoft[1] : one);
    const FloatW impulseScale = select(open, zero, pass.useBias ? pass.limitSoft[2] : zero);
    const FloatW d = -massScale * (velocity + bias) / k - impulseScale * lambda;
    const FloatW next = lambda + d;
    return select(next > zero, next, zero);
}

// solveLimitRow where `on` (and k > 0).
FULCRUM_JOINT_WIDE_INLINE void solveLimitRow(const RowW& r, Ends& e, const FloatW& C, FloatW& lambda, const MaskW& on,
                                             const PassW& pass) {
    const FloatW k = rowInverseMass(r, e);
    const MaskW run = on & !(k <= FloatW(0.0f));
    const FloatW next = nextLimitImpulse(rowVelocity(r, e), C, k, lambda, pass);
    applyRow(r, e, next - lambda, run);
    lambda = select(run, next, lambda);
}

// solvePointBlock where `on`, with the sub-step's K^-1.
FULCRUM_JOINT_WIDE_INLINE void solvePointBlock(Ends& e, const Vec3W& rA, const Vec3W& rB, const Vec3W& C, Vec3W& lambda,
                                               const Mat3W& invK, const MaskW& on, const PassW& pass) {
    const Vec3W cdot = e.vB + cross(e.wB, rB) - e.vA - cross(e.wA, rA);
    const Vec3W bias = pass.useBias ? C * pass.soft[0] : Vec3W{};
    const FloatW massScale = pass.useBias ? pass.soft[1] : FloatW(1.0f);
    const FloatW impulseScale = pass.useBias ? pass.soft[2] : FloatW(0.0f);
    const Vec3W d = -(invK * (cdot + bias)) * massScale - lambda * impulseScale;
    lambda = select(on, lambda + d, lambda);
    applyPoint(e, rA, rB, d, on);
}

FULCRUM_JOINT_WIDE_INLINE void scatterEnds(SolverBody* bodies, const std::uint32_t* writeA, const std::uint32_t* writeB,
                                           const Ends& e) {
    scatterVelocity(bodies, writeA, e.a, e.vA, e.wA);
    scatterVelocity(bodies, writeB, e.b, e.vB, e.wB);
}

// The lanes every block kind fills alike (the block builds below and in
// cone_twist_wide.hpp, hinge_wide.hpp): the two solver bodies,
// which of them are written back (static and kinematic ends never are), the
// constraint record, and the step's anchors and centre delta.
template <class Block>
void setBodyLane(Block& k, int l, const JointConstraint& j, std::uint32_t index, const SolverBody* bodies) {
    k.bodyA[l] = j.bodyA;
    k.bodyB[l] = j.bodyB;
    k.writeA[l] = bodies[j.bodyA].invMass > 0 ? j.bodyA : kEmptyLane;
    k.writeB[l] = bodies[j.bodyB].invMass > 0 ? j.bodyB : kEmptyLane;
    k.constraint[l] = index;
    setLane(k.rA0, l, j.rA0);
    setLane(k.rB0, l, j.rB0);
    setLane(k.centreDelta, l, j.centreDelta);
}
// An unused lane: body 0 (the static body) on both ends, never written back.
template <class Block>
void setEmptyBodyLane(Block& k, int l) {
    k.bodyA[l] = k.bodyB[l] = 0;
    k.writeA[l] = k.writeB[l] = kEmptyLane;
    k.constraint[l] = 0;
}

// What hinge and cone-twist blocks both hold per lane: the two ends (gather:
// solver body, 0 for static; scatter: the body if dynamic, else kEmptyLane),
// where store() puts the lane's impulses, the refresh the frame was computed
// at, and the step's start (anchors, centre delta, rest pose, local axes).
struct FramedLanes {
    std::uint32_t bodyA[kLanes], bodyB[kLanes];
    std::uint32_t writeA[kLanes], writeB[kLanes];
    std::uint32_t constraint[kLanes];
    std::uint32_t laneCount = 0;
    std::uint64_t frameAt = 0;
    Vec3W rA0, rB0, centreDelta;
    QuatW qA0, qB0, relative0Conjugate;
    Vec3W localAxisA, localAxisB;
};

// The rest pose and the axes hinge and cone-twist blocks both carry (their
// frames: cone_twist_wide.hpp, hinge_wide.hpp). The rest
// rotation is stored conjugated, spelled out here rather than through the
// math headers' inline conjugate (no shared inline copy in the AVX2 file).
FULCRUM_JOINT_WIDE_INLINE void setQuatLane(QuatW& q, int l, const Quat& v) {
    setLane(q.w, l, v.w);
    setLane(q.x, l, v.x);
    setLane(q.y, l, v.y);
    setLane(q.z, l, v.z);
}
template <class Block>
void setRestPoseLane(Block& k, int l, const JointConstraint& j) {
    setQuatLane(k.qA0, l, j.qA0);
    setQuatLane(k.qB0, l, j.qB0);
    const Quat& rest = j.relative0;
    setQuatLane(k.relative0Conjugate, l, Quat{rest.w, -rest.x, -rest.y, -rest.z});
    setLane(k.localAxisA, l, j.localAxisA);
    setLane(k.localAxisB, l, j.localAxisB);
}
// An unused lane's rest pose: identities and a unit axis (finite values).
template <class Block>
void setEmptyRestPoseLane(Block& k, int l) {
    setQuatLane(k.qA0, l, Quat{});
    setQuatLane(k.qB0, l, Quat{});
    setQuatLane(k.relative0Conjugate, l, Quat{});
    setLane(k.localAxisA, l, Vec3{0, 0, 1});
    setLane(k.localAxisB, l, Vec3{0, 0, 1});
}

}  // namespace
}  // namespace fulcrum::detail::FULCRUM_JOINT_WIDE_NS

#include "solver/joints/ball_wide.hpp"
#include "solver/joints/cone_twist_wide.hpp"
#include "solver/joints/hinge_wide.hpp"

namespace fulcrum::detail::FULCRUM_JOINT_WIDE_NS {
namespace {

// The blocks of every kind, and the order they run in: entry b of order_ is
// block b (its kind and its place in its kind's array).
class Blocks final : public WideJoints {
public:
    explicit Blocks(SimdPath path) : path_(path) {}
    SimdPath path() const override { return path_; }
    int lanes() const override { return kLanes; }
    std::size_t size() const override { return order_.size(); }
    // The cone-twist and hinge arrays are not reserved for every joint (a
    // few kB per block, for kinds a scene may not have): they grow to the
    // largest step's size and keep it (clear() keeps capacity), so steady
    // state allocates nothing (tests/allocation).
    void reserve(std::size_t blocks) override {
        if (order_.capacity() < blocks) order_.reserve(2 * blocks);
        if (ball_.capacity() < blocks) ball_.reserve(2 * blocks);
    }
    void clear() override {
        order_.clear();
        ball_.clear();
        coneTwist_.clear();
        hinge_.clear();
        FULCRUM_JOINT_WIDE_LEAVE();
    }
    void build(const JointConstraint* constraints, const std::uint32_t* indices, int laneCount,
               const SolverBody* bodies) override {
        switch (wideKind(constraints[indices[0]])) {
            case WideKind::Ball:
                order_.push_back({WideKind::Ball, static_cast<std::uint32_t>(ball_.size())});
                buildBlock(ball_.emplace_back(), constraints, indices, laneCount, bodies);
                break;
            case WideKind::ConeTwist:
                order_.push_back({WideKind::ConeTwist, static_cast<std::uint32_t>(coneTwist_.size())});
                buildConeTwistBlock(coneTwist_.emplace_back(), constraints, indices, laneCount, bodies);
                break;
            case WideKind::Hinge:
                order_.push_back({WideKind::Hinge, static_cast<std::uint32_t>(hinge_.size())});
                buildHingeBlock(hinge_.emplace_back(), constraints, indices, laneCount, bodies);
                break;
            case WideKind::NotWide: break;
        }
        FULCRUM_JOINT_WIDE_LEAVE();
    }
    void warmStart(std::size_t first, std::size_t count, SolverBody* bodies, JointConstraint* constraints,
                   const JointContext& ctx) override {
        forRuns(first, count, [&](WideKind kind, std::uint32_t begin, std::uint32_t n) {
            switch (kind) {
                case WideKind::Ball: warmStartBlocks(ball_.data() + begin, n, bodies, ctx.rotations, ctx.generation); break;
                case WideKind::ConeTwist:
                    warmStartConeTwistBlocks(coneTwist_.data() + begin, n, bodies, constraints, ctx);
                    break;
                case WideKind::Hinge: warmStartHingeBlocks(hinge_.data() + begin, n, bodies, constraints, ctx); break;
                case WideKind::NotWide: break;
            }
        });
        FULCRUM_JOINT_WIDE_LEAVE();
    }
    void solve(std::size_t first, std::size_t count, SolverBody* bodies, JointConstraint* constraints,
               const JointContext& ctx) override {
        forRuns(first, count, [&](WideKind kind, std::uint32_t begin, std::uint32_t n) {
            switch (kind) {
                case WideKind::Ball:
                    if (ctx.useBias) {
                        solveBlocks<true>(ball_.data() + begin, n, bodies, ctx.rotations, ctx.generation, ctx.soft);
                    } else {
                        solveBlocks<false>(ball_.data() + begin, n, bodies, ctx.rotations, ctx.generation, ctx.soft);
                    }
                    break;
                case WideKind::ConeTwist: solveConeTwistBlocks(coneTwist_.data() + begin, n, bodies, constraints, ctx); break;
                case WideKind::Hinge: solveHingeBlocks(hinge_.data() + begin, n, bodies, constraints, ctx); break;
                case WideKind::NotWide: break;
            }
        });
        FULCRUM_JOINT_WIDE_LEAVE();
    }
    void store(JointConstraint* constraints) const override {
        for (const BallBlock& k : ball_) {
            for (std::uint32_t lane = 0; lane < k.laneCount; ++lane) {
                const int l = static_cast<int>(lane);
                Vec3& impulse = constraints[k.constraint[lane]].impulse.linear;
                impulse.x = getLane(k.impulse.x, l);
                impulse.y = getLane(k.impulse.y, l);
                impulse.z = getLane(k.impulse.z, l);
            }
        }
        for (const ConeTwistBlock& k : coneTwist_) storeConeTwistBlock(k, constraints);
        for (const HingeBlock& k : hinge_) storeHingeBlock(k, constraints);
        FULCRUM_JOINT_WIDE_LEAVE();
    }

private:
    struct Entry {
        WideKind kind;
        std::uint32_t index;  // in its kind's array
    };
    // f(kind, first index, count) over the runs of one kind (consecutive
    // in their array) among blocks [first, first + count).
    template <class F>
    void forRuns(std::size_t first, std::size_t count, F&& f) const {
        std::size_t b = first;
        const std::size_t end = first + count;
        while (b < end) {
            const Entry start = order_[b];
            std::uint32_t n = 1;
            while (b + n < end && order_[b + n].kind == start.kind && order_[b + n].index == start.index + n) ++n;
            f(start.kind, start.index, n);
            b += n;
        }
    }
    SimdPath path_;
    std::vector<Entry> order_;
    std::vector<BallBlock> ball_;
    std::vector<ConeTwistBlock> coneTwist_;
    std::vector<HingeBlock> hinge_;
};

}  // namespace
}  // namespace fulcrum::detail::FULCRUM_JOINT_WIDE_NS
