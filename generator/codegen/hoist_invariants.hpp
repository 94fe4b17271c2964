#pragma once
// Loop-invariant code motion for a traced function that a generated loop calls many times with
// only some inputs changed (the closure's Newton step: only the dependent coordinates move).
// The values that depend on the unchanged inputs alone are computed once, before the loop.
#include <functional>

#include "codegen/traced_function.hpp"

namespace mbgen::codegen {

/// f split where its values stop depending on the changing inputs alone.
struct HoistedFunction {
  /// Inputs: f's. One output, `invariants`: the invariant values that `body` reads, in f's id
  /// order (not `w`, which names the workspace of functions split into parts).
  TracedFunction setup;
  /// Inputs: f's, then `invariants`. Outputs: f's, equal to f's bit for bit (the same operations
  /// on the same operands, in the same relative order: commutative operands keep their sides).
  TracedFunction body;
};

/// `varies(argument, index)`: whether that input element changes between the calls of the loop.
/// A value is invariant when it depends on no varying input; `invariants` holds each invariant
/// value (not a constant or an input) that a varying value or an output uses. `setup` is named
/// f.name + "_setup", `body` keeps f's name and documentation.
HoistedFunction hoist_invariants(const TracedFunction& f, const std::function<bool(int argument, int index)>& varies);

}  // namespace mbgen::codegen
