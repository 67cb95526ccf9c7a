#include "harness/verify/report_compare.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <span>

#include "base/errors.h"
#include "base/json_number.h"
#include "harness/verify/block_pyramid.h"

namespace pcbench {
namespace {

using Json = nlohmann::ordered_json;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Why a pair of runs with the same id is not compared ("" when it is).
std::string why_not_compared(const ReportRun& a, const ReportRun& b, std::string_view name_a,
                             std::string_view name_b) {
  std::vector<std::string> reasons;
  for (const auto& [run, name] : {std::pair{&a, name_a}, std::pair{&b, name_b}}) {
    if (run->status != "ok") {
      reasons.push_back(fmt::format("status {} in {}{}", run->status, name,
                                    run->error.empty() ? "" : fmt::format(" ({})", run->error)));
    } else if (run->estimates.size() < 2) {
      reasons.push_back(fmt::format("{} replicate(s) in {}; a test needs at least 2",
                                    run->estimates.size(), name));
    }
  }
  return join_names(reasons, "; ");
}

}  // namespace

bool ComparisonOutcome::as_expected() const {
  return std::all_of(comparisons.begin(), comparisons.end(),
                     [](const Comparison& c) { return c.result == c.expect; });
}

void set_test_figures(Comparison& c, const TwoSampleTest& test) {
  c.statistic = test.statistic;
  c.dof = test.dof;
  c.mean_a = test.mean_a;
  c.mean_b = test.mean_b;
  c.stderr_a = test.stderr_a;
  c.stderr_b = test.stderr_b;
}

Comparison comparison_from(const TwoSampleTest& test, std::string a, std::string b,
                           std::size_t replicates_a, std::size_t replicates_b) {
  Comparison c;
  c.a = std::move(a);
  c.b = std::move(b);
  set_test_figures(c, test);
  c.p_value = test.p_value;
  c.p_adjusted = test.p_value;
  c.replicates_a = replicates_a;
  c.replicates_b = replicates_b;
  return c;
}

ComparisonOutcome compare_reports(const ReportData& a, const ReportData& b, double alpha,
                                  std::string_view name_a, std::string_view name_b) {
  if (!(alpha > 0.0 && alpha <= 1.0)) {
    throw InputError(fmt::format("alpha {} is not in (0, 1]", alpha));
  }
  ComparisonOutcome outcome;
  std::map<std::string, const ReportRun*> runs_of_b;
  for (const ReportRun& run : b.runs) runs_of_b.emplace(run.id, &run);
  std::map<std::string, const ReportRun*> runs_of_a;
  for (const ReportRun& run : a.runs) runs_of_a.emplace(run.id, &run);

  for (const ReportRun& run_a : a.runs) {
    const auto found = runs_of_b.find(run_a.id);
    if (found == runs_of_b.end()) {
      outcome.only_in_a.push_back(run_a.id);
      continue;
    }
    const ReportRun& run_b = *found->second;
    const std::string why = why_not_compared(run_a, run_b, name_a, name_b);
    if (!why.empty()) {
      outcome.not_compared.push_back({.id = run_a.id, .reason = why});
      continue;
    }
    Comparison c = comparison_from(welch_two_sample(run_a.estimates, run_b.estimates), run_a.id,
                                   run_b.id, run_a.estimates.size(), run_b.estimates.size());
    c.estimator = run_a.estimator;
    c.integrand = run_a.integrand;
    c.alpha = alpha;
    outcome.comparisons.push_back(std::move(c));
  }
  for (const ReportRun& run_b : b.runs) {
    if (!runs_of_a.count(run_b.id)) outcome.only_in_b.push_back(run_b.id);
  }

  // Holm over the comparisons whose test is defined (a NaN p-value has no place in the order).
  std::vector<Comparison*> family;
  for (Comparison& c : outcome.comparisons) {
    if (std::isnan(c.p_value)) {
      c.result = "inconclusive";
      c.p_adjusted = c.p_value;
      c.min_detectable_difference = std::numeric_limits<double>::quiet_NaN();
      c.reason = "the test is undefined (the spread of the estimates is not finite)";
    } else {
      family.push_back(&c);
    }
  }
  std::vector<double> p_values;
  for (const Comparison* c : family) p_values.push_back(c->p_value);
  const std::vector<double> adjusted = holm_adjusted(p_values);
  const double share = alpha / static_cast<double>(std::max<std::size_t>(family.size(), 1));
  for (std::size_t i = 0; i < family.size(); ++i) {
    Comparison& c = *family[i];
    c.p_adjusted = adjusted[i];
    const bool differs = c.p_adjusted <= alpha;
    c.result = differs ? "biased" : "consistent";
    c.min_detectable_difference =
        detectable_multiplier(share, c.dof) * std::hypot(c.stderr_a, c.stderr_b);
    const std::string difference =
        fmt::format("mean({}) - mean({}) = {:.6g}, {:.3g} standard errors", name_a, name_b,
                    c.mean_a - c.mean_b, c.statistic);
    c.reason = differs
                   ? fmt::format("the means differ: {} (Holm-adjusted p = {:.3g} <= alpha = {})",
                                 difference, c.p_adjusted, alpha)
                   : fmt::format(
                         "no difference detected: {} (Holm-adjusted p = {:.3g} > alpha = {}); a "
                         "difference of {:.3g} would be found with 80% power",
                         difference, c.p_adjusted, alpha, c.min_detectable_difference);
  }

  if (a.seed && b.seed && *a.seed == *b.seed) {
    outcome.warnings.push_back(fmt::format(
        "{} and {} both used seed {}: runs with the same id drew the same random numbers, so "
        "their replicates are not independent samples and the p-values are not valid (unchanged "
        "code gives identical numbers); run one of them again with another --seed",
        name_a, name_b, *a.seed));
  }
  return outcome;
}

ComparisonOutcome compare_report_files(const std::filesystem::path& a,
                                       const std::filesystem::path& b, double alpha) {
  const ReportData report_a = read_report(a);
  const ReportData report_b = read_report(b);
  return compare_reports(report_a, report_b, alpha, a.string(), b.string());
}

namespace {

// A block comparison's fields: every scale with its power and requirement, and the tiles' figures
// under their earlier names (tile_*: the finest scale, which the page's map draws).
Json scales_json(const Comparison& c) {
  const std::vector<Comparison::BlockP> differing = blocks_differing(c);
  Json scales = Json::array();
  double factor = 0.0;  // the largest over the scales with a requirement
  bool met = true;
  std::optional<std::uint32_t> coarsest;
  for (std::uint32_t s = 0; s < c.scales.size(); ++s) {
    const Comparison::Scale& scale = c.scales[s];
    Json blocks = Json::array();
    for (const Comparison::BlockP& t : differing) {
      if (t.scale == s) blocks.push_back(Json::array({t.x, t.y, t.channel}));
    }
    if (!blocks.empty()) coarsest = scale.block;
    Json entry{{"block", scale.block},
               {"columns", scale.columns},
               {"rows", scale.rows},
               {"tests", scale.tests},
               {"bright_tests", scale.bright_tests},
               {"alpha_share", scale.alpha_share},
               {"relative_mdb", finite_or_null(scale.relative_mdb)},
               {"median_relative_mdb", finite_or_null(scale.median_relative_mdb)},
               {"required_mdb", nullptr},
               {"meets_requirement", nullptr},
               {"samples_factor_for_required_mdb", nullptr},
               {"min_p_adjusted", finite_or_null(scale.min_p_adjusted)},
               {"blocks_differing", blocks}};
    if (scale.required_mdb) {
      const double f = samples_factor(scale.relative_mdb, *scale.required_mdb);
      const bool meets = scale.relative_mdb <= *scale.required_mdb;  // false for NaN
      entry["required_mdb"] = *scale.required_mdb;
      entry["meets_requirement"] = meets;
      entry["samples_factor_for_required_mdb"] = finite_or_null(f);
      met = met && meets;
      factor = std::isnan(f) || std::isnan(factor) ? kNaN : std::max(factor, f);
    }
    scales.push_back(std::move(entry));
  }
  const Comparison::Scale& tiles = c.scales.front();
  Json tiles_differing = Json::array();
  for (const Comparison::BlockP& t : differing) {
    if (t.scale == 0) tiles_differing.push_back(Json::array({t.x, t.y, t.channel}));
  }
  return Json{{"tile_relative_mdb", finite_or_null(tiles.relative_mdb)},
              {"bright_tiles", tiles.bright_tests},
              {"tile_alpha_share", tiles.alpha_share},
              {"tile_columns", tiles.columns},
              {"tile_rows", tiles.rows},
              {"tiles_differing", tiles_differing},
              {"samples_factor_for_required_mdb", finite_or_null(factor)},
              {"requirements_met", met},
              {"coarsest_differing_block", coarsest ? Json(*coarsest) : Json(nullptr)},
              {"paired", c.paired},
              {"scales", scales}};
}

}  // namespace

nlohmann::ordered_json comparison_json(const Comparison& c) {
  Json out{{"a", c.a},
           {"b", c.b},
           {"test", c.test},
           {"statistic", finite_or_null(c.statistic)},
           {"p_value", finite_or_null(c.p_value)},
           {"p_adjusted", finite_or_null(c.p_adjusted)},
           {"alpha", c.alpha},
           {"result", c.result},
           {"expect", c.expect},
           {"estimator", c.estimator},
           {"integrand", c.integrand},
           {"dof", finite_or_null(c.dof)},
           {"reason", c.reason},
           {"mean_a", finite_or_null(c.mean_a)},
           {"mean_b", finite_or_null(c.mean_b)},
           {"stderr_a", finite_or_null(c.stderr_a)},
           {"stderr_b", finite_or_null(c.stderr_b)},
           {"replicates_a", c.replicates_a},
           {"replicates_b", c.replicates_b},
           {"min_detectable_difference", finite_or_null(c.min_detectable_difference)}};
  if (!c.scales.empty()) out.update(scales_json(c));
  return out;
}

std::vector<Comparison::BlockP> blocks_differing(const Comparison& c) {
  std::vector<Comparison::BlockP> out;
  if (c.result != "biased") return out;
  // p_value is the smallest block's p; 0 (a non-finite block) leaves no factor to scale by.
  const double factor = c.p_value > 0.0 ? c.p_adjusted / c.p_value : 1.0;
  for (const Comparison::BlockP& t : c.block_p_values) {
    if (t.p_adjusted <= c.p_value || t.p_adjusted * factor <= c.alpha) out.push_back(t);
  }
  return out;
}

nlohmann::ordered_json comparisons_json(const std::vector<Comparison>& comparisons) {
  Json out = Json::array();
  for (const Comparison& c : comparisons) out.push_back(comparison_json(c));
  return out;
}

nlohmann::ordered_json outcome_json(const ComparisonOutcome& outcome) {
  Json not_compared = Json::array();
  for (const UncomparedRun& run : outcome.not_compared) {
    not_compared.push_back(Json{{"id", run.id}, {"reason", run.reason}});
  }
  return Json{{"comparisons", comparisons_json(outcome.comparisons)},
              {"only_in_a", outcome.only_in_a},
              {"only_in_b", outcome.only_in_b},
              {"not_compared", not_compared},
              {"warnings", outcome.warnings}};
}

}  // namespace pcbench
