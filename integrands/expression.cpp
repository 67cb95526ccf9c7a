#include "integrands/expression.h"

#include <fmt/format.h>
#include <muParser.h>

#include <algorithm>
#include <numbers>
#include <optional>

#include "base/errors.h"
#include "integrands/expression_syntax.h"
#include "integrands/point_integrand.h"

namespace pcbench {

std::vector<ParamSpec> ExpressionModel::params() {
  std::vector<ParamSpec> specs = {
      {.name = "f",
       .type = ParamType::kText,
       .description = "muparser expression in x0.. (light side) and y0.. (camera side)",
       .required = true}};
  for (ParamSpec& spec : point_dimension_params()) specs.push_back(std::move(spec));
  specs.push_back({.name = "exact",
                   .type = ParamType::kReal,
                   .description = "exact value of the integral, if known",
                   .optional = true});
  return specs;
}

ExpressionModel::ExpressionModel(const ResolvedParams& params)
    : expression_(params.text("f")),
      light_dims_(static_cast<int>(params.integer("light_dims"))),
      camera_dims_(static_cast<int>(params.integer("camera_dims"))),
      exact_(params.has("exact") ? params.real("exact") : 0.0),
      has_exact_(params.has("exact")) {
  // muparser parses lazily: evaluate once now so that a syntax error, an unknown variable or what
  // f must not hold (expression_syntax.h) is bad input before any run starts, not a failure
  // inside one (or a silently different integrand).
  std::optional<ExpressionProblem> problem;
  try {
    bind();
    std::fill_n(variables_.get(), light_dims_ + camera_dims_, 0.5);
    parser_->Eval();
    problem = unsupported_construct(*parser_);
  } catch (const mu::Parser::exception_type& e) {
    problem = ExpressionProblem{.position = e.GetPos(), .message = e.GetMsg()};
  }
  if (!problem) return;
  // muparser may report the position one past the end of the text; keep the caret on it.
  const int pos = std::clamp(problem->position, 0, static_cast<int>(expression_.size()));
  std::vector<std::string> names;
  for (int i = 0; i < light_dims_; ++i) names.push_back(fmt::format("x{}", i));
  for (int i = 0; i < camera_dims_; ++i) names.push_back(fmt::format("y{}", i));
  throw InputError(
      fmt::format("integrand 'expr', parameter 'f', position {}: {}\n  {}\n  {:>{}}\n"
                  "variables: {} (light_dims={}, camera_dims={})",
                  pos, problem->message, expression_, "^", pos + 1, join_names(names), light_dims_,
                  camera_dims_));
}

ExpressionModel::ExpressionModel(const ExpressionModel& other)
    : expression_(other.expression_),
      light_dims_(other.light_dims_),
      camera_dims_(other.camera_dims_),
      exact_(other.exact_),
      has_exact_(other.has_exact_) {
  bind();
}

ExpressionModel::~ExpressionModel() = default;

void ExpressionModel::bind() {
  const int count = light_dims_ + camera_dims_;
  variables_ = std::make_unique<double[]>(static_cast<std::size_t>(count));
  parser_ = std::make_unique<mu::Parser>();
  // muparser 2.3.3 built with GCC (Debian's) defines _pi as 3.141592653589
  // (muParserTemplateMagic.h: a shorter pi for speed), 2.5e-13 relative below pi: an integrand
  // written with _pi would differ from its exact integral by that, which verify reports as bias
  // once the standard error is smaller. Every constant muparser defines (_pi and _e; a test checks
  // that list) is defined again at full double precision.
  parser_->DefineConst("_pi", std::numbers::pi);
  parser_->DefineConst("_e", std::numbers::e);
  for (int i = 0; i < light_dims_; ++i) {
    parser_->DefineVar(fmt::format("x{}", i), &variables_[static_cast<std::size_t>(i)]);
  }
  for (int i = 0; i < camera_dims_; ++i) {
    parser_->DefineVar(fmt::format("y{}", i),
                       &variables_[static_cast<std::size_t>(light_dims_ + i)]);
  }
  parser_->SetExpr(expression_);
}

Reference ExpressionModel::reference() const {
  if (!has_exact_) return {};
  return {.value = exact_, .kind = ReferenceKind::kExact};
}

double ExpressionModel::f(const double* x, const double* y) {
  std::copy_n(x, light_dims_, variables_.get());
  std::copy_n(y, camera_dims_, variables_.get() + light_dims_);
  return parser_->Eval();
}

}  // namespace pcbench
