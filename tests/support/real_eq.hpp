#pragma once
// EXPECT_REAL_EQ / ASSERT_REAL_EQ: equal within 4 units in the last place of
// Real, so a test states "the same value, up to rounding" once for both
// builds: GoogleTest's FLOAT_EQ in the float build, DOUBLE_EQ in the
// FULCRUM_DOUBLE build (docs/double-precision.md).
#include <gtest/gtest.h>

#if FULCRUM_DOUBLE
#define EXPECT_REAL_EQ EXPECT_DOUBLE_EQ
#define ASSERT_REAL_EQ ASSERT_DOUBLE_EQ
#else
#define EXPECT_REAL_EQ EXPECT_FLOAT_EQ
#define ASSERT_REAL_EQ ASSERT_FLOAT_EQ
#endif
