// What muparser accepts in an expression but an integrand must not be:
//   - several values, `x0, y0`: muparser evaluates each and Eval() returns the last, so the
//     integrand would silently be the last one;
//   - an assignment, `x0=2`: it writes to a variable the sampler set, and f is its value.
// A comma between a function's arguments (`min(x0, y0)`) and the comparisons `==`, `<=`, `>=`,
// `!=` are other tokens and stay valid.
#pragma once

#include <optional>
#include <string>

namespace mu {
class Parser;
}

namespace pcbench {

struct ExpressionProblem {
  int position = 0;  // of the offending character in the expression
  std::string message;
};

// The first such construct in the parser's expression, or nothing. The expression must have
// evaluated once without error (the scan reads the tokens muparser read, it does not check them).
std::optional<ExpressionProblem> unsupported_construct(mu::Parser& parser);

}  // namespace pcbench
