#pragma once
// Real's bit pattern as an unsigned integer of the same size (32 bits in the
// float build, 64 in the FULCRUM_DOUBLE build), for code that works on the
// bits: a minimum taken with one atomic compare-exchange, a zero test of
// several values at once.
#include <bit>
#include <cstdint>
#include <type_traits>

#include "fulcrum/math/vec3.hpp"

namespace fulcrum::detail {

using RealBits = std::conditional_t<sizeof(Real) == sizeof(std::uint64_t), std::uint64_t, std::uint32_t>;
static_assert(sizeof(RealBits) == sizeof(Real));

// The bits without the sign: zero for +0 and -0 only (a NaN stays non-zero).
inline RealBits magnitudeBits(Real x) { return std::bit_cast<RealBits>(x) & (~RealBits(0) >> 1); }

}  // namespace fulcrum::detail

namespace fulcrum::detail {

// What error messages call Real's precision: "single-precision" or "double-precision".
inline constexpr const char* kRealPrecision = sizeof(Real) == sizeof(double) ? "double-precision" : "single-precision";

}  // namespace fulcrum::detail
