#include "integrands/expression.h"

#include <gtest/gtest.h>
#include <muParser.h>

#include <barrier>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "base/errors.h"
#include "base/rng.h"
#include "integrands/point_integrand.h"
#include "integrands/registry.h"

namespace pcbench {
namespace {

ResolvedParams expression_params(const ParamText& supplied) {
  const std::vector<ParamSpec> specs = ExpressionModel::params();
  return resolve_params(specs, supplied, "integrand 'expr'");
}

ExpressionModel model(const ParamText& supplied) {
  return ExpressionModel(expression_params(supplied));
}

// The InputError message of building the model, or "" when it builds.
std::string model_error(const ParamText& supplied) {
  try {
    model(supplied);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

std::vector<std::string> lines_of(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// Checks that `message` shows `expression` with a caret under character `position`.
void expect_caret(const std::string& message, const std::string& expression, std::size_t position) {
  const std::vector<std::string> lines = lines_of(message);
  std::size_t at = lines.size();
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i] == "  " + expression) at = i;
  }
  ASSERT_LT(at + 1, lines.size()) << "no expression line followed by a caret line in:\n" << message;
  EXPECT_EQ(lines[at + 1], "  " + std::string(position, ' ') + "^") << message;
  EXPECT_TRUE(contains(message, "position " + std::to_string(position))) << message;
}

TEST(ExpressionEvaluate, ProductOfOneLightAndOneCameraVariable) {
  ExpressionModel m = model({{"f", "x0*y0"}});
  EXPECT_EQ(m.light_dims(), 1);
  EXPECT_EQ(m.camera_dims(), 1);
  const double points[][2] = {{0.5, 0.25}, {0.0, 0.9}, {1.0, 1.0}, {0.3, 0.7}};
  for (const auto& p : points) {
    EXPECT_DOUBLE_EQ(m.f(&p[0], &p[1]), p[0] * p[1]) << p[0] << ", " << p[1];
  }
}

TEST(ExpressionEvaluate, FunctionsOfTheVariables) {
  ExpressionModel m = model({{"f", "sin(x0) + exp(-y0) + sqrt(x0*y0)"}});
  const double x = 0.4, y = 0.8;
  EXPECT_DOUBLE_EQ(m.f(&x, &y), std::sin(0.4) + std::exp(-0.8) + std::sqrt(0.4 * 0.8));
}

TEST(ExpressionEvaluate, SeveralDimensionsOnEachSide) {
  ExpressionModel m = model({{"f", "x0 + 10*x1 + 100*y0 + 1000*y1 + 10000*y2"},
                             {"light_dims", "2"},
                             {"camera_dims", "3"}});
  EXPECT_EQ(m.light_dims(), 2);
  EXPECT_EQ(m.camera_dims(), 3);
  const double x[] = {0.125, 0.25};
  const double y[] = {0.5, 0.75, 0.375};
  EXPECT_DOUBLE_EQ(m.f(x, y), 0.125 + 2.5 + 50.0 + 750.0 + 3750.0);
}

TEST(ExpressionEvaluate, ConstantExpressionIgnoresThePoint) {
  ExpressionModel m = model({{"f", "2.5"}});
  const double x = 0.1, y = 0.2;
  EXPECT_EQ(m.f(&x, &y), 2.5);
}

TEST(ExpressionConstants, PiAndEAreTheNearestDoubles) {
  const double x = 0.3, y = 0.6;
  EXPECT_EQ(model({{"f", "_pi"}}).f(&x, &y), std::numbers::pi);
  EXPECT_EQ(model({{"f", "_e"}}).f(&x, &y), std::numbers::e);
  EXPECT_EQ(model({{"f", "_pi + 0*x0*y0"}}).f(&x, &y), std::numbers::pi);
}

TEST(ExpressionConstants, EveryConstantOfMuparserIsDefinedAgain) {
  // The constants pcbench defines at full precision; one muparser defines beyond these (a newer
  // version) would keep muparser's value, which may be short (its _pi is 3.141592653589 in a GCC
  // build), until it is added to ExpressionModel and here.
  const std::map<std::string, double> redefined = {{"_pi", std::numbers::pi},
                                                   {"_e", std::numbers::e}};
  const mu::Parser plain;
  ASSERT_FALSE(plain.GetConst().empty()) << "muparser defines no constants: nothing is checked";
  const double x = 0.3, y = 0.6;
  for (const auto& [name, muparser_value] : plain.GetConst()) {
    const auto found = redefined.find(name);
    if (found == redefined.end()) {
      ADD_FAILURE() << "muparser defines " << name << " = " << muparser_value
                    << ", which pcbench does not define again";
      continue;
    }
    EXPECT_EQ(model({{"f", name}}).f(&x, &y), found->second) << name;
  }
}

TEST(ExpressionErrors, SyntaxErrorShowsPositionCaretAndVariables) {
  const std::string message = model_error({{"f", "x0 +* y0"}});
  ASSERT_FALSE(message.empty()) << "the syntax error was not reported";
  EXPECT_TRUE(contains(message, "parameter 'f'")) << message;
  EXPECT_TRUE(contains(message, "variables: x0, y0")) << message;
  expect_caret(message, "x0 +* y0", 4);  // the unexpected '*'
}

TEST(ExpressionErrors, UnknownVariableShowsPositionCaretAndVariables) {
  const std::string message = model_error({{"f", "x0*z0"}});
  ASSERT_FALSE(message.empty()) << "the unknown variable was not reported";
  EXPECT_TRUE(contains(message, "z0")) << message;
  EXPECT_TRUE(contains(message, "variables: x0, y0 (light_dims=1, camera_dims=1)")) << message;
  expect_caret(message, "x0*z0", 3);
}

TEST(ExpressionErrors, VariableBeyondTheDeclaredDimensionsIsUnknown) {
  const std::string message = model_error({{"f", "x2"}, {"light_dims", "2"}});
  ASSERT_FALSE(message.empty()) << "x2 was accepted with light_dims=2";
  EXPECT_TRUE(contains(message, "variables: x0, x1, y0 (light_dims=2, camera_dims=1)")) << message;
  expect_caret(message, "x2", 0);

  const std::string camera = model_error({{"f", "x0 + y1"}});
  ASSERT_FALSE(camera.empty()) << "y1 was accepted with camera_dims=1";
  expect_caret(camera, "x0 + y1", 5);
}

TEST(ExpressionErrors, SeveralValuesPointAtTheCommaBetweenThem) {
  const std::string message = model_error({{"f", "x0, y0"}});
  ASSERT_FALSE(message.empty()) << "x0, y0 was accepted (muparser returns two values)";
  EXPECT_TRUE(contains(message,
                       "integrand 'expr', parameter 'f', position 2: ',' outside a "
                       "function's arguments separates several expressions"))
      << message;
  EXPECT_TRUE(contains(message, "variables: x0, y0")) << message;
  expect_caret(message, "x0, y0", 2);
  // The comma outside the function's parentheses, not the one between its arguments.
  expect_caret(model_error({{"f", "min(x0, y0), x0"}}), "min(x0, y0), x0", 11);
  expect_caret(model_error({{"f", " x0 ,y0"}}), " x0 ,y0", 4);
  expect_caret(model_error({{"f", "1e-3*x0,2.5"}}), "1e-3*x0,2.5", 7);
}

TEST(ExpressionErrors, AssignmentPointsAtTheEquals) {
  const std::string message = model_error({{"f", "x0=2"}});
  ASSERT_FALSE(message.empty()) << "the assignment x0=2 was accepted";
  EXPECT_TRUE(contains(message,
                       "integrand 'expr', parameter 'f', position 2: '=' assigns to a "
                       "variable"))
      << message;
  expect_caret(message, "x0=2", 2);
  expect_caret(model_error({{"f", "(x0=2)+1"}}), "(x0=2)+1", 3);
  expect_caret(model_error({{"f", "y0 == 1 + (x0 = 0.5)"}}), "y0 == 1 + (x0 = 0.5)", 14);
  EXPECT_THROW(model({{"f", "x0=2"}}), InputError);
  EXPECT_THROW(model({{"f", "x0, y0"}}), InputError);
}

TEST(ExpressionEvaluate, CommasBetweenArgumentsAndComparisonsStayValid) {
  const double x = 0.25, y = 0.75;
  EXPECT_EQ(model({{"f", "min(x0, y0)"}}).f(&x, &y), 0.25);
  EXPECT_EQ(model({{"f", "max(x0, y0, 0.5)"}}).f(&x, &y), 0.75);
  EXPECT_EQ(model({{"f", "sum(x0, y0) + avg(x0,y0)"}}).f(&x, &y), 1.5);
  EXPECT_EQ(model({{"f", "min(max(x0, y0), 0.5)"}}).f(&x, &y), 0.5);
  EXPECT_EQ(model({{"f", "atan2(y0, x0)"}}).f(&x, &y), std::atan2(0.75, 0.25));
  EXPECT_EQ(model({{"f", "x0 == y0"}}).f(&x, &y), 0.0);
  EXPECT_EQ(model({{"f", "x0 != y0"}}).f(&x, &y), 1.0);
  EXPECT_EQ(model({{"f", "x0 <= y0"}}).f(&x, &y), 1.0);
  EXPECT_EQ(model({{"f", "x0 >= y0"}}).f(&x, &y), 0.0);
  EXPECT_EQ(model({{"f", "x0 < y0 ? min(x0, 1) : y0"}}).f(&x, &y), 0.25);
}

TEST(ExpressionErrors, ErrorIsAnInputErrorSoItIsBadInput) {
  EXPECT_THROW(model({{"f", "x0 +* y0"}}), InputError);
  EXPECT_THROW(model({{"f", "x0 y0"}}), InputError);
  EXPECT_THROW(model({{"f", "(x0"}}), InputError);
}

TEST(ExpressionCopy, CopiesEvaluateIndependently) {
  ExpressionModel original = model({{"f", "x0 - 2*y0"}});
  ExpressionModel copy(original);
  ExpressionModel copy_of_copy(copy);
  // Interleaved: a copy whose parser still read the original's variables would return the
  // original's last inputs.
  for (int i = 0; i < 20; ++i) {
    const double xa = 0.01 * i, ya = 0.5;
    const double xb = 0.9, yb = 0.02 * i;
    const double xc = 0.3 + 0.01 * i, yc = 0.1;
    EXPECT_DOUBLE_EQ(original.f(&xa, &ya), xa - 2 * ya) << i;
    EXPECT_DOUBLE_EQ(copy.f(&xb, &yb), xb - 2 * yb) << i;
    EXPECT_DOUBLE_EQ(copy_of_copy.f(&xc, &yc), xc - 2 * yc) << i;
    EXPECT_DOUBLE_EQ(original.f(&xa, &ya), xa - 2 * ya) << i;
  }
}

TEST(ExpressionCopy, CopyOutlivesTheOriginal) {
  std::optional<ExpressionModel> original(model({{"f", "x0*x1 + y0"}, {"light_dims", "2"}}));
  ExpressionModel copy(*original);
  original.reset();  // a copy bound to the original's variables would now read freed memory
  const double x[] = {0.5, 0.5};
  const double y = 0.125;
  EXPECT_DOUBLE_EQ(copy.f(x, &y), 0.375);
}

TEST(ExpressionReference, ExactWhenGivenNoneOtherwise) {
  const ExpressionModel with_exact = model({{"f", "x0*y0"}, {"exact", "0.25"}});
  const Reference exact = with_exact.reference();
  EXPECT_EQ(exact.kind, ReferenceKind::kExact);
  EXPECT_EQ(exact.value, 0.25);
  EXPECT_EQ(exact.uncertainty, 0.0);

  const ExpressionModel without = model({{"f", "x0*y0"}});
  const Reference none = without.reference();
  EXPECT_EQ(none.kind, ReferenceKind::kNone);
  EXPECT_TRUE(std::isnan(none.value));

  const ExpressionModel copied(with_exact);
  EXPECT_EQ(copied.reference().kind, ReferenceKind::kExact);
  EXPECT_EQ(copied.reference().value, 0.25);
}

TEST(ExpressionReference, ExactZeroIsStillExact) {
  const ExpressionModel m = model({{"f", "x0 - 0.5"}, {"exact", "0"}});
  EXPECT_EQ(m.reference().kind, ReferenceKind::kExact);
  EXPECT_EQ(m.reference().value, 0.0);
}

TEST(ExpressionReference, IntegrandFromTheRegistryReportsIt) {
  const IntegrandEntry& entry = find_integrand("expr");
  const std::unique_ptr<Integrand> integrand =
      entry.make(expression_params({{"f", "x0*y0"}, {"exact", "0.25"}}));
  EXPECT_EQ(integrand->reference().kind, ReferenceKind::kExact);
  EXPECT_EQ(integrand->reference().value, 0.25);
}

// Evaluates f over `rounds` batches (all pairs of 16 light and 16 camera paths each) with one
// workspace, returning every value in order.
std::vector<double> evaluate_rounds(const Integrand& integrand, std::uint32_t rounds,
                                    std::barrier<>* start) {
  const std::unique_ptr<PathWorkspace> workspace = integrand.make_workspace();
  constexpr std::uint32_t kPaths = 16;
  std::vector<PathPair> pairs;
  for (std::uint32_t l = 0; l < kPaths; ++l) {
    for (std::uint32_t c = 0; c < kPaths; ++c) pairs.push_back({l, c});
  }
  std::vector<double> batch(pairs.size());
  std::vector<double> all;
  all.reserve(std::size_t{rounds} * pairs.size());
  if (start != nullptr) start->arrive_and_wait();
  for (std::uint32_t round = 0; round < rounds; ++round) {
    workspace->clear();
    workspace->sample_paths(PathSide::kLight, {.key = 99, .purpose = StreamPurpose::kLightPool},
                            round, 1, kPaths);
    workspace->sample_paths(PathSide::kCamera, {.key = 99, .purpose = StreamPurpose::kCameraPath},
                            round * kPaths, kPaths, 1);
    workspace->connect(pairs, batch);
    all.insert(all.end(), batch.begin(), batch.end());
  }
  return all;
}

TEST(ExpressionThreads, WorkspacesOnTwoThreadsMatchOneThread) {
  const PointIntegrand<ExpressionModel> integrand(model(
      {{"f", "sin(3*x0) * x1 + y0^2 - exp(-y1) * x0"}, {"light_dims", "2"}, {"camera_dims", "2"}}));
  constexpr std::uint32_t kRounds = 1500;
  const std::vector<double> expected = evaluate_rounds(integrand, kRounds, nullptr);
  ASSERT_EQ(expected.size(), std::size_t{kRounds} * 256);
  // The values are not all the same (the check below would be vacuous otherwise).
  EXPECT_NE(expected.front(), expected.back());

  std::barrier<> start(2);
  std::vector<double> first, second;
  std::thread a([&] { first = evaluate_rounds(integrand, kRounds, &start); });
  std::thread b([&] { second = evaluate_rounds(integrand, kRounds, &start); });
  a.join();
  b.join();
  EXPECT_TRUE(first == expected) << "thread 1 differs from the single-thread values";
  EXPECT_TRUE(second == expected) << "thread 2 differs from the single-thread values";
}

TEST(ExpressionThreads, SingleThreadValuesAreTheExpressionAtTheSampledPoints) {
  // Cross-check the workspace against a direct evaluation of the same points.
  const PointIntegrand<ExpressionModel> integrand(model({{"f", "x0 * y0 + 1"}}));
  const std::unique_ptr<PathWorkspace> workspace = integrand.make_workspace();
  workspace->sample_paths(PathSide::kLight, {.key = 5, .purpose = StreamPurpose::kLightPool}, 0, 1,
                          4);
  workspace->sample_paths(PathSide::kCamera, {.key = 5, .purpose = StreamPurpose::kCameraPath}, 0,
                          4, 1);
  const std::vector<PathPair> pairs = {{0, 0}, {1, 2}, {3, 3}};
  std::vector<double> values(pairs.size());
  workspace->connect(pairs, values);
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    RandomStream light(
        {.key = 5, .purpose = StreamPurpose::kLightPool, .sample = 0, .path = pairs[i].light});
    RandomStream camera(
        {.key = 5, .purpose = StreamPurpose::kCameraPath, .sample = pairs[i].camera, .path = 0});
    EXPECT_DOUBLE_EQ(values[i], light.uniform() * camera.uniform() + 1) << i;
  }
}

}  // namespace
}  // namespace pcbench
