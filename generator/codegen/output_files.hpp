#pragma once
// Writing generated files safely: never over a file mbgen did not write (recognised by its
// banner), always through a temporary file and a rename (an interrupted run leaves no half file),
// and not at all when the contents are unchanged (build systems see no new time stamp).
#include <string>
#include <vector>

#include "codegen/generate_robot.hpp"

namespace mbgen::codegen {

struct WriteReport {
  std::vector<std::string> written, unchanged;
};

/// Writes `files` into `directory` (created if missing). Throws std::runtime_error, naming the
/// file, if one exists that mbgen did not write; then nothing is written at all.
WriteReport write_generated_files(const std::string& directory, const std::vector<GeneratedFile>& files);

/// Hex SHA-256 of `bytes` (OpenSSL).
std::string sha256_hex(const std::string& bytes);

/// Hex SHA-256 of a file's bytes (OpenSSL); throws std::runtime_error if it cannot be read.
std::string sha256_of_file(const std::string& path);

}  // namespace mbgen::codegen
