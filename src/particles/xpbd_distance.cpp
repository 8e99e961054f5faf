#include "particles/xpbd_distance.hpp"

#include <algorithm>
#include <cmath>
#include <type_traits>

#if (defined(__SSE2__) || defined(_M_X64)) && !FULCRUM_DOUBLE  // float lanes: the double build runs the scalar loop
#include <immintrin.h>
#define FULCRUM_PARTICLES_SSE2 1
#else
#define FULCRUM_PARTICLES_SSE2 0
#endif
// The 8-wide kernel is compiled for AVX2 with a function attribute and chosen
// at run time, so the portable default build (-march=x86-64, SSE2) uses it on
// every CPU that has it. Same results either way: lanes are independent
// constraints of one colour, each computing the scalar formula.
#if FULCRUM_PARTICLES_SSE2 && defined(__GNUC__) && (defined(__x86_64__) || defined(__i386__))
#define FULCRUM_PARTICLES_AVX2 1
#define FULCRUM_AVX2_TARGET __attribute__((target("avx2")))
#else
#define FULCRUM_PARTICLES_AVX2 0
#endif

namespace fulcrum::detail {

namespace {

// Below this squared length the two particles coincide: no direction to push along.
constexpr Real kCoincident2 = Real(1e-24);

// How the lanes of a chunk find their particles (DistanceBatches::layout_).
// Offsets are for 4 lanes; 8 lanes continue the pattern (see rebuild).
enum ChunkLayout : std::uint8_t {
    kGather = 0,       // anywhere: one scalar load per lane, coordinate and end
    kContiguous = 1,   // a0 + {0,1,2,3}, b0 + {0,1,2,3}: one load per coordinate and end
    kInterleaved = 2,  // a = a0 + {0,2,4,6}, b = a + 1 (a row's links): 8 floats from a0, 1 shuffle each
    kPairs = 3,        // a = a0 + {0,1,4,5}, b = a + 2 (a row's bend links): 8 floats from a0
};

int detectedLanes() {
#if FULCRUM_PARTICLES_AVX2
    if (__builtin_cpu_supports("avx2")) return 8;
#endif
#if FULCRUM_PARTICLES_SSE2
    return 4;
#else
    return 1;
#endif
}
int gLanesOverride = 0;

// One constraint, scalar. The SIMD kernels below perform exactly these
// operations in the same order, so a lane's result is bit-identical to this.
// `First`: lambda is 0 (every sub-step starts from 0), so it is not read.
// `Keep`: a later iteration reads lambda, so store it; with one iteration per
// sub-step (the default) neither happens: 8 bytes less traffic per constraint.
template <bool First, bool Keep>
inline void solveOne(ParticleSoA& p, std::uint32_t a, std::uint32_t b, Real rest, Real inverseDenominator,
                     Real alphaTilde, bool unilateral, Real& lambda) {
    const Real dx = p.x[a] - p.x[b], dy = p.y[a] - p.y[b], dz = p.z[a] - p.z[b];
    const Real len2 = dx * dx + dy * dy + dz * dz;
    if (len2 < kCoincident2) {
        if constexpr (First && Keep) lambda = 0;
        return;
    }
    const Real len = std::sqrt(len2);
    const Real C = len - rest;
    if (unilateral && C <= 0) {  // a slack tether does nothing
        if constexpr (First && Keep) lambda = 0;
        return;
    }
    const Real dLambda = (-C - alphaTilde * (First ? Real(0) : lambda)) * inverseDenominator;
    if constexpr (Keep) lambda = First ? dLambda : lambda + dLambda;
    const Real s = dLambda / len;
    const Real wa = p.w[a], wb = p.w[b];
    const Real nx = dx * s, ny = dy * s, nz = dz * s;
    p.x[a] += nx * wa; p.y[a] += ny * wa; p.z[a] += nz * wa;
    p.x[b] -= nx * wb; p.y[b] -= ny * wb; p.z[b] -= nz * wb;
}

// The slots of one sweep, handed to the SIMD kernels.
struct SlotArrays {
    const std::uint32_t* a;
    const std::uint32_t* b;
    const Real* rest;
    const Real* inverseDenominator;
    Real* lambda;
    const std::uint8_t* layout;
    Real alphaTilde;
    bool unilateral;
};

#if FULCRUM_PARTICLES_SSE2
inline __m128 gather4(const Real* v, const std::uint32_t* index) {
    return _mm_set_ps(v[index[3]], v[index[2]], v[index[1]], v[index[0]]);
}
inline void scatter4(Real* v, const std::uint32_t* index, __m128 value) {
    alignas(16) float lanes[4];
    _mm_store_ps(lanes, value);
    for (int i = 0; i < 4; ++i) v[index[i]] = lanes[i];
}
// Split / merge an 8-float window [a0, a0 + 8) into the a and b lanes.
template <ChunkLayout Layout>
inline void split4(const Real* v, __m128& outA, __m128& outB) {
    const __m128 lo = _mm_loadu_ps(v), hi = _mm_loadu_ps(v + 4);
    if constexpr (Layout == kInterleaved) {
        outA = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0));
        outB = _mm_shuffle_ps(lo, hi, _MM_SHUFFLE(3, 1, 3, 1));
    } else {
        outA = _mm_movelh_ps(lo, hi);
        outB = _mm_movehl_ps(hi, lo);
    }
}
template <ChunkLayout Layout>
inline void merge4(Real* v, __m128 inA, __m128 inB) {
    if constexpr (Layout == kInterleaved) {
        _mm_storeu_ps(v, _mm_unpacklo_ps(inA, inB));
        _mm_storeu_ps(v + 4, _mm_unpackhi_ps(inA, inB));
    } else {
        _mm_storeu_ps(v, _mm_movelh_ps(inA, inB));
        _mm_storeu_ps(v + 4, _mm_movehl_ps(inB, inA));
    }
}

// Four independent constraints (one colour), slots k..k+3.
template <ChunkLayout Layout, bool First, bool Keep>
inline void solveFour(ParticleSoA& p, const SlotArrays& s, std::size_t k) {
    const std::uint32_t* a = s.a + k;
    const std::uint32_t* b = s.b + k;
    __m128 ax, ay, az, bx, by, bz, wa, wb;
    const std::uint32_t a0 = a[0];
    if constexpr (Layout == kContiguous) {
        const std::uint32_t b0 = b[0];
        ax = _mm_loadu_ps(&p.x[a0]); ay = _mm_loadu_ps(&p.y[a0]); az = _mm_loadu_ps(&p.z[a0]);
        bx = _mm_loadu_ps(&p.x[b0]); by = _mm_loadu_ps(&p.y[b0]); bz = _mm_loadu_ps(&p.z[b0]);
        wa = _mm_loadu_ps(&p.w[a0]); wb = _mm_loadu_ps(&p.w[b0]);
    } else if constexpr (Layout == kInterleaved || Layout == kPairs) {
        split4<Layout>(&p.x[a0], ax, bx); split4<Layout>(&p.y[a0], ay, by); split4<Layout>(&p.z[a0], az, bz);
        split4<Layout>(&p.w[a0], wa, wb);
    } else {
        ax = gather4(p.x.data(), a); ay = gather4(p.y.data(), a); az = gather4(p.z.data(), a);
        bx = gather4(p.x.data(), b); by = gather4(p.y.data(), b); bz = gather4(p.z.data(), b);
        wa = gather4(p.w.data(), a); wb = gather4(p.w.data(), b);
    }
    const __m128 dx = _mm_sub_ps(ax, bx), dy = _mm_sub_ps(ay, by), dz = _mm_sub_ps(az, bz);
    const __m128 len2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(dx, dx), _mm_mul_ps(dy, dy)), _mm_mul_ps(dz, dz));
    __m128 valid = _mm_cmpge_ps(len2, _mm_set1_ps(kCoincident2));
    const __m128 len = _mm_sqrt_ps(len2);
    const __m128 C = _mm_sub_ps(len, _mm_loadu_ps(s.rest + k));
    if (s.unilateral) valid = _mm_and_ps(valid, _mm_cmpgt_ps(C, _mm_setzero_ps()));
    const __m128 oldLambda = First ? _mm_setzero_ps() : _mm_loadu_ps(s.lambda + k);
    const __m128 negC = _mm_xor_ps(C, _mm_set1_ps(-0.0f));  // exact negation, as the scalar -C
    __m128 dLambda = _mm_mul_ps(_mm_sub_ps(negC, _mm_mul_ps(_mm_set1_ps(s.alphaTilde), oldLambda)),
                                _mm_loadu_ps(s.inverseDenominator + k));
    dLambda = _mm_and_ps(valid, dLambda);
    if constexpr (Keep) _mm_storeu_ps(s.lambda + k, First ? dLambda : _mm_add_ps(oldLambda, dLambda));
    // Invalid lanes divide 0 by 1: they move nothing.
    const __m128 safeLen = _mm_or_ps(_mm_and_ps(valid, len), _mm_andnot_ps(valid, _mm_set1_ps(1)));
    const __m128 sc = _mm_div_ps(dLambda, safeLen);
    const __m128 nx = _mm_mul_ps(dx, sc), ny = _mm_mul_ps(dy, sc), nz = _mm_mul_ps(dz, sc);
    ax = _mm_add_ps(ax, _mm_mul_ps(nx, wa)); ay = _mm_add_ps(ay, _mm_mul_ps(ny, wa)); az = _mm_add_ps(az, _mm_mul_ps(nz, wa));
    bx = _mm_sub_ps(bx, _mm_mul_ps(nx, wb)); by = _mm_sub_ps(by, _mm_mul_ps(ny, wb)); bz = _mm_sub_ps(bz, _mm_mul_ps(nz, wb));
    if constexpr (Layout == kContiguous) {
        const std::uint32_t b0 = b[0];
        _mm_storeu_ps(&p.x[a0], ax); _mm_storeu_ps(&p.y[a0], ay); _mm_storeu_ps(&p.z[a0], az);
        _mm_storeu_ps(&p.x[b0], bx); _mm_storeu_ps(&p.y[b0], by); _mm_storeu_ps(&p.z[b0], bz);
    } else if constexpr (Layout == kInterleaved || Layout == kPairs) {
        merge4<Layout>(&p.x[a0], ax, bx); merge4<Layout>(&p.y[a0], ay, by); merge4<Layout>(&p.z[a0], az, bz);
    } else {
        scatter4(p.x.data(), a, ax); scatter4(p.y.data(), a, ay); scatter4(p.z.data(), a, az);
        scatter4(p.x.data(), b, bx); scatter4(p.y.data(), b, by); scatter4(p.z.data(), b, bz);
    }
}

// Chunks of 4 of the colour [begin, end); returns where the scalar tail starts.
template <bool First, bool Keep>
std::size_t solveChunksOfFour(ParticleSoA& p, const SlotArrays& s, std::size_t begin, std::size_t end) {
    std::size_t k = begin;
    for (; k + 4 <= end; k += 4) {
        switch (s.layout[k]) {
            case kContiguous: solveFour<kContiguous, First, Keep>(p, s, k); break;
            case kInterleaved: solveFour<kInterleaved, First, Keep>(p, s, k); break;
            case kPairs: solveFour<kPairs, First, Keep>(p, s, k); break;
            default: solveFour<kGather, First, Keep>(p, s, k); break;
        }
    }
    return k;
}
#endif

#if FULCRUM_PARTICLES_AVX2
// 8 lanes. AVX shuffles work within each 128-bit half, so the 16-float
// window of an interleaved or pairs chunk splits into lanes in the order
// of constraints {0, 1, 4, 5 | 2, 3, 6, 7}; rebuild() stores those chunks'
// slots in that order, so no cross-half permute is needed.
FULCRUM_AVX2_TARGET inline __m256 gather8(const Real* v, const std::uint32_t* index) {
    return _mm256_set_ps(v[index[7]], v[index[6]], v[index[5]], v[index[4]], v[index[3]], v[index[2]], v[index[1]],
                         v[index[0]]);
}
FULCRUM_AVX2_TARGET inline void scatter8(Real* v, const std::uint32_t* index, __m256 value) {
    alignas(32) float lanes[8];
    _mm256_store_ps(lanes, value);
    for (int i = 0; i < 8; ++i) v[index[i]] = lanes[i];
}
template <ChunkLayout Layout>
FULCRUM_AVX2_TARGET inline void split8(const Real* v, __m256& outA, __m256& outB) {
    const __m256 lo = _mm256_loadu_ps(v), hi = _mm256_loadu_ps(v + 8);
    if constexpr (Layout == kInterleaved) {
        outA = _mm256_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0));
        outB = _mm256_shuffle_ps(lo, hi, _MM_SHUFFLE(3, 1, 3, 1));
    } else {
        outA = _mm256_shuffle_ps(lo, hi, _MM_SHUFFLE(1, 0, 1, 0));
        outB = _mm256_shuffle_ps(lo, hi, _MM_SHUFFLE(3, 2, 3, 2));
    }
}
template <ChunkLayout Layout>
FULCRUM_AVX2_TARGET inline void merge8(Real* v, __m256 inA, __m256 inB) {
    if constexpr (Layout == kInterleaved) {
        _mm256_storeu_ps(v, _mm256_unpacklo_ps(inA, inB));
        _mm256_storeu_ps(v + 8, _mm256_unpackhi_ps(inA, inB));
    } else {
        _mm256_storeu_ps(v, _mm256_shuffle_ps(inA, inB, _MM_SHUFFLE(1, 0, 1, 0)));
        _mm256_storeu_ps(v + 8, _mm256_shuffle_ps(inA, inB, _MM_SHUFFLE(3, 2, 3, 2)));
    }
}

template <ChunkLayout Layout, bool First, bool Keep>
FULCRUM_AVX2_TARGET inline void solveEight(ParticleSoA& p, const SlotArrays& s, std::size_t k) {
    const std::uint32_t* a = s.a + k;
    const std::uint32_t* b = s.b + k;
    __m256 ax, ay, az, bx, by, bz, wa, wb;
    const std::uint32_t a0 = a[0];
    if constexpr (Layout == kContiguous) {
        const std::uint32_t b0 = b[0];
        ax = _mm256_loadu_ps(&p.x[a0]); ay = _mm256_loadu_ps(&p.y[a0]); az = _mm256_loadu_ps(&p.z[a0]);
        bx = _mm256_loadu_ps(&p.x[b0]); by = _mm256_loadu_ps(&p.y[b0]); bz = _mm256_loadu_ps(&p.z[b0]);
        wa = _mm256_loadu_ps(&p.w[a0]); wb = _mm256_loadu_ps(&p.w[b0]);
    } else if constexpr (Layout == kInterleaved || Layout == kPairs) {
        split8<Layout>(&p.x[a0], ax, bx); split8<Layout>(&p.y[a0], ay, by); split8<Layout>(&p.z[a0], az, bz);
        split8<Layout>(&p.w[a0], wa, wb);
    } else {
        ax = gather8(p.x.data(), a); ay = gather8(p.y.data(), a); az = gather8(p.z.data(), a);
        bx = gather8(p.x.data(), b); by = gather8(p.y.data(), b); bz = gather8(p.z.data(), b);
        wa = gather8(p.w.data(), a); wb = gather8(p.w.data(), b);
    }
    const __m256 dx = _mm256_sub_ps(ax, bx), dy = _mm256_sub_ps(ay, by), dz = _mm256_sub_ps(az, bz);
    const __m256 len2 = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(dx, dx), _mm256_mul_ps(dy, dy)), _mm256_mul_ps(dz, dz));
    __m256 valid = _mm256_cmp_ps(len2, _mm256_set1_ps(kCoincident2), _CMP_GE_OQ);
    const __m256 len = _mm256_sqrt_ps(len2);
    const __m256 C = _mm256_sub_ps(len, _mm256_loadu_ps(s.rest + k));
    if (s.unilateral) valid = _mm256_and_ps(valid, _mm256_cmp_ps(C, _mm256_setzero_ps(), _CMP_GT_OQ));
    const __m256 oldLambda = First ? _mm256_setzero_ps() : _mm256_loadu_ps(s.lambda + k);
    const __m256 negC = _mm256_xor_ps(C, _mm256_set1_ps(-0.0f));
    __m256 dLambda = _mm256_mul_ps(_mm256_sub_ps(negC, _mm256_mul_ps(_mm256_set1_ps(s.alphaTilde), oldLambda)),
                                   _mm256_loadu_ps(s.inverseDenominator + k));
    dLambda = _mm256_and_ps(valid, dLambda);
    if constexpr (Keep) _mm256_storeu_ps(s.lambda + k, First ? dLambda : _mm256_add_ps(oldLambda, dLambda));
    const __m256 safeLen = _mm256_blendv_ps(_mm256_set1_ps(1), len, valid);
    const __m256 sc = _mm256_div_ps(dLambda, safeLen);
    const __m256 nx = _mm256_mul_ps(dx, sc), ny = _mm256_mul_ps(dy, sc), nz = _mm256_mul_ps(dz, sc);
    ax = _mm256_add_ps(ax, _mm256_mul_ps(nx, wa)); ay = _mm256_add_ps(ay, _mm256_mul_ps(ny, wa));
    az = _mm256_add_ps(az, _mm256_mul_ps(nz, wa));
    bx = _mm256_sub_ps(bx, _mm256_mul_ps(nx, wb)); by = _mm256_sub_ps(by, _mm256_mul_ps(ny, wb));
    bz = _mm256_sub_ps(bz, _mm256_mul_ps(nz, wb));
    if constexpr (Layout == kContiguous) {
        const std::uint32_t b0 = b[0];
        _mm256_storeu_ps(&p.x[a0], ax); _mm256_storeu_ps(&p.y[a0], ay); _mm256_storeu_ps(&p.z[a0], az);
        _mm256_storeu_ps(&p.x[b0], bx); _mm256_storeu_ps(&p.y[b0], by); _mm256_storeu_ps(&p.z[b0], bz);
    } else if constexpr (Layout == kInterleaved || Layout == kPairs) {
        merge8<Layout>(&p.x[a0], ax, bx); merge8<Layout>(&p.y[a0], ay, by); merge8<Layout>(&p.z[a0], az, bz);
    } else {
        scatter8(p.x.data(), a, ax); scatter8(p.y.data(), a, ay); scatter8(p.z.data(), a, az);
        scatter8(p.x.data(), b, bx); scatter8(p.y.data(), b, by); scatter8(p.z.data(), b, bz);
    }
}

template <bool First, bool Keep>
FULCRUM_AVX2_TARGET std::size_t solveChunksOfEight(ParticleSoA& p, const SlotArrays& s, std::size_t begin, std::size_t end) {
    std::size_t k = begin;
    for (; k + 8 <= end; k += 8) {
        switch (s.layout[k]) {
            case kContiguous: solveEight<kContiguous, First, Keep>(p, s, k); break;
            case kInterleaved: solveEight<kInterleaved, First, Keep>(p, s, k); break;
            case kPairs: solveEight<kPairs, First, Keep>(p, s, k); break;
            default: solveEight<kGather, First, Keep>(p, s, k); break;
        }
    }
    return k;
}
#endif

}  // namespace

int distanceSimdLanes() { return gLanesOverride > 0 ? gLanesOverride : detectedLanes(); }

void setDistanceSimdLanes(int lanes) {
    const int best = detectedLanes();
    gLanesOverride = lanes <= 0 ? 0 : (lanes >= 8 ? std::min(8, best) : (lanes >= 4 ? std::min(4, best) : 1));
}

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
    // Chunk layouts for the lane count of this machine (distanceSimdLanes()).
    lanes_ = static_cast<std::uint8_t>(distanceSimdLanes());
    const std::size_t lanes = lanes_;
    const auto matches = [&](std::size_t k, auto offsetOfLane, std::uint32_t bOffset, bool fixedOffset) {
        for (std::size_t i = 0; i < lanes; ++i) {
            const std::uint32_t da = offsetOfLane(i);
            if (a_[k + i] != a_[k] + da) return false;
            const std::uint32_t expectedB = fixedOffset ? a_[k + i] + bOffset : b_[k] + da;
            if (b_[k + i] != expectedB) return false;
        }
        return true;
    };
    const auto run = [](std::size_t i) { return static_cast<std::uint32_t>(i); };
    const auto even = [](std::size_t i) { return static_cast<std::uint32_t>(2 * i); };
    const auto pairs = [](std::size_t i) { return static_cast<std::uint32_t>((i / 2) * 4 + (i % 2)); };  // 0,1,4,5,8,9,...
    // 8-lane windows come out of the shuffles as constraints {0,1,4,5,2,3,6,7}.
    static constexpr std::size_t kHalves[8] = {0, 1, 4, 5, 2, 3, 6, 7};
    for (std::size_t c = 0; lanes > 1 && c + 1 < colourStart_.size(); ++c) {
        for (std::size_t k = colourStart_[c]; k + lanes <= colourStart_[c + 1]; k += lanes) {
            if (matches(k, run, 0, false)) layout_[k] = kContiguous;
            else if (matches(k, even, 1, true)) layout_[k] = kInterleaved;
            else if (matches(k, pairs, 2, true)) layout_[k] = kPairs;
            else layout_[k] = kGather;
            if (lanes == 8 && (layout_[k] == kInterleaved || layout_[k] == kPairs)) {
                std::uint32_t a[8], b[8], src[8];
                for (std::size_t i = 0; i < 8; ++i) {
                    a[i] = a_[k + kHalves[i]];
                    b[i] = b_[k + kHalves[i]];
                    src[i] = sourceIndex_[k + kHalves[i]];
                }
                for (std::size_t i = 0; i < 8; ++i) {
                    a_[k + i] = a[i];
                    b_[k + i] = b[i];
                    sourceIndex_[k + i] = src[i];
                }
            }
        }
    }
}

void DistanceBatches::prepare(const DistanceConstraintGroup& group, const std::vector<Real>& inverseMass, Real substep,
                              DistanceOrder order) {
    bool same = group.constraints.size() == source_.size() && !colourStart_.empty() && order == order_ &&
                lanes_ == distanceSimdLanes();
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

template <bool First, bool Keep>
void DistanceBatches::solveRange(ParticleSoA& p, std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
        solveOne<First, Keep>(p, a_[k], b_[k], rest_[k], inverseDenominator_[k], alphaTilde_, unilateral_, lambda_[k]);
    }
}

void DistanceBatches::solve(ParticleSoA& p, bool firstIteration, bool lastIteration) {
    if (firstIteration) {
        if (lastIteration) sweep<true, false>(p);
        else sweep<true, true>(p);
    } else {
        sweep<false, true>(p);
    }
}

// Slots [begin, end) of one colour: whole chunks of lanes_ in SIMD lanes from
// `begin`, then the rest one by one.
template <bool First, bool Keep>
void DistanceBatches::solveColourRange(ParticleSoA& p, std::size_t begin, std::size_t end) {
    [[maybe_unused]] const SlotArrays slots{a_.data(), b_.data(), rest_.data(), inverseDenominator_.data(),
                                            lambda_.data(), layout_.data(), alphaTilde_, unilateral_};
    std::size_t k = begin;
#if FULCRUM_PARTICLES_AVX2
    if (lanes_ == 8) k = solveChunksOfEight<First, Keep>(p, slots, begin, end);
#endif
#if FULCRUM_PARTICLES_SSE2
    if (lanes_ == 4) k = solveChunksOfFour<First, Keep>(p, slots, begin, end);
#endif
    solveRange<First, Keep>(p, k, end);
}

template <bool First, bool Keep>
void DistanceBatches::sweep(ParticleSoA& p) {
    for (std::size_t c = 0; c + 1 < colourStart_.size(); ++c) solveColourRange<First, Keep>(p, colourStart_[c], colourStart_[c + 1]);
    solveRange<First, Keep>(p, sequentialBegin_, a_.size());
}

namespace {
constexpr std::uint32_t kSequentialStage = UINT32_MAX;
}

void DistanceBatches::addSweepStages(StagedParallel& stages, std::uint32_t kind) const {
    const std::size_t lanes = lanes_ > 1 ? lanes_ : 1;
    for (std::size_t c = 0; c + 1 < colourStart_.size(); ++c) {
        const std::size_t n = colourStart_[c + 1] - colourStart_[c];
        const auto colour = static_cast<std::uint32_t>(c);
        if (n >= kParallelSlots) {
            stages.add(kind, colour, 0, static_cast<std::uint32_t>(n / lanes), kChunksPerUnit);
        } else {
            stages.add(kind, colour, 0, n > 0 ? 1 : 0, 1);
        }
    }
    if (sequentialBegin_ < a_.size()) stages.add(kind, kSequentialStage, 0, 1, 1);
}

// Units of a split colour are chunk ranges [first, last) counted from the
// colour's start, so every chunk starts where the serial sweep starts it (its
// layout_ entry is for that start); the unit with the last chunk also takes
// the colour's tail, as the serial sweep does.
template <bool First, bool Keep>
void DistanceBatches::runStage(ParticleSoA& p, std::uint32_t arg, std::uint32_t first, std::uint32_t last) {
    if (arg == kSequentialStage) {
        solveRange<First, Keep>(p, sequentialBegin_, a_.size());
        return;
    }
    const std::size_t begin = colourStart_[arg], end = colourStart_[arg + 1];
    if (end - begin < kParallelSlots) {
        solveColourRange<First, Keep>(p, begin, end);
        return;
    }
    const std::size_t lanes = lanes_ > 1 ? lanes_ : 1;
    const std::size_t chunks = (end - begin) / lanes;
    const std::size_t from = begin + first * lanes;
    const std::size_t to = last == chunks ? end : begin + last * lanes;
    solveColourRange<First, Keep>(p, from, to);
}

void DistanceBatches::runSweepStage(ParticleSoA& p, bool firstIteration, bool lastIteration, std::uint32_t arg,
                                    std::uint32_t first, std::uint32_t last) {
    if (firstIteration) {
        if (lastIteration) runStage<true, false>(p, arg, first, last);
        else runStage<true, true>(p, arg, first, last);
    } else {
        runStage<false, true>(p, arg, first, last);
    }
}

}  // namespace fulcrum::detail
