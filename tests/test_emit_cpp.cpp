// Where emit_statements (generator/codegen/emit_cpp.hpp) writes a function's outputs: as soon as
// their values exist (early_outputs), all at the end, or at the end except the outputs named in
// early_anyway (the closure's Newton step writes its factor early and its residual rows last).
#include <gtest/gtest.h>

#include <string>

#include "codegen/emit_cpp.hpp"

namespace mbgen::codegen {
namespace {

/// x (2 entries): t = x0 x1, u = t + x0, out: a = [t], b = [sqrt(u u)]. The last statement
/// reading an input is u's, so the earliest place for a is right after u.
TracedFunction two_outputs() {
  TracedFunction f;
  f.name = "two";
  f.inputs = {{"x", 2, ""}};
  f.outputs = {{"a", 1, ""}, {"b", 1, ""}};
  ExpressionGraph& g = f.graph;
  const int x0 = g.input(0, 0), x1 = g.input(0, 1);
  const int t = g.binary(Op::Mul, x0, x1);
  const int u = g.binary(Op::Add, t, x0);
  const int b = g.unary(Op::Sqrt, g.binary(Op::Mul, u, u));
  f.output_ids = {{t}, {b}};
  return f;
}

/// The position of `text` in `body`, failing the test when it is absent.
std::size_t position_of(const std::string& body, const std::string& text) {
  const std::size_t at = body.find(text);
  EXPECT_NE(at, std::string::npos) << text << " not in:\n" << body;
  return at;
}

TEST(EmitStatements, OutputsAreWrittenEarlyLateOrLateButTheNamedOnes) {
  const TracedFunction f = two_outputs();
  StatementStyle style;
  const std::string early = emit_statements(f, style);
  const std::size_t last_statement_early = early.rfind("const S ");
  EXPECT_LT(position_of(early, "a[0] = "), last_statement_early) << early;  // before sqrt's statements

  style.early_outputs = false;
  const std::string late = emit_statements(f, style);
  const std::size_t last_statement_late = late.rfind("const S ");
  EXPECT_GT(position_of(late, "a[0] = "), last_statement_late) << late;
  EXPECT_GT(position_of(late, "b[0] = "), last_statement_late) << late;

  style.early_anyway = {"a"};
  const std::string mixed = emit_statements(f, style);
  const std::size_t last_statement_mixed = mixed.rfind("const S ");
  EXPECT_LT(position_of(mixed, "a[0] = "), last_statement_mixed) << mixed;
  EXPECT_GT(position_of(mixed, "b[0] = "), last_statement_mixed) << mixed;
  EXPECT_GT(position_of(mixed, "a[0] = "), position_of(mixed, "x[1]")) << "every input read first:\n" << mixed;
  // Each output written once.
  EXPECT_EQ(mixed.find("a[0] = ", position_of(mixed, "a[0] = ") + 1), std::string::npos) << mixed;
  EXPECT_EQ(mixed.find("b[0] = ", position_of(mixed, "b[0] = ") + 1), std::string::npos) << mixed;
}

}  // namespace
}  // namespace mbgen::codegen
