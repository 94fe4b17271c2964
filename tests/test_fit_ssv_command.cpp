// `mbgen fit-ssv` as a user runs it (generator/cli/fit_ssv_command.cpp): TALOS's compounds written
// as extras that `inspect` loads and prunes, the same bytes twice, a file it did not write left
// alone, bad options refused, and the picture's data.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const std::string kTalos = mbgen::test::shared_robot("talos/talos_reduced.urdf");
const std::string kPackage = "--package-path example-robot-data=" + mbgen::test::shared_robot("talos/meshes/example-robot-data");

fs::path scratch(const std::string& leaf) {
  const fs::path dir = fs::temp_directory_path() / "mbgen_test_fit_ssv_command";
  fs::create_directories(dir);
  return dir / leaf;
}

/// Runs mbgen with `arguments`; returns the exit status, stdout in `out` (stderr to `err` if given).
int run(const std::string& arguments, const fs::path& out, const fs::path& err = "/dev/null") {
  const std::string cmd = std::string(MBGEN_BINARY) + " " + arguments + " >" + out.string() + " 2>" + err.string();
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

TEST(FitSsvCommand, TalosCompoundsLoadAsExtrasAndInspectPrunesTheirPairs) {
  const fs::path yaml = scratch("talos.yaml"), again = scratch("talos_again.yaml"), pictures = scratch("picture");
  fs::remove(yaml), fs::remove(again), fs::remove_all(pictures);
  ASSERT_EQ(run("fit-ssv " + kTalos + " --floating " + kPackage + " --out " + yaml.string() + " --picture-data " + pictures.string(),
                scratch("fit.txt")),
            0);
  const std::string report = read(scratch("fit.txt"));
  EXPECT_NE(report.find("48 links fitted"), std::string::npos) << report;
  ASSERT_EQ(run("fit-ssv " + kTalos + " --floating " + kPackage + " --out " + again.string(), scratch("fit2.txt")), 0);
  EXPECT_EQ(read(yaml), read(again));  // deterministic, to the byte
  EXPECT_EQ(read(yaml).rfind("# Written by mbgen fit-ssv", 0), 0u);
  // Each of the 48 links' compounds, one line per primitive, in the mesh order of the picture.
  EXPECT_GT(fs::file_size(pictures / "mesh.dat"), 1000u);
  EXPECT_GT(fs::file_size(pictures / "ssv.dat"), 1000u);

  ASSERT_EQ(run("inspect " + kTalos + " --floating --samples 300 --extras " + yaml.string(), scratch("inspect.txt")), 0);
  const std::string inspect = read(scratch("inspect.txt"));
  EXPECT_NE(inspect.find("ssv compounds (52):"), std::string::npos) << inspect;
  EXPECT_NE(inspect.find("collision pairs:"), std::string::npos) << inspect;
  EXPECT_NE(inspect.find("kept    base_link - arm_left_3_link"), std::string::npos) << inspect;
  EXPECT_EQ(inspect.find("without an SSV"), std::string::npos) << inspect;  // every mesh link has its compound
  // Without the fitted extras, inspect names the links that lack one and how to fit them.
  ASSERT_EQ(run("inspect " + kTalos + " --floating --samples 10", scratch("bare.txt")), 0);
  EXPECT_NE(read(scratch("bare.txt")).find("collision meshes or boxes without an SSV on 48 link(s)"), std::string::npos);
}

// An SDFormat link's mesh, named by a model:// URI, found through --package-path and fitted; the
// compound loads back as the SDF's extras.
TEST(FitSsvCommand, SdfMeshByModelUri) {
  const fs::path sdf = std::string(MBGEN_TEST_DATA) + "/sdf/one_mesh_link.sdf", yaml = scratch("one_link.yaml");
  fs::remove(yaml);
  ASSERT_EQ(run("fit-ssv " + sdf.string() + " " + kPackage + " --out " + yaml.string(), scratch("sdf_fit.txt")), 0);
  EXPECT_NE(read(scratch("sdf_fit.txt")).find("1 link fitted"), std::string::npos) << read(scratch("sdf_fit.txt"));
  ASSERT_EQ(run("inspect " + sdf.string() + " --extras " + yaml.string(), scratch("sdf_inspect.txt")), 0);
  EXPECT_NE(read(scratch("sdf_inspect.txt")).find("ssv compounds (1):"), std::string::npos) << read(scratch("sdf_inspect.txt"));
  // Without the package path, the reference is named with its fix.
  EXPECT_EQ(run("fit-ssv " + sdf.string() + " --out " + scratch("none.yaml").string(), scratch("sdf_none.txt"), scratch("sdf_none_err.txt")),
            0);
  EXPECT_NE(read(scratch("sdf_none_err.txt")).find("--package-path example-robot-data=DIR"), std::string::npos)
      << read(scratch("sdf_none_err.txt"));
}

TEST(FitSsvCommand, NeverOverwritesAFileItDidNotWriteAndRefusesBadOptions) {
  const fs::path mine = scratch("mine.yaml");
  std::ofstream(mine) << "robot: talos\n";
  EXPECT_EQ(run("fit-ssv " + kTalos + " " + kPackage + " --out " + mine.string(), scratch("o.txt"), scratch("e.txt")), 3);
  EXPECT_EQ(read(mine), "robot: talos\n");
  EXPECT_NE(read(scratch("e.txt")).find("was not written by mbgen fit-ssv"), std::string::npos) << read(scratch("e.txt"));

  EXPECT_EQ(run("fit-ssv " + kTalos + " " + kPackage + " --budget 0 --out " + scratch("b.yaml").string(), scratch("o.txt")), 2);
  EXPECT_EQ(run("fit-ssv " + kTalos + " --package-path nonsense --out " + scratch("b.yaml").string(), scratch("o.txt"),
                scratch("e.txt")),
            2);
  EXPECT_NE(read(scratch("e.txt")).find("expected NAME=DIR"), std::string::npos) << read(scratch("e.txt"));
  // Without the package path every mesh is a warning naming its link and reference: only the
  // camera's box (rgbd_link) is fitted.
  const fs::path none = scratch("none.yaml");
  fs::remove(none);
  EXPECT_EQ(run("fit-ssv " + kTalos + " --out " + none.string(), scratch("o.txt"), scratch("e.txt")), 0);
  const std::string warnings = read(scratch("e.txt"));
  EXPECT_NE(warnings.find("package 'example-robot-data' is unknown"), std::string::npos) << warnings;
  EXPECT_NE(warnings.find("link 'torso_2_link' gets no fitted SSV"), std::string::npos) << warnings;
  EXPECT_NE(read(scratch("o.txt")).find("1 link fitted, 4 primitives"), std::string::npos) << read(scratch("o.txt"));
}

// A robot without meshes or boxes (panda_collision: spheres and cylinders) gets an empty section
// that still loads as extras.
TEST(FitSsvCommand, NoMeshesGiveAnEmptySectionThatLoads) {
  const fs::path yaml = scratch("panda.yaml");
  fs::remove(yaml);
  const std::string panda = mbgen::test::shared_robot("panda/panda_collision.urdf");
  ASSERT_EQ(run("fit-ssv " + panda + " --out " + yaml.string(), scratch("p.txt")), 0);
  EXPECT_NE(read(scratch("p.txt")).find("0 links fitted"), std::string::npos);
  EXPECT_NE(read(yaml).find("ssv: {}"), std::string::npos) << read(yaml);
  EXPECT_EQ(run("inspect " + panda + " --samples 10 --extras " + yaml.string(), scratch("pi.txt"), scratch("pe.txt")), 0)
      << read(scratch("pe.txt"));
}

}  // namespace
