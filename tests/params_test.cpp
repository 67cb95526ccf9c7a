#include "base/params.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "base/errors.h"
#include "base/rng.h"

namespace pcbench {
namespace {

const ParamSpec kIntSpec{.name = "light_dims",
                         .type = ParamType::kInt,
                         .default_value = "1",
                         .description = "dimensions",
                         .min = 1,
                         .max = 32};
const ParamSpec kRealSpec{.name = "center",
                          .type = ParamType::kReal,
                          .default_value = "0.5",
                          .description = "shift",
                          .min = 0,
                          .max = 1};
const ParamSpec kUnboundedRealSpec{
    .name = "exact", .type = ParamType::kReal, .description = "exact value"};
const ParamSpec kTextSpec{.name = "f", .type = ParamType::kText, .description = "expression"};
const ParamSpec kChoiceSpec{.name = "pool",
                            .type = ParamType::kChoice,
                            .default_value = "fresh",
                            .description = "pool sharing",
                            .choices = {"fresh", "shared"}};

// The InputError message of parse_param(spec, text), or "" when it does not throw.
std::string parse_error(const ParamSpec& spec, const std::string& text) {
  try {
    parse_param(spec, text, "somewhere");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// ---------------------------------------------------------------------------------------------
// parse_param: integers

TEST(ParamsParseInt, AcceptsDecimalIntegersInsideTheInclusiveRange) {
  EXPECT_EQ(std::get<std::int64_t>(parse_param(kIntSpec, "1", "w")), 1);
  EXPECT_EQ(std::get<std::int64_t>(parse_param(kIntSpec, "17", "w")), 17);
  EXPECT_EQ(std::get<std::int64_t>(parse_param(kIntSpec, "32", "w")), 32);
  const ParamSpec wide{.name = "k", .type = ParamType::kInt};
  EXPECT_EQ(std::get<std::int64_t>(parse_param(wide, "-5", "w")), -5);
  EXPECT_EQ(std::get<std::int64_t>(parse_param(wide, "0", "w")), 0);
}

TEST(ParamsParseInt, RejectsOutOfRangeNamingTheRange) {
  for (const char* text : {"0", "33", "-1", "1000000"}) {
    const std::string message = parse_error(kIntSpec, text);
    ASSERT_FALSE(message.empty()) << text;
    EXPECT_NE(message.find("out of range"), std::string::npos) << message;
    EXPECT_NE(message.find("[1, 32]"), std::string::npos) << message;
    EXPECT_NE(message.find("'light_dims'"), std::string::npos) << message;
    EXPECT_NE(message.find(std::string("'") + text + "'"), std::string::npos) << message;
    EXPECT_EQ(message.rfind("somewhere", 0), 0u) << message;
  }
}

TEST(ParamsParseInt, RejectsWrongTypeEmptyAndTrailingGarbage) {
  for (const char* text : {"", "3x", "3.5", "3.0", "1e1", "x", "three", "3 ", "0x10", "--3"}) {
    const std::string message = parse_error(kIntSpec, text);
    EXPECT_NE(message.find("not an integer"), std::string::npos)
        << "input '" << text << "': " << message;
  }
}

TEST(ParamsParseInt, RejectsValuesThatOverflowSixtyFourBits) {
  const ParamSpec wide{.name = "k", .type = ParamType::kInt};
  EXPECT_NE(parse_error(wide, "99999999999999999999").find("not an integer"), std::string::npos);
  EXPECT_NE(parse_error(wide, "-99999999999999999999").find("not an integer"), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// parse_param: reals

TEST(ParamsParseReal, AcceptsFiniteNumbersInsideTheInclusiveRange) {
  EXPECT_EQ(std::get<double>(parse_param(kRealSpec, "0", "w")), 0.0);
  EXPECT_EQ(std::get<double>(parse_param(kRealSpec, "1", "w")), 1.0);
  EXPECT_EQ(std::get<double>(parse_param(kRealSpec, "0.1", "w")), 0.1);
  EXPECT_EQ(std::get<double>(parse_param(kRealSpec, "2.5e-1", "w")), 0.25);
  EXPECT_EQ(std::get<double>(parse_param(kUnboundedRealSpec, "-1e300", "w")), -1e300);
}

TEST(ParamsParseReal, RejectsOutOfRange) {
  for (const char* text : {"-0.001", "1.0000001", "2"}) {
    const std::string message = parse_error(kRealSpec, text);
    EXPECT_NE(message.find("out of range"), std::string::npos) << text << ": " << message;
    EXPECT_NE(message.find("[0, 1]"), std::string::npos) << message;
  }
}

TEST(ParamsParseReal, RejectsNonFiniteValues) {
  for (const char* text : {"nan", "NaN", "-nan", "inf", "-inf", "Infinity", "1e400", "-1e400"}) {
    const std::string message = parse_error(kUnboundedRealSpec, text);
    EXPECT_NE(message.find("not a finite number"), std::string::npos)
        << "input '" << text << "': " << message;
  }
}

TEST(ParamsParseReal, RejectsWrongTypeEmptyAndTrailingGarbage) {
  for (const char* text : {"", "3x", "0.5.5", "x", "1,5", "0.5 ", "1e", "fresh"}) {
    const std::string message = parse_error(kUnboundedRealSpec, text);
    EXPECT_NE(message.find("not a finite number"), std::string::npos)
        << "input '" << text << "': " << message;
  }
}

// ---------------------------------------------------------------------------------------------
// parse_param: text and choices

TEST(ParamsParseText, KeepsTextAsGivenAndRejectsEmpty) {
  EXPECT_EQ(std::get<std::string>(parse_param(kTextSpec, "x0 * y0 + 1", "w")), "x0 * y0 + 1");
  const std::string message = parse_error(kTextSpec, "");
  EXPECT_NE(message.find("empty"), std::string::npos) << message;
  EXPECT_NE(message.find("'f'"), std::string::npos) << message;
}

TEST(ParamsParseChoice, AcceptsOnlyListedChoicesAndNamesThem) {
  EXPECT_EQ(std::get<std::string>(parse_param(kChoiceSpec, "shared", "w")), "shared");
  EXPECT_EQ(std::get<std::string>(parse_param(kChoiceSpec, "fresh", "w")), "fresh");
  for (const char* text : {"", "Shared", "shared ", "share", "1"}) {
    const std::string message = parse_error(kChoiceSpec, text);
    EXPECT_NE(message.find("not a valid choice"), std::string::npos) << text << ": " << message;
    EXPECT_NE(message.find("fresh | shared"), std::string::npos) << message;
  }
}

// ---------------------------------------------------------------------------------------------
// resolve_params

std::vector<ParamSpec> example_specs() {
  return {
      {.name = "f", .type = ParamType::kText, .description = "expression", .required = true},
      {.name = "light_dims",
       .type = ParamType::kInt,
       .default_value = "2",
       .description = "dims",
       .min = 1,
       .max = 32},
      {.name = "center",
       .type = ParamType::kReal,
       .default_value = "0.25",
       .description = "shift",
       .min = 0,
       .max = 1},
      {.name = "pool",
       .type = ParamType::kChoice,
       .default_value = "fresh",
       .description = "pool",
       .choices = {"fresh", "shared"}},
      {.name = "exact", .type = ParamType::kReal, .description = "exact value", .optional = true},
  };
}

TEST(ParamsResolve, FillsDefaultsWithTheirTypes) {
  const std::vector<ParamSpec> specs = example_specs();
  const ResolvedParams resolved = resolve_params(specs, {{"f", "x0"}}, "owner");
  EXPECT_EQ(resolved.text("f"), "x0");
  EXPECT_EQ(resolved.integer("light_dims"), 2);
  EXPECT_EQ(resolved.real("center"), 0.25);
  EXPECT_EQ(resolved.text("pool"), "fresh");
  EXPECT_EQ(resolved.values().size(), 4u);  // everything but the unset optional `exact`
}

TEST(ParamsResolve, SuppliedValuesOverrideDefaults) {
  const std::vector<ParamSpec> specs = example_specs();
  const ResolvedParams resolved = resolve_params(
      specs,
      {{"f", "x0"}, {"light_dims", "5"}, {"center", "0.75"}, {"pool", "shared"}, {"exact", "0.5"}},
      "owner");
  EXPECT_EQ(resolved.integer("light_dims"), 5);
  EXPECT_EQ(resolved.real("center"), 0.75);
  EXPECT_EQ(resolved.text("pool"), "shared");
  ASSERT_TRUE(resolved.has("exact"));
  EXPECT_EQ(resolved.real("exact"), 0.5);
}

TEST(ParamsResolve, MissingRequiredParameterIsAnInputErrorNamingIt) {
  const std::vector<ParamSpec> specs = example_specs();
  try {
    resolve_params(specs, {{"light_dims", "3"}}, "integrand 'expr'");
    FAIL() << "a missing required parameter was accepted";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("'f'"), std::string::npos) << message;
    EXPECT_NE(message.find("required"), std::string::npos) << message;
    EXPECT_NE(message.find("integrand 'expr'"), std::string::npos) << message;
  }
}

TEST(ParamsResolve, OptionalParameterStaysUnsetWhenNotSupplied) {
  const std::vector<ParamSpec> specs = example_specs();
  const ResolvedParams resolved = resolve_params(specs, {{"f", "x0"}}, "owner");
  EXPECT_FALSE(resolved.has("exact"));
  EXPECT_THROW(resolved.real("exact"), std::logic_error);
}

TEST(ParamsResolve, BadSuppliedValueIsAnInputErrorNamingOwnerAndParameter) {
  const std::vector<ParamSpec> specs = example_specs();
  try {
    resolve_params(specs, {{"f", "x0"}, {"light_dims", "3x"}}, "integrand 'expr'");
    FAIL() << "a malformed integer was accepted";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("integrand 'expr'"), std::string::npos) << message;
    EXPECT_NE(message.find("'light_dims'"), std::string::npos) << message;
  }
}

TEST(ParamsResolve, IgnoresKeysTheSpecsDoNotDeclare) {
  const std::vector<ParamSpec> specs = example_specs();
  const ResolvedParams resolved =
      resolve_params(specs, {{"f", "x0"}, {"M", "not even a number"}}, "owner");
  EXPECT_FALSE(resolved.has("M"));
}

TEST(ParamsResolve, RealAccessorWidensIntegers) {
  ResolvedParams resolved;
  resolved.set("n", std::int64_t{7});
  EXPECT_EQ(resolved.real("n"), 7.0);
  EXPECT_EQ(resolved.integer("n"), 7);
}

// ---------------------------------------------------------------------------------------------
// to_text

TEST(ParamsToText, CanonicalFormsOfNumbersAndText) {
  EXPECT_EQ(to_text(ParamValue{0.1}), "0.1");
  EXPECT_EQ(to_text(ParamValue{4.0}), "4");
  EXPECT_EQ(to_text(ParamValue{-2.5}), "-2.5");
  EXPECT_EQ(to_text(ParamValue{0.1 + 0.2}), "0.30000000000000004");
  EXPECT_EQ(to_text(ParamValue{std::int64_t{42}}), "42");
  EXPECT_EQ(to_text(ParamValue{std::int64_t{-7}}), "-7");
  EXPECT_EQ(to_text(ParamValue{std::numeric_limits<std::int64_t>::max()}), "9223372036854775807");
  EXPECT_EQ(to_text(ParamValue{std::numeric_limits<std::int64_t>::min()}), "-9223372036854775808");
  EXPECT_EQ(to_text(ParamValue{std::string("x0 * y0")}), "x0 * y0");
}

// Equal values spelled differently must get the same canonical text (run ids hash it).
TEST(ParamsToText, DifferentSpellingsOfOneRealGiveOneText) {
  const std::string canonical = to_text(parse_param(kUnboundedRealSpec, "4", "w"));
  EXPECT_EQ(canonical, "4");
  for (const char* spelling : {"4.0", "4.", "4e0", "0.4e1", "+4", "4.000"}) {
    EXPECT_EQ(to_text(parse_param(kUnboundedRealSpec, spelling, "w")), canonical) << spelling;
  }
}

// The canonical form is the shortest one that reads back to the same double.
TEST(ParamsToText, RealsReadBackExactly) {
  RandomStream rng({.key = 2024});
  for (int i = 0; i < 2000; ++i) {
    const double magnitude = std::pow(10.0, 40.0 * rng.uniform() - 20.0);
    const double value = (rng.uniform() < 0.5 ? -1.0 : 1.0) * magnitude * rng.uniform();
    const std::string text = to_text(ParamValue{value});
    EXPECT_EQ(std::strtod(text.c_str(), nullptr), value) << text;
  }
}

}  // namespace
}  // namespace pcbench
