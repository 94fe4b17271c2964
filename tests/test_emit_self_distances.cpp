// emit_self_distances: how the pair blocks are laid out in the generated source. Many SSV calls
// go into noinline parts of at most 48 calls (g++'s time on one function grows faster than its
// size), each pair exactly once and in order; a scene with few calls keeps them in one function.
// What the code computes is tested against the generic runtime in test_generated_self_distances.
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>
#include <string>

#include "codegen/generate_robot.hpp"
#include "codegen/templates.hpp"
#include "model/load_description.hpp"

namespace mbgen::test {
namespace {

namespace fs = std::filesystem;

std::string self_distances_source(const std::string& urdf, const std::string& extras, gen::BaseType base) {
  gen::LoadOptions load;
  load.base = base;
  if (!extras.empty()) load.extras_file = extras;
  const gen::Description description = gen::load_description(urdf, load);
  codegen::CodegenOptions options;
  options.name = "robot";
  options.scalars = codegen::ScalarChoice::Double;
  options.outputs = {"distances"};
  const codegen::TemplateSet templates = codegen::TemplateSet::load((fs::path(MBGEN_SOURCE_DIR) / "templates" / "cpp").string());
  for (const codegen::GeneratedFile& file : codegen::generate_robot(description, options, templates))
    if (file.filename == "robot_self_distances.cpp") return file.contents;
  ADD_FAILURE() << "no robot_self_distances.cpp generated for " << urdf;
  return {};
}

int count(const std::string& text, const std::string& piece) {
  int n = 0;
  for (std::size_t at = text.find(piece); at != std::string::npos; at = text.find(piece, at + 1)) ++n;
  return n;
}

TEST(EmitSelfDistances, ManySsvCallsGoIntoPartsOfAtMost48EachPairOnceInOrder) {
  const std::string root(MBGEN_SOURCE_DIR);
  const std::string source = self_distances_source(root + "/robots/lola/lola.urdf", root + "/robots/lola/lola.yaml",
                                                   gen::BaseType::Floating);
  const std::regex part(R"(// Pairs (\d+) to (\d+) of distances_impl \((\d+) SSV calls\)\.\n)"
                        R"(template <typename S, bool compact>\nMBGEN_GENERATED_NOINLINE void pairs_(\d+)_to_(\d+)\()");
  int next = 0, parts = 0, calls = 0;
  for (auto it = std::sregex_iterator(source.begin(), source.end(), part); it != std::sregex_iterator(); ++it, ++parts) {
    const std::smatch& m = *it;
    EXPECT_EQ(std::stoi(m[1]), next) << "parts must cover the pairs in order, without gaps";
    EXPECT_EQ(m[1], m[4]);
    EXPECT_EQ(m[2], m[5]);
    EXPECT_LE(std::stoi(m[3]), 48) << m[0];
    EXPECT_GT(std::stoi(m[3]), 0) << m[0];
    calls += std::stoi(m[3]);
    // distances_impl calls each part once.
    const std::string call = "  pairs_" + m[1].str() + "_to_" + m[2].str() + "<S, compact>(P, J, threshold, distance, near, ";
    EXPECT_EQ(count(source, call), 1) << call;
    next = std::stoi(m[2]) + 1;
  }
  EXPECT_EQ(next, 178) << "Lola's scene keeps 178 pairs";
  EXPECT_EQ(calls, 247) << "Lola's 178 pairs hold 247 shape pairs (711 before the spheres inside its rods' and housings' capsules were left out)";
  EXPECT_GE(parts, 247 / 48 + 1);
  // Every pair's block exactly once.
  for (int k = 0; k < 178; ++k)
    EXPECT_EQ(count(source, "  {  // pair " + std::to_string(k) + ": "), 1) << "pair " << k;
  EXPECT_NE(source.find("#define MBGEN_GENERATED_NOINLINE"), std::string::npos);
}

TEST(EmitSelfDistances, FewSsvCallsStayInOneFunction) {
  const std::string source = self_distances_source(std::string(MBGEN_SHARED_ROBOTS) + "/iiwa14/iiwa14_primitive_collision.urdf",
                                                   "", gen::BaseType::Fixed);
  const int pairs = count(source, "  {  // pair ");
  ASSERT_GT(pairs, 0) << "the test needs a scene with pairs";
  EXPECT_EQ(source.find("pairs_0_to_"), std::string::npos);
  EXPECT_EQ(source.find("MBGEN_GENERATED_NOINLINE"), std::string::npos);
}

}  // namespace
}  // namespace mbgen::test
