#include "codegen/scene_functions.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "load/load_error.hpp"
#include "load/name_match.hpp"

namespace mbgen::codegen {

namespace {

/// Adds what the emitted rows need, and the rows emitted with all of a set, until nothing changes.
void close_over_needs(FunctionSelection& s) {
  for (bool grew = true; grew;) {
    grew = false;
    for (const GeneratedFunction& f : function_catalog()) {
      bool bring = false;
      if (s.emits(f.name)) {
        for (const std::string& needed : f.needs) grew |= s.emitted.insert(needed).second;
      } else if (!f.with_all_of.empty()) {
        bring = true;
        for (const std::string& g : f.with_all_of) bring = bring && s.emits(g);
      }
      if (bring) grew |= s.emitted.insert(f.name).second;
    }
  }
}

}  // namespace

FunctionSelection select_functions(const std::vector<std::string>& outputs, bool contact) {
  FunctionSelection s;
  const std::vector<std::string> known = scene_outputs();
  // `all` beside named outputs: everything but the on-request rows, and those named.
  const bool everything = std::find(outputs.begin(), outputs.end(), "all") != outputs.end();
  for (const std::string& output : outputs)
    if (output != "all" && std::find(known.begin(), known.end(), output) == known.end())
      throw std::invalid_argument(fmt::format("unknown output '{}': the outputs are {} (or all)", output, fmt::join(known, ", ")));
  std::vector<std::string> wanted = outputs;
  if (contact && !outputs.empty()) wanted.push_back(kSimulationOutput);
  for (const GeneratedFunction& f : function_catalog()) {
    bool brought = ((outputs.empty() || everything) && !f.on_request) || f.always;
    for (const std::string& output : f.outputs) brought = brought || std::find(wanted.begin(), wanted.end(), output) != wanted.end();
    if (brought) s.emitted.insert(f.name);
  }
  close_over_needs(s);
  s.backend = true;
  for (const GeneratedFunction& f : function_catalog()) {
    (s.emits(f.name) ? s.generated : s.left_out).push_back(f.name);
    for (const std::string& output : f.outputs)
      if (output == kSimulationOutput) s.backend = s.backend && s.emits(f.name);
  }
  return s;
}

FunctionSelection select_functions(const gen::Description& description, const std::vector<std::string>& outputs,
                                   std::string* reason) {
  const bool contact = description.scene && description.scene->contact;
  if (outputs.size() == 1 && outputs[0] == "all") return select_functions(std::vector<std::string>{}, contact);
  if (!outputs.empty()) {
    if (reason) *reason = fmt::format("not among --outputs {}, nor needed by them", fmt::join(outputs, ","));
    return select_functions(outputs, contact);
  }
  const std::vector<std::string> scene = description.scene ? description.scene->outputs : std::vector<std::string>{};
  const std::vector<std::string> known = scene_outputs();
  for (std::size_t i = 0; i < scene.size(); ++i) {
    if (std::find(known.begin(), known.end(), scene[i]) != known.end()) continue;
    const std::vector<int>& lines = description.scene->output_lines;
    const std::string hint = gen::did_you_mean(scene[i], known);
    throw gen::LoadError(description.extras_file, i < lines.size() ? lines[i] : 0, fmt::format("scene: outputs[{}]", i),
                         fmt::format("'{}' is not one of {}", scene[i], fmt::join(known, ", ")),
                         hint.empty() ? fmt::format("write one of {}", fmt::join(known, ", ")) : hint);
  }
  if (reason)
    *reason = fmt::format("not among the outputs of {}'s scene, nor needed by them",
                          std::filesystem::path(description.extras_file).filename().string());
  return select_functions(scene, contact);
}

}  // namespace mbgen::codegen
