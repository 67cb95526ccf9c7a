#include "integrands/expression_syntax.h"

#include <muParser.h>
#include <muParserTokenReader.h>

namespace pcbench {
namespace {

// muparser's reader of numbers is protected; its token reader needs it to read "2" as a value.
struct NumberReader : mu::Parser {
  using mu::Parser::IsVal;
};

}  // namespace

std::optional<ExpressionProblem> unsupported_construct(mu::Parser& parser) {
  // muparser's own token reader, over the parser's functions, operators, constants and variables:
  // it tells an argument separator from the other commas and an assignment from `==`, `<=`, …,
  // which a scan of the characters would have to redo. (GetNumResults() > 1 says that there are
  // several values, not where.) GetExpr() is the text with the space muparser appends, which its
  // number reader needs after a number at the end; positions are those of the text.
  mu::ParserTokenReader reader(&parser);
  reader.AddValIdent(&NumberReader::IsVal);
  reader.SetFormula(parser.GetExpr());
  int depth = 0;  // open parentheses; muparser refuses a comma in parentheses of no function
  for (;;) {
    const auto token = reader.ReadNextToken();
    switch (token.GetCode()) {
      case mu::cmBO:
        ++depth;
        break;
      case mu::cmBC:
        --depth;
        break;
      case mu::cmARG_SEP:
        if (depth == 0) {
          return ExpressionProblem{
              .position = reader.GetPos() - 1,
              .message =
                  "',' outside a function's arguments separates several expressions, and "
                  "f must be one (a comma may only separate arguments, as in min(x0, y0))"};
        }
        break;
      case mu::cmASSIGN:
        return ExpressionProblem{
            .position = reader.GetPos() - 1,
            .message =
                "'=' assigns to a variable, and f must not change its variables (a "
                "comparison is '==')"};
      case mu::cmEND:
        return std::nullopt;
      default:
        break;
    }
  }
}

}  // namespace pcbench
