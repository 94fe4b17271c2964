#pragma once
// What every emitter needs to frame its code: the template set of the flavour, the robot's name,
// the header's name, the banner, and the scalars wanted.
#include <string>
#include <vector>

#include "codegen/templates.hpp"

namespace mbgen::codegen {

enum class ScalarChoice { Double, Float, Both };

/// Statements per part above which a function is split (split_statements; mbgen generate
/// --max-statements sets EmitContext::max_statements_per_part). g++'s register allocation grows
/// faster than linearly with a function's size: wl16_like's full_accelerations (~39k statements
/// per scalar) took 200 s in one piece at -O3.
inline constexpr int kMaxStatementsPerPart = 20000;

/// `S` wrappers wanted by the choice: double first.
std::vector<std::string> scalar_types(ScalarChoice choice);

struct EmitContext {
  const TemplateSet& templates;
  std::string robot;   ///< namespace / prefix, a valid identifier
  std::string header;  ///< header_file.fmt rendered
  std::string banner;  ///< banner.fmt rendered
  ScalarChoice scalars = ScalarChoice::Both;
  int max_statements_per_part = kMaxStatementsPerPart;
  /// sin and cos of computed values by sincos_of<S> (sincos.fmt) instead of libm (those of inputs
  /// are sincos_of's always, sincos_all): with --batch, so that the one-state functions compute
  /// what the batch computes, bit for bit.
  bool inline_sincos = false;

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
