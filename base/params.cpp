#include "base/params.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "base/errors.h"

namespace pcbench {

const ParamValue& ResolvedParams::at(const std::string& name) const {
  const auto it = values_.find(name);
  if (it == values_.end()) throw std::logic_error("parameter not resolved: " + name);
  return it->second;
}

std::int64_t ResolvedParams::integer(const std::string& name) const {
  return std::get<std::int64_t>(at(name));
}

double ResolvedParams::real(const std::string& name) const {
  const ParamValue& value = at(name);
  if (const auto* i = std::get_if<std::int64_t>(&value)) return static_cast<double>(*i);
  return std::get<double>(value);
}

const std::string& ResolvedParams::text(const std::string& name) const {
  return std::get<std::string>(at(name));
}

std::string to_text(const ParamValue& value) {
  if (const auto* i = std::get_if<std::int64_t>(&value)) return fmt::format("{}", *i);
  // -0 and 0 are the same parameter value, and must give the same run id.
  if (const auto* r = std::get_if<double>(&value)) return fmt::format("{}", *r == 0.0 ? 0.0 : *r);
  return std::get<std::string>(value);
}

std::string describe_type(const ParamSpec& spec) {
  const auto range = [&](const char* type) {
    std::string out = type;
    if (spec.min > -1e300 && spec.max < 1e300) {
      out += fmt::format(" in [{}, {}]", spec.min, spec.max);
    } else if (spec.min > -1e300) {
      out += fmt::format(" >= {}", spec.min);
    } else if (spec.max < 1e300) {
      out += fmt::format(" <= {}", spec.max);
    }
    return out;
  };
  switch (spec.type) {
    case ParamType::kInt:
      return range("integer");
    case ParamType::kReal:
      return range("number");
    case ParamType::kText:
      return "text";
    case ParamType::kChoice:
      return "one of " + join_names(spec.choices, " | ");
  }
  return "?";
}

ParamValue parse_param(const ParamSpec& spec, const std::string& text, const std::string& where) {
  const auto fail = [&](const std::string& why) {
    return InputError(fmt::format("{}: parameter '{}' = '{}': {}; expected {}", where, spec.name,
                                  text, why, describe_type(spec)));
  };
  // strtod and strtoll skip leading blanks; refuse them so that " 3" and "3 " are treated alike.
  if (!text.empty() && std::isspace(static_cast<unsigned char>(text.front())) &&
      (spec.type == ParamType::kInt || spec.type == ParamType::kReal)) {
    throw fail("leading blank");
  }
  const auto check_range = [&](double v) {
    if (v < spec.min || v > spec.max) throw fail("out of range");
  };
  switch (spec.type) {
    case ParamType::kInt: {
      errno = 0;
      char* end = nullptr;
      const long long v = std::strtoll(text.c_str(), &end, 10);
      if (text.empty() || *end != '\0' || errno == ERANGE) throw fail("not an integer");
      check_range(static_cast<double>(v));
      return static_cast<std::int64_t>(v);
    }
    case ParamType::kReal: {
      errno = 0;
      char* end = nullptr;
      const double v = std::strtod(text.c_str(), &end);
      if (text.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(v)) {
        throw fail("not a finite number");
      }
      check_range(v);
      return v;
    }
    case ParamType::kText:
      if (text.empty()) throw fail("empty");
      return text;
    case ParamType::kChoice:
      if (std::find(spec.choices.begin(), spec.choices.end(), text) == spec.choices.end()) {
        throw fail("not a valid choice");
      }
      return text;
  }
  throw fail("unknown type");
}

ResolvedParams resolve_params(std::span<const ParamSpec> specs, const ParamText& supplied,
                              const std::string& owner) {
  ResolvedParams resolved;
  for (const ParamSpec& spec : specs) {
    const auto it = supplied.find(spec.name);
    if (it != supplied.end()) {
      resolved.set(spec.name, parse_param(spec, it->second, owner));
    } else if (spec.required) {
      throw InputError(fmt::format("{}: parameter '{}' is required ({}: {})", owner, spec.name,
                                   describe_type(spec), spec.description));
    } else if (!spec.optional) {
      resolved.set(spec.name, parse_param(spec, spec.default_value, owner + " (default)"));
    }
  }
  return resolved;
}

}  // namespace pcbench
