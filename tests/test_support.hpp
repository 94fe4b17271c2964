#pragma once
// Shared by the tests: the robot descriptions to run on, seeded random states, and a relative
// error measure. Tolerances are stated in each test.
#include <algorithm>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "mbgen/gen/description.hpp"
#include "mbgen/mbgen.hpp"

namespace mbgen::test {

/// Every URDF in ../shared/robots and robots/, sorted (the test names stay stable).
inline std::vector<std::string> all_urdfs() {
  std::vector<std::string> files;
  for (const char* root : {MBGEN_SHARED_ROBOTS, MBGEN_SOURCE_DIR "/robots"}) {
    if (!std::filesystem::exists(root)) continue;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(root))
      if (entry.is_regular_file() && entry.path().extension() == ".urdf") files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

inline std::string shared_robot(const std::string& relative) { return std::string(MBGEN_SHARED_ROBOTS) + "/" + relative; }

/// A readable test-name suffix for a path: its parent folder and stem.
inline std::string short_name(const std::string& path) {
  std::filesystem::path p(path);
  std::string s = p.parent_path().filename().string() + "_" + p.stem().string();
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}

/// Loads the tree model of a URDF alone (no extras), fixed or floating base.
inline Model load_tree(const std::string& path, gen::BaseType base) {
  gen::LoadOptions options;
  options.base = base;
  options.pick_up_robot_yaml = false;
  return gen::load_description(path, options).model;
}

/// The bases a URDF can be loaded with: fixed always; floating unless the robot hangs from a
/// "world" link by moving joints only (the loader refuses that, see test_load_urdf.cpp).
inline std::vector<gen::BaseType> loadable_bases(const std::string& path) {
  std::vector<gen::BaseType> bases{gen::BaseType::Fixed};
  gen::LoadOptions options;
  options.base = gen::BaseType::Floating;
  options.pick_up_robot_yaml = false;
  try {
    gen::load_description(path, options);
    bases.push_back(gen::BaseType::Floating);
  } catch (const std::exception&) {
  }
  return bases;
}

/// A URDF and the base to load it with: the parameter of the tests that run on every robot.
struct UrdfCase {
  std::string path;
  gen::BaseType base;
};
inline void PrintTo(const UrdfCase& c, std::ostream* os) {
  *os << c.path << (c.base == gen::BaseType::Fixed ? " fixed" : " floating");
}
/// Every URDF with every base it loads with.
inline std::vector<UrdfCase> all_urdf_cases() {
  std::vector<UrdfCase> out;
  for (const std::string& path : all_urdfs())
    for (gen::BaseType base : loadable_bases(path)) out.push_back({path, base});
  return out;
}
/// Test-name suffix for INSTANTIATE_TEST_SUITE_P over all_urdf_cases().
inline std::string urdf_case_name(const ::testing::TestParamInfo<UrdfCase>& info) {
  return short_name(info.param.path) + (info.param.base == gen::BaseType::Fixed ? "_fixed" : "_floating");
}

/// Configurations q (+) h v and q (-) h v on the manifold, for central differences.
struct CentralPair {
  VecX<double> plus, minus;
};
inline CentralPair central_pair(const Model& model, const VecX<double>& q, const VecX<double>& v, double h) {
  CentralPair p{VecX<double>(model.nq()), VecX<double>(model.nq())};
  integrate<double>(model, q, v * h, p.plus);
  integrate<double>(model, q, v * -h, p.minus);
  return p;
}

/// ||a - b|| / max(1, ||b||): relative for large values, absolute near zero.
template <typename A, typename B> double relative_error(const A& a, const B& b) {
  return (a - b).norm() / std::max(1.0, static_cast<double>(b.norm()));
}

}  // namespace mbgen::test
