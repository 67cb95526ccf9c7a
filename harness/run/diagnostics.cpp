#include "harness/run/diagnostics.h"

#include <algorithm>
#include <boost/math/distributions/binomial.hpp>
#include <boost/math/special_functions/gamma.hpp>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace pcbench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// ---------------------------------------------------------------------------------------------
// Tail shape

// Fewer excesses than this give no usable fit: the estimate's standard deviation, ~(1 + k) /
// sqrt(M), would exceed 1/2, the whole distance from a light tail to an infinite variance.
constexpr std::size_t kMinExcesses = 5;

// PSIS's weakly informative prior on k: as if 10 more excesses had come from a GPD with k = 0.5
// (Vehtari et al.; loo's gpdfit(wip = TRUE), arviz's _gpdfit).
constexpr double kPriorCount = 10.0;
constexpr double kPriorShape = 0.5;

struct GpdFit {
  double k = kNaN;
  double sigma = kNaN;
};

// Zhang & Stephens (2009): the posterior mean of theta = -k / sigma over a grid of 30 + sqrt(n)
// points placed by their empirical-Bayes prior, with k profiled out (k(theta) = mean of
// log(1 - theta x)); then k and sigma at that theta. Written in PSIS's sign convention (k > 0 is
// a heavy tail), following loo's gpdfit. `x` is ascending and positive.
GpdFit zhang_stephens(const std::vector<double>& x) {
  const double n = static_cast<double>(x.size());
  const std::size_t grid = 30 + static_cast<std::size_t>(std::sqrt(n));
  const double x_max = x.back();
  const double quartile = x[static_cast<std::size_t>(n / 4.0 + 0.5) - 1];
  const auto shape_at = [&x, n](double theta) {
    double sum = 0.0;
    for (double xi : x) sum += std::log1p(-theta * xi);
    return sum / n;
  };
  std::vector<double> theta(grid);
  std::vector<double> log_likelihood(grid);
  double max_log_likelihood = -std::numeric_limits<double>::infinity();
  for (std::size_t j = 0; j < grid; ++j) {
    // Every theta < 1 / x_max, so 1 - theta x > 0 for every excess.
    theta[j] = 1.0 / x_max +
               (1.0 - std::sqrt(static_cast<double>(grid) / (static_cast<double>(j + 1) - 0.5))) /
                   (3.0 * quartile);
    const double k = shape_at(theta[j]);
    // Profile log-likelihood; theta = 0 exactly (k = 0, the exponential) is a 0/0 left out.
    const double l = n * (std::log(-theta[j] / k) - k - 1.0);
    log_likelihood[j] = std::isfinite(l) ? l : -std::numeric_limits<double>::infinity();
    max_log_likelihood = std::max(max_log_likelihood, log_likelihood[j]);
  }
  if (!std::isfinite(max_log_likelihood)) return {};
  // Posterior weights exp(l_j) / sum exp(l), relative to the largest so that nothing overflows.
  double weight_sum = 0.0;
  double theta_sum = 0.0;
  for (std::size_t j = 0; j < grid; ++j) {
    const double w = std::exp(log_likelihood[j] - max_log_likelihood);
    weight_sum += w;
    theta_sum += w * theta[j];
  }
  const double theta_mean = theta_sum / weight_sum;
  GpdFit fit;
  fit.k = shape_at(theta_mean);
  // sigma = -k / theta, whose limit at theta = 0 (the exponential) is the mean excess.
  if (theta_mean != 0.0) {
    fit.sigma = -fit.k / theta_mean;
  } else {
    double sum = 0.0;
    for (double xi : x) sum += xi;
    fit.sigma = sum / n;
  }
  return fit;
}

// ---------------------------------------------------------------------------------------------
// Kolmogorov–Smirnov

// Below this P(D_n >= d), 1 - P(D_n < d) has lost more than 5 of its ~15 digits to cancellation,
// while twice the one-sided probability differs from it by P(D+ >= d and D- >= d), asymptotically
// 2 exp(-8 n d^2) against p = 2 exp(-2 n d^2): the upper tail uses the latter. At the switch the
// two were checked to agree to 1e-9 relative for every n <= 1000, a difference that is the
// rounding of the exact method.
constexpr double kMillerBelow = 1e-5;

// log C(n, j) with Boost's lgamma: std::lgamma writes the global signgam, a data race when
// diagnostics run on several threads.
double log_choose(double n, double j) {
  return boost::math::lgamma(n + 1.0) - boost::math::lgamma(j + 1.0) -
         boost::math::lgamma(n - j + 1.0);
}

// Smirnov's one-sided P(D+_n >= d) for 0 < d < 1, exactly (Birnbaum & Tingey 1951):
//   d sum_{j=0}^{floor(n(1-d))} C(n, j) (1 - d - j/n)^(n-j) (d + j/n)^(j-1).
// Every term is positive, so the sum keeps its relative precision however small it is; summed in
// logs so that no term under- or overflows.
double smirnov_one_sided(double d, std::uint64_t n) {
  const double nd = static_cast<double>(n);
  const auto last = static_cast<std::uint64_t>(std::floor(nd * (1.0 - d)));
  std::vector<double> log_terms;
  log_terms.reserve(last + 1);
  for (std::uint64_t j = 0; j <= last && j < n; ++j) {
    const double jd = static_cast<double>(j);
    const double below = 1.0 - d - jd / nd;
    if (below <= 0.0) break;  // the term is 0 (d n + j = n up to rounding)
    log_terms.push_back(log_choose(nd, jd) + (nd - jd) * std::log(below) +
                        (jd - 1.0) * std::log(d + jd / nd));
  }
  if (log_terms.empty()) return 0.0;
  const double top = *std::max_element(log_terms.begin(), log_terms.end());
  double sum = 0.0;
  for (double l : log_terms) sum += std::exp(l - top);
  return std::exp(std::log(d) + top + std::log(sum));
}

// A square matrix times 2^exponent. Rescaling by powers of two is exact, unlike Marsaglia et al.'s
// factor 1e140, and keeps the entries of H^n (which grow like e^n) in range.
struct ScaledMatrix {
  std::vector<double> entries;  // row-major
  long exponent = 0;
};

void normalize(ScaledMatrix& a) {
  const double top = *std::max_element(a.entries.begin(), a.entries.end());
  if (top <= 0.0) return;
  int shift = 0;
  std::frexp(top, &shift);
  for (double& v : a.entries) v = std::ldexp(v, -shift);
  a.exponent += shift;
}

ScaledMatrix multiply(const ScaledMatrix& a, const ScaledMatrix& b, std::size_t m) {
  ScaledMatrix out;
  out.entries.assign(m * m, 0.0);
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t l = 0; l < m; ++l) {
      const double a_il = a.entries[i * m + l];
      if (a_il == 0.0) continue;
      for (std::size_t j = 0; j < m; ++j) out.entries[i * m + j] += a_il * b.entries[l * m + j];
    }
  }
  out.exponent = a.exponent + b.exponent;
  normalize(out);
  return out;
}

// P(D_n < d) by Marsaglia, Tsang & Wang (2003): with k = floor(n d) + 1, m = 2k - 1 and
// h = k - n d, it is n! / n^n times the (k, k) entry of H^n for their m × m matrix H (Durbin's
// representation). Exact up to rounding; cost O(m^3 log n).
double marsaglia_tsang_wang_cdf(double d, std::uint64_t n) {
  const double nd = static_cast<double>(n) * d;
  const auto k = static_cast<std::size_t>(std::floor(nd)) + 1;
  const std::size_t m = 2 * k - 1;
  const double h = static_cast<double>(k) - nd;
  std::vector<double> inverse_factorial(m + 1, 1.0);
  for (std::size_t g = 1; g <= m; ++g) {
    inverse_factorial[g] = inverse_factorial[g - 1] / static_cast<double>(g);
  }
  ScaledMatrix power;
  power.entries.assign(m * m, 0.0);
  // H: 1 on and below the superdiagonal, corrected in the first column and last row, and entry
  // (i, j) divided by (i - j + 1)!.
  std::vector<double>& a = power.entries;
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = 0; j <= std::min(i + 1, m - 1); ++j) a[i * m + j] = 1.0;
  }
  for (std::size_t i = 0; i < m; ++i) {
    a[i * m] -= std::pow(h, static_cast<double>(i + 1));
    a[(m - 1) * m + i] -= std::pow(h, static_cast<double>(m - i));
  }
  if (2.0 * h - 1.0 > 0.0) a[(m - 1) * m] += std::pow(2.0 * h - 1.0, static_cast<double>(m));
  for (std::size_t i = 0; i < m; ++i) {
    for (std::size_t j = 0; j <= i; ++j) a[i * m + j] *= inverse_factorial[i - j + 1];
  }
  normalize(power);
  // H^n by repeated squaring.
  ScaledMatrix result;
  bool have_result = false;
  for (std::uint64_t e = n; e > 0; e >>= 1) {
    if (e & 1) {
      result = have_result ? multiply(result, power, m) : power;
      have_result = true;
    }
    if (e > 1) power = multiply(power, power, m);
  }
  // Times n! / n^n, one factor i / n at a time, renormalizing as it shrinks.
  double s = result.entries[(k - 1) * m + (k - 1)];
  long exponent = result.exponent;
  const double n_double = static_cast<double>(n);
  for (std::uint64_t i = 1; i <= n; ++i) {
    s = s * static_cast<double>(i) / n_double;
    int shift = 0;
    s = std::frexp(s, &shift);
    exponent += shift;
  }
  if (s == 0.0) return 0.0;
  return std::ldexp(s, static_cast<int>(std::clamp(exponent, -2000L, 2000L)));
}

// Q(lambda) = lim P(sqrt(n) D_n > lambda) = 2 sum_{j>=1} (-1)^(j-1) exp(-2 j^2 lambda^2).
// For small lambda that series converges slowly and cancels; there the CDF's theta-function form
// sqrt(2 pi) / lambda sum_{j>=1} exp(-(2j-1)^2 pi^2 / (8 lambda^2)) converges fast instead.
double kolmogorov_limit_p_value(double lambda) {
  if (lambda <= 0.0) return 1.0;
  constexpr double kPi = std::numbers::pi;
  if (lambda < 1.18) {
    const double a = -kPi * kPi / (8.0 * lambda * lambda);
    double sum = 0.0;
    for (int j = 1; j <= 100; ++j) {
      const double odd = 2.0 * j - 1.0;
      const double term = std::exp(a * odd * odd);
      sum += term;
      if (term <= 1e-17 * sum) break;
    }
    return std::clamp(1.0 - std::sqrt(2.0 * kPi) / lambda * sum, 0.0, 1.0);
  }
  double sum = 0.0;
  for (int j = 1; j <= 100; ++j) {
    const double term = std::exp(-2.0 * j * j * lambda * lambda);
    sum += (j % 2 == 1) ? term : -term;
    if (term <= 1e-17 * sum) break;
  }
  return std::clamp(2.0 * sum, 0.0, 1.0);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Tail shape

std::size_t pareto_tail_size(std::uint64_t total_count) {
  if (total_count < 2) return 0;
  const double n = static_cast<double>(total_count);
  const double m = std::ceil(std::min(0.2 * n, 3.0 * std::sqrt(n)));
  return static_cast<std::size_t>(std::min(m, n - 1.0));
}

TailShape pareto_tail_shape(std::span<const double> largest_descending, std::uint64_t total_count) {
  for (std::size_t i = 0; i < largest_descending.size(); ++i) {
    if (!std::isfinite(largest_descending[i])) {
      throw std::invalid_argument("pareto_tail_shape: a value is not finite");
    }
    if (i > 0 && largest_descending[i] > largest_descending[i - 1]) {
      throw std::invalid_argument("pareto_tail_shape: values are not in descending order");
    }
  }
  if (largest_descending.size() > total_count) {
    throw std::invalid_argument("pareto_tail_shape: more largest values than the sample holds");
  }
  if (largest_descending.size() < 2) return {};
  const std::size_t m = std::min(pareto_tail_size(total_count), largest_descending.size() - 1);
  const double threshold = largest_descending[m];
  // Excesses, ascending; ties with the threshold (excess 0) carry no information on the shape.
  std::vector<double> excesses;
  excesses.reserve(m);
  for (std::size_t i = m; i-- > 0;) {
    const double excess = largest_descending[i] - threshold;
    if (excess > 0.0) excesses.push_back(excess);
  }
  if (excesses.size() < kMinExcesses) return {};
  const GpdFit fit = zhang_stephens(excesses);
  if (std::isnan(fit.k)) return {};
  TailShape out;
  out.k_unadjusted = fit.k;
  // PSIS's prior adjustment, applied because (1) it is what PSIS reports (loo and arviz apply it),
  // so k̂ reads against their thresholds (0.5, 0.7), (2) it steadies k̂ of short tails (the caller
  // may hold only a few largest values), and (3) being a pull towards exactly
  // kInfiniteVarianceShape, it never moves k̂ across that line: k - 0.5 = M (k_unadjusted - 0.5) /
  // (M + 10). At the M of 10^5 samples (949) it moves k̂ by 1% of its distance to 0.5; sigma stays
  // the unadjusted fit's, as in PSIS.
  const double count = static_cast<double>(excesses.size());
  out.k = (count * fit.k + kPriorCount * kPriorShape) / (count + kPriorCount);
  out.sigma = fit.sigma;
  out.tail_size = excesses.size();
  out.threshold = threshold;
  return out;
}

// ---------------------------------------------------------------------------------------------
// Kolmogorov–Smirnov

double ks_p_value(double d, std::uint64_t n) {
  if (std::isnan(d) || n == 0) return kNaN;
  const double nd = static_cast<double>(n);
  if (d <= 0.5 / nd) return 1.0;  // D_n >= 1 / (2n) always
  if (d >= 1.0) return 0.0;
  if (n > kKsExactMaxN) {
    // Vrbik's correction: Q at sqrt(n) d + 1/(6 sqrt(n)) + (sqrt(n) d - 1)/(4n), where 1/(6
    // sqrt(n)) is the exact expansion's n^(-1/2) term; Stephens's (sqrt(n) + 0.12 + 0.11/sqrt(n)) d
    // overshoots it in the tail (2% off at p = 1e-4, n = 1000, against Vrbik's 0.6%).
    const double root = std::sqrt(nd);
    const double lambda = root * d;
    return kolmogorov_limit_p_value(lambda + 1.0 / (6.0 * root) + (lambda - 1.0) / (4.0 * nd));
  }
  // D+ >= d and D- >= d cannot both hold when d >= 1/2, so there P(D_n >= d) = 2 P(D+_n >= d).
  const double twice_one_sided = 2.0 * smirnov_one_sided(d, n);
  if (d >= 0.5 || twice_one_sided < kMillerBelow) return std::min(1.0, twice_one_sided);
  return std::clamp(1.0 - marsaglia_tsang_wang_cdf(d, n), 0.0, 1.0);
}

KsResult ks_uniform(std::vector<double> values) {
  if (values.empty()) throw std::invalid_argument("ks_uniform: no values");
  for (double v : values) {
    if (!(v >= 0.0 && v <= 1.0)) {  // also NaN
      throw std::invalid_argument("ks_uniform: a value is outside [0, 1] or NaN");
    }
  }
  std::sort(values.begin(), values.end());
  const double n = static_cast<double>(values.size());
  double d = 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double rank = static_cast<double>(i);
    d = std::max({d, (rank + 1.0) / n - values[i], values[i] - rank / n});
  }
  return {.statistic = d, .p_value = ks_p_value(d, values.size()), .n = values.size()};
}

// ---------------------------------------------------------------------------------------------
// Binomial

namespace {

void check_binomial(std::uint64_t successes, std::uint64_t trials, double p, const char* who) {
  if (successes > trials) {
    throw std::invalid_argument(std::string(who) + ": more successes than trials");
  }
  if (trials > (std::uint64_t{1} << 53)) {
    throw std::invalid_argument(std::string(who) + ": more than 2^53 trials");
  }
  if (!(p >= 0.0 && p <= 1.0)) {
    throw std::invalid_argument(std::string(who) + ": p is not in [0, 1]");
  }
}

}  // namespace

double binomial_test_p_value(std::uint64_t successes, std::uint64_t trials, double p) {
  check_binomial(successes, trials, p, "binomial_test_p_value");
  if (trials == 0) return 1.0;
  // Degenerate distributions: the observed outcome is either the only possible one or impossible.
  if (p == 0.0) return successes == 0 ? 1.0 : 0.0;
  if (p == 1.0) return successes == trials ? 1.0 : 0.0;
  const double n = static_cast<double>(trials);
  const double x = static_cast<double>(successes);
  const boost::math::binomial_distribution<double> dist(n, p);
  const double mean = n * p;
  if (x == mean) return 1.0;
  const double limit = boost::math::pdf(dist, x) * (1.0 + 1e-7);
  const auto pdf = [&dist](std::uint64_t i) {
    return boost::math::pdf(dist, static_cast<double>(i));
  };
  // The mode is floor((n + 1) p), so the pmf does not increase on [ceil(np), n] and does not
  // decrease on [0, floor(np)]: the outcomes of the other side no more likely than x form a tail,
  // found by bisection rather than R's sum over every outcome (trials may be ~10^9).
  if (x < mean) {
    // Smallest j in [ceil(np), n] with pmf(j) <= limit, or n + 1 if none.
    std::uint64_t lo = static_cast<std::uint64_t>(std::ceil(mean));
    std::uint64_t hi = trials + 1;
    while (lo < hi) {
      const std::uint64_t mid = lo + (hi - lo) / 2;
      if (pdf(mid) <= limit) {
        hi = mid;
      } else {
        lo = mid + 1;
      }
    }
    const double upper =
        lo <= trials ? boost::math::cdf(boost::math::complement(dist, static_cast<double>(lo - 1)))
                     : 0.0;
    return std::min(1.0, boost::math::cdf(dist, x) + upper);
  }
  // Number of j in [0, floor(np)] with pmf(j) <= limit: they are 0 .. count - 1.
  std::uint64_t lo = 0;
  std::uint64_t hi = static_cast<std::uint64_t>(std::floor(mean)) + 1;
  while (lo < hi) {
    const std::uint64_t mid = lo + (hi - lo) / 2;
    if (pdf(mid) <= limit) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  const double lower = lo > 0 ? boost::math::cdf(dist, static_cast<double>(lo - 1)) : 0.0;
  return std::min(1.0, lower + boost::math::cdf(boost::math::complement(dist, x - 1.0)));
}

double binomial_upper_p_value(std::uint64_t successes, std::uint64_t trials, double p) {
  check_binomial(successes, trials, p, "binomial_upper_p_value");
  if (successes == 0) return 1.0;
  if (p == 0.0) return 0.0;
  if (p == 1.0) return 1.0;
  const boost::math::binomial_distribution<double> dist(static_cast<double>(trials), p);
  return boost::math::cdf(boost::math::complement(dist, static_cast<double>(successes - 1)));
}

}  // namespace pcbench
