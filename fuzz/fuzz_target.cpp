// A libFuzzer entry point for one of fuzz_inputs.hpp's functions, chosen at compile time
// (MBGEN_FUZZ_FUNCTION: urdf, mjcf, extras, inspect).
#include <cstddef>
#include <cstdint>

#include "fuzz_inputs.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  mbgen::fuzz::MBGEN_FUZZ_FUNCTION(data, size);
  return 0;
}
