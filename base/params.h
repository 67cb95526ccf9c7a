// Typed parameters of estimators and integrands.
//
// Each registry entry declares its parameters (name, type, default, range or choices). Supplied
// values arrive as text (from `--param k=v` or a suite file) and are checked against the
// declaration before any work: an unknown key, a value of the wrong type or out of range is an
// InputError naming the valid choices. The resolved set, defaults filled in, is what a factory
// receives and what the report records as the effective parameters.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace pcbench {

enum class ParamType { kInt, kReal, kText, kChoice };

struct ParamSpec {
  std::string name = {};
  ParamType type = ParamType::kReal;
  std::string default_value = {};  // text form; empty with `required` means no default
  std::string description = {};
  std::vector<std::string> choices = {};  // kChoice only
  double min = -1e300;                    // kInt, kReal: inclusive bounds
  double max = 1e300;
  bool required = false;
  bool optional = false;  // may stay unset (e.g. an expression integrand's `exact`)
  // A parameter added to an estimator after runs were recorded: at this value (its text form)
  // it is left out of the run's id, so those runs keep their ids and random streams
  // (harness/plan/plan.cpp, assign_id).
  std::optional<std::string> omitted_from_id_at = std::nullopt;
};

using ParamValue = std::variant<std::int64_t, double, std::string>;

// Supplied, unchecked values: key -> text.
using ParamText = std::map<std::string, std::string>;

class ResolvedParams {
 public:
  bool has(const std::string& name) const { return values_.count(name) != 0; }
  std::int64_t integer(const std::string& name) const;
  double real(const std::string& name) const;
  const std::string& text(const std::string& name) const;
  const std::map<std::string, ParamValue>& values() const { return values_; }

  void set(const std::string& name, ParamValue value) { values_[name] = std::move(value); }

 private:
  const ParamValue& at(const std::string& name) const;
  std::map<std::string, ParamValue> values_;
};

// Canonical text of a value: integers in decimal, reals in the shortest form that reads back to
// the same double, text as is. Run ids hash this form.
std::string to_text(const ParamValue& value);

// Parses one supplied value against its declaration; `where` prefixes error messages.
ParamValue parse_param(const ParamSpec& spec, const std::string& text, const std::string& where);

// Resolves the keys of `supplied` that `specs` declares; fills defaults for the rest.
// Keys not in `specs` are ignored here: the caller checks that every key has an owner.
ResolvedParams resolve_params(std::span<const ParamSpec> specs, const ParamText& supplied,
                              const std::string& owner);

std::string describe_type(const ParamSpec& spec);

}  // namespace pcbench
