// Where emit_statements (generator/codegen/emit_cpp.hpp) writes a function's outputs: as soon as
// their values exist (early_outputs), all at the end, or at the end except the outputs named in
// early_anyway (the closure's Newton step writes its factor early and its residual rows last); and
// how a one-state function takes the sines and cosines of its inputs: all at once, first; and
// where split_statements writes many constant output entries: by a function of their own; and which
// statements carry the attribute that stores output entries one by one (pack_output_stores).
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

/// x (3 entries): a = sin x0 cos x2, b = cos x0 + sin(sqrt x1), c = sin x2 (an output that is a sine).
TracedFunction trigonometry() {
  TracedFunction f;
  f.name = "trig";
  f.inputs = {{"x", 3, ""}};
  f.outputs = {{"a", 1, ""}, {"b", 1, ""}, {"c", 1, ""}};
  ExpressionGraph& g = f.graph;
  const int x0 = g.input(0, 0), x1 = g.input(0, 1), x2 = g.input(0, 2);
  const int sin_x0 = g.unary(Op::Sin, x0);  // first: the prologue's order is the order of first use
  const int a = g.binary(Op::Mul, sin_x0, g.unary(Op::Cos, x2));
  const int b = g.binary(Op::Add, g.unary(Op::Cos, x0), g.unary(Op::Sin, g.unary(Op::Sqrt, x1)));
  f.output_ids = {{a}, {b}, {g.unary(Op::Sin, x2)}};
  return f;
}

std::size_t count_of(const std::string& body, const std::string& text) {
  std::size_t n = 0;
  for (std::size_t at = body.find(text); at != std::string::npos; at = body.find(text, at + 1)) ++n;
  return n;
}

TEST(EmitStatements, AStepIsASelectForOneStateAndLaneByLaneForABatch) {
  TracedFunction f;
  f.name = "step";
  f.inputs = {{"x", 1, ""}};
  f.outputs = {{"s", 2, ""}};
  ExpressionGraph& g = f.graph;
  const int x = g.input(0, 0);
  // A constant's step folds (1 for 2.5, 0 at 0: the slope a select's max(0, 0) takes).
  EXPECT_EQ(g.unary(Op::Step, g.constant(2.5)), g.constant(1.0));
  EXPECT_EQ(g.unary(Op::Step, g.constant(0.0)), g.constant(0.0));
  f.output_ids = {{g.unary(Op::Step, g.binary(Op::Mul, x, x)), g.unary(Op::Step, x)}};
  const std::string one = emit_statements(f);
  position_of(one, "> S(0) ? S(1) : S(0)");
  StatementStyle batch;
  batch.lanes = 4;
  const std::string lanes = emit_statements(f, batch);
  position_of(lanes, "lanes_step(");
  EXPECT_EQ(count_operations(f).max, 2);  // counted with the selects
}

TEST(EmitStatements, SinesAndCosinesOfInputsComeFirstAllAtOnce) {
  const TracedFunction f = trigonometry();
  const std::string body = emit_statements(f, {});
  // Each input angle once, in the order of first use, padded with zeros to 4 lanes; then sincos_all.
  EXPECT_EQ(body.find("  const S _angle[4] = {x[0], x[2], S(0), S(0)};\n  S _sin[4], _cos[4];\n  sincos_all(_angle, _sin, _cos);\n"), 0u)
      << body;
  EXPECT_NE(body.find("_sin[0] * _cos[1]"), std::string::npos) << body;
  EXPECT_NE(body.find("c[0] = _sin[1];"), std::string::npos) << body;
  // A sine of a computed value stays where it is computed.
  EXPECT_NE(body.find("std::sin(_t"), std::string::npos) << body;
  EXPECT_EQ(count_of(body, "std::sin(x["), 0u) << body;
  EXPECT_EQ(count_of(body, "std::cos("), 0u) << body;
  // With inline_sincos that one is sincos_of, and the prologue is the same.
  const std::string inline_body = emit_statements(f, {0, true});
  EXPECT_EQ(inline_body.find("  const S _angle[4]"), 0u) << inline_body;
  EXPECT_NE(inline_body.find("sincos_of<S>(_t"), std::string::npos) << inline_body;
  // A batch has no prologue: every lane's sine comes from sincos_of on vectors.
  const std::string batch = emit_statements(f, {2, true});
  EXPECT_EQ(batch.find("_angle"), std::string::npos) << batch;
  EXPECT_NE(batch.find("sincos_of<S>(lanes_load<V>(x[0]))"), std::string::npos) << batch;
}

TEST(SplitStatements, PartsReadTheBodysSinesAndCosines) {
  const TracedFunction f = trigonometry();
  const SplitStatements split = split_statements(f, "trig", 2, {});
  ASSERT_FALSE(split.parts.empty());
  EXPECT_EQ(split.body.find("  const S _angle[4]"), 0u) << split.body;
  // Pointers 4 entries into the padded arrays of 4 (the bias is min(16, the padded size)).
  EXPECT_NE(split.body.find("trig_part0<S>(x, _sin + 4, _cos + 4, w);"), std::string::npos) << split.body;
  EXPECT_NE(split.parts.find("void trig_part0(const S* x, const S* __restrict _sin, const S* __restrict _cos, S* w)"),
            std::string::npos)
      << split.parts;
  EXPECT_EQ(split.parts.find("_angle"), std::string::npos) << split.parts;
  EXPECT_EQ(count_of(split.body + split.parts, "sincos_all"), 1u);
}

/// trigonometry() (4 statements besides the prologue's sines) with output c replaced by a chain of
/// additions onto sin x2: kStatementsApartFrom statements in all, just enough to be kept apart.
TracedFunction large_trigonometry() {
  TracedFunction f = trigonometry();
  int chain = f.output_ids[2][0];
  for (int k = 4; k < kStatementsApartFrom; ++k) chain = f.graph.binary(Op::Add, chain, f.graph.input(0, 1));
  f.output_ids[2] = {chain};
  return f;
}

TEST(SplitStatements, ALargeUnsplitFunctionWithSinesKeepsItsStatementsApartReadingThemThroughPointers) {
  TracedFunction f = large_trigonometry();
  const int chain = f.output_ids[2][0];
  const SplitStatements apart = split_statements(f, "trig", 100 * kStatementsApartFrom, {});
  // The body computes the sines, then calls the statements with pointers 4 entries in (the
  // arrays' padded size, below 16): slot k is read as [k - 4].
  EXPECT_EQ(apart.body,
            "  const S _angle[4] = {x[0], x[2], S(0), S(0)};\n  S _sin[4], _cos[4];\n  sincos_all(_angle, _sin, _cos);\n"
            "  trig_statements<S>(x, a, b, c, _sin + 4, _cos + 4);\n");
  EXPECT_NE(apart.parts.find("MBGEN_GENERATED_NOINLINE void trig_statements(const S* x, S* a, S* b, S* c, const S* __restrict _sin, "
                             "const S* __restrict _cos) {\n  (void)x;\n  (void)_sin;\n  (void)_cos;\n"),
            std::string::npos)
      << apart.parts.substr(0, 2000);
  EXPECT_NE(apart.parts.find("_sin[-4] * _cos[-3]"), std::string::npos) << apart.parts.substr(0, 2000);
  EXPECT_NE(apart.parts.find(" = x[1] + _sin[-3];"), std::string::npos) << apart.parts.substr(0, 2000);
  EXPECT_EQ(apart.parts.find("_angle"), std::string::npos);
  // Its statements are emit_statements' after the prologue, the slots renamed.
  std::string whole = emit_statements(f, {});
  whole = whole.substr(whole.find("sincos_all(_angle, _sin, _cos);\n") + 32);
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"_sin[0]", "_sin[-4]"}, {"_sin[1]", "_sin[-3]"}, {"_cos[0]", "_cos[-4]"},
                                 {"_cos[1]", "_cos[-3]"}})
    for (std::size_t at = whole.find(from); at != std::string::npos; at = whole.find(from, at)) whole.replace(at, from.size(), to);
  EXPECT_NE(apart.parts.find(whole), std::string::npos);
  // One statement fewer, or no sines of inputs: nothing apart.
  const Node& last = f.graph.node(chain);
  f.output_ids[2] = {f.graph.node(last.a).op == Op::Input ? last.b : last.a};
  const SplitStatements small = split_statements(f, "trig", 100 * kStatementsApartFrom, {});
  EXPECT_TRUE(small.parts.empty());
  EXPECT_TRUE(small.body == emit_statements(f, {}));  // (not EXPECT_EQ: a thousand lines)
  EXPECT_NE(small.body.find("_sin[0] * _cos[1]"), std::string::npos);
  TracedFunction plain;
  plain.name = "plain";
  plain.inputs = {{"x", 2, ""}};
  plain.outputs = {{"y", 1, ""}};
  int sum = plain.graph.input(0, 0);
  for (int k = 0; k < kStatementsApartFrom; ++k) sum = plain.graph.binary(Op::Mul, sum, plain.graph.input(0, 1));
  plain.output_ids = {{sum}};
  const SplitStatements together = split_statements(plain, "plain", 100 * kStatementsApartFrom, {});
  EXPECT_TRUE(together.parts.empty());
  EXPECT_TRUE(together.body == emit_statements(plain, {}));
}

TEST(SplitStatements, AFunctionWhoseRowAsksForScalarStoresHasItsStatementsCarryTheAttribute) {
  // The large function of the test above, with and without pack_output_stores.
  TracedFunction f = large_trigonometry();
  const std::string head = "MBGEN_GENERATED_NOINLINE MBGEN_GENERATED_SCALAR_STORES void trig_statements(const S* x";
  EXPECT_EQ(split_statements(f, "trig", 100 * kStatementsApartFrom, {}).parts.find("SCALAR_STORES"), std::string::npos);
  f.pack_output_stores = false;
  const SplitStatements scalar = split_statements(f, "trig", 100 * kStatementsApartFrom, {});
  EXPECT_NE(scalar.parts.find(head), std::string::npos) << scalar.parts.substr(0, 2000);
  EXPECT_EQ(count_of(scalar.parts, "SCALAR_STORES"), 1u);
  // The statements are the same: only how g++ compiles them changes.
  const SplitStatements packed = [&] {
    TracedFunction g = f;
    g.pack_output_stores = true;
    return split_statements(g, "trig", 100 * kStatementsApartFrom, {});
  }();
  std::string without = scalar.parts;
  without.erase(without.find("MBGEN_GENERATED_SCALAR_STORES "), std::string("MBGEN_GENERATED_SCALAR_STORES ").size());
  EXPECT_TRUE(without == packed.parts);
  EXPECT_EQ(scalar.body, packed.body);
  // Split into parts, which write no outputs (the caller does), or over lanes: no attribute.
  EXPECT_EQ(split_statements(f, "trig", 16, {}).parts.find("SCALAR_STORES"), std::string::npos);
  EXPECT_EQ(split_statements(f, "trig", 100 * kStatementsApartFrom, {2, true}).parts.find("SCALAR_STORES"), std::string::npos);
}

/// out (zeros + 1 entries): out[0] = x0 x1, the rest zero.
TracedFunction mostly_zeros(int zeros) {
  TracedFunction f;
  f.name = "sparse";
  f.inputs = {{"x", 2, ""}};
  f.outputs = {{"out", zeros + 1, ""}};
  ExpressionGraph& g = f.graph;
  f.output_ids = {{g.binary(Op::Mul, g.input(0, 0), g.input(0, 1))}};
  for (int k = 0; k < zeros; ++k) f.output_ids[0].push_back(g.constant(0.0));
  return f;
}

TEST(SplitStatements, ManyConstantOutputsAreWrittenLastByAFunctionOfTheirOwn) {
  const SplitStatements many = split_statements(mostly_zeros(256), "sparse", 1000, {});
  EXPECT_NE(many.parts.find("MBGEN_GENERATED_NOINLINE void sparse_constants(S* out) {"), std::string::npos) << many.parts;
  EXPECT_EQ(count_of(many.parts, "] = S(0);"), 256u) << many.parts;
  EXPECT_EQ(count_of(many.body, "S(0)"), 0u) << many.body;
  const std::string call = "  sparse_constants<S>(out);\n";
  ASSERT_GE(many.body.size(), call.size());
  EXPECT_EQ(many.body.substr(many.body.size() - call.size()), call) << "called last:\n" << many.body;
  EXPECT_NE(many.body.find("out[0] = "), std::string::npos) << many.body;
  // Fewer stay in place; a batch keeps them (its stores are vectors already).
  const SplitStatements few = split_statements(mostly_zeros(255), "sparse", 1000, {});
  EXPECT_TRUE(few.parts.empty()) << few.parts;
  EXPECT_EQ(count_of(few.body, "] = S(0);"), 255u) << few.body;
  EXPECT_EQ(split_statements(mostly_zeros(256), "sparse", 1000, {2, true}).parts.find("_constants"), std::string::npos);
}

}  // namespace
}  // namespace mbgen::codegen
