#include "harness/session/summary.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <ostream>
#include <string>

namespace pcbench {
namespace {

constexpr std::size_t kColumns = 9;
using Row = std::array<std::string, kColumns>;

// Parameters as "k=v k=v": the pool size and draws always (they tell the rows of a grid
// apart), the others only where they differ from their declared default.
std::string changed_params(const std::vector<ParamSpec>& specs, const ResolvedParams& params) {
  std::string out;
  for (const ParamSpec& spec : specs) {
    if (!params.has(spec.name)) continue;
    const std::string value = to_text(params.values().at(spec.name));
    const bool always = spec.name == "M" || spec.name == "K";
    if (!always && !spec.default_value.empty() &&
        value == to_text(parse_param(spec, spec.default_value, "default"))) {
      continue;
    }
    if (!out.empty()) out += ' ';
    out += spec.name + "=" + value;
  }
  constexpr std::size_t kMaxWidth = 40;
  if (out.size() > kMaxWidth) out = out.substr(0, kMaxWidth - 3) + "...";
  return out.empty() ? "-" : out;
}

std::string number(double value) {
  return std::isfinite(value) ? fmt::format("{:.6g}", value) : std::string("-");
}

Row row_of(const RunRecord& record) {
  const RunPlan& plan = *record.plan;
  const RunResult& result = record.result;
  std::string params = changed_params(plan.estimator->params, plan.estimator_params);
  const std::string integrand_params =
      changed_params(plan.integrand->params, plan.integrand_params);
  if (params == "-") {
    params = integrand_params;
  } else if (integrand_params != "-") {
    params += " " + integrand_params;
  }
  const bool has_stats = result.status == RunStatus::kOk || result.status == RunStatus::kInvalid;
  const Aggregates& a = record.aggregates;
  const std::string estimate =
      has_stats ? fmt::format("{} ± {}", number(a.mean), number(a.stderr_of_mean)) : "-";
  const std::string reference =
      result.reference.kind == ReferenceKind::kNone ? "-" : number(result.reference.value);
  // Fixed point up to 1e4 standard errors; beyond (a run that almost never hit its integrand has
  // a standard error near 0), three digits and an exponent keep the column narrow.
  const double z = a.bias / a.stderr_of_mean;
  const std::string bias_in_se =
      has_stats && std::isfinite(a.bias) && a.stderr_of_mean > 0.0
          ? (std::fabs(z) < 1e4 ? fmt::format("{:+.2f}", z) : fmt::format("{:+.2e}", z))
          : "-";
  // The smallest bias this row could see (80% power), as a share of ∫∫ |f|.
  const std::string detectable =
      record.verdict && std::isfinite(record.verdict->min_detectable_bias_vs_mean_abs)
          ? fmt::format("{:.2g}%", 100.0 * record.verdict->min_detectable_bias_vs_mean_abs)
          : "-";
  std::string verdict = to_string(result.status);
  if (record.verdict) {
    verdict = record.verdict->result;
    if (record.verdict->result != record.verdict->expect) {
      verdict += fmt::format(" (expected {})", record.verdict->expect);
    }
  }
  return {plan.estimator->name,
          plan.integrand->name,
          params,
          estimate,
          reference,
          bias_in_se,
          detectable,
          fmt::format("{:.2f}", result.wall_seconds),
          verdict};
}

}  // namespace

void print_summary(const std::vector<RunRecord>& records, std::ostream& out) {
  std::vector<Row> rows = {{"estimator", "integrand", "params", "mean ± stderr", "reference",
                            "bias/se", "mdb/|f|", "seconds", "verdict"}};
  for (const RunRecord& record : records) rows.push_back(row_of(record));
  // Widths in code points: "±" is two bytes in UTF-8 but one column on screen.
  const auto columns = [](const std::string& text) {
    return static_cast<std::size_t>(std::count_if(text.begin(), text.end(), [](char c) {
      return (static_cast<unsigned char>(c) & 0xC0) != 0x80;
    }));
  };
  std::array<std::size_t, kColumns> width{};
  for (const Row& row : rows) {
    for (std::size_t c = 0; c < kColumns; ++c) width[c] = std::max(width[c], columns(row[c]));
  }
  for (const Row& row : rows) {
    std::string line;
    for (std::size_t c = 0; c < kColumns; ++c) {
      line += row[c];
      if (c + 1 < kColumns) line += std::string(width[c] - columns(row[c]) + 2, ' ');
    }
    out << line << "\n";
  }
  // Rows that are not simply consistent say why.
  for (const RunRecord& record : records) {
    const Verdict* v = record.verdict ? &*record.verdict : nullptr;
    const bool plain_pass = v != nullptr && v->result == "consistent" && v->expect == "consistent";
    if (plain_pass && record.earlier_stages.empty()) continue;
    std::string why = v != nullptr ? v->result + ": " + v->reason : record.result.error;
    if (!record.earlier_stages.empty()) {
      std::string budgets;
      for (const StageRecord& stage : record.earlier_stages) {
        budgets += fmt::format("{} ({}) -> ", stage.samples, stage.result);
      }
      why = fmt::format("escalated {}{} samples; {}", budgets, record.plan->samples, why);
    }
    out << fmt::format("  {} × {} ({}): {}\n", record.plan->estimator->name,
                       record.plan->integrand->name, record.plan->id, why);
  }
}

}  // namespace pcbench

namespace pcbench {

void print_efficiency_ratios(const nlohmann::json& ratios, std::ostream& out) {
  for (const nlohmann::json& r : ratios) {
    out << fmt::format(
        "  efficiency of {} on {}: {:.3g}x [{:.3g}, {:.3g}] ({:.0f}%; variance {:.3g}x, cost "
        "{:.3g}x{})\n",
        r["estimator"].get<std::string>(), r["integrand"].get<std::string>(),
        r["ratio"].get<double>(), r["low"].get<double>(), r["high"].get<double>(),
        100.0 * r["level"].get<double>(), r["variance_ratio"].get<double>(),
        r["cost_ratio"].get<double>(), r["interleaved"].get<bool>() ? ", interleaved" : "");
  }
}

}  // namespace pcbench
