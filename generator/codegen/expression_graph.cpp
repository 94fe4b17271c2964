#include "codegen/expression_graph.hpp"

#include <cmath>
#include <cstring>
#include <utility>

namespace mbgen::codegen {

namespace {
std::uint64_t bits_of(double x) {
  if (x == 0) x = 0.0;  // -0 and +0 are one constant
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}
bool commutative(Op op) { return op == Op::Add || op == Op::Mul || op == Op::Max; }
}  // namespace

std::size_t ExpressionGraph::KeyHash::operator()(const Key& k) const {
  std::uint64_t h = static_cast<std::uint64_t>(k.op) * 0x9E3779B97F4A7C15ull;
  for (std::uint64_t x : {std::uint64_t(std::uint32_t(k.a)), std::uint64_t(std::uint32_t(k.b)),
                          std::uint64_t(std::uint32_t(k.input)), std::uint64_t(std::uint32_t(k.index)), k.bits})
    h = (h ^ x) * 0x100000001B3ull + (h >> 29);
  return static_cast<std::size_t>(h);
}

namespace {
thread_local long g_graph_limit = kDefaultGraphLimit;
}  // namespace

GraphLimit::GraphLimit(long max_nodes) : previous_(g_graph_limit) { g_graph_limit = max_nodes; }
GraphLimit::~GraphLimit() { g_graph_limit = previous_; }
long GraphLimit::current() { return g_graph_limit; }

int ExpressionGraph::intern(const Node& n) {
  Key key{n.op, n.a, n.b, n.input, n.index, n.op == Op::Constant ? bits_of(n.value) : 0};
  auto it = index_.find(key);
  if (it != index_.end()) return it->second;
  if (static_cast<long>(nodes_.size()) >= g_graph_limit) throw GraphLimitExceeded(g_graph_limit);
  nodes_.push_back(n);
  if (n.op == Op::Constant && n.value == 0) nodes_.back().value = 0.0;
  const int id = static_cast<int>(nodes_.size()) - 1;
  index_.emplace(key, id);
  return id;
}

int ExpressionGraph::constant(double value) {
  Node n{Op::Constant};
  n.value = value;
  return intern(n);
}

int ExpressionGraph::input(int argument, int index) {
  Node n{Op::Input};
  n.input = argument;
  n.index = index;
  return intern(n);
}

int ExpressionGraph::unary(Op op, int a) {
  const Node& na = node(a);
  if (na.op == Op::Constant) {
    switch (op) {
      case Op::Neg: return constant(-na.value);
      case Op::Sin: return constant(std::sin(na.value));
      case Op::Cos: return constant(std::cos(na.value));
      case Op::Sqrt: return constant(std::sqrt(na.value));
      case Op::Step: return constant(na.value > 0 ? 1.0 : 0.0);
      default: break;
    }
  }
  if (op == Op::Neg && na.op == Op::Neg) return na.a;
  Node n{op};
  n.a = a;
  return intern(n);
}

int ExpressionGraph::binary(Op op, int a, int b) {
  // Folding keeps results bit-identical to evaluating the unfolded expression with doubles.
  if (is_constant(a) && is_constant(b)) {
    const double x = node(a).value, y = node(b).value;
    switch (op) {
      case Op::Add: return constant(x + y);
      case Op::Sub: return constant(x - y);
      case Op::Mul: return constant(x * y);
      case Op::Div: return constant(x / y);
      case Op::Max: return constant(x > y ? x : y);
      case Op::Pow: return constant(std::pow(x, y));
      default: break;
    }
  }
  switch (op) {
    case Op::Add:
      if (is_constant(a, 0)) return b;
      if (is_constant(b, 0)) return a;
      // (x - y) + (y - x): 0 for every finite x and y, as x - x below (IEEE subtraction is
      // antisymmetric). The floating base's v x v terms of the recursions are such sums.
      if (node(a).op == Op::Sub && node(b).op == Op::Sub && node(a).a == node(b).b && node(a).b == node(b).a) return constant(0);
      if (node(b).op == Op::Neg) return binary(Op::Sub, a, node(b).a);
      if (node(a).op == Op::Neg) return binary(Op::Sub, b, node(a).a);
      break;
    case Op::Sub:
      // x - x: the same node on both sides, 0 for every finite x. The closure Jacobian's entries
      // of joints above a loop are such differences (a joint moves both closure frames alike), and
      // a structural zero there keeps the Givens QR of Phi_z from a 0 / 0 rotation.
      if (a == b) return constant(0);
      if (is_constant(b, 0)) return a;
      if (is_constant(a, 0)) return unary(Op::Neg, b);
      if (node(b).op == Op::Neg) return binary(Op::Add, a, node(b).a);
      break;
    case Op::Mul:
      if (is_constant(a, 0) || is_constant(b, 0)) return constant(0);
      if (is_constant(a, 1)) return b;
      if (is_constant(b, 1)) return a;
      if (is_constant(a, -1)) return unary(Op::Neg, b);
      if (is_constant(b, -1)) return unary(Op::Neg, a);
      if (node(a).op == Op::Neg && node(b).op == Op::Neg) return binary(Op::Mul, node(a).a, node(b).a);
      if (node(a).op == Op::Neg) return unary(Op::Neg, binary(Op::Mul, node(a).a, b));
      if (node(b).op == Op::Neg) return unary(Op::Neg, binary(Op::Mul, a, node(b).a));
      break;
    case Op::Div:
      if (is_constant(a, 0)) return constant(0);
      if (is_constant(b, 1)) return a;
      if (is_constant(b, -1)) return unary(Op::Neg, a);
      break;
    default: break;
  }
  if (commutative(op) && a > b) std::swap(a, b);
  Node n{op};
  n.a = a;
  n.b = b;
  return intern(n);
}

}  // namespace mbgen::codegen
