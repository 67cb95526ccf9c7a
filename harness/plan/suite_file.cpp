#include "harness/plan/suite_file.h"

#include <fmt/format.h>

#include <limits>

#include "base/json_input.h"
#include "base/text_file.h"

namespace pcbench {
namespace {

using Json = JsonInput::Json;

const std::vector<std::string> kTopKeys = {
    "name",    "description", "defaults",        "runs",        "grid",
    "compare", "interleave",  "strategy_images", "require_mdb", "paired"};
const std::vector<std::string> kDefaultsKeys = {"samples", "seconds", "replicates", "seed"};
const std::vector<std::string> kRowKeys = {"estimator", "integrand",  "params", "samples",
                                           "seconds",   "replicates", "expect"};
const std::vector<std::string> kCompareModes = {"pairwise", "none"};

class SuiteParser {
 public:
  explicit SuiteParser(std::string file) : in_(std::move(file)) {}

  SuiteRequest parse(const std::string& text) {
    const Json root = in_.parse(text);
    in_.require_object(root, "");
    in_.check_keys(root, "", kTopKeys);
    SuiteRequest suite;
    suite.name = root.contains("name") ? in_.string_at(root["name"], "/name") : "unnamed";
    if (root.contains("compare")) {
      suite.compare_pairwise = in_.choice_at(root["compare"], "/compare", "comparison mode",
                                             kCompareModes) == "pairwise";
    }
    if (root.contains("interleave")) {
      suite.interleave = in_.boolean_at(root["interleave"], "/interleave");
    }
    if (root.contains("paired")) suite.paired = in_.boolean_at(root["paired"], "/paired");
    if (root.contains("strategy_images")) {
      suite.strategy_images = in_.boolean_at(root["strategy_images"], "/strategy_images");
    }
    if (root.contains("require_mdb")) {
      const Json& requirements = root["require_mdb"];
      in_.require_object(requirements, "/require_mdb");
      for (const auto& [scale, value] : requirements.items()) {
        const std::string pointer = JsonInput::member("/require_mdb", scale);
        const std::string where = fmt::format("{}: {}", in_.source(), pointer);
        if (value.is_null()) {
          suite.scale_requirements.drop(scale, where);
        } else {
          suite.scale_requirements.set(scale, in_.number_at(value, pointer), where);
        }
      }
    }
    if (root.contains("defaults")) {
      const Json& defaults = root["defaults"];
      in_.require_object(defaults, "/defaults");
      in_.check_keys(defaults, "/defaults", kDefaultsKeys);
      suite.seconds = seconds_at(defaults, "/defaults");
      if (defaults.contains("samples")) {
        suite.samples = in_.integer_at(defaults["samples"], "/defaults/samples", 1, kMaxSamples);
      }
      if (defaults.contains("replicates")) {
        suite.replicates = static_cast<std::uint32_t>(
            in_.integer_at(defaults["replicates"], "/defaults/replicates", 2, kMaxReplicates));
      }
      if (defaults.contains("seed")) {
        suite.seed = in_.integer_at(defaults["seed"], "/defaults/seed", 0,
                                    std::numeric_limits<std::int64_t>::max());
      }
    }
    for (const char* section : {"runs", "grid"}) {
      if (!root.contains(section)) continue;
      const std::string where = JsonInput::member("", section);
      const Json& rows = root[section];
      in_.require_array(rows, where);
      for (std::size_t i = 0; i < rows.size(); ++i) {
        suite.grids.push_back(
            row(rows[i], JsonInput::element(where, i), std::string(section) == "grid"));
      }
    }
    if (suite.grids.empty()) in_.fail("", "the suite has no \"runs\" and no \"grid\" entries");
    return suite;
  }

 private:
  // A parameter value as text: strings as they are, numbers in their shortest exact form.
  std::string scalar_text(const Json& value, const std::string& pointer) const {
    if (value.is_string()) return value.get<std::string>();
    if (value.is_number() || value.is_boolean()) return value.dump();
    in_.fail(pointer,
             fmt::format("must be a string or a number, not {}", JsonInput::excerpt(value)));
  }

  // `value` or `[values...]` (lists only where `allow_list`).
  std::vector<std::string> texts(const Json& value, const std::string& pointer,
                                 bool allow_list) const {
    if (!value.is_array()) return {scalar_text(value, pointer)};
    if (!allow_list) in_.fail(pointer, "a list is only allowed in \"grid\" entries");
    if (value.empty()) in_.fail(pointer, "empty list");
    std::vector<std::string> out;
    for (std::size_t i = 0; i < value.size(); ++i) {
      out.push_back(scalar_text(value[i], JsonInput::element(pointer, i)));
    }
    return out;
  }

  // An equal-time budget ("seconds": CPU seconds per replicate), exclusive with
  // "samples" in the same object.
  std::optional<double> seconds_at(const Json& object, const std::string& pointer) const {
    if (!object.contains("seconds")) return std::nullopt;
    if (object.contains("samples")) {
      in_.fail(pointer, "give \"samples\" or \"seconds\", not both");
    }
    const Json& value = object["seconds"];
    if (!value.is_number() || !(value.get<double>() >= kMinSecondsPerReplicate) ||
        value.get<double>() > kMaxSecondsPerReplicate) {
      in_.fail(
          pointer + "/seconds",
          fmt::format("must be a number of seconds in [{:g}, {:.0e}], not {}",
                      kMinSecondsPerReplicate, kMaxSecondsPerReplicate, JsonInput::excerpt(value)));
    }
    return value.get<double>();
  }

  GridRequest row(const Json& value, const std::string& pointer, bool is_grid) const {
    in_.require_object(value, pointer);
    in_.check_keys(value, pointer, kRowKeys);
    const std::optional<double> seconds = seconds_at(value, pointer);
    GridRequest grid;
    grid.where = fmt::format("{}: {}", in_.source(), pointer);
    const Json& estimator = in_.required(value, pointer, "estimator");
    const Json& integrand = in_.required(value, pointer, "integrand");
    grid.estimators = texts(estimator, pointer + "/estimator", is_grid);
    grid.integrands = texts(integrand, pointer + "/integrand", is_grid);
    if (value.contains("params")) {
      const Json& params = value["params"];
      in_.require_object(params, pointer + "/params");
      for (const auto& item : params.items()) {
        grid.params[item.key()] =
            texts(item.value(), JsonInput::member(pointer + "/params", item.key()), is_grid);
      }
    }
    if (value.contains("samples")) {
      grid.samples = in_.integer_at(value["samples"], pointer + "/samples", 1, kMaxSamples);
    }
    if (value.contains("replicates")) {
      grid.replicates = static_cast<std::uint32_t>(
          in_.integer_at(value["replicates"], pointer + "/replicates", 2, kMaxReplicates));
    }
    if (value.contains("expect")) {
      grid.expect = in_.string_at(value["expect"], pointer + "/expect");
    }
    grid.seconds = seconds;
    return grid;
  }

  JsonInput in_;
};

}  // namespace

SuiteRequest parse_suite(const std::string& text, const std::string& file_name) {
  return SuiteParser(file_name).parse(text);
}

SuiteRequest load_suite(const std::string& path) {
  return parse_suite(read_text_file(path, "the suite file"), path);
}

}  // namespace pcbench
