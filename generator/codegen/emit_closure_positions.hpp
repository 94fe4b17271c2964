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

/// closure_positions_source.fmt for `model`: closure_positions_impl<S> (C++ on the
/// ClosureStatus, ClosureResult and ClosureOptions the template declares or the header does)
/// and the entry points (closure_entry_point.fmt). Every robot has it: without loops it returns
/// at once.
std::string emit_closure_positions_definition(const Model& model, const EmitContext& ctx);

}  // namespace mbgen::codegen
