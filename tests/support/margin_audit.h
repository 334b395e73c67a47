#pragma once
// The tolerance audit (cmake -DHARMONIA_TEST_MARGIN_AUDIT=ON; docs/testing.md, "Testing"): included
// before every test source, it turns each floating-point EXPECT/ASSERT comparison (LT, LE, GT, GE,
// NEAR) into one that also appends "file:line value bound ratio" to $HARMONIA_MARGIN_LOG, where
// ratio is how much of the bound the value uses (1 = on the bound, above 1 = failed). A bound that
// a test meets with a ratio above 0.5 sits within 2x of what one machine computed: it is read again
// to see whether it follows from the problem. The assertions pass and fail exactly as without the
// audit; each operand is evaluated once.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <type_traits>

namespace harmonia::testing::audit {

// How much of the bound `value` uses for "value below bound" (LT, LE) or "value above bound"
// (GT, GE, with below = false): value / bound where both have the same sign and the bound is not
// zero, else no ratio (NaN).
inline double used_share(double value, double bound, bool below) {
  if (bound == 0.0 || !std::isfinite(value) || !std::isfinite(bound)) return std::nan("");
  if (below) return (bound > 0.0 && value >= 0.0) ? value / bound : std::nan("");
  return (bound < 0.0 && value <= 0.0) ? value / bound : std::nan("");
}

inline void record(const char* file, int line, const char* expression, double value, double bound,
                   double share) {
  static std::mutex mutex;
  const char* path = std::getenv("HARMONIA_MARGIN_LOG");
  if (path == nullptr || std::isnan(share)) return;
  const std::lock_guard<std::mutex> lock(mutex);
  if (std::FILE* log = std::fopen(path, "a")) {
    std::fprintf(log, "%s:%d\t%.6g\t%.6g\t%.4f\t%s\n", file, line, value, bound, share,
                 expression);
    std::fclose(log);
  }
}

template <typename A, typename B>
constexpr bool kFloating = std::is_floating_point_v<std::decay_t<A>> ||
                           std::is_floating_point_v<std::decay_t<B>>;

template <typename A, typename B>
::testing::AssertionResult compare(const char* file, int line, const char* a_text,
                                   const char* b_text, const A& a, const B& b, int kind) {
  // kind: 0 LT, 1 LE, 2 GT, 3 GE.
  if constexpr (kFloating<A, B> && std::is_arithmetic_v<std::decay_t<A>> &&
                std::is_arithmetic_v<std::decay_t<B>>) {
    const auto value = static_cast<double>(a), bound = static_cast<double>(b);
    record(file, line, a_text, value, bound, used_share(value, bound, kind < 2));
  }
  switch (kind) {
    case 0: return ::testing::internal::CmpHelperLT(a_text, b_text, a, b);
    case 1: return ::testing::internal::CmpHelperLE(a_text, b_text, a, b);
    case 2: return ::testing::internal::CmpHelperGT(a_text, b_text, a, b);
    default: return ::testing::internal::CmpHelperGE(a_text, b_text, a, b);
  }
}

inline ::testing::AssertionResult near(const char* file, int line, const char* a_text,
                                       const char* b_text, const char* tolerance_text, double a,
                                       double b, double tolerance) {
  record(file, line, a_text, std::abs(a - b), tolerance,
         used_share(std::abs(a - b), tolerance, true));
  return ::testing::internal::DoubleNearPredFormat(a_text, b_text, tolerance_text, a, b,
                                                   tolerance);
}

}  // namespace harmonia::testing::audit

#define HARMONIA_AUDIT_CMP(a, b, kind, on_failure)                                              \
  GTEST_ASSERT_(::harmonia::testing::audit::compare(__FILE__, __LINE__, #a, #b, (a), (b), kind), \
                on_failure)
#undef EXPECT_LT
#undef EXPECT_LE
#undef EXPECT_GT
#undef EXPECT_GE
#undef EXPECT_NEAR
#undef ASSERT_LT
#undef ASSERT_LE
#undef ASSERT_GT
#undef ASSERT_GE
#undef ASSERT_NEAR
#define EXPECT_LT(a, b) HARMONIA_AUDIT_CMP(a, b, 0, GTEST_NONFATAL_FAILURE_)
#define EXPECT_LE(a, b) HARMONIA_AUDIT_CMP(a, b, 1, GTEST_NONFATAL_FAILURE_)
#define EXPECT_GT(a, b) HARMONIA_AUDIT_CMP(a, b, 2, GTEST_NONFATAL_FAILURE_)
#define EXPECT_GE(a, b) HARMONIA_AUDIT_CMP(a, b, 3, GTEST_NONFATAL_FAILURE_)
#define ASSERT_LT(a, b) HARMONIA_AUDIT_CMP(a, b, 0, GTEST_FATAL_FAILURE_)
#define ASSERT_LE(a, b) HARMONIA_AUDIT_CMP(a, b, 1, GTEST_FATAL_FAILURE_)
#define ASSERT_GT(a, b) HARMONIA_AUDIT_CMP(a, b, 2, GTEST_FATAL_FAILURE_)
#define ASSERT_GE(a, b) HARMONIA_AUDIT_CMP(a, b, 3, GTEST_FATAL_FAILURE_)
#define EXPECT_NEAR(a, b, tolerance)                                                            \
  GTEST_ASSERT_(::harmonia::testing::audit::near(__FILE__, __LINE__, #a, #b, #tolerance, (a), (b), \
                                                 (tolerance)),                                  \
                GTEST_NONFATAL_FAILURE_)
#define ASSERT_NEAR(a, b, tolerance)                                                            \
  GTEST_ASSERT_(::harmonia::testing::audit::near(__FILE__, __LINE__, #a, #b, #tolerance, (a), (b), \
                                                 (tolerance)),                                  \
                GTEST_FATAL_FAILURE_)
