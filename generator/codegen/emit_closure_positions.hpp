#pragma once
// The generated closure_positions: Newton on the closures for the dependent coordinates, as the
// runtime's closure_positions (closure_positions.hpp) does it. The step itself is traced
// (trace_closure_newton_step) and emitted as straight-line code; the loop around it (residual
// test, pivot-ratio test, step limiting, iteration cap) is a small fixed loop printed here, since
// it branches on values.
#include <string>

#include "codegen/emit_cpp.hpp"
#include "mbgen/model.hpp"

namespace mbgen::codegen {

/// Header part: ClosureStatus, ClosureResult, ClosureOptions with per-scalar defaults, and the
/// closure_positions declarations (every robot has them: without loops they return at once).
std::string emit_closure_positions_declaration(ScalarChoice scalars);

/// The .cpp body (without banner) of closure_positions for `model` in namespace `ns`.
std::string emit_closure_positions_definition(const Model& model, const std::string& ns, const std::string& header,
                                              ScalarChoice scalars);

}  // namespace mbgen::codegen
