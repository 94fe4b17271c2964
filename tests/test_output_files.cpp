// Writing files safely (generator/codegen/output_files.cpp): generated files are written only over
// mbgen's own, all or none; unchanged contents keep their time stamp; every write goes through a
// temporary beside the target and a rename, leaves no temporary behind, and a write that cannot
// happen is refused with the temporary's name.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "codegen/output_files.hpp"

namespace {

namespace fs = std::filesystem;
using mbgen::codegen::GeneratedFile;
using mbgen::codegen::OutputRefused;

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

/// A fresh, empty directory for one test.
fs::path scratch(const std::string& leaf) {
  const fs::path dir = fs::temp_directory_path() / "mbgen_test_output_files" / leaf;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

/// The directory's entries' names, sorted (a temporary left behind would show here).
std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

const std::string kOwn = std::string(mbgen::codegen::kBannerFirstLine) + "\nint x;\n";

TEST(OutputFiles, WriteViaTemporaryReplacesTheFileAndLeavesNoTemporary) {
  const fs::path dir = scratch("replace");
  const fs::path target = dir / "page.html";
  write(target, "old");
  mbgen::codegen::write_via_temporary(target.string(), "new contents\n");
  EXPECT_EQ(read(target), "new contents\n");
  EXPECT_EQ(entries(dir), std::vector<std::string>{"page.html"});
}

TEST(OutputFiles, AWriteThatCannotHappenIsRefusedNamingTheTemporary) {
  const fs::path dir = scratch("missing_directory");
  const fs::path target = dir / "no_such_directory" / "page.html";
  try {
    mbgen::codegen::write_via_temporary(target.string(), "text");
    FAIL() << "a write into a missing directory was not refused";
  } catch (const OutputRefused& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("no_such_directory/.page.html.tmp"), std::string::npos) << what;
    EXPECT_NE(what.find("cannot write"), std::string::npos) << what;
  }
  EXPECT_TRUE(entries(dir).empty());
}

/// The rename is the step that can fail after the temporary exists (here the target is a
/// directory): refused naming the target, and the temporary is not left behind.
TEST(OutputFiles, AFailedRenameIsRefusedAndLeavesNoTemporary) {
  const fs::path dir = scratch("rename_fails");
  fs::create_directories(dir / "page.html");
  write(dir / "page.html" / "inside", "x");
  try {
    mbgen::codegen::write_via_temporary((dir / "page.html").string(), "text");
    FAIL() << "a rename over a non-empty directory was not refused";
  } catch (const OutputRefused& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("page.html: error: cannot replace it"), std::string::npos) << what;
  }
  EXPECT_EQ(entries(dir), std::vector<std::string>{"page.html"});
}

TEST(OutputFiles, GeneratedFilesAreWrittenOnlyOverMbgensOwnAndAllOrNone) {
  const fs::path dir = scratch("foreign");
  write(dir / "b.hpp", "// a user's file\n");
  const std::vector<GeneratedFile> files{{"a.hpp", kOwn}, {"b.hpp", kOwn}};
  try {
    mbgen::codegen::write_generated_files(dir.string(), files);
    FAIL() << "a user's file was overwritten";
  } catch (const OutputRefused& e) {
    EXPECT_NE(std::string(e.what()).find("b.hpp: error: the file exists and was not written by mbgen"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(read(dir / "b.hpp"), "// a user's file\n");
  EXPECT_EQ(entries(dir), std::vector<std::string>{"b.hpp"}) << "a.hpp was written although b.hpp was refused";
}

TEST(OutputFiles, UnchangedFilesKeepTheirTimeStampAndChangedOnesAreRewritten) {
  const fs::path dir = scratch("unchanged");
  const std::vector<GeneratedFile> first{{"a.hpp", kOwn}, {"b.hpp", kOwn}};
  const auto report1 = mbgen::codegen::write_generated_files(dir.string(), first);
  EXPECT_EQ(report1.written.size(), 2u);
  const auto stamp = fs::last_write_time(dir / "a.hpp");
  fs::last_write_time(dir / "a.hpp", stamp - std::chrono::hours(1));  // so a rewrite would show
  const std::vector<GeneratedFile> second{{"a.hpp", kOwn}, {"b.hpp", kOwn + "int y;\n"}};
  const auto report2 = mbgen::codegen::write_generated_files(dir.string(), second);
  EXPECT_EQ(report2.unchanged, std::vector<std::string>{(dir / "a.hpp").string()});
  EXPECT_EQ(report2.written, std::vector<std::string>{(dir / "b.hpp").string()});
  EXPECT_EQ(fs::last_write_time(dir / "a.hpp"), stamp - std::chrono::hours(1));
  EXPECT_EQ(read(dir / "b.hpp"), kOwn + "int y;\n");
  EXPECT_EQ(entries(dir), (std::vector<std::string>{"a.hpp", "b.hpp"}));
}

}  // namespace
