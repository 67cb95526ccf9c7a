#include "harness/plan/suite_file.h"

#include <fmt/format.h>

#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "base/errors.h"

namespace pcbench {
namespace {

using Json = nlohmann::json;

class SuiteParser {
 public:
  explicit SuiteParser(std::string file) : file_(std::move(file)) {}

  SuiteRequest parse(const std::string& text) {
    Json root;
    // JSON lets a key repeat and the last value silently win ("M": 4, "M": 64); refuse it.
    std::vector<std::set<std::string>> keys_of_open_objects;
    const auto refuse_duplicates = [&](int, Json::parse_event_t event, Json& parsed) {
      if (event == Json::parse_event_t::object_start) keys_of_open_objects.emplace_back();
      if (event == Json::parse_event_t::object_end) keys_of_open_objects.pop_back();
      if (event == Json::parse_event_t::key &&
          !keys_of_open_objects.back().insert(parsed.get<std::string>()).second) {
        throw InputError(fmt::format("{}: key '{}' appears twice in one object", file_,
                                     parsed.get<std::string>()));
      }
      return true;
    };
    try {
      root = Json::parse(text, refuse_duplicates);
    } catch (const Json::parse_error& e) {
      // e.byte is the offset of the error; turn it into a line and column.
      throw InputError(fmt::format("{}:{}: JSON syntax error: {}", file_,
                                   line_and_column(text, e.byte), e.what()));
    } catch (const Json::out_of_range& e) {
      // A number too large for a double ("samples": 1e999) is not a syntax error to the parser.
      throw InputError(json_number_error(text, file_, e.what()));
    }
    require_object(root, "");
    check_keys(root, "",
               {"name", "description", "defaults", "runs", "grid", "compare", "interleave",
                "strategy_images"});
    SuiteRequest suite;
    suite.name = root.contains("name") ? string_at(root["name"], "/name") : "unnamed";
    if (root.contains("compare")) {
      const std::string compare = string_at(root["compare"], "/compare");
      if (compare != "pairwise" && compare != "none") {
        fail("/compare",
             fmt::format("'{}' is not a comparison mode; valid: pairwise, none", compare));
      }
      suite.compare_pairwise = compare == "pairwise";
    }
    if (root.contains("interleave")) {
      if (!root["interleave"].is_boolean()) fail("/interleave", "must be true or false");
      suite.interleave = root["interleave"].get<bool>();
    }
    if (root.contains("strategy_images")) {
      if (!root["strategy_images"].is_boolean()) {
        fail("/strategy_images", "must be true or false");
      }
      suite.strategy_images = root["strategy_images"].get<bool>();
    }
    if (root.contains("defaults")) {
      const Json& defaults = root["defaults"];
      require_object(defaults, "/defaults");
      check_keys(defaults, "/defaults", {"samples", "seconds", "replicates", "seed"});
      suite.seconds = seconds_at(defaults, "/defaults");
      if (defaults.contains("samples")) {
        suite.samples = integer_at(defaults["samples"], "/defaults/samples", 1, kMaxSamples);
      }
      if (defaults.contains("replicates")) {
        suite.replicates = static_cast<std::uint32_t>(
            integer_at(defaults["replicates"], "/defaults/replicates", 2, kMaxReplicates));
      }
      if (defaults.contains("seed")) {
        suite.seed = integer_at(defaults["seed"], "/defaults/seed", 0,
                                std::numeric_limits<std::int64_t>::max());
      }
    }
    for (const char* section : {"runs", "grid"}) {
      if (!root.contains(section)) continue;
      const std::string where = fmt::format("/{}", section);
      const Json& rows = root[section];
      if (!rows.is_array()) fail(where, "must be an array");
      for (std::size_t i = 0; i < rows.size(); ++i) {
        suite.grids.push_back(
            row(rows[i], fmt::format("{}/{}", where, i), std::string(section) == "grid"));
      }
    }
    if (suite.grids.empty()) fail("", "the suite has no \"runs\" and no \"grid\" entries");
    return suite;
  }

 private:
  [[noreturn]] void fail(const std::string& pointer, const std::string& why) const {
    throw InputError(fmt::format("{}: {}: {}", file_, pointer.empty() ? "/" : pointer, why));
  }

  void require_object(const Json& value, const std::string& pointer) const {
    if (!value.is_object()) fail(pointer, "must be an object");
  }

  void check_keys(const Json& object, const std::string& pointer,
                  const std::vector<std::string>& valid) const {
    const std::set<std::string> allowed(valid.begin(), valid.end());
    for (const auto& item : object.items()) {
      if (!allowed.count(item.key())) {
        fail(pointer + "/" + item.key(),
             fmt::format("unknown key '{}'; valid keys: {}", item.key(), join_names(valid)));
      }
    }
  }

  std::string string_at(const Json& value, const std::string& pointer) const {
    if (!value.is_string()) fail(pointer, "must be a string");
    return value.get<std::string>();
  }

  std::uint64_t integer_at(const Json& value, const std::string& pointer, std::uint64_t min,
                           std::uint64_t max) const {
    if (!value.is_number_integer() || (value.is_number_integer() && !value.is_number_unsigned() &&
                                       value.get<std::int64_t>() < 0)) {
      fail(pointer, fmt::format("must be an integer in [{}, {}]", min, max));
    }
    const auto v = value.get<std::uint64_t>();
    if (v < min || v > max) fail(pointer, fmt::format("{} is out of range [{}, {}]", v, min, max));
    return v;
  }

  // A parameter value as text: strings as they are, numbers in their shortest exact form.
  std::string scalar_text(const Json& value, const std::string& pointer) const {
    if (value.is_string()) return value.get<std::string>();
    if (value.is_number() || value.is_boolean()) return value.dump();
    fail(pointer, "must be a string or a number");
  }

  // `value` or `[values...]` (lists only where `allow_list`).
  std::vector<std::string> texts(const Json& value, const std::string& pointer,
                                 bool allow_list) const {
    if (!value.is_array()) return {scalar_text(value, pointer)};
    if (!allow_list) fail(pointer, "a list is only allowed in \"grid\" entries");
    if (value.empty()) fail(pointer, "empty list");
    std::vector<std::string> out;
    for (std::size_t i = 0; i < value.size(); ++i) {
      out.push_back(scalar_text(value[i], fmt::format("{}/{}", pointer, i)));
    }
    return out;
  }

  // An equal-time budget ("seconds": CPU seconds per replicate), exclusive with
  // "samples" in the same object.
  std::optional<double> seconds_at(const Json& object, const std::string& pointer) const {
    if (!object.contains("seconds")) return std::nullopt;
    if (object.contains("samples")) {
      fail(pointer, "give \"samples\" or \"seconds\", not both");
    }
    const Json& value = object["seconds"];
    if (!value.is_number() || !(value.get<double>() >= kMinSecondsPerReplicate) ||
        value.get<double>() > kMaxSecondsPerReplicate) {
      fail(pointer + "/seconds", fmt::format("must be a number of seconds in [{:g}, {:.0e}]",
                                             kMinSecondsPerReplicate, kMaxSecondsPerReplicate));
    }
    return value.get<double>();
  }

  GridRequest row(const Json& value, const std::string& pointer, bool is_grid) const {
    require_object(value, pointer);
    check_keys(value, pointer,
               {"estimator", "integrand", "params", "samples", "seconds", "replicates", "expect"});
    const std::optional<double> seconds = seconds_at(value, pointer);
    GridRequest grid;
    grid.where = fmt::format("{}: {}", file_, pointer);
    if (!value.contains("estimator")) fail(pointer, "missing \"estimator\"");
    if (!value.contains("integrand")) fail(pointer, "missing \"integrand\"");
    grid.estimators = texts(value["estimator"], pointer + "/estimator", is_grid);
    grid.integrands = texts(value["integrand"], pointer + "/integrand", is_grid);
    if (value.contains("params")) {
      const Json& params = value["params"];
      require_object(params, pointer + "/params");
      for (const auto& item : params.items()) {
        grid.params[item.key()] = texts(item.value(), pointer + "/params/" + item.key(), is_grid);
      }
    }
    if (value.contains("samples")) {
      grid.samples = integer_at(value["samples"], pointer + "/samples", 1, kMaxSamples);
    }
    if (value.contains("replicates")) {
      grid.replicates = static_cast<std::uint32_t>(
          integer_at(value["replicates"], pointer + "/replicates", 2, kMaxReplicates));
    }
    if (value.contains("expect")) grid.expect = string_at(value["expect"], pointer + "/expect");
    grid.seconds = seconds;
    return grid;
  }

  std::string file_;
};

}  // namespace

SuiteRequest parse_suite(const std::string& text, const std::string& file_name) {
  return SuiteParser(file_name).parse(text);
}

SuiteRequest load_suite(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open the suite file", path));
  std::ostringstream text;
  text << in.rdbuf();
  return parse_suite(text.str(), path);
}

}  // namespace pcbench
