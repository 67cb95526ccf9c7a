#include "harness/session/summary.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <ostream>
#include <string>

namespace pcbench {
namespace {

constexpr std::size_t kColumns = 9;
// Beyond this many runs the table no longer shows the answer at a glance: a matrix follows it.
constexpr std::size_t kMatrixAfterRows = 20;
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

// Equal-time efficiency: 1 / (relative MSE at one CPU second) for scene runs (their image
// section), 1 / (variance × seconds per sample) otherwise; 0 when there is none.
double efficiency_of(const RunRecord& record) {
  if (record.image) {
    const auto found = record.image->find("efficiency");
    return found != record.image->end() && found->is_number() ? found->get<double>() : 0.0;
  }
  const double e = record.aggregates.efficiency;
  return std::isfinite(e) && e > 0.0 ? e : 0.0;
}

std::string estimator_label(const RunRecord& record) {
  const std::string params =
      changed_params(record.plan->estimator->params, record.plan->estimator_params);
  return record.plan->estimator->name + (params == "-" ? "" : " " + params);
}

std::string integrand_label(const RunRecord& record) {
  const std::string params =
      changed_params(record.plan->integrand->params, record.plan->integrand_params);
  return record.plan->integrand->name + (params == "-" ? "" : " " + params);
}

// "ok 1.7x": the verdict (ok, BIASED, inconcl., or the status of a run without one; "!" when it
// is not what was expected) and the efficiency relative to the column's baseline.
std::string matrix_cell(const RunRecord& record, double baseline) {
  std::string text = to_string(record.result.status);
  if (record.verdict) {
    const std::string& r = record.verdict->result;
    text = r == "consistent" ? "ok" : r == "biased" ? "BIASED" : "inconcl.";
    if (r != record.verdict->expect) text += "!";
  }
  const double e = efficiency_of(record);
  if (baseline > 0.0 && e > 0.0) text += fmt::format(" {:.2g}x", e / baseline);
  return text;
}

// The answer at a glance when the table is long: estimator × integrand, each cell the run's
// verdict and its equal-time efficiency relative to the column's first run not expected biased
// (the same matrix as the top of the page, results/plot/answer_view.py).
void print_matrix(const std::vector<RunRecord>& records, std::ostream& out) {
  // A column is named by its integrand, and by its parameters only where another column has the
  // same integrand (an expression's text would make the column as wide as the table).
  std::map<std::string, std::vector<std::string>> labels_of;
  for (const RunRecord& record : records) {
    auto& labels = labels_of[record.plan->integrand->name];
    const std::string label = integrand_label(record);
    if (std::find(labels.begin(), labels.end(), label) == labels.end()) labels.push_back(label);
  }
  const auto column_of = [&](const RunRecord& record) {
    const std::string& name = record.plan->integrand->name;
    return labels_of[name].size() > 1 ? integrand_label(record) : name;
  };
  std::vector<std::string> rows, columns;
  std::map<std::string, double> baseline;
  std::map<std::pair<std::string, std::string>, std::string> cells;
  for (const RunRecord& record : records) {
    const std::string column = column_of(record);
    if (std::find(columns.begin(), columns.end(), column) == columns.end()) {
      columns.push_back(column);
    }
    const bool honest = !record.verdict || record.verdict->expect != "biased";
    if (!baseline.contains(column) && honest && efficiency_of(record) > 0.0) {
      baseline[column] = efficiency_of(record);
    }
  }
  for (const RunRecord& record : records) {
    const std::string row = estimator_label(record);
    if (std::find(rows.begin(), rows.end(), row) == rows.end()) rows.push_back(row);
    const std::string column = column_of(record);
    std::string& cell = cells[{row, column}];
    if (!cell.empty()) cell += ", ";
    cell += matrix_cell(record, baseline.contains(column) ? baseline[column] : 0.0);
  }
  std::size_t row_width = 0;
  for (const std::string& row : rows) row_width = std::max(row_width, row.size());
  std::vector<std::size_t> width;
  for (const std::string& column : columns) {
    std::size_t w = column.size();
    for (const std::string& row : rows) w = std::max(w, cells[{row, column}].size());
    width.push_back(w);
  }
  out << fmt::format(
      "\nverdicts (ok, BIASED, inconcl.; ! not as expected) and equal-time "
      "efficiency relative to the first honest run per column:\n");
  std::string head(row_width, ' ');
  for (std::size_t c = 0; c < columns.size(); ++c) {
    head += "  " + columns[c] + std::string(width[c] - columns[c].size(), ' ');
  }
  out << head << "\n";
  for (const std::string& row : rows) {
    std::string line = row + std::string(row_width - row.size(), ' ');
    for (std::size_t c = 0; c < columns.size(); ++c) {
      const std::string& cell = cells[{row, columns[c]}];
      line += "  " + (cell.empty() ? std::string("-") : cell) +
              std::string(width[c] - std::max<std::size_t>(cell.size(), 1), ' ');
    }
    out << line << "\n";
  }
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
  if (records.size() > kMatrixAfterRows) print_matrix(records, out);
  // Rows that are not simply consistent say why.
  for (const RunRecord& record : records) {
    const Verdict* v = record.verdict ? &*record.verdict : nullptr;
    const bool plain_pass = v != nullptr && v->result == "consistent" && v->expect == "consistent";
    if (plain_pass && record.earlier_stages.empty()) continue;
    std::string why = v != nullptr ? v->result + ": " + v->reason : record.result.error;
    if (!record.earlier_stages.empty()) {
      std::string budgets;
      for (const RunRecord& stage : record.earlier_stages) {
        budgets += fmt::format("{} ({}) -> ", stage.plan->samples, stage.verdict->result);
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
