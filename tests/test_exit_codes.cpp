// exit_codes (generator/cli/exit_codes.hpp): one table for every command (README "Exit codes"),
// each code shown by each command that can give it, and run_command's mapping of what a command
// throws.
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli/exit_codes.hpp"

namespace mbgen::cli {
namespace {

namespace fs = std::filesystem;

const std::string kData = MBGEN_TEST_DATA;
const std::string kArm = kData + "/tiny_arm.urdf";

/// Runs `mbgen ARGS`, output discarded; its exit status.
int mbgen(const std::string& args) {
  const int status = std::system((std::string(MBGEN_BINARY) + " " + args + " >/dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

fs::path fresh(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("mbgen_exit_codes_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(ExitCodes, Generate) {
  const fs::path out = fresh("generate");
  EXPECT_EQ(mbgen("generate " + kArm + " --outputs mass_matrix --quiet --out " + out.string()), kSuccess);
  EXPECT_EQ(mbgen("generate " + kData + "/bad/negative_mass.urdf --quiet --out " + out.string()), kBadInput);
  EXPECT_EQ(mbgen("generate " + kArm + " --extras " + kData + "/extras/unknown_output.yaml --quiet --out " + out.string()), kBadInput);
  EXPECT_EQ(mbgen("generate " + kArm + " --out " + out.string() + " --outputs mass_matrx"), kUsage);
  EXPECT_EQ(mbgen("generate " + kArm + " --out " + out.string() + " --no-such-option"), kUsage);
  EXPECT_EQ(mbgen("generate " + kArm), kUsage);  // --out missing
  const fs::path foreign = fresh("generate_foreign");
  std::ofstream(foreign / "tiny_arm.hpp") << "// mine\n";
  EXPECT_EQ(mbgen("generate " + kArm + " --quiet --out " + foreign.string()), kOutputRefused);
}

TEST(ExitCodes, Inspect) {
  EXPECT_EQ(mbgen("inspect " + kArm), kSuccess);
  EXPECT_EQ(mbgen("inspect " + kData + "/bad/negative_mass.urdf"), kBadInput);
  EXPECT_EQ(mbgen("inspect " + kArm + " --extras " + kData + "/extras/unknown_output.yaml --json"), kBadInput);
  EXPECT_EQ(mbgen("inspect /no/such/file.urdf"), kUsage);
  EXPECT_EQ(mbgen("inspect " + kArm + " --fixed --floating"), kUsage);
  EXPECT_EQ(mbgen("inspect " + kArm + " --package-path nonsense"), kUsage);
}

TEST(ExitCodes, FitSsv) {
  // tiny_arm has no meshes: nothing to fit, an empty `ssv:` written.
  const fs::path out = fresh("fit") / "fit.yaml";
  EXPECT_EQ(mbgen("fit-ssv " + kArm + " --quiet --out " + out.string()), kSuccess);
  EXPECT_EQ(mbgen("fit-ssv " + kData + "/bad/negative_mass.urdf --quiet --out " + out.string()), kBadInput);
  EXPECT_EQ(mbgen("fit-ssv " + kArm + " --budget 0 --out " + out.string()), kUsage);
  // --repair-inertia acts in fit-ssv as in the other commands: an indefinite inertia is refused
  // without it and repaired with it.
  const std::string indefinite = kData + "/inertia/indefinite_antenna.urdf";
  EXPECT_EQ(mbgen("fit-ssv " + indefinite + " --quiet --out " + out.string()), kBadInput);
  EXPECT_EQ(mbgen("fit-ssv " + indefinite + " --repair-inertia --quiet --out " + out.string()), kSuccess);
  const fs::path foreign = fresh("fit_foreign") / "fit.yaml";
  std::ofstream(foreign) << "robot: mine\n";
  EXPECT_EQ(mbgen("fit-ssv " + kArm + " --quiet --out " + foreign.string()), kOutputRefused);
}

TEST(ExitCodes, NoCommandIsAUsageError) {
  EXPECT_EQ(mbgen(""), kUsage);
  EXPECT_EQ(mbgen("no-such-command"), kUsage);
  EXPECT_EQ(mbgen("--version"), kSuccess);
  EXPECT_EQ(mbgen("generate --help"), kSuccess);
}

/// run_command maps what a body throws to the table, and says which it was.
TEST(ExitCodes, RunCommandMapsWhatABodyThrows) {
  const auto code = [](auto&& thrower, std::string* message = nullptr) {
    std::ostringstream err;
    const int c = run_command("robot.urdf", err, [&]() -> int { thrower(); return kSuccess; });
    if (message) *message = err.str();
    return c;
  };
  EXPECT_EQ(code([] {}), kSuccess);
  EXPECT_EQ(code([] { throw gen::LoadError("robot.urdf", 3, "link 'a'", "negative mass", "fix it"); }), kBadInput);
  EXPECT_EQ(code([] { throw std::invalid_argument("sub-system: Phi_z must be square"); }), kBadInput);
  EXPECT_EQ(code([] { throw std::runtime_error("cannot read the file"); }), kBadInput);
  EXPECT_EQ(code([] { throw codegen::OutputRefused("x.hpp: the file exists"); }), kOutputRefused);
  std::string message;
  EXPECT_EQ(code([] { throw std::logic_error("function catalogue: f was not traced"); }, &message), kInternalError);
  EXPECT_NE(message.find("robot.urdf: internal error (a bug in mbgen"), std::string::npos) << message;
}

}  // namespace
}  // namespace mbgen::cli
