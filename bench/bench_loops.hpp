#pragma once
#include "bench_support.hpp"

namespace mbgen::bench {
/// Registers the closed-loop forward dynamics benchmarks (bench_loops.cpp).
void add_loop_benchmarks();
}  // namespace mbgen::bench
