#pragma once
#include "bench_support.hpp"

namespace mbgen::bench {
/// Registers derivatives/<robot>/{generated,generic,finite_differences} and
/// id_derivatives/<robot>/{generated,generic} for iiwa14, hyq and talos (bench_derivatives.cpp).
void add_derivative_benchmarks(const Robot& robot);
/// The same in independent coordinates for the closed-loop robots lola and cassie_like.
void add_loop_derivative_benchmarks();
}  // namespace mbgen::bench
