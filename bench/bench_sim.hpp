#pragma once
#include "bench_support.hpp"

namespace mbgen::bench {
/// Registers the simulation-step benchmarks (bench_sim.cpp).
void add_sim_benchmarks();
}  // namespace mbgen::bench
