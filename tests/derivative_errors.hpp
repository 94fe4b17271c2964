#pragma once
// How far a derivative is from its reference, for the derivative tests (test_rnea_derivatives.cpp,
// test_loop_dynamics_derivatives.cpp, test_actuator_forces_derivatives.cpp, the generated ones):
// max-norms, relative to the reference's; and the conversions the generated functions' tests compare
// through (their row-major arrays of double or float against the runtime's Eigen results).
#include <vector>

#include "mbgen/spatial/types.hpp"

namespace mbgen::test {

/// |got - want| / |want| (max-norms; over 1 where want is zero).
inline double max_relative(const MatX<double>& got, const MatX<double>& want) {
  const double scale = want.cwiseAbs().maxCoeff();
  return (got - want).cwiseAbs().maxCoeff() / (scale > 0 ? scale : 1.0);
}

/// The same for a result of a solve with M, weighted by M: |M (got - want)| / (|M| |want|), all
/// max-norms. Any two ways of solving with an ill-conditioned M (the parallel_legs models' light
/// links: their tree's M reaches a condition number of 1e9) differ by up to cond(M) eps in the
/// directions M hardly resists; M times the difference is what each solve answers for.
inline double weighted_relative(const MatX<double>& M, const MatX<double>& got, const MatX<double>& want) {
  const double scale = M.cwiseAbs().maxCoeff() * want.cwiseAbs().maxCoeff();
  return (M * (got - want)).cwiseAbs().maxCoeff() / (scale > 0 ? scale : 1.0);
}

/// x as a std::vector of T (a generated function's input in its scalar).
template <typename T> std::vector<T> as(const VecX<double>& x) {
  std::vector<T> out(static_cast<std::size_t>(x.size()));
  for (int k = 0; k < x.size(); ++k) out[static_cast<std::size_t>(k)] = static_cast<T>(x[k]);
  return out;
}

/// A generated function's row-major rows x cols array as a double matrix.
template <typename T> MatX<double> matrix(const std::vector<T>& x, int rows, int cols) {
  MatX<double> m(rows, cols);
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) m(r, c) = static_cast<double>(x[static_cast<std::size_t>(r * cols + c)]);
  return m;
}

}  // namespace mbgen::test
