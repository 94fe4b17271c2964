#pragma once
// Shared pieces of the tracers (trace_dynamics.cpp, trace_loop_maps.cpp): symbolic inputs, node
// ids of symbolic results, and the argument specs of the generated signatures.
#include <fmt/format.h>

#include <vector>

#include "codegen/symbolic.hpp"
#include "codegen/traced_function.hpp"
#include "mbgen/mbgen.hpp"

namespace mbgen::codegen::tracing {

using SymVec = VecX<Sym>;

/// Symbolic input vector: element i of argument `argument`.
inline SymVec inputs(int argument, int size) {
  SymVec x(size);
  for (int i = 0; i < size; ++i) x[i] = Sym::input(argument, i);
  return x;
}

/// Symbolic n x n input matrix, row-major as every emitted matrix is: element (r, c) is element
/// r n + c of argument `argument`.
inline MatX<Sym> square_input(int argument, int n) {
  MatX<Sym> m(n, n);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) m(r, c) = Sym::input(argument, r * n + c);
  return m;
}

/// Node ids of a symbolic matrix in row-major order, as every emitted matrix is.
inline std::vector<int> ids_of(const Eigen::Ref<const MatX<Sym>>& m) {
  std::vector<int> ids;
  for (int r = 0; r < m.rows(); ++r)
    for (int c = 0; c < m.cols(); ++c) ids.push_back(m(r, c).id());
  return ids;
}

inline int num_independent(const Model& m) { return m.structure().num_independent(); }

inline ArraySpec q_spec(const Model& m) { return {"q", m.nq(), fmt::format("[{}] joint positions", m.nq())}; }
inline ArraySpec closed_q_spec(const Model& m) {
  return {"q", m.nq(), fmt::format("[{}] joint positions of every tree joint, loops closed (closure_positions)", m.nq())};
}
inline ArraySpec v_spec(const Model& m, const char* name, const char* what) {
  return {name, m.nv(), fmt::format("[{}] {}", m.nv(), what)};
}
inline ArraySpec y_spec(const Model& m, const char* name, const char* what) {
  const int ny = num_independent(m);
  return {name, ny, fmt::format("[{}] {}, independent_joint_names order", ny, what)};
}

}  // namespace mbgen::codegen::tracing
