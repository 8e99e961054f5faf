#include "particles/xpbd_distance.hpp"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <type_traits>

#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#define FULCRUM_PARTICLES_SSE2 1
#else
#define FULCRUM_PARTICLES_SSE2 0
#endif

namespace fulcrum::detail {

namespace {

// Below this squared length the two particles coincide: no direction to push along.
constexpr Real kCoincident2 = Real(1e-24);

// How the 4 lanes of a chunk find their particles (DistanceBatches::layout_).
enum ChunkLayout : std::uint8_t {
    kGather = 0,       // anywhere: 8 scalar loads per coordinate
    kContiguous = 1,   // a0 + {0,1,2,3}, b0 + {0,1,2,3}: one load per coordinate and end
    kInterleaved = 2,  // a = a0 + {0,2,4,6}, b = a + 1 (a row's links): 8 floats from a0, 1 shuffle each
    kPairs = 3,        // a = a0 + {0,1,4,5}, b = a + 2 (a row's bend links): 8 floats from a0
};

// One constraint, scalar. The SIMD kernel below performs exactly these
// operations in the same order, so a lane's result is bit-identical to this.
// `FirstIteration`: lambda is 0 (every sub-step starts from 0), so it is
// neither read nor reset; with one iteration per sub-step (the default) that
// skips 8 bytes of memory traffic per constraint, and the reset.
template <bool FirstIteration>
inline void solveOne(ParticleSoA& p, std::uint32_t a, std::uint32_t b, Real rest, Real inverseDenominator,
                     Real alphaTilde, bool unilateral, Real& lambda) {
    const Real dx = p.x[a] - p.x[b], dy = p.y[a] - p.y[b], dz = p.z[a] - p.z[b];
    const Real len2 = dx * dx + dy * dy + dz * dz;
    if (len2 < kCoincident2) {
        if constexpr (FirstIteration) lambda = 0;
        return;
    }
    const Real len = std::sqrt(len2);
    const Real C = len - rest;
    if (unilateral && C <= 0) {  // a slack tether does nothing
        if constexpr (FirstIteration) lambda = 0;
        return;
    }
    const Real dLambda = (-C - alphaTilde * (FirstIteration ? Real(0) : lambda)) * inverseDenominator;
    lambda = FirstIteration ? dLambda : lambda + dLambda;
    const Real s = dLambda / len;
    const Real wa = p.w[a], wb = p.w[b];
    const Real nx = dx * s, ny = dy * s, nz = dz * s;
    p.x[a] += nx * wa; p.y[a] += ny * wa; p.z[a] += nz * wa;
    p.x[b] -= nx * wb; p.y[b] -= ny * wb; p.z[b] -= nz * wb;
}

#if FULCRUM_PARTICLES_SSE2
inline __m128 gather(const Real* v, const std::uint32_t* index) {
    return _mm_set_ps(v[index[3]], v[index[2]], v[index[1]], v[index[0]]);
}
inline void scatter(Real* v, const std::uint32_t* index, __m128 value) {
    alignas(16) float lanes[4];
    _mm_store_ps(lanes, value);
    v[index[0]] = lanes[0];
    v[index[1]] = lanes[1];
    v[index[2]] = lanes[2];
    v[index[3]] = lanes[3];
}

// Four independent constraints (one colour), slots k..k+3.
template <ChunkLayout Layout, bool FirstIteration>
inline void solveFour(ParticleSoA& p, const std::uint32_t* a, const std::uint32_t* b, const Real* rest,
                      const Real* inverseDenominator, Real* lambda, __m128 alphaTilde, bool unilateral) {
    __m128 ax, ay, az, bx, by, bz, wa, wb;
    const std::uint32_t a0 = a[0];
    // Split / merge an 8-float window [a0, a0 + 8) into the a and b lanes.
    const auto split = [](const Real* v, __m128& outA, __m128& outB) {
        const __m128 lo = _mm_loadu_ps(v), hi = _mm_loadu_ps(v + 4);
        if constexpr (Layout == kInterleaved) {
            outA = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0));
            outB = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(3, 1, 3, 1));
        } else {
            outA = _mm_movelh_ps(lo, hi);
            outB = _mm_movehl_ps(hi, lo);
        }
    };
    const auto merge = [](Real* v, __m128 inA, __m128 inB) {
        if constexpr (Layout == kInterleaved) {
            _mm_storeu_ps(v, _mm_unpacklo_ps(inA, inB));
            _mm_storeu_ps(v + 4, _mm_unpackhi_ps(inA, inB));
        } else {
            _mm_storeu_ps(v, _mm_movelh_ps(inA, inB));
            _mm_storeu_ps(v + 4, _mm_movehl_ps(inB, inA));
        }
    };
    if constexpr (Layout == kContiguous) {
        const std::uint32_t b0 = b[0];
        ax = _mm_loadu_ps(&p.x[a0]); ay = _mm_loadu_ps(&p.y[a0]); az = _mm_loadu_ps(&p.z[a0]);
        bx = _mm_loadu_ps(&p.x[b0]); by = _mm_loadu_ps(&p.y[b0]); bz = _mm_loadu_ps(&p.z[b0]);
        wa = _mm_loadu_ps(&p.w[a0]); wb = _mm_loadu_ps(&p.w[b0]);
    } else if constexpr (Layout == kInterleaved || Layout == kPairs) {
        split(&p.x[a0], ax, bx); split(&p.y[a0], ay, by); split(&p.z[a0], az, bz);
        split(&p.w[a0], wa, wb);
    } else {
        ax = gather(p.x.data(), a); ay = gather(p.y.data(), a); az = gather(p.z.data(), a);
        bx = gather(p.x.data(), b); by = gather(p.y.data(), b); bz = gather(p.z.data(), b);
        wa = gather(p.w.data(), a); wb = gather(p.w.data(), b);
    }
    const __m128 dx = _mm_sub_ps(ax, bx), dy = _mm_sub_ps(ay, by), dz = _mm_sub_ps(az, bz);
    const __m128 len2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
    __m128 valid = _mm_cmpge_ps(len2, _mm_set1_ps(kCoincident2));
    const __m128 len = _mm_sqrt_ps(len2);
    const __m128 C = _mm_sub_ps(len, _mm_loadu_ps(rest));
    if (unilateral) valid = _mm_and_ps(valid, _mm_cmpgt_ps(C, _mm_setzero_ps()));
    const __m128 oldLambda = FirstIteration ? _mm_setzero_ps() : _mm_loadu_ps(lambda);
    const __m128 negC = _mm_xor_ps(C, _mm_set1_ps(-0.0f));  // exact negation, as the scalar -C
    __m128 dLambda = _mm_mul_ps(_mm_sub_ps(negC, _mm_mul_ps(alphaTilde, oldLambda)), _mm_loadu_ps(inverseDenominator));
    dLambda = _mm_and_ps(valid, dLambda);
    _mm_storeu_ps(lambda, FirstIteration ? dLambda : _mm_add_ps(oldLambda, dLambda));
    // Invalid lanes divide 0 by 1: they move nothing.
    const __m128 safeLen = _mm_or_ps(_mm_and_ps(valid, len), _mm_andnot_ps(valid, _mm_set1_ps(1)));
    const __m128 s = _mm_div_ps(dLambda, safeLen);
    const __m128 nx = _mm_mul_ps(dx, s), ny = _mm_mul_ps(dy, s), nz = _mm_mul_ps(dz, s);
    ax = _mm_add_ps(ax, _mm_mul_ps(nx, wa)); ay = _mm_add_ps(ay, _mm_mul_ps(ny, wa)); az = _mm_add_ps(az, _mm_mul_ps(nz, wa));
    bx = _mm_sub_ps(bx, _mm_mul_ps(nx, wb)); by = _mm_sub_ps(by, _mm_mul_ps(ny, wb)); bz = _mm_sub_ps(bz, _mm_mul_ps(nz, wb));
    if constexpr (Layout == kContiguous) {
        const std::uint32_t b0 = b[0];
        _mm_storeu_ps(&p.x[a0], ax); _mm_storeu_ps(&p.y[a0], ay); _mm_storeu_ps(&p.z[a0], az);
        _mm_storeu_ps(&p.x[b0], bx); _mm_storeu_ps(&p.y[b0], by); _mm_storeu_ps(&p.z[b0], bz);
    } else if constexpr (Layout == kInterleaved || Layout == kPairs) {
        merge(&p.x[a0], ax, bx); merge(&p.y[a0], ay, by); merge(&p.z[a0], az, bz);
    } else {
        scatter(p.x.data(), a, ax); scatter(p.y.data(), a, ay); scatter(p.z.data(), a, az);
        scatter(p.x.data(), b, bx); scatter(p.y.data(), b, by); scatter(p.z.data(), b, bz);
    }
}
#endif

}  // namespace

void DistanceBatches::rebuild(const DistanceConstraintGroup& group, DistanceOrder order) {
    source_ = group.constraints;
    order_ = order;
    const std::size_t count = source_.size();
    struct Entry {
        std::uint32_t lo, hi, offset, parity, index;
    };
    std::vector<Entry> entries;
    entries.reserve(count);
    std::vector<std::uint32_t> sequential;
    std::uint32_t particleCount = 0;
    for (std::uint32_t g = 0; g < count; ++g) {
        const DistanceConstraint& c = source_[g];
        particleCount = std::max(particleCount, std::max(c.a, c.b) + 1);
        if (c.a == c.b || order != DistanceOrder::Coloured) {
            sequential.push_back(g);
            continue;
        }
        const std::uint32_t lo = std::min(c.a, c.b), hi = std::max(c.a, c.b), d = hi - lo;
        entries.push_back({lo, hi, d, (lo / d) & 1u, g});
    }
    std::sort(entries.begin(), entries.end(), [](const Entry& l, const Entry& r) {
        if (l.offset != r.offset) return l.offset < r.offset;
        if (l.parity != r.parity) return l.parity < r.parity;
        if (l.lo != r.lo) return l.lo < r.lo;
        return l.index < r.index;
    });

    a_.clear(); b_.clear(); sourceIndex_.clear(); colourStart_.clear();
    // A colour must not touch a particle twice; `stamp` marks the particles of
    // the colour being filled (duplicates go to the sequential list).
    std::vector<std::uint32_t> stamp(particleCount, 0);
    std::uint32_t colour = 0;
    for (std::size_t e = 0; e < entries.size();) {
        std::size_t end = e;
        while (end < entries.size() && entries[end].offset == entries[e].offset && entries[end].parity == entries[e].parity) ++end;
        ++colour;
        colourStart_.push_back(a_.size());
        for (std::size_t k = e; k < end; ++k) {
            const Entry& en = entries[k];
            if (stamp[en.lo] == colour || stamp[en.hi] == colour) {
                sequential.push_back(en.index);
                continue;
            }
            stamp[en.lo] = stamp[en.hi] = colour;
            // Keep the group's orientation (a, b): the update is symmetric,
            // but this keeps lambda's sign as the group defines it.
            a_.push_back(source_[en.index].a);
            b_.push_back(source_[en.index].b);
            sourceIndex_.push_back(en.index);
        }
        if (colourStart_.back() == a_.size()) colourStart_.pop_back();  // all went sequential
        e = end;
    }
    sequentialBegin_ = a_.size();
    colourStart_.push_back(sequentialBegin_);
    std::sort(sequential.begin(), sequential.end());  // in the group's order
    if (order == DistanceOrder::Backward) std::reverse(sequential.begin(), sequential.end());
    for (std::uint32_t g : sequential) {
        a_.push_back(source_[g].a);
        b_.push_back(source_[g].b);
        sourceIndex_.push_back(g);
    }
    const std::size_t slots = a_.size();
    rest_.resize(slots);
    inverseDenominator_.resize(slots);
    lambda_.assign(slots, 0);
    layout_.assign(slots, 0);
    const auto matches = [&](std::size_t k, const std::uint32_t (&da)[4], std::uint32_t offset, bool fixedOffset) {
        for (std::size_t i = 0; i < 4; ++i) {
            if (a_[k + i] != a_[k] + da[i]) return false;
            const std::uint32_t expectedB = fixedOffset ? a_[k + i] + offset : b_[k] + da[i];
            if (b_[k + i] != expectedB) return false;
        }
        return true;
    };
    static constexpr std::uint32_t kRun[4] = {0, 1, 2, 3}, kEven[4] = {0, 2, 4, 6}, kPair[4] = {0, 1, 4, 5};
    for (std::size_t c = 0; c + 1 < colourStart_.size(); ++c) {
        for (std::size_t k = colourStart_[c]; k + 4 <= colourStart_[c + 1]; k += 4) {
            if (matches(k, kRun, 0, false)) layout_[k] = kContiguous;
            else if (matches(k, kEven, 1, true)) layout_[k] = kInterleaved;
            else if (matches(k, kPair, 2, true)) layout_[k] = kPairs;
            else layout_[k] = kGather;
        }
    }
}

void DistanceBatches::prepare(const DistanceConstraintGroup& group, const std::vector<Real>& inverseMass, Real substep,
                              DistanceOrder order) {
    bool same = group.constraints.size() == source_.size() && !colourStart_.empty() && order == order_;
    for (std::size_t g = 0; same && g < source_.size(); ++g) {
        same = group.constraints[g].a == source_[g].a && group.constraints[g].b == source_[g].b;
    }
    if (!same) rebuild(group, order);
    unilateral_ = group.unilateral;
    alphaTilde_ = group.compliance / (substep * substep);
    for (std::size_t k = 0; k < a_.size(); ++k) {
        rest_[k] = group.constraints[sourceIndex_[k]].restLength;
        const Real denominator = inverseMass[a_[k]] + inverseMass[b_[k]] + alphaTilde_;
        inverseDenominator_[k] = denominator > 0 ? 1 / denominator : 0;  // 0: both ends immovable
    }
}

template <bool FirstIteration>
void DistanceBatches::solveRange(ParticleSoA& p, std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
        solveOne<FirstIteration>(p, a_[k], b_[k], rest_[k], inverseDenominator_[k], alphaTilde_, unilateral_, lambda_[k]);
    }
}

void DistanceBatches::solve(ParticleSoA& p, bool firstIteration) {
    if (firstIteration) sweep<true>(p);
    else sweep<false>(p);
}

template <bool FirstIteration>
void DistanceBatches::sweep(ParticleSoA& p) {
    for (std::size_t c = 0; c + 1 < colourStart_.size(); ++c) {
        const std::size_t begin = colourStart_[c], end = colourStart_[c + 1];
        std::size_t k = begin;
#if FULCRUM_PARTICLES_SSE2
        const __m128 alphaTilde = _mm_set1_ps(alphaTilde_);
        for (; k + 4 <= end; k += 4) {
            const auto args = std::make_tuple(&a_[k], &b_[k], &rest_[k], &inverseDenominator_[k], &lambda_[k]);
            const auto run = [&](auto layout) {
                solveFour<decltype(layout)::value, FirstIteration>(p, std::get<0>(args), std::get<1>(args), std::get<2>(args),
                                                   std::get<3>(args), std::get<4>(args), alphaTilde, unilateral_);
            };
            switch (layout_[k]) {
                case kContiguous: run(std::integral_constant<ChunkLayout, kContiguous>{}); break;
                case kInterleaved: run(std::integral_constant<ChunkLayout, kInterleaved>{}); break;
                case kPairs: run(std::integral_constant<ChunkLayout, kPairs>{}); break;
                default: run(std::integral_constant<ChunkLayout, kGather>{}); break;
            }
        }
#endif
        solveRange<FirstIteration>(p, k, end);
    }
    solveRange<FirstIteration>(p, sequentialBegin_, a_.size());
}

}  // namespace fulcrum::detail
