#pragma once
// Batch functions (`mbgen generate --batch W`): a function over W states at once, for
// sampling-based control and learning that evaluate thousands of states per control step. The
// arrays are structures of arrays (q[i][w]: entry i of state w) and the body is the one-state
// function's statements on GCC vectors of W lanes (emit_statements with lanes): the same
// operations in the same order, so lane w equals the one-state function on state w bit for bit
// under the same compiler flags, and g++ emits packed instructions for the arithmetic.
#include <string>
#include <vector>

#include "codegen/emit_context.hpp"
#include "codegen/traced_function.hpp"

namespace mbgen::codegen {

// Which functions `--batch` emits over W states is the catalogue's (function_catalog.hpp,
// batched_functions()): the straight-line dynamics and kinematics, and the derivatives (their
// solves after the trace on the lanes too: emit_derivatives.hpp). Not batched: closure_positions
// (a Newton iteration whose steps differ per state), the loop maps, self_distances (its near set
// branches per pair) and the contact functions.

/// Batch widths g++ vectors can hold: a power of two from 2 to 16.
bool valid_batch_width(int lanes);

/// `<function>_batch`: the entry points' function name (public_name.fmt) and file (source_file.fmt).
std::string batch_name(const std::string& function);

/// function_declaration.fmt for f's batch entry points.
std::string emit_batch_declaration(const TracedFunction& f, int lanes, const EmitContext& ctx);

/// batch_source.fmt: the source file of f's batch entry points. A function with work outputs
/// (the derivatives) brings what runs after its trace: `helpers` (placed after the lanes' helpers,
/// before the trace) and its own `entry_points`.
std::string emit_batch_definition(const TracedFunction& f, int lanes, const EmitContext& ctx, const std::string& helpers = "",
                                  const std::string& entry_points = "");

}  // namespace mbgen::codegen
