// expr: an integrand written as a muparser expression in a suite or on the command line.
//
//   f            the expression; light-side variables x0, x1, ..., camera-side y0, y1, ...,
//                each uniform on [0, 1] (p(x) = p(y) = 1); muparser's constants _pi and _e at
//                full double precision
//   light_dims   number of x variables (default 1)
//   camera_dims  number of y variables (default 1)
//   exact        optional: the exact value of ∫∫ f, which becomes the reference
//
// Each workspace (one per thread) owns its own parser bound to its own variables: a muparser
// Parser holds pointers to the variables it was given, so copies must bind new ones.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "base/params.h"
#include "integrands/integrand.h"

namespace mu {
class Parser;
}

namespace pcbench {

class ExpressionModel {
 public:
  static std::vector<ParamSpec> params();

  // Parses and test-evaluates the expression; throws InputError pointing into it.
  explicit ExpressionModel(const ResolvedParams& params);
  ExpressionModel(const ExpressionModel& other);
  ExpressionModel& operator=(const ExpressionModel&) = delete;
  ~ExpressionModel();

  int light_dims() const { return light_dims_; }
  int camera_dims() const { return camera_dims_; }
  Reference reference() const;

  double f(const double* x, const double* y);

 private:
  void bind();

  std::string expression_;
  int light_dims_;
  int camera_dims_;
  double exact_;
  bool has_exact_;
  std::unique_ptr<double[]> variables_;  // x0.., then y0..; stable addresses for the parser
  std::unique_ptr<mu::Parser> parser_;
};

}  // namespace pcbench
