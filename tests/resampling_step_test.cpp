// The resampling step on hostile importances: weights whose sum overflows, pools whose weights
// span more than the double range, subnormal weights, each with and without flush-to-zero and
// denormals-are-zero (the MXCSR modes Embree asks for). On every pool the step must give a proper
// P (positive wherever w > 0, summing to 1) with finite weights, and the enumerated expectation
// of the estimate must equal connecting to the whole pool.
#include "estimators/resampling_step.h"

#include <gtest/gtest.h>
#include <pmmintrin.h>

#include <algorithm>
#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <vector>

namespace pcbench {
namespace {

// Sets FTZ and DAZ on this thread for its lifetime (or leaves MXCSR alone), then restores it.
class FloatingPointModes {
 public:
  explicit FloatingPointModes(bool flush) : saved_(_mm_getcsr()) {
    if (!flush) return;
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
  }
  ~FloatingPointModes() { _mm_setcsr(saved_); }
  FloatingPointModes(const FloatingPointModes&) = delete;
  FloatingPointModes& operator=(const FloatingPointModes&) = delete;

 private:
  unsigned saved_;
};

// E[Σ_terms coefficient × c_index] over every draw sequence, c_j = 1: the estimate of a pool whose
// contributions f / (p(x) p(y)) are all 1, whose exact value is then 1 (connecting to every path).
double enumerated_expectation(const ResamplingStep& step, const std::vector<double>& w) {
  const std::vector<double> ones(w.size(), 1.0);
  double expectation = 0.0;
  step.enumerate({.importance = w, .contributions = ones},
                 [&](double probability, std::span<const Term> terms) {
                   for (const Term& t : terms) expectation += probability * t.coefficient;
                 });
  return expectation;
}

// w > 0 from its bits, so that DAZ (which reads a subnormal as 0) cannot change the answer.
bool has_positive_bits(double w) {
  return std::bit_cast<std::uint64_t>(w) != 0 && !std::signbit(w);
}

struct HostilePool {
  const char* what;
  std::vector<double> w;
};

std::vector<HostilePool> hostile_pools() {
  return {
      {"sum beyond DBL_MAX", {0.6 * DBL_MAX, 0.6 * DBL_MAX, 1.0, 0.0}},
      {"1e300 beside 1e-300", {1e300, 1e-300, 1.0}},
      {"share 1e-320 (subnormal)", {1e300, 1e-20}},
      {"share below DBL_MIN", {1e200, 1e-109, 3.0}},
      {"subnormal weight", {1.0, 1e-310}},
      {"all subnormal", {1e-310, 3e-312}},
      {"subnormal sum", {0.0, 1e-310, 0.0, 2e-310}},
      {"zero and positive", {0.0, 1e-300, 0.0}},
  };
}

TEST(ResamplingStepHostile, PmfIsProperAndPositiveWhereverImportanceIs) {
  for (const bool flush : {false, true}) {
    const FloatingPointModes modes(flush);
    for (const double u : {0.0, 0.1}) {
      for (const HostilePool& pool : hostile_pools()) {
        const auto m = static_cast<std::uint32_t>(pool.w.size());
        const ResamplingStep step({.M = m,
                                   .K = 2,
                                   .selection = Selection::kImportance,
                                   .scheme = DrawScheme::kIndependent,
                                   .uniform_mix = u});
        std::vector<double> pmf;
        step.build_pmf({.importance = pool.w}, pmf);
        double total = 0.0;
        for (std::uint32_t j = 0; j < m; ++j) {
          SCOPED_TRACE(::testing::Message()
                       << pool.what << ", u = " << u << ", FTZ/DAZ " << flush << ", j = " << j);
          ASSERT_TRUE(std::isfinite(pmf[j]));
          // Positive wherever w is (w = 0 only has the uniform share), and normal: a subnormal
          // P would weigh its draw by 1 / (M K P) = inf.
          if (has_positive_bits(pool.w[j]) || u > 0.0) {
            EXPECT_GE(pmf[j], DBL_MIN);
          } else {
            // 0 without uniform mixing, unless the pool reads as all-zero (subnormal weights
            // under DAZ) and P falls back to uniform.
            EXPECT_TRUE(pmf[j] == 0.0 || pmf[j] == 1.0 / m) << pmf[j];
          }
          total += pmf[j];
        }
        EXPECT_NEAR(total, 1.0, 1e-15) << pool.what << ", u = " << u << ", FTZ/DAZ " << flush;
      }
    }
  }
}

// Eq. (2) in expectation: E[estimate] = (1/M) Σ_j c_j = 1 on every hostile pool, for each draw
// scheme (without uniform mixing: independent draws only, see below). Without the scaling, a sum
// beyond DBL_MAX makes P sum to u (the estimate 1/u times too large); without the floor, a share
// below DBL_MIN is 0 under FTZ (the path is lost: the estimate misses its 1/M) or subnormal without
// it (its weight 1/(M K P) is inf).
TEST(ResamplingStepHostile, EnumeratedExpectationIsConnectingToThePool) {
  for (const bool flush : {false, true}) {
    const FloatingPointModes modes(flush);
    for (const double u : {0.0, 0.1}) {
      for (const DrawScheme scheme :
           {DrawScheme::kIndependent, DrawScheme::kStratified, DrawScheme::kSystematic}) {
        for (const HostilePool& pool : hostile_pools()) {
          // A zero importance needs the uniform share (u > 0) to be reachable at all. And without
          // the uniform share a P far below 2^-53 (the resolution of a uniform in [0, 1)) is an
          // empty interval of any inverse CDF in double precision: stratified and systematic
          // draws, enumerated through that CDF, cannot reach it (nor can a sampled independent
          // draw, though its enumeration uses P itself). u > 0 keeps every P >= u/M.
          if (u == 0.0 && std::find(pool.w.begin(), pool.w.end(), 0.0) != pool.w.end()) continue;
          if (u == 0.0 && scheme != DrawScheme::kIndependent) continue;
          const ResamplingStep step({.M = static_cast<std::uint32_t>(pool.w.size()),
                                     .K = 2,
                                     .selection = Selection::kImportance,
                                     .scheme = scheme,
                                     .uniform_mix = u});
          EXPECT_NEAR(enumerated_expectation(step, pool.w), 1.0, 1e-12)
              << pool.what << ", u = " << u << ", scheme " << static_cast<int>(scheme)
              << ", FTZ/DAZ " << flush;
        }
      }
    }
  }
}

// The modes the tests above rely on are really in force: a subnormal operand reads as 0 (DAZ)
// and a result below DBL_MIN is flushed to 0 (FTZ).
TEST(ResamplingStepHostile, FlushToZeroModesTakeEffect) {
  volatile double subnormal = 1e-310;
  volatile double a = 1e-160;
  volatile double b = 1e-150;
  {
    const FloatingPointModes modes(true);
    EXPECT_EQ(subnormal * 2.0, 0.0);
    EXPECT_EQ(a * b, 0.0);
  }
  EXPECT_GT(subnormal * 2.0, 0.0);
  EXPECT_GT(a * b, 0.0);
}

}  // namespace
}  // namespace pcbench
