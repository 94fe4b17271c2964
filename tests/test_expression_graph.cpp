// The expression graph's folding and simplification (generator/codegen/expression_graph.cpp):
// each rule gives the node the unsimplified expression would evaluate to for finite inputs,
// constants fold bit for bit as doubles compute them, and equal expressions are one node.
#include <gtest/gtest.h>

#include <cmath>

#include "codegen/expression_graph.hpp"

namespace mbgen::codegen {
namespace {

TEST(ExpressionGraph, ConstantsFoldAsDoublesCompute) {
  ExpressionGraph g;
  const int a = g.constant(0.1), b = g.constant(0.2);
  EXPECT_EQ(g.node(g.binary(Op::Add, a, b)).value, 0.1 + 0.2);
  EXPECT_EQ(g.node(g.binary(Op::Div, a, b)).value, 0.1 / 0.2);
  EXPECT_EQ(g.node(g.unary(Op::Sqrt, b)).value, std::sqrt(0.2));
  EXPECT_EQ(g.node(g.binary(Op::Max, a, b)).value, 0.2);
  EXPECT_EQ(g.node(g.unary(Op::Step, a)).value, 1.0);
  EXPECT_EQ(g.node(g.unary(Op::Step, g.constant(-0.1))).value, 0.0);
  EXPECT_EQ(g.node(g.unary(Op::Step, g.constant(0.0))).value, 0.0);
}

TEST(ExpressionGraph, EqualExpressionsAreOneNode) {
  ExpressionGraph g;
  const int x = g.input(0, 0), y = g.input(0, 1);
  EXPECT_EQ(g.binary(Op::Mul, x, y), g.binary(Op::Mul, y, x));  // commutative operands ordered
  EXPECT_EQ(g.binary(Op::Max, x, y), g.binary(Op::Max, y, x));
  EXPECT_NE(g.binary(Op::Sub, x, y), g.binary(Op::Sub, y, x));
  EXPECT_EQ(g.unary(Op::Step, x), g.unary(Op::Step, x));
}

TEST(ExpressionGraph, IdentitiesOfFiniteValues) {
  ExpressionGraph g;
  const int x = g.input(0, 0), y = g.input(0, 1), zero = g.constant(0), one = g.constant(1);
  EXPECT_EQ(g.binary(Op::Add, x, zero), x);
  EXPECT_EQ(g.binary(Op::Mul, one, x), x);
  EXPECT_EQ(g.binary(Op::Mul, x, zero), zero);
  EXPECT_EQ(g.unary(Op::Neg, g.unary(Op::Neg, x)), x);
  EXPECT_EQ(g.binary(Op::Sub, x, x), zero);
  // (x - y) + (y - x) is 0: IEEE subtraction is antisymmetric, so the two differences cancel
  // exactly (the floating base's v x v terms); the same differences in one order do not.
  const int d = g.binary(Op::Sub, x, y), e = g.binary(Op::Sub, y, x);
  EXPECT_EQ(g.binary(Op::Add, d, e), zero);
  EXPECT_EQ(g.binary(Op::Add, e, d), zero);
  EXPECT_NE(g.binary(Op::Add, d, d), zero);
  const int z = g.input(0, 2);
  EXPECT_NE(g.binary(Op::Add, d, g.binary(Op::Sub, y, z)), zero);
  // What the rule relies on, in doubles: (a - b) + (b - a) == 0 for finite a, b.
  for (double a : {0.1, -3.7e12, 1e-300, 5.0})
    for (double b : {0.3, 2.2e-16, -7.5, 5.0}) EXPECT_EQ((a - b) + (b - a), 0.0) << a << " " << b;
}

}  // namespace
}  // namespace mbgen::codegen
