// The 4-lane ball-joint kernels (SSE2 on x86-64, portable C++ elsewhere) and
// the choice of width (joint_wide.hpp). The path itself is chosen as the
// contact solver's is (contact_wide.hpp: FULCRUM_SIMD, else the widest the CPU runs).
#include "solver/joints/joint_wide.hpp"
#include "solver/joints/joint_wide_checks.hpp"

#include "math/simd.hpp"
#include "solver/joints/joint_types.hpp"

#if defined(FULCRUM_SIMD_PORTABLE) || !FULCRUM_SIMD_HAS_SSE2
#define FULCRUM_JOINT_WIDE_POLICY simd::PortablePolicy<4>
#else
#define FULCRUM_JOINT_WIDE_POLICY simd::Sse2Policy
#endif
#define FULCRUM_JOINT_WIDE_NS joint_sse2
#include "solver/joints/joint_wide_kernels.hpp"

namespace fulcrum::detail {

WideKind wideKind(const JointConstraint& j) {
    return jointWideKind(j);
}

std::unique_ptr<WideJoints> makeWideJoints(SimdPath path) {
    if (path == SimdPath::Sse2) return std::make_unique<joint_sse2::Blocks>(SimdPath::Sse2);
    if (path == SimdPath::Avx2 && avx2Available() && avx2JointKernelsCompiled()) return makeAvx2Joints();
    return nullptr;
}

bool wideAtan2(SimdPath path, const Real* y, const Real* x, Real* out, std::size_t n) {
    if (path == SimdPath::Sse2) {
        joint_sse2::atan2Array(y, x, out, n);
        return true;
    }
    if (path == SimdPath::Avx2 && avx2Available() && avx2JointKernelsCompiled()) return avx2JointAtan2(y, x, out, n);
    return false;
}

bool wideCoupledInverseMass(SimdPath path, const Real* K, const Real* Kia, const Real* kaa, Real* c, Real* schur,
                            bool* ok, std::size_t n) {
#ifdef FULCRUM_JOINT_WIDE_DOUBLE_LANES
    if (path == SimdPath::Sse2) {
        joint_sse2::coupledArray(K, Kia, kaa, c, schur, ok, n);
        return true;
    }
#endif
    if (path == SimdPath::Avx2 && avx2Available() && avx2JointKernelsCompiled()) {
        return avx2JointCoupledInverseMass(K, Kia, kaa, c, schur, ok, n);
    }
    return false;
}

}  // namespace fulcrum::detail
