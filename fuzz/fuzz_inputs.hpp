#pragma once
// What the fuzz targets do with one input (fuzz/README.md), shared with the regression test
// (tests/test_fuzz_regressions.cpp) so that a finding, once fixed, stays fixed in the normal
// suite. Each writes the bytes to a file of its own temporary folder (the loaders read paths)
// and loads it; a LoadError is the expected answer to bad input, anything else escapes: an
// exception of another type, a crash, a sanitizer report or a hang is a finding. Each returns
// true when the input loaded, false on a LoadError.
#include <cstddef>
#include <cstdint>

namespace mbgen::fuzz {

/// The bytes as a URDF: read_description.
bool urdf(const std::uint8_t* data, std::size_t size);
/// The bytes as an MJCF file: read_description.
bool mjcf(const std::uint8_t* data, std::size_t size);
/// The bytes as the YAML extras of robots/mechanisms/ankle_2dof.urdf: read_description.
bool extras(const std::uint8_t* data, std::size_t size);
/// The whole `inspect` path: the bytes up to a line "---extras---" as a URDF, the rest (if any)
/// as its extras; load_description (validation, topology, assembly, sub-systems) and the
/// collision scene (200 samples).
bool inspect(const std::uint8_t* data, std::size_t size);

/// The separator of inspect's two parts.
inline constexpr const char* kExtrasSeparator = "\n---extras---\n";

}  // namespace mbgen::fuzz
