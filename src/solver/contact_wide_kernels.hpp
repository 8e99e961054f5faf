// The wide contact kernels, written once over a simd.hpp policy and compiled
// once per width (contact_wide.hpp): a translation unit defines
//   FULCRUM_WIDE_NS      the namespace of this copy (sse2, avx2)
//   FULCRUM_WIDE_POLICY  the simd.hpp policy (simd::Sse2Policy, simd::Avx2Policy)
// and includes this file once. Everything here is in an unnamed namespace, so
// the AVX2 copy's functions and block types are its translation unit's own:
// the linker can never pick an AVX2-compiled copy of them for code that runs
// on a CPU without AVX2. (Shared inline functions this file calls, Vec3 and
// std:: ones, are inlined: `nm contact_wide_avx2.cpp.o` lists no weak code
// symbols but FloatWide<Avx2Policy>'s own, which only AVX2 code calls, checked
// 2026-11-22 in Release and in the ASan build. Keep it so: scalar helpers that are not
// inlined everywhere (in the ASan build, fulcrum::inverse(Mat3) was not) are
// called through a function defined in contact_wide.cpp, like rollingMassOf.)
#ifndef FULCRUM_WIDE_NS
#error "define FULCRUM_WIDE_NS and FULCRUM_WIDE_POLICY before including contact_wide_kernels.hpp"
#endif
// FULCRUM_WIDE_LEAVE(): run as each entry point returns. The AVX2 copy defines
// it as _mm256_zeroupper(): GCC 12 let a kernel reached by a tail call from
// its entry point return with the upper halves of the ymm registers dirty, and
// every legacy-SSE instruction after it (the rest of the step is SSE2 code)
// then paid for the dirty state: box_pile, 270 steps, perf samples of
// ContactSolver::updateDeltas 119 (4-lane path) -> 383 (8-lane), of
// integratePositions 277 -> 497, and the 8-lane step 8-15 % slower than the
// 4-lane one although it ran 16 % fewer instructions. The statement after
// the call also keeps the compiler from making it a tail call.
#ifndef FULCRUM_WIDE_LEAVE
#define FULCRUM_WIDE_LEAVE() ((void)0)
#endif

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <type_traits>
#include <vector>

#include "math/simd.hpp"
#include "contacts/contact.hpp"
#include "solver/contact_solver.hpp"
#include "solver/contact_wide.hpp"

namespace fulcrum::detail {
// (inverse of invIA + invIB, or zero if singular: the rolling-resistance mass.
// Defined in contact_wide.cpp, so that it is compiled without AVX2.)
Mat3 rollingMassOf(const Mat3& invIA, const Mat3& invIB);
}  // namespace fulcrum::detail

namespace fulcrum::detail::FULCRUM_WIDE_NS {
namespace {

using Policy = FULCRUM_WIDE_POLICY;
using FloatW = simd::FloatWide<Policy>;
using MaskW = simd::MaskWide<Policy>;
using Vec3W = simd::Vec3Wide<Policy>;
using simd::kEmptyLane;
constexpr int kWideLanes = Policy::kLanes;

// End A's fields last (zeroA, rAxn, angA), on lines of their own: a block
// whose end A is the static world in every lane (WideContactBlock::staticA)
// reads zeroA in their place and never touches the rest (staticAKernels).
struct alignas(64) WidePoint {
    Vec3W rBxn, angB;
    FloatW baseSeparation, normalMass, normalImpulse, maxNormalImpulse, relativeVelocity;
    FloatW stepImpulse, approachVelocity;  // ConstraintPoint's
    FloatW zeroA;                          // dot(+0, rAxn): A's term, a signed zero, where A is static (staticAKernels)
    Vec3W rAxn, angA;
};

// What a block needs only when a lane has more than one point or rolling
// resistance, kept out of the block so that blocks of one-point contacts
// (sphere piles) are dense: measured on sphere_pile, see docs/solver.md.
struct WideBlockExtra {
    WidePoint points[3];                             // points 1-3
    Vec3W rollingMass0, rollingMass1, rollingMass2;  // columns
    Vec3W rollingImpulse;
};

// kWideLanes constraints of one colour. Lanes past laneCount are empty: no
// bodies, zero masses and impulses. Points past a lane's count are zero.
struct WideContactBlock {
    std::uint32_t bodyA[kWideLanes], bodyB[kWideLanes];    // gather: solver body (0: static)
    std::uint32_t writeA[kWideLanes], writeB[kWideLanes];  // scatter: the body if dynamic, else kEmptyLane
    std::uint32_t laneCount = 0, pointCount = 0;           // pointCount: the largest of the lanes
    bool rolling = false;                                  // a lane has rolling resistance
    bool bouncy = false;                                   // a lane has restitution
    // Every lane's end A (B) is solver body 0, the static world: all zeros
    // (BodyStore::beginStep) and never written, so the kernels take zeros for
    // it without the gather and skip its scatter (gatherEnd): the same values.
    // A static A also selects the kernels that skip A's rows (staticAKernels).
    bool staticA = false, staticB = false;
    WideBlockExtra* extra = nullptr;                       // points 1-3 and rolling; set iff pointCount > 1 or rolling
    Vec3W normal, tangent1, tangent2;
    FloatW friction, biasRate, massScale, impulseScale, minusPushMax;
    WidePoint point0;
    Vec3W rBc1, rBc2, angB1, angB2, twistB;
    FloatW k11, k12, k22, tangentImpulse1, tangentImpulse2, twistMass, twistImpulse, twistRadius;
    // End A's friction rows last, as in WidePoint: zeroA1, zeroA2 (dot(+0,
    // rAc1), dot(+0, rAc2)) stand in for them where A is static in every lane.
    FloatW zeroA1, zeroA2;
    Vec3W rAc1, rAc2, angA1, angA2, twistA;
    // Cold: relax, restitution and store only.
    FloatW stepTangent1, stepTangent2;  // ContactConstraint::stepTangent1, 2
    FloatW rollingResistance, restitution;
    std::uint32_t contact[kWideLanes], manifold[kWideLanes];  // where store() writes each lane's results
    std::uint32_t lanePoints[kWideLanes];                  // each lane's point count

    WidePoint& point(std::uint32_t i) { return i == 0 ? point0 : extra->points[i - 1]; }
    const WidePoint& point(std::uint32_t i) const { return i == 0 ? point0 : extra->points[i - 1]; }
};

static_assert(sizeof(SolverBody) == 24 * sizeof(Real) && std::is_trivially_copyable_v<SolverBody>,
              "the wide kernels read a solver body as 24 floats: v, invMass, w, dp, dtheta, invI, padding");

// Float offsets in SolverBody (checked by the static_assert above and the field order).
constexpr int kInvIOffset = 13;

// One lane of a wide value, written in place (simd.hpp).
using simd::setLane;

// The body state one kernel needs, gathered by whole rows (simd.hpp: 2-2.7x
// faster than field-by-field gathers).
struct WideBody {
    Vec3W v, w, dp, dtheta;
    FloatW invMass;
    FloatW spare;  // float 7 of the row (dp.x), written back unchanged
};

#define FULCRUM_WIDE_INLINE inline __attribute__((always_inline))

// The rows of a block's end as WideBody's fields (gatherBody, gatherEnd).
template <int K>
FULCRUM_WIDE_INLINE WideBody bodyOfRows(const std::array<FloatW, K>& row) {
    WideBody b;
    b.v = {row[0], row[1], row[2]};
    b.invMass = row[3];
    b.w = {row[4], row[5], row[6]};
    b.spare = row[7];
    if constexpr (K >= 16) {
        b.dp = {row[7], row[8], row[9]};
        b.dtheta = {row[10], row[11], row[12]};
    }
    return b;
}

template <int K>
FULCRUM_WIDE_INLINE WideBody gatherBody(const SolverBody* bodies, const std::uint32_t* index,
                                        std::array<FloatW, K>& row) {
    row = FloatW::gatherTransposed<K>(bodies, index);
    return bodyOfRows<K>(row);
}

// A block's end: gathered, or solver body 0's zeros where every lane's end is
// the static world (WideContactBlock::staticA/B). A transposed gather of 16
// floats is ~110 instructions, and its scatter ~50, per block and pass: a
// tenth of a solve pass (ten boxes on the ground, all their blocks' A static).
template <int K>
FULCRUM_WIDE_INLINE WideBody gatherEnd(bool isStatic, const SolverBody* bodies, const std::uint32_t* index,
                                       std::array<FloatW, K>& row) {
    if (isStatic) {
        row.fill(FloatW(0.0f));
    } else {
        row = FloatW::gatherTransposed<K>(bodies, index);
    }
    return bodyOfRows<K>(row);
}

// Writes v and w (floats 0-7 of each row; invMass and dp.x unchanged).
FULCRUM_WIDE_INLINE void scatterVelocity(SolverBody* bodies, const std::uint32_t* index, const WideBody& b) {
    const std::array<FloatW, 8> row = {b.v.x, b.v.y, b.v.z, b.invMass, b.w.x, b.w.y, b.w.z, b.spare};
    FloatW::scatterTransposed<8>(bodies, index, row);
}
// scatterVelocity of a block's end, none for the static world (no lane writes it).
FULCRUM_WIDE_INLINE void scatterEnd(bool isStatic, SolverBody* bodies, const std::uint32_t* index, const WideBody& b) {
    if (!isStatic) scatterVelocity(bodies, index, b);
}

struct WideMat3 {
    Vec3W c0, c1, c2;
};
// Same operation order as fulcrum's Mat3 * Vec3: c0 x + c1 y + c2 z.
Vec3W operator*(const WideMat3& m, const Vec3W& v) { return m.c0 * v.x + m.c1 * v.y + m.c2 * v.z; }

WideMat3 gatherInverseInertia(const SolverBody* bodies, const std::uint32_t* index) {
    const std::array<FloatW, 24> row = FloatW::gatherTransposed<24>(bodies, index);
    constexpr int o = kInvIOffset;
    return {{row[o], row[o + 1], row[o + 2]},
            {row[o + 3], row[o + 4], row[o + 5]},
            {row[o + 6], row[o + 7], row[o + 8]}};
}


// Measured on a settled 600-sphere pile (callgrind, 30 steps): building one
// constraint in a scratch ContactConstraint and packing it into its lane took
// ~840 + ~220 instructions; built four at a time here: ~450 per constraint
// (docs/solver.md).
void buildBlock(WideContactBlock& k, WideBlockExtra& extra, const LaneSource* lanes, int laneCount,
                const SolverBody* bodies, const Vec3* startCom, bool staticAKernels) {
    // Every field is written exactly once below (no clearBlock first: the
    // blocks are cold memory, and clearing them first doubled the stores; with
    // it, 40 % of buildBlock's samples stalled on the store buffer, perf on the
    // 10,000-sphere pile).
    k.pointCount = 0;
    k.rolling = false;
    k.bouncy = false;
    k.extra = nullptr;
    std::uint32_t anyBodyA = 0, anyBodyB = 0;  // ORed: zero iff every lane's end is the static world
    for (int l = 0; l < laneCount; ++l) {
        k.pointCount = std::max(k.pointCount, lanes[l].pointCount);
        k.rolling = k.rolling || lanes[l].rollingResistance > 0;
        anyBodyA |= lanes[l].bodyA;
        anyBodyB |= lanes[l].bodyB;
    }
    k.staticA = anyBodyA == 0;
    k.staticB = anyBodyB == 0;
    if (k.pointCount > 1 || k.rolling) {
        // Only the rolling columns need zeros first (setLane fills the lanes
        // with rolling resistance); points 1-3 are written below up to
        // pointCount, and no kernel reads a point past it. Zeroing the whole
        // extra was 2.2 KB of stores per block and step.
        if (k.rolling) {
            const FloatW zero = 0.0f;
            extra.rollingMass0 = extra.rollingMass1 = extra.rollingMass2 = extra.rollingImpulse = Vec3W{zero, zero, zero};
        }
        k.extra = &extra;
    }
    for (int l = laneCount; l < kWideLanes; ++l) {
        k.bodyA[l] = k.bodyB[l] = 0;
        k.writeA[l] = k.writeB[l] = kEmptyLane;
        k.contact[l] = k.manifold[l] = k.lanePoints[l] = 0;
    }
    if (k.pointCount == 0) k.point0 = WidePoint{};  // not produced by the narrow phase; kept safe
    // The per-lane inputs, lane by lane (zero in empty lanes).
    alignas(32) Real nx[kWideLanes] = {}, ny[kWideLanes] = {}, nz[kWideLanes] = {}, sign[kWideLanes] = {};
    alignas(32) Real count[kWideLanes] = {}, friction[kWideLanes] = {}, restitution[kWideLanes] = {};
    alignas(32) Real rolling[kWideLanes] = {}, biasRate[kWideLanes] = {}, massScale[kWideLanes] = {};
    alignas(32) Real impulseScale[kWideLanes] = {}, twistImpulse[kWideLanes] = {}, active[kWideLanes] = {};
    alignas(32) Real minusPushMax[kWideLanes] = {};
    alignas(32) Real fx[kWideLanes] = {}, fy[kWideLanes] = {}, fz[kWideLanes] = {};
    alignas(32) Real cax[kWideLanes] = {}, cay[kWideLanes] = {}, caz[kWideLanes] = {};
    alignas(32) Real cbx[kWideLanes] = {}, cby[kWideLanes] = {}, cbz[kWideLanes] = {};
    alignas(32) Real px[4][kWideLanes] = {}, py[4][kWideLanes] = {}, pz[4][kWideLanes] = {};
    alignas(32) Real depth[4][kWideLanes] = {}, impulse[4][kWideLanes] = {};
    for (int l = 0; l < laneCount; ++l) {
        const LaneSource& src = lanes[l];
        const LaneSource& m = src;
        const SolverBody& ba = bodies[src.bodyA];
        const SolverBody& bb = bodies[src.bodyB];
        k.bodyA[l] = src.bodyA;
        k.bodyB[l] = src.bodyB;
        k.writeA[l] = ba.invMass > 0 ? src.bodyA : kEmptyLane;
        k.writeB[l] = bb.invMass > 0 ? src.bodyB : kEmptyLane;
        k.contact[l] = src.contact;
        k.manifold[l] = src.manifoldIndex;
        k.lanePoints[l] = m.pointCount;
        if (src.restitution != 0) k.bouncy = true;
        active[l] = 1;
        nx[l] = m.normal.x;
        ny[l] = m.normal.y;
        nz[l] = m.normal.z;
        sign[l] = std::copysign(Real(1), m.normal.z);
        count[l] = static_cast<Real>(m.pointCount);
        friction[l] = src.friction;
        restitution[l] = src.restitution;
        rolling[l] = src.rollingResistance;
        biasRate[l] = src.biasRate;
        massScale[l] = src.massScale;
        impulseScale[l] = src.impulseScale;
        minusPushMax[l] = -src.pushMax;
        fx[l] = m.frictionImpulse.x;
        fy[l] = m.frictionImpulse.y;
        fz[l] = m.frictionImpulse.z;
        twistImpulse[l] = m.twistImpulse;
        const Vec3 comA = startCom[src.bodyA], comB = startCom[src.bodyB];
        cax[l] = comA.x, cay[l] = comA.y, caz[l] = comA.z;
        cbx[l] = comB.x, cby[l] = comB.y, cbz[l] = comB.z;
        for (std::uint32_t i = 0; i < m.pointCount; ++i) {
            const LaneSource::Point& p = m.points[i];
            px[i][l] = p.position.x;
            py[i][l] = p.position.y;
            pz[i][l] = p.position.z;
            depth[i][l] = p.depth;
            impulse[i][l] = p.normalImpulse;
        }
        if (src.rollingResistance > 0) {
            const Mat3 rollingMass = rollingMassOf(ba.invI, bb.invI);
            setLane(extra.rollingMass0, l, rollingMass.c0);
            setLane(extra.rollingMass1, l, rollingMass.c1);
            setLane(extra.rollingMass2, l, rollingMass.c2);
            setLane(extra.rollingImpulse, l, m.rollingImpulse);
        }
    }
    k.laneCount = static_cast<std::uint32_t>(laneCount);

    const FloatW zero = 0.0f, one = 1.0f;
    const MaskW laneActive = FloatW::load(active) > zero;
    const auto keep = [&](MaskW mask, FloatW v) { return select(mask, v, zero); };
    const auto keep3 = [&](MaskW mask, const Vec3W& v) { return Vec3W{keep(mask, v.x), keep(mask, v.y), keep(mask, v.z)}; };

    std::array<FloatW, 8> rowA, rowB;
    const WideBody a = gatherBody<8>(bodies, k.bodyA, rowA);
    const WideBody b = gatherBody<8>(bodies, k.bodyB, rowB);
    const WideMat3 invIA = gatherInverseInertia(bodies, k.bodyA);
    const WideMat3 invIB = gatherInverseInertia(bodies, k.bodyB);
    const FloatW mA = a.invMass, mB = b.invMass;
    const Vec3W comA{FloatW::load(cax), FloatW::load(cay), FloatW::load(caz)};
    const Vec3W comB{FloatW::load(cbx), FloatW::load(cby), FloatW::load(cbz)};
    const Vec3W n{FloatW::load(nx), FloatW::load(ny), FloatW::load(nz)};

    // orthonormalBasis (vec3.hpp), lane-wise.
    const FloatW s = FloatW::load(sign);
    const FloatW basisA = FloatW(-1.0f) / (s + n.z);
    const FloatW basisB = n.x * n.y * basisA;
    const Vec3W t1{one + s * n.x * n.x * basisA, s * basisB, -s * n.x};
    const Vec3W t2{basisB, s + n.y * n.y * basisA, -n.y};

    k.normal = n;  // zero in empty lanes already
    k.tangent1 = keep3(laneActive, t1);
    k.tangent2 = keep3(laneActive, t2);
    k.friction = FloatW::load(friction);
    k.restitution = FloatW::load(restitution);
    k.rollingResistance = FloatW::load(rolling);
    k.biasRate = FloatW::load(biasRate);
    k.massScale = FloatW::load(massScale);
    k.impulseScale = FloatW::load(impulseScale);
    k.minusPushMax = FloatW::load(minusPushMax);

    const FloatW pointCount = FloatW::load(count);
    Vec3W position[4];
    MaskW pointActive[4];
    Vec3W centre{zero, zero, zero};
    for (std::uint32_t i = 0; i < k.pointCount; ++i) {
        const MaskW on = pointCount > FloatW(static_cast<Real>(i));
        pointActive[i] = on;
        const Vec3W p{FloatW::load(px[i]), FloatW::load(py[i]), FloatW::load(pz[i])};
        position[i] = p;
        const Vec3W rA = p - comA;
        const Vec3W rB = p - comB;
        const Vec3W rAxn = cross(rA, n);
        const Vec3W rBxn = cross(rB, n);
        const Vec3W angA = invIA * rAxn;
        const Vec3W angB = invIB * rBxn;
        const FloatW kn = mA + mB + dot(rAxn, angA) + dot(rBxn, angB);
        const Vec3W dv = b.v + cross(b.w, rB) - a.v - cross(a.w, rA);
        WidePoint& wp = k.point(i);
        const Vec3W keptAxn = keep3(on, rAxn);
        wp.zeroA = dot(Vec3W{zero, zero, zero}, keptAxn);  // staticAKernels
        if (!k.staticA || !staticAKernels) {  // never read where A is static in every lane
            wp.rAxn = keptAxn;
            wp.angA = keep3(on, angA);
        }
        wp.rBxn = keep3(on, rBxn);
        wp.angB = keep3(on, angB);
        wp.baseSeparation = keep(on, -FloatW::load(depth[i]));
        wp.normalMass = keep(on & (kn > zero), one / kn);
        wp.normalImpulse = FloatW::load(impulse[i]);
        wp.maxNormalImpulse = zero;
        wp.stepImpulse = zero;
        wp.relativeVelocity = keep(on, dot(n, dv));
        wp.approachVelocity = wp.relativeVelocity;
        centre = select(on, centre + p, centre);
    }
    centre = centre * (one / pointCount);
    const Vec3W rAc = centre - comA;
    const Vec3W rBc = centre - comB;
    FloatW radius = zero;
    for (std::uint32_t i = 0; i < k.pointCount; ++i) {
        radius = select(pointActive[i], radius + length(position[i] - centre), radius);
    }
    k.twistRadius = keep(laneActive, radius / pointCount);

    const Vec3W rAc1 = cross(rAc, t1), rAc2 = cross(rAc, t2);
    const Vec3W rBc1 = cross(rBc, t1), rBc2 = cross(rBc, t2);
    const Vec3W angA1 = invIA * rAc1, angA2 = invIA * rAc2;
    const Vec3W angB1 = invIB * rBc1, angB2 = invIB * rBc2;
    const Vec3W keptAc1 = keep3(laneActive, rAc1), keptAc2 = keep3(laneActive, rAc2);
    k.zeroA1 = dot(Vec3W{zero, zero, zero}, keptAc1);  // staticAKernels
    k.zeroA2 = dot(Vec3W{zero, zero, zero}, keptAc2);
    const bool rowsA = !k.staticA || !staticAKernels;  // never read where A is static in every lane
    if (rowsA) {
        k.rAc1 = keptAc1;
        k.rAc2 = keptAc2;
        k.angA1 = keep3(laneActive, angA1);
        k.angA2 = keep3(laneActive, angA2);
    }
    k.rBc1 = keep3(laneActive, rBc1);
    k.rBc2 = keep3(laneActive, rBc2);
    k.angB1 = keep3(laneActive, angB1);
    k.angB2 = keep3(laneActive, angB2);
    const FloatW mSum = mA + mB;
    const FloatW t11 = mSum + dot(rAc1, angA1) + dot(rBc1, angB1);
    const FloatW t12 = dot(rAc1, angA2) + dot(rBc1, angB2);
    const FloatW t22 = mSum + dot(rAc2, angA2) + dot(rBc2, angB2);
    const FloatW det = t11 * t22 - t12 * t12;
    const MaskW invertible = laneActive & (det > zero);
    const FloatW inv = one / det;
    k.k11 = keep(invertible, t22 * inv);
    k.k12 = keep(invertible, -t12 * inv);
    k.k22 = keep(invertible, t11 * inv);
    const Vec3W twistA = invIA * n, twistB = invIB * n;
    if (rowsA) k.twistA = twistA;  // n is zero in empty lanes
    k.twistB = twistB;
    const FloatW kt = dot(n, twistA) + dot(n, twistB);
    k.twistMass = keep(laneActive & (kt > zero), one / kt);
    const Vec3W frictionImpulse{FloatW::load(fx), FloatW::load(fy), FloatW::load(fz)};
    k.tangentImpulse1 = keep(laneActive, dot(frictionImpulse, t1));
    k.tangentImpulse2 = keep(laneActive, dot(frictionImpulse, t2));
    k.stepTangent1 = zero;
    k.stepTangent2 = zero;
    k.twistImpulse = FloatW::load(twistImpulse);
}

// Blocks whose end A is the static world in every lane (staticA; on Jolt's
// ConvexVsMesh the mesh is end A of about half the constraints, and the lane
// order puts them together): the kernels below, instantiated with kStaticA,
// read none of end A's rows (rAxn, angA, rAc1, rAc2, angA1, angA2, twistA:
// 3 of a point's 10 lines, 7 of a block's) and give the same bits as the
// general kernel on the same block. Why exactly the same:
// - End A is gathered as +0 in every float (gatherEnd; solver body 0 is
//   SolverBody{}), so vA, wA, a.dp and a.dtheta start +0. Every update of
//   vA and wA subtracts a product with a +0 factor (a.invMass, or angA,
//   angA1, angA2, twistA, which are invIA (+0) times a row), a signed zero,
//   and +0 - (+0) = +0 - (-0) = +0 in round-to-nearest: vA and wA stay +0
//   through the whole block (for finite impulses; an infinite one makes a
//   NaN there, which the general kernel would carry into B's lane, where
//   that impulse has already put an infinity or a NaN).
// - So vB - vA, wB - wA and b.dp - a.dp are vB, wB and b.dp, bit for bit
//   (x - (+0) = x for every x, -0 and NaN included).
// - The terms dot(wA, rAxn) and dot(a.dtheta, rAxn) are dot(+0, rAxn), a
//   signed zero that depends on rAxn's signs (-0 when every component is
//   negative) and changes a sum only when the rest is -0: the build stores
//   it (WidePoint::zeroA, and zeroA1, zeroA2 for the friction rows, the
//   same dot on the same kept rows), and the kernel subtracts it where the
//   general kernel subtracts the dot.
// - Nothing of A is scattered (scatterEnd), so A's updates themselves,
//   once they are not read, are dropped.
// tests/solver/static_end_test.cpp holds the two paths to each other bit
// for bit (WideBlocks::setStaticAKernels(false): the general kernel and the
// full build everywhere, the reference).

// The twin of ContactSolver::warmStart's loop body.
template <bool kStaticA>
FULCRUM_WIDE_INLINE void warmStartBlock(WideContactBlock& k, SolverBody* bodies) {
    std::array<FloatW, 8> rowA, rowB;
    WideBody a, b = gatherEnd<8>(k.staticB, bodies, k.bodyB, rowB);
    if constexpr (!kStaticA) a = gatherEnd<8>(k.staticA, bodies, k.bodyA, rowA);
    Vec3W vA = a.v, wA = a.w, vB = b.v, wB = b.w;
    FloatW total = 0.0f;
    for (std::uint32_t i = 0; i < k.pointCount; ++i) {
        const WidePoint& cp = k.point(i);
        total += cp.normalImpulse;
        if constexpr (!kStaticA) wA -= cp.angA * cp.normalImpulse;
        wB += cp.angB * cp.normalImpulse;
    }
    const Vec3W P = k.normal * total + k.tangent1 * k.tangentImpulse1 + k.tangent2 * k.tangentImpulse2;
    if constexpr (!kStaticA) vA -= P * a.invMass;
    vB += P * b.invMass;
    Vec3W dwB = k.angB1 * k.tangentImpulse1 + k.angB2 * k.tangentImpulse2 + k.twistB * k.twistImpulse;
    if (k.rolling) dwB += gatherInverseInertia(bodies, k.bodyB) * k.extra->rollingImpulse;
    if constexpr (!kStaticA) {
        Vec3W dwA = k.angA1 * k.tangentImpulse1 + k.angA2 * k.tangentImpulse2 + k.twistA * k.twistImpulse;
        if (k.rolling) dwA += gatherInverseInertia(bodies, k.bodyA) * k.extra->rollingImpulse;
        wA -= dwA;
        a.v = vA;
        a.w = wA;
        scatterEnd(k.staticA, bodies, k.writeA, a);
    }
    wB += dwB;
    b.v = vB;
    b.w = wB;
    scatterEnd(k.staticB, bodies, k.writeB, b);
}

void warmStartWide(WideContactBlock* blocks, std::size_t count, SolverBody* bodies, bool staticAKernels) {
    for (std::size_t bi = 0; bi < count; ++bi) {
        WideContactBlock& k = blocks[bi];
        if (k.staticA && staticAKernels) {
            warmStartBlock<true>(k, bodies);
        } else {
            warmStartBlock<false>(k, bodies);
        }
    }
}

// x - y, or x where y is end A's +0 (staticAKernels: the same bits).
template <bool kStaticA, class T>
FULCRUM_WIDE_INLINE T lessA(const T& x, const T& y) {
    if constexpr (kStaticA) {
        (void)y;
        return x;
    } else {
        return x - y;
    }
}

// The twin of ContactSolver::solvePass.
template <bool useBias, bool kStaticA>
FULCRUM_WIDE_INLINE void solveBlock(WideContactBlock& k, SolverBody* bodies, FloatW invH) {
    const FloatW zero = 0.0f, one = 1.0f;
    std::array<FloatW, 16> rowA, rowB;
    WideBody a, b = gatherEnd<16>(k.staticB, bodies, k.bodyB, rowB);
    if constexpr (!kStaticA) a = gatherEnd<16>(k.staticA, bodies, k.bodyA, rowA);
    Vec3W vA = a.v, wA = a.w, vB = b.v, wB = b.w;
    const FloatW mA = a.invMass, mB = b.invMass;
    const Vec3W dp = lessA<kStaticA>(b.dp, a.dp);
    const Vec3W n = k.normal;
    FloatW totalNormal = zero;
    for (std::uint32_t i = 0; i < k.pointCount; ++i) {
        WidePoint& cp = k.point(i);
        FloatW s = cp.baseSeparation + dot(n, dp) + dot(b.dtheta, cp.rBxn);
        if constexpr (kStaticA) {
            s = s - cp.zeroA;
        } else {
            s = s - dot(a.dtheta, cp.rAxn);
        }
        const MaskW speculative = s > zero;
        FloatW bias, massScale, impulseScale;
        if constexpr (useBias) {
            bias = select(speculative, s * invH, max(k.minusPushMax, k.biasRate * s));
            massScale = select(speculative, one, k.massScale);
            impulseScale = select(speculative, zero, k.impulseScale);
        } else {
            bias = select(speculative, s * invH, zero);
            massScale = one;
            impulseScale = zero;
        }
        FloatW vn = dot(n, lessA<kStaticA>(vB, vA)) + dot(wB, cp.rBxn);
        if constexpr (kStaticA) {
            vn = vn - cp.zeroA;
        } else {
            vn = vn - dot(wA, cp.rAxn);
        }
        FloatW impulse = -cp.normalMass * massScale * (vn + bias) - impulseScale * cp.normalImpulse;
        const FloatW newImpulse = max(zero, cp.normalImpulse + impulse);
        impulse = newImpulse - cp.normalImpulse;
        const MaskW first = (impulse > zero) & (cp.maxNormalImpulse == zero);
        if constexpr (useBias) cp.relativeVelocity = select(first, min(vn, cp.relativeVelocity), cp.relativeVelocity);
        cp.approachVelocity = select(first, min(vn, cp.approachVelocity), cp.approachVelocity);
        cp.normalImpulse = newImpulse;
        cp.maxNormalImpulse = max(impulse, cp.maxNormalImpulse);
        if constexpr (!useBias) cp.stepImpulse += newImpulse;
        totalNormal += newImpulse;
        const Vec3W P = n * impulse;
        if constexpr (!kStaticA) {
            vA -= P * mA;
            wA -= cp.angA * impulse;
        }
        vB += P * mB;
        wB += cp.angB * impulse;
    }

    {
        const Vec3W dv = lessA<kStaticA>(vB, vA);
        FloatW v1 = dot(dv, k.tangent1) + dot(wB, k.rBc1);
        FloatW v2 = dot(dv, k.tangent2) + dot(wB, k.rBc2);
        if constexpr (kStaticA) {
            v1 = v1 - k.zeroA1;
            v2 = v2 - k.zeroA2;
        } else {
            v1 = v1 - dot(wA, k.rAc1);
            v2 = v2 - dot(wA, k.rAc2);
        }
        const FloatW old1 = k.tangentImpulse1, old2 = k.tangentImpulse2;
        FloatW new1 = old1 - (k.k11 * v1 + k.k12 * v2);
        FloatW new2 = old2 - (k.k12 * v1 + k.k22 * v2);
        const FloatW maxFriction = k.friction * totalNormal;
        const FloatW mag2 = new1 * new1 + new2 * new2;
        const MaskW outside = mag2 > maxFriction * maxFriction;
        if (outside.any()) {
            const FloatW scale = maxFriction / sqrt(mag2);
            new1 = select(outside, new1 * scale, new1);
            new2 = select(outside, new2 * scale, new2);
        }
        k.tangentImpulse1 = new1;
        k.tangentImpulse2 = new2;
        if constexpr (!useBias) {
            k.stepTangent1 += new1;
            k.stepTangent2 += new2;
        }
        const FloatW d1 = new1 - old1, d2 = new2 - old2;
        const Vec3W P = k.tangent1 * d1 + k.tangent2 * d2;
        if constexpr (!kStaticA) {
            vA -= P * mA;
            wA -= k.angA1 * d1 + k.angA2 * d2;
        }
        vB += P * mB;
        wB += k.angB1 * d1 + k.angB2 * d2;

        const FloatW maxTwist = maxFriction * k.twistRadius;
        const FloatW wn = dot(lessA<kStaticA>(wB, wA), n);
        const FloatW oldT = k.twistImpulse;
        // std::clamp(x, lo, hi) as libstdc++ computes it: min(max(x, lo), hi),
        // with std::max(x, lo) = x < lo ? lo : x and std::min(t, hi) = hi < t ? hi : t.
        const FloatW x = oldT - k.twistMass * wn, lo = -maxTwist;
        const FloatW t = select(x < lo, lo, x);
        const FloatW newT = select(maxTwist < t, maxTwist, t);
        k.twistImpulse = newT;
        const FloatW dT = newT - oldT;
        if constexpr (!kStaticA) wA -= k.twistA * dT;
        wB += k.twistB * dT;
    }

    if (k.rolling) {
        const MaskW active = k.rollingResistance > zero;
        const FloatW maxRolling = k.rollingResistance * totalNormal;
        WideBlockExtra& e = *k.extra;
        const Vec3W oldR = e.rollingImpulse;
        const WideMat3 rollingMass{e.rollingMass0, e.rollingMass1, e.rollingMass2};
        Vec3W newR = oldR - rollingMass * lessA<kStaticA>(wB, wA);
        const FloatW mag2 = lengthSquared(newR);
        const MaskW outside = mag2 > maxRolling * maxRolling;
        const FloatW scale = maxRolling / sqrt(mag2);
        newR = select(outside, newR * scale, newR);
        newR = select(active, newR, oldR);
        e.rollingImpulse = newR;
        const Vec3W T = newR - oldR;
        if constexpr (!kStaticA) wA -= gatherInverseInertia(bodies, k.bodyA) * T;
        wB += gatherInverseInertia(bodies, k.bodyB) * T;
    }

    if constexpr (!kStaticA) {
        a.v = vA;
        a.w = wA;
        scatterEnd(k.staticA, bodies, k.writeA, a);
    }
    b.v = vB;
    b.w = wB;
    scatterEnd(k.staticB, bodies, k.writeB, b);
}

template <bool useBias>
void solveBlocks(WideContactBlock* blocks, std::size_t count, SolverBody* bodies, FloatW invH, bool staticAKernels) {
    for (std::size_t bi = 0; bi < count; ++bi) {
        WideContactBlock& k = blocks[bi];
        if (k.staticA && staticAKernels) {
            solveBlock<useBias, true>(k, bodies, invH);
        } else {
            solveBlock<useBias, false>(k, bodies, invH);
        }
    }
}


void solveWide(WideContactBlock* blocks, std::size_t count, SolverBody* bodies, bool useBias, Real invH,
               bool staticAKernels) {
    if (useBias) {
        solveBlocks<true>(blocks, count, bodies, invH, staticAKernels);
    } else {
        solveBlocks<false>(blocks, count, bodies, invH, staticAKernels);
    }
}

// The twin of ContactSolver::applyRestitution: a lane takes part where the
// scalar loop would not `continue` (restitution != 0, approached faster than
// the threshold, received impulse); elsewhere it adds an exact zero.
template <bool kStaticA>
FULCRUM_WIDE_INLINE void restitutionBlock(WideContactBlock& k, SolverBody* bodies, FloatW minusThreshold) {
    const FloatW zero = 0.0f;
    std::array<FloatW, 8> rowA, rowB;
    WideBody a, b = gatherEnd<8>(k.staticB, bodies, k.bodyB, rowB);
    if constexpr (!kStaticA) a = gatherEnd<8>(k.staticA, bodies, k.bodyA, rowA);
    Vec3W vA = a.v, wA = a.w, vB = b.v, wB = b.w;
    const MaskW bouncy = k.restitution != zero;
    for (std::uint32_t i = 0; i < k.pointCount; ++i) {
        WidePoint& cp = k.point(i);
        const MaskW apply = bouncy & !(cp.relativeVelocity > minusThreshold) & !(cp.maxNormalImpulse == zero);
        FloatW vn = dot(k.normal, lessA<kStaticA>(vB, vA)) + dot(wB, cp.rBxn);
        if constexpr (kStaticA) {
            vn = vn - cp.zeroA;
        } else {
            vn = vn - dot(wA, cp.rAxn);
        }
        FloatW impulse = -cp.normalMass * (vn + k.restitution * cp.relativeVelocity);
        const FloatW newImpulse = max(zero, cp.normalImpulse + impulse);
        impulse = newImpulse - cp.normalImpulse;
        cp.normalImpulse = select(apply, newImpulse, cp.normalImpulse);
        cp.maxNormalImpulse = select(apply, max(impulse, cp.maxNormalImpulse), cp.maxNormalImpulse);
        impulse = select(apply, impulse, zero);
        cp.stepImpulse += impulse;
        const Vec3W P = k.normal * impulse;
        if constexpr (!kStaticA) {
            vA -= P * a.invMass;
            wA -= cp.angA * impulse;
        }
        vB += P * b.invMass;
        wB += cp.angB * impulse;
    }
    if constexpr (!kStaticA) {
        a.v = vA;
        a.w = wA;
        scatterEnd(k.staticA, bodies, k.writeA, a);
    }
    b.v = vB;
    b.w = wB;
    scatterEnd(k.staticB, bodies, k.writeB, b);
}

void restitutionWide(WideContactBlock* blocks, std::size_t count, SolverBody* bodies, Real threshold, bool staticAKernels) {
    const FloatW minusThreshold = -threshold;
    for (std::size_t bi = 0; bi < count; ++bi) {
        WideContactBlock& k = blocks[bi];
        if (!k.bouncy) continue;
        if (k.staticA && staticAKernels) {
            restitutionBlock<true>(k, bodies, minusThreshold);
        } else {
            restitutionBlock<false>(k, bodies, minusThreshold);
        }
    }
}

// The twin of ContactSolver::store: impulses for the next step's warm start
// and the end-of-step depths, lane by lane into the contacts' manifolds.
template <bool kStaticA>
FULCRUM_WIDE_INLINE void storeBlock(const WideContactBlock& k, const SolverBody* bodies, Contact* contacts) {
    std::array<FloatW, 16> rowA, rowB;
    WideBody a;
    if constexpr (!kStaticA) a = gatherEnd<16>(k.staticA, bodies, k.bodyA, rowA);
    const WideBody b = gatherEnd<16>(k.staticB, bodies, k.bodyB, rowB);
    const Vec3W dp = lessA<kStaticA>(b.dp, a.dp);
    alignas(32) Real impulse[4][kWideLanes], maxImpulse[4][kWideLanes], depth[4][kWideLanes];
    alignas(32) Real stepImpulse[4][kWideLanes], approachVelocity[4][kWideLanes];
    for (std::uint32_t i = 0; i < k.pointCount; ++i) {
        const WidePoint& cp = k.point(i);
        FloatW s = cp.baseSeparation + dot(k.normal, dp) + dot(b.dtheta, cp.rBxn);
        if constexpr (kStaticA) {
            s = s - cp.zeroA;
        } else {
            s = s - dot(a.dtheta, cp.rAxn);
        }
        const FloatW d = -s;
        d.store(depth[i]);
        cp.normalImpulse.store(impulse[i]);
        cp.maxNormalImpulse.store(maxImpulse[i]);
        cp.stepImpulse.store(stepImpulse[i]);
        cp.approachVelocity.store(approachVelocity[i]);
    }
    const Vec3W friction = k.tangent1 * k.tangentImpulse1 + k.tangent2 * k.tangentImpulse2;
    const Vec3W stepFriction = k.tangent1 * k.stepTangent1 + k.tangent2 * k.stepTangent2;
    for (std::uint32_t lane = 0; lane < k.laneCount; ++lane) {
        const int l = static_cast<int>(lane);
        CachedManifold& m = contacts[k.contact[lane]].manifolds[k.manifold[lane]];
        for (std::uint32_t i = 0; i < k.lanePoints[lane]; ++i) {
            CachedPoint& dst = m.points[i];
            dst.normalImpulse = impulse[i][lane];
            dst.maxNormalImpulse = maxImpulse[i][lane];
            dst.stepNormalImpulse = stepImpulse[i][lane];
            dst.approachVelocity = approachVelocity[i][lane];
            dst.depthAfter = depth[i][lane];
        }
        m.frictionImpulse = friction.lane(l);
        m.twistImpulse = k.twistImpulse.lane(l);
        m.stepFrictionImpulse = stepFriction.lane(l);
        m.rollingImpulse = k.rolling ? k.extra->rollingImpulse.lane(l) : Vec3{};
    }
}

void storeWide(const WideContactBlock* blocks, std::size_t count, const SolverBody* bodies, Contact* contacts,
               bool staticAKernels) {
    for (std::size_t bi = 0; bi < count; ++bi) {
        const WideContactBlock& k = blocks[bi];
        if (k.staticA && staticAKernels) {
            storeBlock<true>(k, bodies, contacts);
        } else {
            storeBlock<false>(k, bodies, contacts);
        }
    }
}

// The blocks of one step at this width, and the kernels over them.
class Blocks final : public WideBlocks {
public:
    explicit Blocks(SimdPath path) : path_(path) {}
    SimdPath path() const override { return path_; }
    int lanes() const override { return kWideLanes; }
    std::size_t size() const override { return blocks_.size(); }
    void reserve(std::size_t blocks) override {
        if (blocks_.capacity() < blocks) blocks_.reserve(2 * blocks);
        if (extras_.capacity() < blocks) extras_.reserve(2 * blocks);
    }
    void resize(std::size_t blocks) override {
        blocks_.resize(blocks);
        if (extras_.size() < blocks) extras_.resize(blocks);  // never shrinks: no re-initialising
        FULCRUM_WIDE_LEAVE();
    }
    void build(std::size_t block, const LaneSource* lanes, int laneCount, const SolverBody* bodies,
               const Vec3* startCom) override {
        buildBlock(blocks_[block], extras_[block], lanes, laneCount, bodies, startCom, staticAKernels_);
        FULCRUM_WIDE_LEAVE();
    }
    void warmStart(std::size_t first, std::size_t count, SolverBody* bodies) override {
        warmStartWide(blocks_.data() + first, count, bodies, staticAKernels_);
        FULCRUM_WIDE_LEAVE();
    }
    void solve(std::size_t first, std::size_t count, SolverBody* bodies, bool useBias, Real invH) override {
        solveWide(blocks_.data() + first, count, bodies, useBias, invH, staticAKernels_);
        FULCRUM_WIDE_LEAVE();
    }
    void restitution(SolverBody* bodies, Real threshold) override {
        restitutionWide(blocks_.data(), blocks_.size(), bodies, threshold, staticAKernels_);
        FULCRUM_WIDE_LEAVE();
    }
    void laneTargets(std::size_t block, const std::uint32_t*& contact, const std::uint32_t*& manifold,
                     std::uint32_t& laneCount) const override {
        const WideContactBlock& k = blocks_[block];
        contact = k.contact;
        manifold = k.manifold;
        laneCount = k.laneCount;
    }
    void store(std::size_t first, std::size_t count, const SolverBody* bodies, Contact* contacts) const override {
        storeWide(blocks_.data() + first, count, bodies, contacts, staticAKernels_);
        FULCRUM_WIDE_LEAVE();
    }
    void setStaticAKernels(bool on) override { staticAKernels_ = on; }
    std::size_t staticABlocks() const override {
        std::size_t n = 0;
        for (const WideContactBlock& k : blocks_) n += k.staticA && staticAKernels_ ? 1 : 0;
        FULCRUM_WIDE_LEAVE();
        return n;
    }
    std::size_t pointRuns() const override {
        std::size_t runs = 0;
        for (const WideContactBlock& k : blocks_) runs += k.pointCount;
        FULCRUM_WIDE_LEAVE();
        return runs;
    }

private:
    SimdPath path_;
    bool staticAKernels_ = true;  // setStaticAKernels
    std::vector<WideContactBlock> blocks_;  // the coloured constraints, kWideLanes per block
    std::vector<WideBlockExtra> extras_;    // per block; touched only by blocks that need it
};

}  // namespace
}  // namespace fulcrum::detail::FULCRUM_WIDE_NS
