#pragma once
#include "bench_support.hpp"

namespace mbgen::bench {
/// Registers derivatives/<robot>/{generated,generic,finite_differences} and
/// id_derivatives/<robot>/{generated,generic} for iiwa14, hyq and talos (bench_derivatives.cpp).
void add_derivative_benchmarks(const Robot& robot);
}  // namespace mbgen::bench
