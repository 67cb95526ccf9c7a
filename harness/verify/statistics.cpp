#include "harness/verify/statistics.h"

#include <fmt/format.h>

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/non_central_t.hpp>
#include <boost/math/distributions/normal.hpp>
#include <boost/math/distributions/students_t.hpp>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "base/tally.h"
#include "harness/run/diagnostics.h"
#include "harness/verify/rounding_bound.h"

namespace pcbench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Spread {
  double mean = kNaN;
  double variance = kNaN;  // of one replicate's estimate, n - 1 in the denominator
};

// ∫∫ |f|: the reference's when known, else the replicates' estimate of it.
double mean_abs_of(const std::vector<ReplicateResult>& replicates, const Reference& reference) {
  if (std::isfinite(reference.magnitude)) return reference.magnitude;
  CompensatedSum sum;
  for (const ReplicateResult& rep : replicates) sum.add(rep.mean_abs);
  return sum.value() / static_cast<double>(replicates.size());
}

Spread spread(const std::vector<ReplicateResult>& replicates) {
  Tally tally;
  for (std::size_t r = 0; r < replicates.size(); ++r) tally.add(replicates[r].estimate, r);
  return {tally.mean(), tally.variance()};
}

Spread spread(std::span<const double> values) {
  Tally tally;
  for (std::size_t r = 0; r < values.size(); ++r) tally.add(values[r], r);
  return {tally.mean(), tally.variance()};
}

double t_quantile(double probability, double dof) {
  return boost::math::quantile(boost::math::students_t(dof), probability);
}

}  // namespace

double student_t_p_value(double t, double dof) {
  if (std::isnan(t)) return kNaN;
  if (std::isinf(t)) return 0.0;
  return 2.0 *
         boost::math::cdf(boost::math::complement(boost::math::students_t(dof), std::fabs(t)));
}

TwoSampleTest welch_test(double mean_a, double variance_of_mean_a, double dof_a, double mean_b,
                         double variance_of_mean_b, double dof_b) {
  TwoSampleTest out;
  out.mean_a = mean_a;
  out.mean_b = mean_b;
  out.stderr_a = std::sqrt(variance_of_mean_a);
  out.stderr_b = std::sqrt(variance_of_mean_b);
  const double variance = variance_of_mean_a + variance_of_mean_b;
  out.stderr_of_difference = std::sqrt(variance);
  const double difference = mean_a - mean_b;
  if (variance == 0.0) {
    // Neither side varies: the test is exact.
    out.dof = dof_a + dof_b;
    out.statistic = difference == 0.0
                        ? 0.0
                        : std::copysign(std::numeric_limits<double>::infinity(), difference);
    out.p_value = difference == 0.0 ? 1.0 : 0.0;
    return out;
  }
  // Welch–Satterthwaite.
  out.dof = variance * variance /
            (variance_of_mean_a * variance_of_mean_a / dof_a +
             variance_of_mean_b * variance_of_mean_b / dof_b);
  out.statistic = difference / out.stderr_of_difference;
  out.p_value = student_t_p_value(out.statistic, out.dof);
  return out;
}

TwoSampleTest welch_two_sample(std::span<const double> a, std::span<const double> b) {
  const Spread sa = spread(a), sb = spread(b);
  const double na = static_cast<double>(a.size()), nb = static_cast<double>(b.size());
  return welch_test(sa.mean, sa.variance / na, na - 1.0, sb.mean, sb.variance / nb, nb - 1.0);
}

TwoSampleTest paired_t_test(std::span<const double> a, std::span<const double> b) {
  if (a.size() != b.size()) {
    throw std::invalid_argument(
        fmt::format("a paired test needs pairs: {} values against {}", a.size(), b.size()));
  }
  std::vector<double> differences(a.size());
  for (std::size_t r = 0; r < a.size(); ++r) differences[r] = a[r] - b[r];
  const Spread sa = spread(a), sb = spread(b), sd = spread(differences);
  const double n = static_cast<double>(a.size());
  TwoSampleTest out = welch_test(sd.mean, sd.variance / n, n - 1.0, 0.0, 0.0,
                                 std::numeric_limits<double>::infinity());
  // A one-sample test: its dof is n - 1 also where the differences do not vary.
  out.dof = n - 1.0;
  out.mean_a = sa.mean;
  out.mean_b = sb.mean;
  out.stderr_a = std::sqrt(sa.variance / n);
  out.stderr_b = std::sqrt(sb.variance / n);
  return out;
}

std::vector<double> holm_adjusted(std::span<const double> p_values) {
  const std::size_t m = p_values.size();
  std::vector<std::size_t> order(m);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t i, std::size_t j) { return p_values[i] < p_values[j]; });
  std::vector<double> adjusted(m);
  double running_max = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    running_max =
        std::max(running_max, std::min(1.0, p_values[order[k]] * static_cast<double>(m - k)));
    adjusted[order[k]] = running_max;
  }
  return adjusted;
}

std::vector<double> weighted_holm_adjusted(std::span<const double> p_values,
                                           std::span<const double> weights) {
  const std::size_t m = p_values.size();
  if (weights.size() != m) {
    throw std::invalid_argument(
        fmt::format("{} p-values and {} weights", p_values.size(), weights.size()));
  }
  for (double w : weights) {
    if (!(w > 0.0)) throw std::invalid_argument(fmt::format("weight {} is not positive", w));
  }
  std::vector<std::size_t> order(m);
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
    return p_values[i] / weights[i] < p_values[j] / weights[j];
  });
  // The weight still in play at each step: the sum over the tests not yet rejected.
  std::vector<double> remaining(m + 1, 0.0);
  for (std::size_t k = m; k-- > 0;) remaining[k] = remaining[k + 1] + weights[order[k]];
  std::vector<double> adjusted(m);
  double running_max = 0.0;
  for (std::size_t k = 0; k < m; ++k) {
    const std::size_t i = order[k];
    running_max = std::max(running_max, std::min(1.0, p_values[i] / weights[i] * remaining[k]));
    adjusted[i] = running_max;
  }
  return adjusted;
}

double detectable_multiplier(double share, double dof, double power) {
  return t_quantile(1.0 - share / 2.0, dof) + t_quantile(power, dof);
}

double noncentral_t_power(double ncp, double dof, double share) {
  const double critical = t_quantile(1.0 - share / 2.0, dof);
  if (ncp == 0.0) return share;
  const boost::math::non_central_t distribution(dof, std::fabs(ncp));
  return boost::math::cdf(boost::math::complement(distribution, critical)) +
         boost::math::cdf(distribution, -critical);
}

double shifted_t_power(double shift, double dof, double share) {
  const double critical = t_quantile(1.0 - share / 2.0, dof);
  const boost::math::students_t t(dof);
  return boost::math::cdf(boost::math::complement(t, critical - shift)) +
         boost::math::cdf(t, -critical - shift);
}

std::vector<SeriesPoint> convergence_series(const std::vector<ReplicateResult>& replicates,
                                            const Reference& reference) {
  std::vector<SeriesPoint> series;
  if (replicates.empty()) return series;
  const std::size_t points = replicates.front().checkpoints.size();
  const double count = static_cast<double>(replicates.size());
  for (std::size_t k = 0; k < points; ++k) {
    Tally tally;
    CompensatedSum squared_error;
    SeriesPoint point{.samples = replicates.front().checkpoints[k].samples};
    for (std::size_t r = 0; r < replicates.size(); ++r) {
      const Checkpoint& c = replicates[r].checkpoints[k];
      tally.add(c.estimate, r);
      point.cpu_seconds += c.cpu_seconds / count;
      point.seconds += c.seconds / count;
      const double error = c.estimate - reference.value;
      squared_error.add(error * error);
    }
    point.mean = tally.mean();
    point.stderr_of_mean = std::sqrt(tally.variance() / count);
    const bool has_reference = reference.kind != ReferenceKind::kNone;
    point.bias = has_reference ? point.mean - reference.value : kNaN;
    point.rmse = has_reference ? std::sqrt(squared_error.value() / count) : kNaN;
    series.push_back(point);
  }
  return series;
}

double rmse_slope(const std::vector<SeriesPoint>& series) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
  for (const SeriesPoint& p : series) {
    if (!(p.rmse > 0.0) || !std::isfinite(p.rmse)) continue;
    const double x = std::log(static_cast<double>(p.samples));
    const double y = std::log(p.rmse);
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    n += 1;
  }
  if (n < 3) return kNaN;
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

Aggregates aggregate(const std::vector<ReplicateResult>& replicates, const Reference& reference,
                     std::uint64_t samples_per_replicate) {
  Aggregates out;
  const double count = static_cast<double>(replicates.size());
  const Spread s = spread(replicates);
  out.mean = s.mean;
  out.stderr_of_mean = std::sqrt(s.variance / count);
  const bool has_reference = reference.kind != ReferenceKind::kNone;
  if (has_reference) {
    out.bias = s.mean - reference.value;
    CompensatedSum squared_error;
    for (const ReplicateResult& rep : replicates) {
      const double error = rep.estimate - reference.value;
      squared_error.add(error * error);
    }
    const double mse = squared_error.value() / count;
    out.rmse = std::sqrt(mse);
    out.rel_mse = reference.value != 0.0 ? mse / (reference.value * reference.value) : kNaN;
  } else {
    out.bias = out.rmse = out.rel_mse = kNaN;
  }
  double cpu = 0.0;
  for (const ReplicateResult& rep : replicates) cpu += rep.cpu_seconds;
  const double total_samples = count * static_cast<double>(samples_per_replicate);
  out.seconds_per_sample = cpu / total_samples;
  // Per-sample variance from the across-replicate spread: Var[one sample] = N Var[replicate].
  const double per_sample_variance = s.variance * static_cast<double>(samples_per_replicate);
  out.efficiency = 1.0 / (per_sample_variance * out.seconds_per_sample);
  out.mean_abs = mean_abs_of(replicates, reference);
  // Var ∈ [(R-1) s² / χ²_{0.975}, (R-1) s² / χ²_{0.025}] flips into the efficiency's interval.
  if (replicates.size() >= 2) {
    const boost::math::chi_squared chi2(count - 1.0);
    const double scaled = (count - 1.0) * per_sample_variance;
    out.efficiency_low = boost::math::quantile(chi2, 0.025) / (scaled * out.seconds_per_sample);
    out.efficiency_high = boost::math::quantile(chi2, 0.975) / (scaled * out.seconds_per_sample);
  } else {
    out.efficiency_low = out.efficiency_high = kNaN;
  }
  out.series = convergence_series(replicates, reference);
  out.rmse_slope = rmse_slope(out.series);
  return out;
}

SampleDiagnostics diagnose_samples(const std::vector<ReplicateResult>& replicates) {
  SampleDiagnostics d;
  double shape_sum = 0.0;
  int shapes = 0;
  for (const ReplicateResult& rep : replicates) {
    d.nonzero += rep.nonzero;
    d.min_effective_samples = std::isnan(d.min_effective_samples)
                                  ? rep.effective_samples
                                  : std::min(d.min_effective_samples, rep.effective_samples);
    if (rep.n == 0) continue;
    // The tail of the non-zero samples: where most samples are 0, the top 3√n of all of them
    // would reach down into the zeros, which are no tail.
    if (rep.nonzero < 2) continue;
    const std::size_t usable = std::min<std::size_t>(rep.largest.size(), rep.nonzero);
    const TailShape tail =
        pareto_tail_shape(std::span<const double>(rep.largest).first(usable), rep.nonzero);
    if (std::isnan(tail.k)) continue;
    if (shapes == 0) d.tail_size = tail.tail_size;
    shape_sum += tail.k;
    ++shapes;
  }
  if (shapes > 0) d.tail_shape = shape_sum / shapes;
  std::vector<double> shares;
  for (const ReplicateResult& rep : replicates) shares.push_back(rep.largest_square_share);
  if (!shares.empty()) {
    std::sort(shares.begin(), shares.end());
    d.largest_share = shares[shares.size() / 2];
  }
  return d;
}

std::optional<std::string> untestable_reason(const SampleDiagnostics& d) {
  // Few effective samples first: they make the tail statistics meaningless too.
  if (!(d.min_effective_samples >= kMinEffectiveSamples)) {
    return fmt::format(
        "too few effective samples: a replicate has {:.3g} (Kish), below {}; {} non-zero "
        "samples in all; its mean is not near normal, so Student's t has no stated level",
        d.min_effective_samples, kMinEffectiveSamples, d.nonzero);
  }
  if (d.tail_shape > kInfiniteVarianceShape && d.largest_share > kDominantShare) {
    return fmt::format(
        "the variance may be infinite: the tail of |estimates| has Pareto shape k = {:.2f} > 1/2 "
        "(mean over replicates of fits to their {} largest) and one sample holds {:.0f}% of a "
        "replicate's sum of squares (median), so Student's t has no stated level",
        d.tail_shape, d.tail_size, 100.0 * d.largest_share);
  }
  return std::nullopt;
}

Verdict untested_verdict(std::string reason, std::string expect) {
  Verdict v;
  v.test = "none";
  v.statistic = v.dof = v.p_value = v.p_adjusted = kNaN;
  v.min_detectable_bias = v.min_detectable_rel_bias = v.min_detectable_bias_vs_mean_abs = kNaN;
  v.result = "inconclusive";
  v.reason = std::move(reason);
  v.expect = std::move(expect);
  return v;
}

Verdict test_against_reference(const std::vector<ReplicateResult>& replicates,
                               const Reference& reference, std::string expect,
                               double sample_roundings) {
  if (reference.kind == ReferenceKind::kNone) {
    return untested_verdict("no reference value to test against", std::move(expect));
  }
  Verdict v;
  v.expect = std::move(expect);
  const double count = static_cast<double>(replicates.size());
  const Spread s = spread(replicates);
  const double se2 = s.variance / count;
  const double bias = s.mean - reference.value;
  v.tested = true;
  v.reference_value = reference.value;
  v.mean_abs = mean_abs_of(replicates, reference);
  if (reference.uncertainty > 0.0) {
    // Welch: the reference carries its own standard error, with its own dof.
    const TwoSampleTest welch =
        welch_test(s.mean, se2, count - 1.0, reference.value,
                   reference.uncertainty * reference.uncertainty, reference.dof);
    v.test = "welch";
    v.dof = welch.dof;
    v.test_stderr = welch.stderr_of_difference;
    v.statistic = welch.statistic;
    v.p_value = welch.p_value;
  } else {
    v.test = "student_t";
    v.dof = count - 1.0;
    v.test_stderr = std::sqrt(se2);
    v.statistic = bias / v.test_stderr;
    if (se2 == 0.0) {
      // Every replicate gave the same number (and the rounding bound is 0 too, or it replaces
      // this below): the test is exact.
      v.statistic =
          bias == 0.0 ? 0.0 : std::copysign(std::numeric_limits<double>::infinity(), bias);
      v.p_value = bias == 0.0 ? 1.0 : 0.0;
    } else {
      v.p_value = student_t_p_value(v.statistic, v.dof);
    }
  }
  // A difference within what rounding alone can make is no evidence of bias (rounding_bound.h):
  // below the bound, the bound is the standard error. The reference's own half ulp joins it.
  v.measured_stderr = v.test_stderr;
  v.rounding_bound =
      rounding_bound(replicates, sample_roundings) + kUnitRoundoff * std::fabs(reference.value);
  if (v.test_stderr < v.rounding_bound) {
    v.test_stderr = v.rounding_bound;
    v.statistic = bias / v.rounding_bound;
    v.p_value = student_t_p_value(v.statistic, v.dof);
  }
  return v;
}

Verdict test_against_reference(const RunResult& run, std::string expect) {
  return test_against_reference(run.replicates, run.reference, std::move(expect),
                                sample_roundings(run.counters));
}

TwoSampleTest with_rounding_floor(TwoSampleTest test, double bound) {
  test.rounding_bound = bound;
  if (test.stderr_of_difference < bound) {
    test.stderr_of_difference = bound;
    test.statistic = (test.mean_a - test.mean_b) / bound;
    test.p_value = student_t_p_value(test.statistic, test.dof);
  }
  return test;
}

Verdict two_sample_verdict(const TwoSampleTest& test, std::string expect) {
  Verdict v;
  v.test = "welch_two_sample";
  v.expect = std::move(expect);
  v.tested = true;
  v.statistic = test.statistic;
  v.dof = test.dof;
  v.p_value = test.p_value;
  v.test_stderr = test.stderr_of_difference;
  v.rounding_bound = test.rounding_bound;
  v.measured_stderr = std::hypot(test.stderr_a, test.stderr_b);
  v.reference_value = test.mean_b;
  v.mean_abs = std::fabs(test.mean_b);  // the scale of a small difference, absent ∫|f|
  return v;
}

void decide_family(std::vector<Verdict*>& verdicts, double alpha) {
  std::vector<Verdict*> tested;
  for (Verdict* v : verdicts) {
    if (v == nullptr) continue;
    v->alpha = alpha;
    if (v->tested) tested.push_back(v);
  }
  const std::size_t m = tested.size();
  std::vector<double> p_values;
  for (const Verdict* v : tested) p_values.push_back(v->p_value);
  const std::vector<double> adjusted = holm_adjusted(p_values);
  for (std::size_t i = 0; i < m; ++i) {
    Verdict& v = *tested[i];
    v.p_adjusted = adjusted[i];
    const bool reject = v.p_adjusted <= alpha;
    v.result = reject ? "biased" : "consistent";
    if (v.test == kBlockPyramidTest) {
      // A scene's block pyramid (harness/verify/block_verdicts.h): its p-value is already the
      // adjusted minimum over its blocks, scales and channels, its reason says what was tested
      // and with what power.
      v.reason = fmt::format("{} (family Holm-adjusted p = {:.3g} {} alpha = {}): {}",
                             reject ? "some block differs" : "no block differs", v.p_adjusted,
                             reject ? "<=" : ">", alpha, v.reason);
      v.min_detectable_bias = kNaN;
      v.min_detectable_bias_vs_mean_abs = kNaN;
      v.min_detectable_rel_bias = kNaN;
      continue;
    }
    const bool two_sample = v.test == "welch_two_sample";
    // The rounding floor (rounding_bound.h) is stated where it applied.
    const bool at_rounding_bound = v.measured_stderr < v.rounding_bound;
    const std::string floor =
        at_rounding_bound
            ? fmt::format(
                  "standard error {:.3g} below the rounding bound {:.3g} (what rounding alone can "
                  "move {} by): tested against the rounding bound; ",
                  v.measured_stderr, v.rounding_bound, two_sample ? "the difference" : "the mean")
            : "";
    v.reason =
        floor +
        (reject
             ? fmt::format(
                   "{} by {:.3g} {} (Holm-adjusted p = {:.3g} <= "
                   "alpha = {})",
                   two_sample ? "the two means differ" : "the mean differs from the reference",
                   v.statistic, at_rounding_bound ? "rounding bounds" : "standard errors",
                   v.p_adjusted, alpha)
             : fmt::format("no evidence of {}: t = {:.3g}, Holm-adjusted p = {:.3g} > "
                           "alpha = {}",
                           two_sample ? "a difference" : "bias", v.statistic, v.p_adjusted, alpha));
    // The bias a two-sided test at the Bonferroni share alpha / m detects with 80% power
    // (normal-theory approximation with Student quantiles).
    const double share = alpha / static_cast<double>(m);
    v.min_detectable_bias = detectable_multiplier(share, v.dof) * v.test_stderr;
    v.min_detectable_bias_vs_mean_abs = v.min_detectable_bias / v.mean_abs;
    v.min_detectable_rel_bias =
        v.reference_value != 0.0 ? v.min_detectable_bias / std::fabs(v.reference_value) : kNaN;
  }
}

ProportionInterval wilson_interval(std::uint64_t successes, std::uint64_t trials,
                                   double confidence) {
  if (trials == 0) return {0.0, 1.0};
  const double z = boost::math::quantile(boost::math::normal(), 1.0 - (1.0 - confidence) / 2.0);
  const double n = static_cast<double>(trials);
  const double k = static_cast<double>(successes);
  const double z2 = z * z;
  const double centre = (k + z2 / 2.0) / (n + z2);
  const double half = z / (n + z2) * std::sqrt(k * (n - k) / n + z2 / 4.0);
  return {std::max(0.0, centre - half), std::min(1.0, centre + half)};
}

double median_or_nan(std::vector<double> values) {
  if (values.empty() ||
      std::any_of(values.begin(), values.end(), [](double v) { return std::isnan(v); })) {
    return kNaN;
  }
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

}  // namespace pcbench
