#include "codegen/output_files.hpp"

#include <fmt/format.h>
#include <openssl/evp.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace mbgen::codegen {

namespace fs = std::filesystem;

namespace {
std::string read_all(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot read the file", path.string()));
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

std::string sha256_hex(const std::string& bytes) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int length = 0;
  if (EVP_Digest(bytes.data(), bytes.size(), digest, &length, EVP_sha256(), nullptr) != 1)
    throw std::runtime_error("SHA-256 failed (OpenSSL EVP_Digest)");
  std::string hex;
  for (unsigned int i = 0; i < length; ++i) hex += fmt::format("{:02x}", digest[i]);
  return hex;
}

std::string sha256_of_file(const std::string& path) { return sha256_hex(read_all(path)); }

void write_via_temporary(const std::string& path, const std::string& contents) {
  const fs::path target(path);
  const fs::path temporary =
      target.parent_path() / fmt::format(".{}.tmp{}", target.filename().string(), static_cast<long>(::getpid()));
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    out << contents;
    out.close();
    if (!out) {
      std::error_code ignored;
      fs::remove(temporary, ignored);
      throw OutputRefused(fmt::format("{}: error: cannot write (disk full or no permission)", temporary.string()));
    }
  }
  std::error_code ec;
  fs::rename(temporary, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw OutputRefused(fmt::format("{}: error: cannot replace it ({})", path, ec.message()));
  }
}

WriteReport write_generated_files(const std::string& directory, const std::vector<GeneratedFile>& files) {
  const fs::path dir(directory);
  // Check every target first, so a refusal leaves the directory as it was.
  for (const GeneratedFile& f : files) {
    const fs::path target = dir / f.filename;
    if (!fs::exists(target)) continue;
    const std::string existing = read_all(target);
    if (existing.rfind(kBannerFirstLine, 0) != 0)
      throw OutputRefused(fmt::format(
          "{}: error: the file exists and was not written by mbgen (no mbgen banner on its first line)\n"
          "  fix: choose another --out directory or --name, or move the file away; mbgen never overwrites "
          "files it did not write",
          target.string()));
  }
  fs::create_directories(dir);
  WriteReport report;
  for (const GeneratedFile& f : files) {
    const fs::path target = dir / f.filename;
    if (fs::exists(target) && read_all(target) == f.contents) {
      report.unchanged.push_back(target.string());
      continue;
    }
    write_via_temporary(target.string(), f.contents);
    report.written.push_back(target.string());
  }
  return report;
}

}  // namespace mbgen::codegen
