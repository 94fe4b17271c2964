#pragma once
// The expression graph a symbolic scalar records: hash-consed nodes (so equal subexpressions are
// one node: common-subexpression elimination by construction) with constant folding of the
// operations whose result is exact (x*0, x*1, x+0, x-x, -(-x), constant (op) constant).
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace mbgen::codegen {

/// Max: the larger operand (a > b ? a : b), the one value-dependent choice a traced algorithm may
/// make (a guard against 0 / 0, e.g. in a Givens rotation of two numerically zero entries).
/// Step: 1 where the operand is > 0, else 0 (the slope of max(x, 0); printed as a select).
enum class Op : std::uint8_t { Constant, Input, Add, Sub, Mul, Div, Neg, Sin, Cos, Sqrt, Max, Pow, Step };

struct Node {
  Op op;
  int a = -1, b = -1;  ///< operand node ids (Add..Pow)
  double value = 0;    ///< Constant
  int input = -1;      ///< Input: argument number
  int index = -1;      ///< Input: element in that argument
};

/// Counts of arithmetic operations, as printed in the generated functions' comments.
struct OpCount {
  int add = 0, mul = 0, div = 0, neg = 0, trig = 0, sqrt = 0, max = 0, pow = 0;
  int total() const { return add + mul + div + neg + trig + sqrt + max + pow; }
};

/// Thrown when a graph would grow past its limit (GraphLimit): a description too large to unroll.
struct GraphLimitExceeded : std::runtime_error {
  explicit GraphLimitExceeded(long limit)
      : std::runtime_error("expression graph limit exceeded"), limit(limit) {}
  long limit;
};

/// The most nodes a graph may hold while this lives on the thread (default kDefaultGraphLimit):
/// an unrolled function grows with the model (the mass matrix with nv^2), and a 5,000-link
/// description would fill the memory before anything is written.
class GraphLimit {
 public:
  explicit GraphLimit(long max_nodes);
  ~GraphLimit();
  GraphLimit(const GraphLimit&) = delete;
  GraphLimit& operator=(const GraphLimit&) = delete;
  static long current();

 private:
  long previous_;
};

/// 10 million nodes (~100 bytes each while tracing): over 100 times the largest function of the
/// shipped and shared robots (wl16_like's full_accelerations, 78,045 operations).
inline constexpr long kDefaultGraphLimit = 10'000'000;

class ExpressionGraph {
 public:
  int constant(double value);
  int input(int argument, int index);
  int unary(Op op, int a);
  int binary(Op op, int a, int b);

  const Node& node(int id) const { return nodes_[static_cast<std::size_t>(id)]; }
  int size() const { return static_cast<int>(nodes_.size()); }
  bool is_constant(int id) const { return node(id).op == Op::Constant; }
  bool is_constant(int id, double value) const { return is_constant(id) && node(id).value == value; }

 private:
  int intern(const Node& n);
  struct Key {
    Op op;
    int a, b, input, index;
    std::uint64_t bits;
    bool operator==(const Key& o) const {
      return op == o.op && a == o.a && b == o.b && input == o.input && index == o.index && bits == o.bits;
    }
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const;
  };
  std::vector<Node> nodes_;
  std::unordered_map<Key, int, KeyHash> index_;
};

}  // namespace mbgen::codegen
