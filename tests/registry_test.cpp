#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "base/errors.h"
#include "base/params.h"
#include "estimators/registry.h"
#include "examples/examples.h"
#include "integrands/registry.h"

namespace pcbench {
namespace {

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

// docs/reference/INTERFACE.md: each `--param` key is read by exactly one of the estimator and the
// integrand.
TEST(RegistryParams, NoKeyIsDeclaredByBothAnEstimatorAndAnIntegrand) {
  std::set<std::string> estimator_keys;
  for (const EstimatorEntry& e : estimator_registry()) {
    for (const ParamSpec& spec : e.params) estimator_keys.insert(spec.name);
  }
  for (const IntegrandEntry& i : integrand_registry()) {
    for (const ParamSpec& spec : i.params) {
      EXPECT_EQ(estimator_keys.count(spec.name), 0u)
          << "parameter '" << spec.name << "' of integrand '" << i.name
          << "' is also declared by an estimator";
    }
  }
}

TEST(RegistryParams, NamesAreUniqueWithinEachEntry) {
  const auto check = [](const std::string& owner, const std::vector<ParamSpec>& specs) {
    std::set<std::string> names;
    for (const ParamSpec& spec : specs) {
      EXPECT_FALSE(spec.name.empty()) << owner;
      EXPECT_TRUE(names.insert(spec.name).second)
          << owner << " declares '" << spec.name << "' twice";
    }
  };
  for (const EstimatorEntry& e : estimator_registry()) check("estimator " + e.name, e.params);
  for (const IntegrandEntry& i : integrand_registry()) check("integrand " + i.name, i.params);
}

TEST(RegistryNames, UniqueWithinEachTable) {
  std::set<std::string> estimators, integrands;
  ASSERT_FALSE(estimator_registry().empty());
  ASSERT_FALSE(integrand_registry().empty());
  for (const EstimatorEntry& e : estimator_registry()) {
    EXPECT_FALSE(e.name.empty());
    EXPECT_TRUE(estimators.insert(e.name).second) << "estimator '" << e.name << "' twice";
  }
  for (const IntegrandEntry& i : integrand_registry()) {
    EXPECT_FALSE(i.name.empty());
    EXPECT_TRUE(integrands.insert(i.name).second) << "integrand '" << i.name << "' twice";
  }
}

TEST(RegistryEntries, EveryEntryHasADescriptionAndAFactory) {
  for (const EstimatorEntry& e : estimator_registry()) {
    EXPECT_FALSE(e.description.empty()) << "estimator " << e.name;
    EXPECT_TRUE(static_cast<bool>(e.make)) << "estimator " << e.name;
    for (const ParamSpec& spec : e.params) {
      EXPECT_FALSE(spec.description.empty()) << "estimator " << e.name << ", " << spec.name;
    }
  }
  for (const IntegrandEntry& i : integrand_registry()) {
    EXPECT_FALSE(i.description.empty()) << "integrand " << i.name;
    EXPECT_TRUE(static_cast<bool>(i.make)) << "integrand " << i.name;
    for (const ParamSpec& spec : i.params) {
      EXPECT_FALSE(spec.description.empty()) << "integrand " << i.name << ", " << spec.name;
    }
  }
}

// Every default is a valid value of its own declaration (a bad default would only show up when
// a user leaves the key out).
TEST(RegistryDefaults, EveryDefaultParsesUnderItsOwnSpec) {
  const auto check = [](const std::string& owner, const std::vector<ParamSpec>& specs) {
    for (const ParamSpec& spec : specs) {
      EXPECT_LE(spec.min, spec.max) << owner << ", " << spec.name;
      if (spec.type == ParamType::kChoice) {
        EXPECT_FALSE(spec.choices.empty()) << owner << ", " << spec.name;
      }
      if (spec.required || spec.optional) {
        // No default is needed; one that is given must still be valid.
        if (!spec.default_value.empty()) {
          EXPECT_NO_THROW(parse_param(spec, spec.default_value, owner)) << spec.name;
        }
        continue;
      }
      EXPECT_NO_THROW(parse_param(spec, spec.default_value, owner))
          << owner << ", " << spec.name << " = '" << spec.default_value << "'";
    }
  };
  for (const EstimatorEntry& e : estimator_registry()) check("estimator " + e.name, e.params);
  for (const IntegrandEntry& i : integrand_registry()) check("integrand " + i.name, i.params);
}

bool has_required(const std::vector<ParamSpec>& specs) {
  for (const ParamSpec& spec : specs) {
    if (spec.required) return true;
  }
  return false;
}

TEST(RegistryDefaults, EveryEntryWithoutRequiredParametersBuildsFromDefaults) {
  for (const EstimatorEntry& e : estimator_registry()) {
    if (has_required(e.params)) continue;
    const ResolvedParams params = resolve_params(e.params, {}, e.name);
    EXPECT_NE(e.make(params), nullptr) << "estimator " << e.name;
  }
  for (const IntegrandEntry& i : integrand_registry()) {
    if (has_required(i.params)) continue;
    const ResolvedParams params = resolve_params(i.params, {}, i.name);
    EXPECT_NE(i.make(params), nullptr) << "integrand " << i.name;
  }
}

// An entry's named configurations and the parameter sets of its scene tests name only parameters
// of its scene form, with valid values: resolve_params passes over a key it does not declare, so
// a misspelt one would silently leave the default.
TEST(RegistryDefaults, NamedParameterSetsNameOnlyTheirScenesParameters) {
  const std::vector<EstimatorEntry> examples = examples::example_entries();
  for (const auto* table : {&estimator_registry(), &scene_estimator_registry(), &examples}) {
    for (const EstimatorEntry& e : *table) {
      std::vector<NamedParams> sets = e.scene_configurations;
      sets.insert(sets.end(), e.scene_tests.weights.begin(), e.scene_tests.weights.end());
      sets.insert(sets.end(), e.scene_tests.renders.begin(), e.scene_tests.renders.end());
      if (!sets.empty()) {
        EXPECT_TRUE(e.renders_scenes()) << e.name;
      }
      for (const NamedParams& set : sets) {
        for (const auto& entry : set.params) {
          const std::string& key = entry.first;
          EXPECT_TRUE(std::any_of(e.scene_params.begin(), e.scene_params.end(),
                                  [&](const ParamSpec& spec) { return spec.name == key; }))
              << e.name << " " << set.name << ": " << key;
        }
        EXPECT_NO_THROW(resolve_params(e.scene_params, set.params, e.name))
            << e.name << " " << set.name;
      }
    }
  }
}

TEST(RegistryDefaults, ExactIntegrandsGiveAnExactReferenceFromTheirDefaults) {
  int exact_entries = 0;
  for (const IntegrandEntry& i : integrand_registry()) {
    if (!i.exact) continue;
    ++exact_entries;
    ASSERT_FALSE(has_required(i.params))
        << "integrand " << i.name << " is marked exact but has no usable defaults";
    const ResolvedParams params = resolve_params(i.params, {}, i.name);
    const Reference reference = i.make(params)->reference();
    EXPECT_EQ(reference.kind, ReferenceKind::kExact) << "integrand " << i.name;
    EXPECT_TRUE(std::isfinite(reference.value)) << "integrand " << i.name;
    EXPECT_EQ(reference.uncertainty, 0.0) << "integrand " << i.name;
  }
  EXPECT_GT(exact_entries, 0);
}

TEST(RegistryLookup, FindsEveryEntryByName) {
  for (const EstimatorEntry& e : estimator_registry()) {
    EXPECT_EQ(&find_estimator(e.name), &e);
  }
  for (const IntegrandEntry& i : integrand_registry()) {
    EXPECT_EQ(&find_integrand(i.name), &i);
  }
}

TEST(RegistryLookup, UnknownNamesListEveryValidName) {
  try {
    find_estimator("nope");
    FAIL() << "an unknown estimator was found";
  } catch (const InputError& e) {
    for (const EstimatorEntry& entry : estimator_registry()) {
      EXPECT_TRUE(contains(e.what(), entry.name)) << e.what();
    }
  }
  try {
    find_integrand("nope");
    FAIL() << "an unknown integrand was found";
  } catch (const InputError& e) {
    for (const IntegrandEntry& entry : integrand_registry()) {
      EXPECT_TRUE(contains(e.what(), entry.name)) << e.what();
    }
  }
}

}  // namespace
}  // namespace pcbench
