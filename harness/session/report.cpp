#include "harness/session/report.h"

#include <fmt/format.h>

#include <cmath>
#include <nlohmann/json.hpp>

#include "base/json_number.h"
#include "harness/run/replay.h"

namespace pcbench {
namespace {

using Json = nlohmann::ordered_json;

Json param_value(const ParamValue& value) {
  if (const auto* i = std::get_if<std::int64_t>(&value)) return *i;
  if (const auto* r = std::get_if<double>(&value)) return *r;
  return std::get<std::string>(value);
}

Json context_json(const Context& c) {
  Json dirty = nullptr;
  if (c.git_dirty == "true") dirty = true;
  if (c.git_dirty == "false") dirty = false;
  Json context{{"date", c.date},
               {"host", c.host},
               {"cpu", c.cpu},
               {"cores", c.cores},
               {"compiler", c.compiler},
               {"flags", c.flags},
               {"build_type", c.build_type},
               {"git_commit", c.git_commit},
               {"git_dirty", dirty},
               {"argv", c.argv},
               {"seed", c.seed},
               {"threads", c.threads},
               {"pcbench_version", c.version}};
  if (c.restored_runs) context["resumed"] = Json{{"restored_runs", *c.restored_runs}};
  if (c.ranks) context["mpi_ranks"] = *c.ranks;
  return context;
}

// The reference's dof is infinite for exact references by definition: written as null, not
// counted as a non-finite result.
Json reference_json(const Reference& reference, NumberWriter& numbers) {
  if (reference.kind == ReferenceKind::kNone) {
    return Json{{"value", nullptr}, {"kind", "none"}, {"uncertainty", nullptr}, {"dof", nullptr}};
  }
  return Json{{"value", numbers.number(reference.value, "reference/value")},
              {"kind", to_string(reference.kind)},
              {"uncertainty", numbers.number(reference.uncertainty, "reference/uncertainty")},
              {"dof", NumberWriter::optional_number(reference.dof)},
              {"magnitude", NumberWriter::optional_number(reference.magnitude)}};
}

// Figures of a test that was not made (no reference) are null by design; those of a test that
// was made are results, and a non-finite one is named.
Json verdict_json(const Verdict& v, NumberWriter& numbers) {
  const auto figure = [&](double value, const char* name) {
    return v.tested ? numbers.number(value, fmt::format("verdict/{}", name)) : Json(nullptr);
  };
  return Json{
      {"test", v.test},
      {"statistic", figure(v.statistic, "statistic")},
      {"dof", figure(v.dof, "dof")},
      {"p_value", figure(v.p_value, "p_value")},
      {"p_adjusted", figure(v.p_adjusted, "p_adjusted")},
      {"alpha", v.alpha},
      {"result", v.result},
      {"reason", v.reason},
      {"expect", v.expect},
      {"min_detectable_bias", figure(v.min_detectable_bias, "min_detectable_bias")},
      {"min_detectable_rel_bias",
       v.tested && v.reference_value != 0.0
           ? numbers.number(v.min_detectable_rel_bias, "verdict/min_detectable_rel_bias")
           : Json(nullptr)},
      {"min_detectable_bias_vs_mean_abs",
       v.tested && v.mean_abs != 0.0 ? numbers.number(v.min_detectable_bias_vs_mean_abs,
                                                      "verdict/min_detectable_bias_vs_mean_abs")
                                     : Json(nullptr)},
      {"rounding_bound", figure(v.rounding_bound, "rounding_bound")}};
}

// The report keeps the 16 largest |estimates| of a replicate (the tail fit used more).
constexpr std::size_t kReportedLargest = 16;
Json largest_abs(const std::vector<double>& largest) {
  return Json(std::vector<double>(
      largest.begin(),
      largest.begin() + static_cast<std::ptrdiff_t>(std::min(largest.size(), kReportedLargest))));
}

// The earlier stages of an escalated run (empty when it ran once).
Json escalation_json(const std::vector<RunRecord>& stages) {
  Json out = Json::array();
  for (const RunRecord& stage : stages) {
    const Verdict& v = *stage.verdict;
    out.push_back({{"id", stage.plan->id},
                   {"samples", stage.plan->samples},
                   {"p_value", NumberWriter::optional_number(v.p_value)},
                   {"alpha", v.alpha},
                   {"result", v.result},
                   {"reason", v.reason}});
  }
  return out;
}

// The effective parameters of the estimator and the integrand, in one object.
Json params_json(const ResolvedParams& resolved) {
  Json params = Json::object();
  for (const auto& [key, value] : resolved.values()) params[key] = param_value(value);
  return params;
}

Json params_json(const RunPlan& plan) {
  Json params = params_json(plan.estimator_params);
  params.update(params_json(plan.integrand_params));
  return params;
}

// Each replicate's figures. Where the samples of a replicate share a pool, their variance
// estimates nothing useful and is null.
Json replicates_json(const RunResult& result, NumberWriter& numbers) {
  Json replicates = Json::array();
  for (std::size_t r = 0; r < result.replicates.size(); ++r) {
    const ReplicateResult& rep = result.replicates[r];
    const std::string at = fmt::format("replicates/{}/", r);
    replicates.push_back(Json{
        {"estimate", numbers.number(rep.estimate, at + "estimate")},
        {"mean_abs", numbers.number(rep.mean_abs, at + "mean_abs")},
        {"variance", result.independent_samples ? numbers.number(rep.variance, at + "variance")
                                                : Json(nullptr)},
        {"n", rep.n},
        {"nonfinite", rep.nonfinite},
        {"seconds", rep.seconds},
        {"cpu_seconds", rep.cpu_seconds},
        {"largest_abs", largest_abs(rep.largest)},
        {"nonzero", rep.nonzero},
        {"effective_samples", numbers.number(rep.effective_samples, at + "effective_samples")}});
  }
  return replicates;
}

// The figures over all replicates. Without a reference the errors are undefined (null by
// design); so is a relative MSE against a zero reference, and an RMSE slope from fewer than three
// points of the series.
Json aggregates_json(const Aggregates& a, const Reference& reference, NumberWriter& numbers) {
  const bool has_reference = reference.kind != ReferenceKind::kNone;
  const auto with_reference = [&](double value, const char* name) {
    return has_reference ? numbers.number(value, fmt::format("aggregates/{}", name))
                         : Json(nullptr);
  };
  return Json{
      {"mean", numbers.number(a.mean, "aggregates/mean")},
      {"stderr", numbers.number(a.stderr_of_mean, "aggregates/stderr")},
      {"bias", with_reference(a.bias, "bias")},
      {"rmse", with_reference(a.rmse, "rmse")},
      {"rel_mse", has_reference && reference.value != 0.0
                      ? numbers.number(a.rel_mse, "aggregates/rel_mse")
                      : Json(nullptr)},
      {"seconds_per_sample", numbers.number(a.seconds_per_sample, "aggregates/seconds_per_sample")},
      {"efficiency", numbers.number(a.efficiency, "aggregates/efficiency")},
      {"efficiency_low", numbers.number(a.efficiency_low, "aggregates/efficiency_low")},
      {"efficiency_high", numbers.number(a.efficiency_high, "aggregates/efficiency_high")},
      {"rmse_slope", has_reference && a.series.size() >= 3
                         ? numbers.number(a.rmse_slope, "aggregates/rmse_slope")
                         : Json(nullptr)},
      {"mean_abs", numbers.number(a.mean_abs, "aggregates/mean_abs")}};
}

// The convergence series: the replicates' mean and errors at each checkpoint.
Json series_json(const Aggregates& a, bool has_reference, NumberWriter& numbers) {
  Json series = Json::array();
  for (std::size_t k = 0; k < a.series.size(); ++k) {
    const SeriesPoint& p = a.series[k];
    const std::string at = fmt::format("series/{}/", k);
    series.push_back({{"samples", p.samples},
                      {"mean", numbers.number(p.mean, at + "mean")},
                      {"stderr", numbers.number(p.stderr_of_mean, at + "stderr")},
                      {"bias", has_reference ? numbers.number(p.bias, at + "bias") : Json(nullptr)},
                      {"rmse", has_reference ? numbers.number(p.rmse, at + "rmse") : Json(nullptr)},
                      {"cpu_seconds", p.cpu_seconds},
                      {"seconds", p.seconds}});
  }
  return series;
}

// Where the first non-finite sample was, with the command that replays it; null when there was
// none.
Json first_nonfinite_json(const RunPlan& plan, const RunResult& result, std::uint64_t seed) {
  if (!result.first_nonfinite) return nullptr;
  Json where{{"seed", seed},
             {"replicate", result.first_nonfinite->replicate},
             {"sample", result.first_nonfinite->sample}};
  if (const auto command = replay_command(plan, *result.first_nonfinite)) {
    where["replay"] = *command;
  }
  return where;
}

// Scene pixels of one iteration share its light pool (and plain's W·H light paths); an analytic
// estimator's pool is its parameter, else each sample draws afresh.
std::string pool_of(const RunPlan& plan) {
  if (plan.render) return "shared";
  return plan.estimator_params.has("pool") ? plan.estimator_params.text("pool") : "fresh";
}

// How the run's samples were chosen: given, or an equal-time budget and its pilot's measurement.
Json budget_json(const RunPlan& plan) {
  return Json{{"seconds", plan.seconds ? Json(*plan.seconds) : Json(nullptr)},
              {"pilot_samples", plan.pilot_samples},
              {"pilot_cpu_seconds_per_sample", plan.pilot_cpu_per_sample}};
}

// The sample diagnostics behind an inconclusive verdict (harness/run/diagnostics.h).
Json diagnostics_json(const SampleDiagnostics& d) {
  return Json{{"tail_shape", NumberWriter::optional_number(d.tail_shape)},
              {"tail_size", d.tail_size},
              {"largest_share", NumberWriter::optional_number(d.largest_share)},
              {"nonzero_samples", d.nonzero},
              {"min_effective_samples", NumberWriter::optional_number(d.min_effective_samples)}};
}

// The work counters, then a scene run's own (rays by kind, skipped connections, BVH builds).
Json counters_json(const RunResult& result) {
  const Counters& c = result.counters;
  Json counters{{"camera_paths", c.camera_paths},
                {"light_paths", c.light_paths},
                {"connections", c.connections},
                {"importance_evaluations", c.importance_evaluations}};
  for (const auto& [name, count] : result.scene_counters) counters[name] = count;
  return counters;
}

// One run in the report's form. The parts that can hold non-finite results are written first, in
// a fixed order, so that `nonfinite_fields` names them in the same order every time.
Json run_json(const RunRecord& record, std::uint64_t seed) {
  const RunPlan& plan = *record.plan;
  const RunResult& result = record.result;
  NumberWriter numbers;
  const Json replicates = replicates_json(result, numbers);
  Json aggregates = nullptr;
  Json series = Json::array();
  if (result.status == RunStatus::kOk || result.status == RunStatus::kInvalid) {
    aggregates = aggregates_json(record.aggregates, result.reference, numbers);
    series = series_json(record.aggregates, result.reference.kind != ReferenceKind::kNone, numbers);
  }
  Json run{{"id", plan.id},
           {"estimator", plan.estimator->name},
           {"integrand", plan.integrand->name},
           {"params", params_json(plan)},
           // The integrand's share of `params`: what makes runs on the same integrand comparable.
           {"integrand_params", params_json(plan.integrand_params)},
           {"status", to_string(result.status)},
           {"error", result.error.empty() ? Json(nullptr) : Json(result.error)},
           {"reference", reference_json(result.reference, numbers)},
           {"samples", plan.samples},
           {"replicates_requested", plan.replicates},
           {"pool", pool_of(plan)},
           {"streams", plan.paired_streams ? "paired" : "own"},
           {"wall_seconds", result.wall_seconds},
           {"replicates", replicates},
           {"aggregates", aggregates},
           {"verdict", record.verdict ? verdict_json(*record.verdict, numbers) : Json(nullptr)},
           {"escalation", escalation_json(record.earlier_stages)},
           {"budget", budget_json(plan)},
           {"diagnostics", diagnostics_json(record.diagnostics)},
           {"first_nonfinite", first_nonfinite_json(plan, result, seed)},
           {"counters", counters_json(result)},
           {"series", series}};
  if (record.image) run["image"] = *record.image;
  run["nonfinite_fields"] = numbers.nonfinite();
  return run;
}

Json exact_check_json(const ExactRecord& record) {
  const RunPlan& plan = *record.plan;
  const ExactCheck& c = record.check;
  return Json{{"id", plan.id},
              {"estimator", plan.estimator->name},
              {"integrand", plan.integrand->name},
              {"params", params_json(plan)},
              {"applicable", c.applicable},
              {"M", c.M},
              {"K", c.K},
              {"cases", c.cases},
              {"sequences", c.sequences},
              {"expectation_failures", c.expectation_failures},
              {"max_scaled_error", NumberWriter::optional_number(c.max_scaled_error)},
              {"tolerance", kExactTolerance},
              {"support_violations", c.support_violations},
              {"max_multiplicity_error", NumberWriter::optional_number(c.max_multiplicity_error)},
              {"result", c.result},
              {"expect", record.expect},
              {"reason", c.reason}};
}

}  // namespace

std::string report_json(const Context& context, const std::string& suite_name,
                        const std::vector<RunRecord>& runs, const ReportSections& sections) {
  Json runs_json = Json::array();
  for (const RunRecord& record : runs) runs_json.push_back(run_json(record, context.seed));
  Json report{{"schema_version", kSchemaVersion},
              {"suite", suite_name},
              {"context", context_json(context)},
              {"runs", runs_json},
              {"comparisons", sections.comparisons}};
  if (!sections.exact_checks.empty()) {
    Json checks = Json::array();
    for (const ExactRecord& record : sections.exact_checks) {
      checks.push_back(exact_check_json(record));
    }
    report["exact_checks"] = checks;
  }
  if (sections.calibration) report["calibration"] = *sections.calibration;
  if (sections.tile_calibration) report["tile_calibration"] = *sections.tile_calibration;
  if (!sections.external.empty()) report["external"] = sections.external;
  if (sections.image_sets) report["image_sets"] = *sections.image_sets;
  if (!sections.efficiency_ratios.empty()) {
    report["efficiency_ratios"] = sections.efficiency_ratios;
  }
  return report.dump(2) + "\n";
}

nlohmann::json verdict_to_json(const Verdict& verdict) {
  NumberWriter numbers;
  return verdict_json(verdict, numbers);
}

}  // namespace pcbench
