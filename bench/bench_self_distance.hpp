#pragma once
#include "bench_support.hpp"

namespace mbgen::bench {
/// Registers `self_distance/<robot>/generic` (bench_self_distance.cpp).
void add_self_distance_benchmarks();
}  // namespace mbgen::bench
