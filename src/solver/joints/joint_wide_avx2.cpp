// The 8-lane AVX2 joint kernels: joint_wide_kernels.hpp compiled with
// -mavx2 (CMakeLists.txt sets it for this file only, and never -mfma: the
// kernels must round as the scalar reference does; simd.hpp). Used only when
// the CPU has AVX2 (joint_wide.cpp checks before calling makeAvx2Joints).
#include "solver/joints/joint_wide.hpp"
#include "solver/joints/joint_wide_checks.hpp"

#include "math/simd.hpp"

#if FULCRUM_SIMD_HAS_AVX2 && !defined(FULCRUM_SIMD_PORTABLE)
#define FULCRUM_JOINT_WIDE_POLICY simd::Avx2Policy
#define FULCRUM_JOINT_WIDE_NS joint_avx2
#define FULCRUM_JOINT_WIDE_LEAVE() _mm256_zeroupper()  // see contact_wide_kernels.hpp
#include <immintrin.h>
#include "solver/joints/joint_wide_kernels.hpp"

namespace fulcrum::detail {
bool avx2JointKernelsCompiled() { return true; }
std::unique_ptr<WideJoints> makeAvx2Joints() { return std::make_unique<joint_avx2::Blocks>(SimdPath::Avx2); }
bool avx2JointAtan2(const Real* y, const Real* x, Real* out, std::size_t n) {
    joint_avx2::atan2Array(y, x, out, n);
    return true;
}
bool avx2JointCoupledInverseMass(const Real* K, const Real* Kia, const Real* kaa, Real* c, Real* schur, bool* ok,
                                 std::size_t n) {
    joint_avx2::coupledArray(K, Kia, kaa, c, schur, ok, n);
    return true;
}
}  // namespace fulcrum::detail
#else
namespace fulcrum::detail {
bool avx2JointKernelsCompiled() { return false; }
std::unique_ptr<WideJoints> makeAvx2Joints() { return nullptr; }
bool avx2JointAtan2(const Real*, const Real*, Real*, std::size_t) { return false; }
bool avx2JointCoupledInverseMass(const Real*, const Real*, const Real*, Real*, Real*, bool*, std::size_t) { return false; }
}  // namespace fulcrum::detail
#endif
