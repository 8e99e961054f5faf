// The hull support search in eight lanes, over the hull's coordinate rows
// (ConvexHull::vertexRows). CMakeLists.txt compiles this file alone with
// -mavx2 (never -mfma: each dot must round as the scalar dot does), and
// support.cpp calls it only where the CPU has AVX2.
#include "collision/support.hpp"

#if defined(__AVX2__) && !FULCRUM_DOUBLE
#include <immintrin.h>

namespace fulcrum::detail {

bool hullSupportAvx2Compiled() { return true; }

// Each lane scans its own vertices (i = lane mod 8) in order, keeping the
// first of its largest dots, as the scalar scan does; the lanes' winners are
// then merged by value, then by the smaller index, and the last n mod 8
// vertices (later than every lane's) win only when strictly larger: the
// scalar scan's answer, bit for bit (the dot is (x dx + y dy) + z dz in both).
std::uint32_t hullSupportIndexAvx2(const float* x, const float* y, const float* z, std::uint32_t n, const Vec3& d) {
    const std::uint32_t blocks = n / 8;
    const __m256 dx = _mm256_set1_ps(d.x), dy = _mm256_set1_ps(d.y), dz = _mm256_set1_ps(d.z);
    const auto dots = [&](std::uint32_t at) {
        const __m256 px = _mm256_mul_ps(_mm256_loadu_ps(x + at), dx);
        const __m256 py = _mm256_mul_ps(_mm256_loadu_ps(y + at), dy);
        const __m256 pz = _mm256_mul_ps(_mm256_loadu_ps(z + at), dz);
        return _mm256_add_ps(_mm256_add_ps(px, py), pz);
    };
    __m256 best = dots(0);
    __m256 nan = _mm256_cmp_ps(best, best, _CMP_UNORD_Q);
    __m256i bestIndex = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7), index = bestIndex;
    const __m256i eight = _mm256_set1_epi32(8);
    for (std::uint32_t b = 1; b < blocks; ++b) {
        index = _mm256_add_epi32(index, eight);
        const __m256 dd = dots(8 * b);
        nan = _mm256_or_ps(nan, _mm256_cmp_ps(dd, dd, _CMP_UNORD_Q));
        const __m256 larger = _mm256_cmp_ps(dd, best, _CMP_GT_OQ);
        best = _mm256_max_ps(dd, best);  // dd > best ? dd : best, NaN-free when it counts
        bestIndex = _mm256_castps_si256(
            _mm256_blendv_ps(_mm256_castsi256_ps(bestIndex), _mm256_castsi256_ps(index), larger));
    }
    if (_mm256_movemask_ps(nan) != 0) return n;  // the caller's scalar scan decides
    // The merge in registers: the largest value over the lanes, then the
    // smallest index among the lanes that hold it (== takes -0 and +0 alike,
    // as the scan's > does). A loop over the stored lanes cost a 10-point
    // rock's search 30 of its instructions.
    __m256 top8 = _mm256_max_ps(best, _mm256_permute2f128_ps(best, best, 1));
    top8 = _mm256_max_ps(top8, _mm256_shuffle_ps(top8, top8, _MM_SHUFFLE(1, 0, 3, 2)));
    top8 = _mm256_max_ps(top8, _mm256_shuffle_ps(top8, top8, _MM_SHUFFLE(2, 3, 0, 1)));
    const __m256i tied = _mm256_castps_si256(_mm256_cmp_ps(best, top8, _CMP_EQ_OQ));
    __m256i at = _mm256_blendv_epi8(_mm256_set1_epi32(-1), bestIndex, tied);
    at = _mm256_min_epu32(at, _mm256_permute2x128_si256(at, at, 1));
    at = _mm256_min_epu32(at, _mm256_shuffle_epi32(at, _MM_SHUFFLE(1, 0, 3, 2)));
    at = _mm256_min_epu32(at, _mm256_shuffle_epi32(at, _MM_SHUFFLE(2, 3, 0, 1)));
    std::uint32_t top = static_cast<std::uint32_t>(_mm256_cvtsi256_si32(at));
    float topDot = _mm256_cvtss_f32(top8);
    for (std::uint32_t i = 8 * blocks; i < n; ++i) {
        const float dd = (x[i] * d.x + y[i] * d.y) + z[i] * d.z;
        if (dd != dd) return n;
        if (dd > topDot) {
            topDot = dd;
            top = i;
        }
    }
    return top;
}

}  // namespace fulcrum::detail

#else

namespace fulcrum::detail {
bool hullSupportAvx2Compiled() { return false; }
std::uint32_t hullSupportIndexAvx2(const float*, const float*, const float*, std::uint32_t n, const Vec3&) { return n; }
}  // namespace fulcrum::detail

#endif
