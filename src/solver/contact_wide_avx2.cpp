// The 8-lane AVX2 contact kernels: contact_wide_kernels.hpp compiled with
// -mavx2 (CMakeLists.txt sets it for this file only, and never -mfma: the
// kernels must round as the scalar reference does; simd.hpp). Used only when
// the CPU has AVX2 (contact_wide.cpp checks before calling makeAvx2Blocks).
#include "solver/contact_wide.hpp"

#include "math/simd.hpp"
#include "contacts/contact.hpp"
#include "solver/contact_solver.hpp"

#if FULCRUM_SIMD_HAS_AVX2 && !defined(FULCRUM_SIMD_PORTABLE)
#define FULCRUM_WIDE_POLICY simd::Avx2Policy
#define FULCRUM_WIDE_NS avx2
#define FULCRUM_WIDE_LEAVE() _mm256_zeroupper()  // see contact_wide_kernels.hpp
#include <immintrin.h>
#include "solver/contact_wide_kernels.hpp"

namespace fulcrum::detail {
bool avx2KernelsCompiled() { return true; }
std::unique_ptr<WideBlocks> makeAvx2Blocks() { return std::make_unique<avx2::Blocks>(SimdPath::Avx2); }
}  // namespace fulcrum::detail
#else
namespace fulcrum::detail {
bool avx2KernelsCompiled() { return false; }
std::unique_ptr<WideBlocks> makeAvx2Blocks() { return nullptr; }
}  // namespace fulcrum::detail
#endif
