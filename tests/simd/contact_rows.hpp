#pragma once
// A toy contact solver kernel, scalar and wide, shared by tests/simd and
// bench/simd.cpp: one sequential-impulse pass over normal contact rows
// (Catto, "Iterative Dynamics with Temporal Coherence", GDC 2005):
//
//   Cdot   = n·(vB − vA) + (rB×n)·wB − (rA×n)·wA        relative normal speed
//   Δλ     = −m_eff (Cdot + bias)
//   λ_new  = max(λ + Δλ, 0),  Δλ = λ_new − λ            accumulated clamping
//   vA −= n mA⁻¹ Δλ,  wA −= (rA×n) IA⁻¹ Δλ,  vB += ..., wB += ...
//
// (scalar inverse inertia to keep the toy small). The wide kernel gathers
// kLanes rows' bodies, solves them at once and scatters back; rows of one
// bundle share no body, so a bundle equals solving its rows one after another
// and the two kernels give bit-identical bodies and impulses.
#include <algorithm>
#include <array>
#include <cstdint>
#include <random>
#include <vector>

#include "math/simd.hpp"

namespace fulcrum::test {

struct SolverBody {
    Vec3 v;
    float invMass = 0;
    Vec3 w;
    float invInertia = 0;
};

struct ContactRow {
    std::uint32_t a = 0, b = 0;
    Vec3 n, rAxn, rBxn;
    float effectiveMass = 0, bias = 0, impulse = 0;
};

inline void solveRowsScalar(SolverBody* bodies, ContactRow* rows, std::size_t count) {
    for (std::size_t k = 0; k < count; ++k) {
        ContactRow& r = rows[k];
        SolverBody& A = bodies[r.a];
        SolverBody& B = bodies[r.b];
        const float cdot = dot(r.n, B.v - A.v) + dot(r.rBxn, B.w) - dot(r.rAxn, A.w);
        const float lambda = -r.effectiveMass * (cdot + r.bias);
        const float sum = r.impulse + lambda;
        const float total = sum > 0.0f ? sum : 0.0f;  // the expression simd max() implements (not std::max)
        const float applied = total - r.impulse;
        r.impulse = total;
        A.v = A.v - r.n * (A.invMass * applied);
        A.w = A.w - r.rAxn * (A.invInertia * applied);
        B.v = B.v + r.n * (B.invMass * applied);
        B.w = B.w + r.rBxn * (B.invInertia * applied);
    }
}

// kLanes rows in SoA form (AoSoA overall).
template <class P>
struct RowBundle {
    static constexpr int kLanes = P::kLanes;
    std::uint32_t a[kLanes], b[kLanes];
    simd::Vec3Wide<P> n, rAxn, rBxn;
    simd::FloatWide<P> effectiveMass, bias, impulse;
};

// Bundles rows in order; the last bundle's missing lanes are kEmptyLane.
template <class P>
std::vector<RowBundle<P>> bundleRows(const std::vector<ContactRow>& rows) {
    using V = simd::Vec3Wide<P>;
    using W = simd::FloatWide<P>;
    constexpr int N = P::kLanes;
    std::vector<RowBundle<P>> bundles((rows.size() + N - 1) / N);
    for (std::size_t k = 0; k < bundles.size(); ++k) {
        auto row = [&](int i) -> const ContactRow* {
            const std::size_t r = k * N + std::size_t(i);
            return r < rows.size() ? &rows[r] : nullptr;
        };
        RowBundle<P>& bundle = bundles[k];
        for (int i = 0; i < N; ++i) {
            bundle.a[i] = row(i) ? row(i)->a : simd::kEmptyLane;
            bundle.b[i] = row(i) ? row(i)->b : simd::kEmptyLane;
        }
        bundle.n = V::fromLanes([&](int i) { return row(i) ? row(i)->n : Vec3{}; });
        bundle.rAxn = V::fromLanes([&](int i) { return row(i) ? row(i)->rAxn : Vec3{}; });
        bundle.rBxn = V::fromLanes([&](int i) { return row(i) ? row(i)->rBxn : Vec3{}; });
        bundle.effectiveMass = W::fromLanes([&](int i) { return row(i) ? row(i)->effectiveMass : 0.0f; });
        bundle.bias = W::fromLanes([&](int i) { return row(i) ? row(i)->bias : 0.0f; });
        bundle.impulse = W::fromLanes([&](int i) { return row(i) ? row(i)->impulse : 0.0f; });
    }
    return bundles;
}

// The row math, shared by both ways of reaching the bodies.
template <class P>
inline void solveBundle(RowBundle<P>& r, simd::Vec3Wide<P>& vA, simd::Vec3Wide<P>& wA, simd::Vec3Wide<P>& vB,
                        simd::Vec3Wide<P>& wB, simd::FloatWide<P> mA, simd::FloatWide<P> iA, simd::FloatWide<P> mB,
                        simd::FloatWide<P> iB) {
    using W = simd::FloatWide<P>;
    const W cdot = dot(r.n, vB - vA) + dot(r.rBxn, wB) - dot(r.rAxn, wA);
    const W lambda = -r.effectiveMass * (cdot + r.bias);
    const W total = max(r.impulse + lambda, W(0.0f));
    const W applied = total - r.impulse;
    r.impulse = total;
    vA = vA - r.n * (mA * applied);
    wA = wA - r.rAxn * (iA * applied);
    vB = vB + r.n * (mB * applied);
    wB = wB + r.rBxn * (iB * applied);
}

// Bodies gathered field by field (Vec3Wide::gather / FloatWide::gather).
template <class P>
void solveRowsWideByField(SolverBody* bodies, RowBundle<P>* bundles, std::size_t count) {
    using V = simd::Vec3Wide<P>;
    using W = simd::FloatWide<P>;
    for (std::size_t k = 0; k < count; ++k) {
        RowBundle<P>& r = bundles[k];
        V vA = V::gather(bodies, r.a, &SolverBody::v), wA = V::gather(bodies, r.a, &SolverBody::w);
        V vB = V::gather(bodies, r.b, &SolverBody::v), wB = V::gather(bodies, r.b, &SolverBody::w);
        const W mA = W::gather(bodies, r.a, &SolverBody::invMass), iA = W::gather(bodies, r.a, &SolverBody::invInertia);
        const W mB = W::gather(bodies, r.b, &SolverBody::invMass), iB = W::gather(bodies, r.b, &SolverBody::invInertia);
        solveBundle(r, vA, wA, vB, wB, mA, iA, mB, iB);
        vA.scatter(bodies, r.a, &SolverBody::v), wA.scatter(bodies, r.a, &SolverBody::w);
        vB.scatter(bodies, r.b, &SolverBody::v), wB.scatter(bodies, r.b, &SolverBody::w);
    }
}

// Bodies gathered as whole 32-byte structs and transposed (gatherTransposed).
template <class P>
void solveRowsWide(SolverBody* bodies, RowBundle<P>* bundles, std::size_t count) {
    using V = simd::Vec3Wide<P>;
    using W = simd::FloatWide<P>;
    static_assert(sizeof(SolverBody) == 8 * sizeof(float));
    for (std::size_t k = 0; k < count; ++k) {
        RowBundle<P>& r = bundles[k];
        std::array<W, 8> a = W::template gatherTransposed<8>(bodies, r.a);  // v, invMass, w, invInertia
        std::array<W, 8> b = W::template gatherTransposed<8>(bodies, r.b);
        V vA(a[0], a[1], a[2]), wA(a[4], a[5], a[6]), vB(b[0], b[1], b[2]), wB(b[4], b[5], b[6]);
        solveBundle(r, vA, wA, vB, wB, a[3], a[7], b[3], b[7]);
        a = {vA.x, vA.y, vA.z, a[3], wA.x, wA.y, wA.z, a[7]};
        b = {vB.x, vB.y, vB.z, b[3], wB.x, wB.y, wB.z, b[7]};
        W::template scatterTransposed<8>(bodies, r.a, a);
        W::template scatterTransposed<8>(bodies, r.b, b);
    }
}

// A random scene: bodyCount bodies, rowCount rows in which every run of
// `colour` consecutive rows (aligned) touches 2 * colour distinct bodies, so
// bundles of any width dividing `colour` are valid graph colours.
struct RowScene {
    std::vector<SolverBody> bodies;
    std::vector<ContactRow> rows;
};

inline RowScene makeRowScene(std::size_t bodyCount, std::size_t rowCount, std::size_t colour, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> u(-1.0f, 1.0f);
    RowScene s;
    s.bodies.resize(bodyCount);
    for (SolverBody& b : s.bodies) {
        b.v = {u(rng), u(rng), u(rng)};
        b.w = {u(rng), u(rng), u(rng)};
        b.invMass = 0.5f + 0.5f * (u(rng) + 1.0f);
        b.invInertia = 0.5f + (u(rng) + 1.0f);
    }
    std::vector<std::uint32_t> ids(bodyCount);
    for (std::uint32_t k = 0; k < ids.size(); ++k) ids[k] = k;
    s.rows.resize(rowCount);
    for (std::size_t first = 0; first < rowCount; first += colour) {
        std::shuffle(ids.begin(), ids.end(), rng);  // needs bodyCount >= 2 * colour
        for (std::size_t i = 0; i < colour && first + i < rowCount; ++i) {
            ContactRow& r = s.rows[first + i];
            r.a = ids[2 * i];
            r.b = ids[2 * i + 1];
            r.n = normalize(Vec3{u(rng), u(rng), u(rng)});
            const Vec3 rA{u(rng), u(rng), u(rng)}, rB{u(rng), u(rng), u(rng)};
            r.rAxn = cross(rA, r.n);
            r.rBxn = cross(rB, r.n);
            const SolverBody& A = s.bodies[r.a];
            const SolverBody& B = s.bodies[r.b];
            const float k = A.invMass + B.invMass + A.invInertia * dot(r.rAxn, r.rAxn) + B.invInertia * dot(r.rBxn, r.rBxn);
            r.effectiveMass = 1.0f / k;
            r.bias = 0.1f * u(rng);
        }
    }
    return s;
}

}  // namespace fulcrum::test
