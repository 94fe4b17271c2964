// Every input kept under tests/fuzz_regressions/<target>/ (a fuzzer's finding once fixed, or a
// hand-made adversarial input: empty, truncated, binary, alias chains, an include of itself)
// goes through the same function as the fuzz target (fuzz/fuzz_inputs.hpp), built with g++:
// it must end in a result or a LoadError, never a crash or another exception, and quickly.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "fuzz_inputs.hpp"

namespace fs = std::filesystem;

namespace {

using Function = bool (*)(const std::uint8_t*, std::size_t);

/// How long one kept input may take: far below the fuzzers' per-input limit in a release build;
/// under AddressSanitizer (scripts/test_sanitized.sh, 3-20x slower; the slow assembly kept for
/// inspect takes ~10-20 s there) the fuzzers' own limit, which they run under the same
/// sanitizer (fuzz/README.md: 10 s, 60 s for inspect).
double time_limit(double fuzzer_limit) {
#if defined(__SANITIZE_ADDRESS__)
  return fuzzer_limit;
#else
  (void)fuzzer_limit;
  return 2.0;
#endif
}

void replay(const std::string& target, Function f, double fuzzer_limit = 10.0) {
  const fs::path dir = fs::path(MBGEN_SOURCE_DIR) / "tests" / "fuzz_regressions" / target;
  int inputs = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    std::ifstream in(entry.path(), std::ios::binary);
    std::stringstream s;
    s << in.rdbuf();
    const std::string bytes = s.str();
    const auto start = std::chrono::steady_clock::now();
    EXPECT_NO_THROW(f(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size())) << entry.path();
    EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), time_limit(fuzzer_limit))
        << entry.path();
    ++inputs;
  }
  EXPECT_GT(inputs, 0) << dir << " holds no input";
}

}  // namespace

TEST(FuzzRegressions, Urdf) { replay("urdf", mbgen::fuzz::urdf); }
TEST(FuzzRegressions, Mjcf) { replay("mjcf", mbgen::fuzz::mjcf); }
TEST(FuzzRegressions, Extras) { replay("extras", mbgen::fuzz::extras); }
TEST(FuzzRegressions, Inspect) { replay("inspect", mbgen::fuzz::inspect, 60.0); }

// The functions load good input and report bad input as such (a fuzz target that threw on the seeds would
// find nothing else).
TEST(FuzzRegressions, GoodInputPasses) {
  std::ifstream in(fs::path(MBGEN_SOURCE_DIR) / "robots" / "mechanisms" / "four_bar.urdf");
  std::stringstream s;
  s << in.rdbuf();
  const std::string urdf = s.str();
  const auto* bytes = reinterpret_cast<const std::uint8_t*>(urdf.data());
  EXPECT_TRUE(mbgen::fuzz::urdf(bytes, urdf.size()));
  EXPECT_TRUE(mbgen::fuzz::inspect(bytes, urdf.size()));
  const std::string yaml = "closures: []\n";  // the extras target reads its YAML against ankle_2dof
  EXPECT_TRUE(mbgen::fuzz::extras(reinterpret_cast<const std::uint8_t*>(yaml.data()), yaml.size()));
  EXPECT_FALSE(mbgen::fuzz::urdf(bytes, urdf.size() / 2));  // truncated: a LoadError
}
