#pragma once
// Which functions a generation emits (docs/extras.md, `scene: outputs`), from the catalogue
// (function_catalog.hpp): each output the scene lists brings the rows that name it, and what
// those need in turn; the rest are left out. A left-out function is not declared in the header,
// and its source file holds only a note, so that the file list still follows from
// mbgen_add_robot's arguments alone.
#include <set>
#include <string>
#include <vector>

#include "codegen/function_catalog.hpp"
#include "load/description.hpp"

namespace mbgen::codegen {

struct FunctionSelection {
  std::set<std::string> emitted;
  std::vector<std::string> generated;  ///< `emitted` in catalogue order
  std::vector<std::string> left_out;   ///< the rest, catalogue order
  /// NAME::Backend, the simulator's adapter (mbgen/sim/backend.hpp): every function it calls is emitted.
  bool backend = false;
  bool emits(const std::string& function) const { return emitted.count(function) > 0; }
};

/// The functions for `outputs` (scene output names: forward_dynamics, mass_matrix, jacobians,
/// simulation, ...; scene_outputs()). An empty list selects everything (a description without
/// `scene: outputs` gets every function); `contact` (the scene has `contact:`) adds the
/// simulation's functions. Rows marked `always` (closure_positions: the position level of the
/// loops, which every function of a closed system presumes) are emitted whatever the outputs.
/// An output the catalogue does not know throws std::invalid_argument naming the known ones.
/// `all` among the outputs stands for every row but the on-request ones (the derivatives), which
/// come only when named.
FunctionSelection select_functions(const std::vector<std::string>& outputs, bool contact);

/// The selection for a description: `outputs` if given ({"all"}: everything but the on-request
/// rows), else the scene's.
/// `reason` says, for the notes in the generated files, why the rest is left out. An unknown
/// output of the scene is a LoadError naming the extras file, its line and the closest output.
FunctionSelection select_functions(const gen::Description& description, const std::vector<std::string>& outputs,
                                   std::string* reason = nullptr);

}  // namespace mbgen::codegen
