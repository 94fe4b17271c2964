#pragma once
#include "bench_support.hpp"

namespace mbgen::bench {
/// Registers the generated implementations of `robot` (iiwa14, hyq, talos).
void add_generated(const Robot& robot);
}  // namespace mbgen::bench
