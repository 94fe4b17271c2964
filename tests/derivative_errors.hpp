#pragma once
// How far a derivative is from its reference, for the derivative tests (test_rnea_derivatives.cpp,
// test_loop_dynamics_derivatives.cpp, test_actuator_forces_derivatives.cpp, the generated ones):
// max-norms, relative to the reference's.
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

}  // namespace mbgen::test
