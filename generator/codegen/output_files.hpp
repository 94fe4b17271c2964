#pragma once
// Writing generated files safely: never over a file mbgen did not write (recognised by its
// banner), always through a temporary file and a rename (an interrupted run leaves no half file),
// and not at all when the contents are unchanged (build systems see no new time stamp).
#include <stdexcept>
#include <string>
#include <vector>

#include "codegen/generate_robot.hpp"

namespace mbgen::codegen {

/// A file mbgen will not write over (it did not write it), or cannot write.
class OutputRefused : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct WriteReport {
  std::vector<std::string> written, unchanged;
};

/// Writes `files` into `directory` (created if missing). Throws OutputRefused, naming the file, if
/// one exists that mbgen did not write (then nothing is written at all) or one cannot be written.
WriteReport write_generated_files(const std::string& directory, const std::vector<GeneratedFile>& files);

/// Writes `contents` to `path` through a temporary file beside it and a rename, so that an
/// interrupted run leaves the old file or the new one, never half of one, and two runs never share
/// a temporary. The caller has checked that the file is mbgen's to replace. Throws OutputRefused,
/// naming the temporary, if it cannot be written, and naming `path` if the rename fails (e.g.
/// `path` is a directory); the temporary is removed in both cases.
void write_via_temporary(const std::string& path, const std::string& contents);

/// Hex SHA-256 of `bytes` (OpenSSL).
std::string sha256_hex(const std::string& bytes);

/// Hex SHA-256 of a file's bytes (OpenSSL); throws std::runtime_error if it cannot be read.
std::string sha256_of_file(const std::string& path);

}  // namespace mbgen::codegen
