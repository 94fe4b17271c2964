// function_catalog (generator/codegen/function_catalog.hpp): the one list of generated functions,
// against what is written elsewhere about it — the docs' outputs (docs/extras.md), the files
// CMake's mbgen_add_robot declares (cmake/mbgen_function_catalog.cmake reads the catalogue's
// source) — and its own consistency; and the scene's outputs checked against it with the extras
// file's line.
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>

#include "codegen/function_catalog.hpp"
#include "codegen/scene_functions.hpp"
#include "load/load_error.hpp"
#include "model/load_description.hpp"

namespace mbgen::codegen {
namespace {

std::string read(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The backticked words of a text, in order.
std::vector<std::string> backticked(const std::string& text) {
  std::vector<std::string> words;
  const std::regex word("`([a-z_]+)");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), word); it != std::sregex_iterator(); ++it)
    words.push_back((*it)[1]);
  return words;
}

/// docs/extras.md's table "What `scene.outputs` generates": output -> its row's text.
std::map<std::string, std::string> documented_outputs() {
  const std::string doc = read(MBGEN_SOURCE_DIR "/docs/extras.md");
  const std::size_t section = doc.find("### What `scene.outputs` generates");
  EXPECT_NE(section, std::string::npos);
  std::map<std::string, std::string> rows;
  std::istringstream lines(doc.substr(section, doc.find("\n#", section + 1) - section));
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("| `", 0) != 0) continue;
    const std::size_t bar = line.find(" | ", 2);
    rows[backticked(line.substr(0, bar)).at(0)] = line.substr(bar);
  }
  return rows;
}

TEST(FunctionCatalog, TheDocsListTheCataloguesOutputs) {
  const std::map<std::string, std::string> documented = documented_outputs();
  std::vector<std::string> names;
  for (const auto& [output, row] : documented) names.push_back(output);
  EXPECT_EQ(names, scene_outputs());
  // Each output's row names every function of the catalogue that output brings directly.
  for (const GeneratedFunction& f : function_catalog())
    for (const std::string& output : f.outputs) {
      ASSERT_TRUE(documented.count(output)) << output;
      const std::vector<std::string> words = backticked(documented.at(output));
      EXPECT_NE(std::find(words.begin(), words.end(), f.name), words.end()) << output << " does not name " << f.name;
    }
  // The schema's `scene.outputs` entry lists the same outputs.
  const std::string doc = read(MBGEN_SOURCE_DIR "/docs/extras.md");
  const std::size_t key = doc.find("| `scene.outputs` |");
  ASSERT_NE(key, std::string::npos);
  const std::string cell = doc.substr(key + 19, doc.find("Each brings", key) - key - 19);
  std::set<std::string> listed;
  for (const std::string& w : backticked(cell)) listed.insert(w);
  listed.erase("contact");  // "implied by `contact:`"
  EXPECT_EQ(std::vector<std::string>(listed.begin(), listed.end()), scene_outputs());
}

/// What cmake/mbgen_function_catalog.cmake read from the catalogue's source.
std::map<std::string, std::vector<std::string>> cmake_lists() {
  std::map<std::string, std::vector<std::string>> lists;
  const std::regex set(R"(set\((MBGEN_[A-Z_]+) ([a-z_;]+)\))");
  const std::string text = read(MBGEN_FUNCTIONS_CMAKE);
  for (auto it = std::sregex_iterator(text.begin(), text.end(), set); it != std::sregex_iterator(); ++it) {
    std::vector<std::string>& names = lists[(*it)[1]];
    std::istringstream items((*it)[2]);
    for (std::string name; std::getline(items, name, ';');) names.push_back(name);
  }
  return lists;
}

TEST(FunctionCatalog, CMakeDeclaresTheCataloguesFiles) {
  const auto lists = cmake_lists();
  EXPECT_EQ(lists.at("MBGEN_GENERATED_FUNCTIONS"), all_functions());
  EXPECT_EQ(lists.at("MBGEN_BATCHED_FUNCTIONS"), batched_functions());
  EXPECT_EQ(batched_functions().size(), 13u);  // the straight-line dynamics and kinematics, two derivatives
}

TEST(FunctionCatalog, RowsAreConsistent) {
  std::set<std::string> names;
  for (const GeneratedFunction& f : function_catalog()) {
    EXPECT_TRUE(names.insert(f.name).second) << "two rows " << f.name;
    EXPECT_FALSE(std::string(f.summary).empty()) << f.name;
    // A traced row has a tracer; a row with a writer of its own has none, and no batch form.
    EXPECT_EQ(f.writer == Writer::traced, f.trace != nullptr) << f.name;
    if (f.writer != Writer::traced) {
      EXPECT_EQ(f.batch, Batch::no) << f.name;
    }
    // A batch writer of its own belongs to a batched row (the derivatives' solves on the lanes).
    if (f.batch_definition) {
      EXPECT_EQ(f.batch, Batch::yes) << f.name;
    }
    // Every row is reachable: by an output, always, or with a set of others.
    EXPECT_TRUE(!f.outputs.empty() || f.always || !f.with_all_of.empty()) << f.name;
  }
  for (const GeneratedFunction& f : function_catalog()) {
    for (const std::string& g : f.needs) EXPECT_TRUE(names.count(g)) << f.name << " needs unknown " << g;
    for (const std::string& g : f.with_all_of) EXPECT_TRUE(names.count(g)) << f.name << " comes with unknown " << g;
  }
  EXPECT_EQ(find_function("mass_matrx"), nullptr);
  ASSERT_NE(find_function("mass_matrix"), nullptr);
  EXPECT_STREQ(find_function("mass_matrix")->name, "mass_matrix");
}

TEST(FunctionCatalog, NeedsAreClosedTransitively) {
  // contact_accelerations needs full_accelerations, which needs forward_dynamics: the selection of
  // a scene that brings only the first has all three.
  const FunctionSelection s = select_functions({kSimulationOutput}, false);
  for (const char* f : {"contact_accelerations", "full_accelerations", "forward_dynamics"}) EXPECT_TRUE(s.emits(f)) << f;
  // Every need of every emitted function is emitted, for each output alone.
  for (const std::string& output : scene_outputs()) {
    const FunctionSelection one = select_functions({output}, false);
    for (const GeneratedFunction& f : function_catalog())
      if (one.emits(f.name)) {
        for (const std::string& g : f.needs) EXPECT_TRUE(one.emits(g)) << output << ": " << f.name << " without " << g;
      }
  }
}

TEST(FunctionCatalog, AnUnknownSceneOutputNamesTheExtrasLine) {
  gen::LoadOptions options;
  options.extras_file = MBGEN_TEST_DATA "/extras/unknown_output.yaml";
  const gen::Description d = gen::load_description(MBGEN_TEST_DATA "/tiny_arm.urdf", options);
  try {
    (void)select_functions(d, {});
    FAIL() << "no LoadError";
  } catch (const gen::LoadError& e) {
    EXPECT_EQ(e.line(), 5);
    EXPECT_EQ(e.element(), "scene: outputs[1]");
    EXPECT_NE(e.problem().find("'mass_matrx' is not one of"), std::string::npos) << e.what();
    EXPECT_NE(e.fix().find("mass_matrix"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mbgen::codegen
