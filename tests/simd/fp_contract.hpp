#pragma once
// Whether this build contracts scalar `a * b + c` into a fused multiply-add.
// GCC does by default in C++ (-ffp-contract=fast) whenever FMA instructions
// are enabled (-mfma, -march=native on a recent CPU); then scalar expressions
// and their wide twins may round differently, and the bit-identity tests of
// composite expressions (dot, cross, the contact-row solve) cannot hold. Such
// builds should add -ffp-contract=off (docs/threading.md); the tests skip
// those checks, saying why, instead of failing.
#include <cmath>

namespace fulcrum::test {

// Compiled on its own, so the multiply is not shared with the check below.
[[gnu::noinline]] inline float plainMulAdd(float a, float b, float c) { return a * b + c; }

inline bool scalarCodeIsContracted() {
    // a * b = 1 + 2^-11 + 2^-24 exactly: rounded separately the 2^-24 is lost,
    // fused it survives.
    volatile float va = 1.0f + 0x1p-12f, vc = -(1.0f + 0x1p-11f);
    const float a = va, c = vc;
    return plainMulAdd(a, a, c) != 0.0f;
}

}  // namespace fulcrum::test
