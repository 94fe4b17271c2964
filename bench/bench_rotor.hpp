#pragma once
#include "bench_support.hpp"

namespace mbgen::bench {
/// Registers the rotor-model benchmarks (bench_rotor.cpp).
void add_rotor_benchmarks();
}  // namespace mbgen::bench
