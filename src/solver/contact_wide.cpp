// The 4-lane contact kernels (SSE2 on x86-64, portable C++ elsewhere) and the
// choice of width at run time (contact_wide.hpp).
#include "solver/contact_wide.hpp"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>

#include "fulcrum/error.hpp"
#include "math/simd.hpp"
#include "contacts/contact.hpp"
#include "solver/contact_solver.hpp"

#if defined(FULCRUM_SIMD_PORTABLE) || !FULCRUM_SIMD_HAS_SSE2
#define FULCRUM_WIDE_POLICY simd::PortablePolicy<4>
#else
#define FULCRUM_WIDE_POLICY simd::Sse2Policy
#endif
#define FULCRUM_WIDE_NS sse2
#include "solver/contact_wide_kernels.hpp"

namespace fulcrum::detail {

// The scalar part of buildBlock that calls shared inline functions (Mat3
// inverse and determinant): here, so that no AVX2-compiled copy of them
// exists (contact_wide_kernels.hpp). The same operations as buildConstraint's.
Mat3 rollingMassOf(const Mat3& invIA, const Mat3& invIB) {
    const Mat3 kr = invIA + invIB;
    return std::fabs(determinant(kr)) > 0 ? inverse(kr) : Mat3::zero();
}

const char* simdPathName(SimdPath path) {
    switch (path) {
        case SimdPath::Scalar: return "scalar";
        case SimdPath::Sse2: return "sse2";
        case SimdPath::Avx2: return "avx2";
    }
    return "?";
}

bool avx2Available() {
#if (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || defined(__i386__))
    // cpu_init first: a World built by a static constructor may get here
    // before libgcc's own initialiser has run (GCC's documentation).
    static const bool available = [] {
        __builtin_cpu_init();
        return avx2KernelsCompiled() && __builtin_cpu_supports("avx2");
    }();
    return available;
#else
    return false;
#endif
}

SimdPath bestSimdPath() {
#if FULCRUM_DOUBLE
    // The double build's lanes are PortablePolicy<4> (simd.hpp): plain arrays
    // that cost pyramid20 1.7x the scalar solver's instructions (callgrind,
    // docs/double-precision.md), so the scalar solver is its fastest path.
    return SimdPath::Scalar;
#else
    return avx2Available() ? SimdPath::Avx2 : SimdPath::Sse2;
#endif
}

SimdPath simdPathFromSetting(const char* text) {
    if (text == nullptr || *text == 0) return bestSimdPath();
    if (std::strcmp(text, "scalar") == 0) return SimdPath::Scalar;
    if (std::strcmp(text, "sse2") == 0) return SimdPath::Sse2;
    if (std::strcmp(text, "avx2") == 0) return bestSimdPath();  // sse2 where the CPU lacks AVX2
    throw Error(std::string("environment variable FULCRUM_SIMD is '") + text +
                "': expected scalar, sse2 or avx2 (or unset: the fastest this CPU runs)");
}

SimdPath initialSimdPath() {
    static const SimdPath path = simdPathFromSetting(std::getenv("FULCRUM_SIMD"));
    return path;
}

std::unique_ptr<WideBlocks> makeWideBlocks(SimdPath path) {
    if (path == SimdPath::Sse2) return std::make_unique<sse2::Blocks>(SimdPath::Sse2);
    if (path == SimdPath::Avx2 && avx2Available()) return makeAvx2Blocks();
    return nullptr;
}

}  // namespace fulcrum::detail
