#pragma once
// Sym: a scalar that records every operation into the current ExpressionGraph instead of
// computing it. The runtime's generic algorithms, instantiated with Sym, become expression graphs
// that the emitter prints as straight-line C++ ("one implementation of the math", DESIGN.md).
#include <Eigen/Core>
#include <cassert>

#include "codegen/expression_graph.hpp"

namespace mbgen::codegen {

class Sym;

/// Makes `graph` the one every Sym operation records into while this object lives.
class Recording {
 public:
  explicit Recording(ExpressionGraph& graph);
  ~Recording();
  Recording(const Recording&) = delete;
  Recording& operator=(const Recording&) = delete;
  static ExpressionGraph& graph();

 private:
  ExpressionGraph* previous_;
};

class Sym {
 public:
  Sym() : id_(Recording::graph().constant(0.0)) {}
  Sym(double value) : id_(Recording::graph().constant(value)) {}  // NOLINT: constants mix freely
  Sym(int value) : Sym(static_cast<double>(value)) {}             // NOLINT
  static Sym from_id(int id) {
    Sym s(0.0);
    s.id_ = id;
    return s;
  }
  static Sym input(int argument, int index) { return from_id(Recording::graph().input(argument, index)); }
  int id() const { return id_; }

  friend Sym operator+(const Sym& a, const Sym& b) { return from_id(Recording::graph().binary(Op::Add, a.id_, b.id_)); }
  friend Sym operator-(const Sym& a, const Sym& b) { return from_id(Recording::graph().binary(Op::Sub, a.id_, b.id_)); }
  friend Sym operator*(const Sym& a, const Sym& b) { return from_id(Recording::graph().binary(Op::Mul, a.id_, b.id_)); }
  friend Sym operator/(const Sym& a, const Sym& b) { return from_id(Recording::graph().binary(Op::Div, a.id_, b.id_)); }
  friend Sym operator-(const Sym& a) { return from_id(Recording::graph().unary(Op::Neg, a.id_)); }
  friend Sym operator+(const Sym& a) { return a; }
  Sym& operator+=(const Sym& b) { return *this = *this + b; }
  Sym& operator-=(const Sym& b) { return *this = *this - b; }
  Sym& operator*=(const Sym& b) { return *this = *this * b; }
  Sym& operator/=(const Sym& b) { return *this = *this / b; }

  friend Sym sin(const Sym& a) { return from_id(Recording::graph().unary(Op::Sin, a.id_)); }
  friend Sym cos(const Sym& a) { return from_id(Recording::graph().unary(Op::Cos, a.id_)); }
  friend Sym sqrt(const Sym& a) { return from_id(Recording::graph().unary(Op::Sqrt, a.id_)); }
  /// The larger of a and b, decided at run time (found by ADL where the runtime writes
  /// `using std::max; max(x, y)`).
  friend Sym max(const Sym& a, const Sym& b) { return from_id(Recording::graph().binary(Op::Max, a.id_, b.id_)); }
  /// 1 where a > 0, else 0, decided at run time (the contact law's slopes; found by ADL where
  /// the runtime calls unit_step).
  friend Sym unit_step(const Sym& a) { return from_id(Recording::graph().unary(Op::Step, a.id_)); }
  /// a^b (the contact law's exponent other than 1, 1.5 or 2).
  friend Sym pow(const Sym& a, const Sym& b) { return from_id(Recording::graph().binary(Op::Pow, a.id_, b.id_)); }

  /// Comparisons exist only so that Eigen compiles; a traced algorithm must not branch on values.
  /// They are true only for constants that satisfy them (and abort in debug builds otherwise).
  friend bool operator==(const Sym& a, const Sym& b) { return a.id_ == b.id_; }
  friend bool operator!=(const Sym& a, const Sym& b) { return a.id_ != b.id_; }

 private:
  int id_;
};

}  // namespace mbgen::codegen

namespace Eigen {
template <> struct NumTraits<mbgen::codegen::Sym> : GenericNumTraits<mbgen::codegen::Sym> {
  using Real = mbgen::codegen::Sym;
  using NonInteger = mbgen::codegen::Sym;
  using Nested = mbgen::codegen::Sym;
  using Literal = mbgen::codegen::Sym;
  enum { IsComplex = 0, IsInteger = 0, IsSigned = 1, RequireInitialization = 1, ReadCost = 1, AddCost = 1, MulCost = 1 };
  static inline int digits10() { return 15; }
  static inline Real epsilon() { return Real(1e-16); }
  static inline Real dummy_precision() { return Real(1e-12); }
};
}  // namespace Eigen
