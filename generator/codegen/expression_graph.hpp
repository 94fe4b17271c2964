#pragma once
// The expression graph a symbolic scalar records: hash-consed nodes (so equal subexpressions are
// one node: common-subexpression elimination by construction) with constant folding of the
// operations whose result is exact (x*0, x*1, x+0, x-x, -(-x), constant (op) constant).
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace mbgen::codegen {

/// Max: the larger operand (a > b ? a : b), the one value-dependent choice a traced algorithm may
/// make (a guard against 0 / 0, e.g. in a Givens rotation of two numerically zero entries).
enum class Op : std::uint8_t { Constant, Input, Add, Sub, Mul, Div, Neg, Sin, Cos, Sqrt, Max };

struct Node {
  Op op;
  int a = -1, b = -1;  ///< operand node ids (Add..Max)
  double value = 0;    ///< Constant
  int input = -1;      ///< Input: argument number
  int index = -1;      ///< Input: element in that argument
};

/// Counts of arithmetic operations, as printed in the generated functions' comments.
struct OpCount {
  int add = 0, mul = 0, div = 0, neg = 0, trig = 0, sqrt = 0, max = 0;
  int total() const { return add + mul + div + neg + trig + sqrt + max; }
};

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
