// Loop-invariant code motion of traced functions (generator/codegen/hoist_invariants.hpp): the
// setup and the body, evaluated together, give the function's outputs bit for bit, and the body
// no longer computes what depends only on the inputs the loop keeps. The generated closure
// (test_generated) runs the hoisted Newton step against the runtime's.
#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>

#include "codegen/hoist_invariants.hpp"
#include "codegen/trace_loop_maps.hpp"
#include "test_support.hpp"

namespace mbgen::codegen {
namespace {

using test::load_loop_case;
using test::loop_cases;
using test::LoopCase;
using Arrays = std::vector<std::vector<double>>;

/// f's outputs for `inputs`, evaluated node by node as the emitted C++ computes them (a max as
/// `a > b ? a : b`, a its first operand; a step as `a > 0 ? 1 : 0`).
Arrays evaluate(const TracedFunction& f, const Arrays& inputs) {
  std::vector<double> x(static_cast<std::size_t>(f.graph.size()));
  for (int id = 0; id < f.graph.size(); ++id) {
    const Node& n = f.graph.node(id);
    const double a = n.a >= 0 ? x[static_cast<std::size_t>(n.a)] : 0, b = n.b >= 0 ? x[static_cast<std::size_t>(n.b)] : 0;
    double& y = x[static_cast<std::size_t>(id)];
    switch (n.op) {
      case Op::Constant: y = n.value; break;
      case Op::Input: y = inputs.at(static_cast<std::size_t>(n.input)).at(static_cast<std::size_t>(n.index)); break;
      case Op::Add: y = a + b; break;
      case Op::Sub: y = a - b; break;
      case Op::Mul: y = a * b; break;
      case Op::Div: y = a / b; break;
      case Op::Neg: y = -a; break;
      case Op::Sin: y = std::sin(a); break;
      case Op::Cos: y = std::cos(a); break;
      case Op::Sqrt: y = std::sqrt(a); break;
      case Op::Max: y = a > b ? a : b; break;
      case Op::Pow: y = std::pow(a, b); break;
      case Op::Step: y = a > 0 ? 1 : 0; break;
    }
  }
  Arrays out;
  for (const auto& ids : f.output_ids) {
    out.emplace_back();
    for (int id : ids) out.back().push_back(x[static_cast<std::size_t>(id)]);
  }
  return out;
}

/// f evaluated through its hoisted form: the setup, then the body with its invariants.
Arrays evaluate_hoisted(const HoistedFunction& h, Arrays inputs) {
  inputs.push_back(evaluate(h.setup, inputs).at(0));
  return evaluate(h.body, inputs);
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void expect_same_bits(const Arrays& a, const Arrays& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t o = 0; o < a.size(); ++o) {
    ASSERT_EQ(a[o].size(), b[o].size());
    for (std::size_t i = 0; i < a[o].size(); ++i)
      EXPECT_TRUE(same_bits(a[o][i], b[o][i]) || (std::isnan(a[o][i]) && std::isnan(b[o][i])))
          << "output " << o << " element " << i << ": " << a[o][i] << " vs " << b[o][i];
  }
}

/// x (kept by the loop, 3 entries) and y (changed by it, 2 entries):
///   a = sin x0 cos x1, out = [a + y0, max(a, x2 y1), sqrt(a a + 1), a, x0, 2, max(y0, a)].
TracedFunction small_function() {
  TracedFunction f;
  f.name = "small";
  f.inputs = {{"x", 3, ""}, {"y", 2, ""}};
  f.outputs = {{"out", 7, ""}};
  ExpressionGraph& g = f.graph;
  const int x0 = g.input(0, 0), x1 = g.input(0, 1), x2 = g.input(0, 2), y0 = g.input(1, 0), y1 = g.input(1, 1);
  const int a = g.binary(Op::Mul, g.unary(Op::Sin, x0), g.unary(Op::Cos, x1));
  const int root = g.unary(Op::Sqrt, g.binary(Op::Add, g.binary(Op::Mul, a, a), g.constant(1)));
  f.output_ids = {{g.binary(Op::Add, a, y0), g.binary(Op::Max, a, g.binary(Op::Mul, x2, y1)), root, a, x0, g.constant(2),
                   g.binary(Op::Max, y0, a)}};
  return f;
}

TEST(HoistInvariants, SetupAndBodyGiveTheFunctionsOutputsAndTheBodyKeepsOnlyWhatVaries) {
  const TracedFunction f = small_function();
  const HoistedFunction h = hoist_invariants(f, [](int argument, int) { return argument == 1; });
  // invariants: a and sqrt(a a + 1), the invariant statements the varying ones and the outputs read.
  ASSERT_EQ(h.setup.outputs.size(), 1u);
  EXPECT_EQ(h.setup.outputs[0].name, "invariants");
  EXPECT_EQ(h.setup.outputs[0].size, 2);
  EXPECT_EQ(h.setup.name, "small_setup");
  ASSERT_EQ(h.body.inputs.size(), 3u);
  EXPECT_EQ(h.body.inputs[2].name, "invariants");
  // The body: a + y0, x2 y1 and the two maxes; the setup: sin, cos, a, a a, + 1, sqrt.
  EXPECT_EQ(count_operations(h.body).total(), 4);
  EXPECT_EQ(count_operations(h.setup).total(), 6);
  EXPECT_EQ(count_operations(h.setup).trig, 2);
  EXPECT_EQ(count_operations(h.body).trig, 0);

  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2, 2);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (int trial = 0; trial < 100; ++trial) {
    Arrays in = {{u(rng), u(rng), u(rng)}, {u(rng), u(rng)}};
    // NaN operands of the maxes: which side a NaN is on decides the result, so the body must
    // keep each max's operand order.
    if (trial % 4 == 1) in[1][1] = nan;
    if (trial % 4 == 2) in[0][0] = nan;
    if (trial % 4 == 3) in[1][0] = nan;
    SCOPED_TRACE(trial);
    expect_same_bits(evaluate_hoisted(h, in), evaluate(f, in));
  }
}

TEST(HoistInvariants, NothingVaryingPutsEveryStatementInTheSetup) {
  const TracedFunction f = small_function();
  const HoistedFunction h = hoist_invariants(f, [](int, int) { return false; });
  EXPECT_EQ(count_operations(h.body).total(), 0);
  EXPECT_EQ(count_operations(h.setup).total(), count_operations(f).total());
  const Arrays in = {{0.3, -0.2, 1.1}, {0.5, -0.7}};
  expect_same_bits(evaluate_hoisted(h, in), evaluate(f, in));
}

TEST(HoistInvariants, EverythingVaryingLeavesTheSetupEmpty) {
  const TracedFunction f = small_function();
  const HoistedFunction h = hoist_invariants(f, [](int, int) { return true; });
  EXPECT_EQ(h.setup.outputs[0].size, 0);
  EXPECT_EQ(count_operations(h.body).total(), count_operations(f).total());
  const Arrays in = {{0.3, -0.2, 1.1}, {0.5, -0.7}};
  expect_same_bits(evaluate_hoisted(h, in), evaluate(f, in));
}

/// The closure's Newton step on every loop model, the dependent coordinates varying: the hoisted
/// step equals the traced one bit for bit at random configurations, and the setup takes
/// something (the independent joints' sines and cosines at least) out of every iteration.
class HoistNewtonStep : public ::testing::TestWithParam<LoopCase> {};

TEST_P(HoistNewtonStep, EqualsTheTracedStepBitForBit) {
  const gen::Description d = load_loop_case(GetParam());
  const Model& model = d.model;
  std::vector<bool> moves(static_cast<std::size_t>(model.nq()), false);
  for (const SubSystem& sub : model.subsystems)
    for (int z : sub.dependent) moves[static_cast<std::size_t>(model.q_index_of_v(z))] = true;
  const bool only_couplings = std::all_of(model.closures.begin(), model.closures.end(),
                                          [](const LoopClosure& c) { return c.type == ClosureType::Coupling; });
  for (const bool with_velocities : {false, true}) {
    const TracedFunction step = trace_closure_newton_step(model, with_velocities);
    const HoistedFunction h = hoist_invariants(step, [&](int argument, int index) {
      return argument == 0 && moves[static_cast<std::size_t>(index)];
    });
    // A coupling's step (q_b - ratio q_a - offset) may be one subtraction with nothing invariant
    // in it (panda's fingers: ratio 1, offset 0); every closure with kinematics has some.
    if (!only_couplings) {
      EXPECT_LT(count_operations(h.body).total(), count_operations(step).total());
      EXPECT_GT(h.setup.outputs[0].size, 0);
    }
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u(-1, 1);
    for (int trial = 0; trial < 8; ++trial) {
      Arrays in;
      for (const ArraySpec& a : step.inputs) {
        in.emplace_back();
        for (int i = 0; i < a.size; ++i) in.back().push_back(u(rng));
      }
      SCOPED_TRACE(trial);
      expect_same_bits(evaluate_hoisted(h, in), evaluate(step, in));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(LoopModels, HoistNewtonStep, ::testing::ValuesIn(loop_cases()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace mbgen::codegen
