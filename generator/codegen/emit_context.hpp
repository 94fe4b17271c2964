#pragma once
// What every emitter needs to frame its code: the template set of the flavour, the robot's name,
// the header's name, the banner, and the scalars wanted.
#include <string>
#include <vector>

#include "codegen/templates.hpp"

namespace mbgen::codegen {

enum class ScalarChoice { Double, Float, Both };

/// `S` wrappers wanted by the choice: double first.
std::vector<std::string> scalar_types(ScalarChoice choice);

struct EmitContext {
  const TemplateSet& templates;
  std::string robot;   ///< namespace / prefix, a valid identifier
  std::string header;  ///< header_file.fmt rendered
  std::string banner;  ///< banner.fmt rendered
  ScalarChoice scalars = ScalarChoice::Both;

  /// public_name.fmt: the entry point of `function` for `scalar`.
  std::string public_name(const std::string& function, const std::string& scalar) const {
    return templates.render("public_name", {{"robot", robot}, {"function", function}, {"scalar", scalar}});
  }
  /// source_file.fmt: the file that defines `function`.
  std::string source_file(const std::string& function) const {
    return templates.render("source_file", {{"robot", robot}, {"function", function}});
  }
};

}  // namespace mbgen::codegen
