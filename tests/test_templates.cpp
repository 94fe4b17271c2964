// The emitted files' templates (generator/codegen/templates.hpp): mbgen's own sets load, and a
// broken copy is refused before anything is rendered, naming the file, the line and what is
// wrong. (test_generate_command runs the CLI on edited copies; test_c_flavour the c flavour.)
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "codegen/emit_python.hpp"
#include "codegen/templates.hpp"
#include "load/load_error.hpp"

namespace fs = std::filesystem;
using mbgen::codegen::python_template_catalog;
using mbgen::codegen::python_templates_directory;
using mbgen::codegen::template_catalog;
using mbgen::codegen::TemplateSpec;
using mbgen::codegen::TemplateSet;

namespace {

const fs::path kTemplates = fs::path(MBGEN_SOURCE_DIR) / "templates";

std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// A fresh copy of the cpp flavour, for one test to break.
fs::path copy_of_cpp(const std::string& leaf) {
  const fs::path dir = fs::temp_directory_path() / ("mbgen_test_templates_" + leaf);
  fs::remove_all(dir);
  fs::copy(kTemplates / "cpp", dir);
  return dir;
}

void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }

/// The LoadError TemplateSet::load throws for `dir` (fails the test if it loads).
mbgen::gen::LoadError load_error(const fs::path& dir) {
  try {
    TemplateSet::load(dir.string());
  } catch (const mbgen::gen::LoadError& e) {
    return e;
  }
  ADD_FAILURE() << dir << " loaded";
  return mbgen::gen::LoadError("", 0, "", "", "");
}

/// The .fmt files of `dir` (not its folders), each checked to be one of `catalog`'s.
int templates_in(const fs::path& dir, const std::vector<TemplateSpec>& catalog) {
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.is_directory()) continue;
    const std::string name = entry.path().stem().string();
    EXPECT_EQ(entry.path().extension(), ".fmt") << entry.path();
    EXPECT_TRUE(std::any_of(catalog.begin(), catalog.end(), [&](const auto& spec) { return name == spec.name; }))
        << entry.path() << " is not a template mbgen renders";
    ++files;
  }
  return files;
}

}  // namespace

TEST(Templates, EveryFlavourHasEveryTemplateAndNoOther) {
  for (const char* flavour : {"cpp", "c"}) {
    EXPECT_NO_THROW(TemplateSet::load((kTemplates / flavour).string())) << flavour;
    EXPECT_EQ(templates_in(kTemplates / flavour, template_catalog()), static_cast<int>(template_catalog().size())) << flavour;
  }
  // The only folder in a flavour's: the cpp flavour's python/ (below).
  for (const char* flavour : {"cpp", "c"})
    for (const auto& entry : fs::directory_iterator(kTemplates / flavour)) {
      if (entry.is_directory()) {
        EXPECT_TRUE(std::string(flavour) == "cpp" && entry.path().filename() == "python") << entry.path();
      }
    }
}

// The Python module's templates (emit_python.hpp): the cpp flavour's python/ folder, its own catalog.
TEST(Templates, ThePythonModuleHasEveryTemplateAndNoOther) {
  const fs::path dir = fs::path(python_templates_directory((kTemplates / "cpp").string()));
  EXPECT_NO_THROW(TemplateSet::load(dir.string(), python_template_catalog()));
  EXPECT_EQ(templates_in(dir, python_template_catalog()), static_cast<int>(python_template_catalog().size()));
  // A missing one is named, as for the flavours' templates.
  const fs::path copy = fs::temp_directory_path() / "mbgen_python_templates_missing";
  fs::remove_all(copy);
  fs::copy(dir, copy);
  fs::remove(copy / "run_lanes.fmt");
  try {
    TemplateSet::load(copy.string(), python_template_catalog());
    ADD_FAILURE() << "loaded without run_lanes.fmt";
  } catch (const mbgen::gen::LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("template 'run_lanes'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("is missing"), std::string::npos) << e.what();
  }
  fs::remove_all(copy);
}

TEST(Templates, EveryTemplateAndPlaceholderIsDocumented) {
  const std::string doc = read(fs::path(MBGEN_SOURCE_DIR) / "docs" / "templates.md");
  // Each template's row names it (with the folder below the flavour's: "python/") and every placeholder it has.
  const auto documented = [&](const std::vector<TemplateSpec>& catalog, const std::string& folder) {
    for (const auto& spec : catalog) {
      const std::string row = "| `" + folder + spec.name + ".fmt` |";
      const std::size_t at = doc.find(row);
      ASSERT_NE(at, std::string::npos) << folder << spec.name << " has no row in docs/templates.md";
      const std::string line = doc.substr(at, doc.find('\n', at) - at);
      for (const auto& p : spec.placeholders)
        EXPECT_NE(line.find("`{" + std::string(p.name) + "}`"), std::string::npos) << spec.name << ": {" << p.name << "}";
    }
  };
  documented(template_catalog(), "");
  documented(python_template_catalog(), "python/");
}

TEST(Templates, RenderFillsNamedPlaceholdersAndKeepsDoubledBraces) {
  const fs::path dir = copy_of_cpp("render");
  write(dir / "prototype.fmt", "{{ {scalar} }} {public_name}({parameters}); // {function} of {robot}\n");
  const TemplateSet set = TemplateSet::load(dir.string());
  EXPECT_EQ(set.render("prototype", {{"public_name", "f"}, {"parameters", "double* x"}, {"scalar", "double"},
                                     {"function", "fd"}, {"robot", "arm"}}),
            "{ double } f(double* x); // fd of arm");  // the file's final newline is not part of it
  // Name templates are their first line.
  write(dir / "header_file.fmt", "{robot}.hxx\nnotes below the name are ignored\n");
  EXPECT_EQ(TemplateSet::load(dir.string()).render("header_file", {{"robot", "arm"}}), "arm.hxx");
}

TEST(Templates, DigestFollowsTheContents) {
  const fs::path dir = copy_of_cpp("digest");
  const std::string before = TemplateSet::load(dir.string()).digest();
  EXPECT_EQ(before, TemplateSet::load((kTemplates / "cpp").string()).digest());
  write(dir / "input_doc.fmt", "/// input {name}: {doc}\n");
  EXPECT_NE(TemplateSet::load(dir.string()).digest(), before);
  EXPECT_EQ(before.size(), 64u);
}

TEST(Templates, MissingTemplateIsNamed) {
  const fs::path dir = copy_of_cpp("missing");
  fs::remove(dir / "entry_point.fmt");
  const auto e = load_error(dir);
  EXPECT_EQ(e.file(), (dir / "entry_point.fmt").string());
  EXPECT_NE(e.problem().find("missing"), std::string::npos);
  EXPECT_NE(e.fix().find("entry_point.fmt"), std::string::npos);
}

TEST(Templates, UnknownPlaceholderIsNamedWithItsLineAndTheAllowedOnes) {
  const fs::path dir = copy_of_cpp("unknown");
  write(dir / "entry_point.fmt", "// entry point\nvoid {public_name}({parameters}) {{ {fucntion}_impl(); }}\n");
  const auto e = load_error(dir);
  EXPECT_EQ(e.file(), (dir / "entry_point.fmt").string());
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.element(), "placeholder '{fucntion}'");
  EXPECT_NE(e.fix().find("{function}"), std::string::npos) << e.fix();
  // A placeholder of another template is unknown here too.
  write(dir / "entry_point.fmt", "void {public_name}() {{ {body} }}\n");
  EXPECT_EQ(load_error(dir).element(), "placeholder '{body}'");
}

TEST(Templates, PositionalPlaceholdersAreRefused) {
  const fs::path dir = copy_of_cpp("positional");
  for (const char* text : {"void {}();\n", "void {0}();\n", "void {:>8}();\n"}) {
    write(dir / "prototype.fmt", text);
    const auto e = load_error(dir);
    EXPECT_EQ(e.file(), (dir / "prototype.fmt").string()) << text;
    EXPECT_NE(e.problem().find("positional"), std::string::npos) << text;
  }
}

TEST(Templates, UnmatchedBracesAreRefused) {
  const fs::path dir = copy_of_cpp("braces");
  write(dir / "noinline_macro.fmt", "#define X\n}\n");
  auto e = load_error(dir);
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.element(), "'}'");
  EXPECT_NE(e.fix().find("}}"), std::string::npos);
  write(dir / "noinline_macro.fmt", "#define X\nstruct X {\n  int a;\n};\n");
  e = load_error(dir);
  EXPECT_EQ(e.line(), 2);
  EXPECT_EQ(e.element(), "'{'");
  EXPECT_NE(e.fix().find("{{"), std::string::npos);
  // Braces closed on one line read as a placeholder, and the fix says how to write them.
  write(dir / "noinline_macro.fmt", "struct X { int a; };\n");
  e = load_error(dir);
  EXPECT_EQ(e.element(), "placeholder '{ int a; }'");
  EXPECT_NE(e.fix().find("literal braces"), std::string::npos);
}

TEST(Templates, BannerMustKeepMbgensFirstLine) {
  const fs::path dir = copy_of_cpp("banner");
  write(dir / "banner.fmt", "// My company's banner\n// Generated by mbgen {version}\n");
  const auto e = load_error(dir);
  EXPECT_EQ(e.file(), (dir / "banner.fmt").string());
  EXPECT_NE(e.fix().find("overwrites only files"), std::string::npos);
}

TEST(Templates, EmptyNameTemplateIsRefused) {
  const fs::path dir = copy_of_cpp("empty_name");
  write(dir / "source_file.fmt", "\n{robot}_{function}.cpp\n");
  EXPECT_EQ(load_error(dir).file(), (dir / "source_file.fmt").string());
}

TEST(Templates, FormatSpecificationFmtRefusesIsALoadErrorAtRender) {
  const fs::path dir = copy_of_cpp("spec");
  write(dir / "header_file.fmt", "{robot:d}.hpp\n");  // an integer presentation for a string
  const TemplateSet set = TemplateSet::load(dir.string());
  try {
    set.render("header_file", {{"robot", "arm"}});
    FAIL() << "rendered";
  } catch (const mbgen::gen::LoadError& e) {
    EXPECT_EQ(e.file(), (dir / "header_file.fmt").string());
  }
  // Padding is a string format fmt accepts.
  write(dir / "header_file.fmt", "{robot:_>5}.hpp\n");
  EXPECT_EQ(TemplateSet::load(dir.string()).render("header_file", {{"robot", "arm"}}), "__arm.hpp");
}

TEST(Templates, NotAFolder) {
  const auto e = load_error(kTemplates / "no_such_flavour");
  EXPECT_NE(e.problem().find("does not exist"), std::string::npos);
}
