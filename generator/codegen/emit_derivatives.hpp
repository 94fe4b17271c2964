#pragma once
// The generated forward_dynamics_derivatives: its traced part (the forward dynamics, the inverse
// dynamics' derivatives at its accelerations, the mass matrix's factor: aba_derivatives.hpp's
// forward_dynamics_derivatives_before_solves) printed as straight-line code, and the solves with
// that factor printed here as loops over whole rows of dqdd/dq and dqdd/dv (M^-1 is traced:
// Z^T D^-1 Z, aba_derivatives.hpp). Unrolled, the 3 nv solves were two thirds of the function's
// operations and made its code too large for the instruction caches (talos: 150k statements,
// twice Pinocchio's time); as row operations they are short and vectorise.
#include <string>

#include "codegen/emit_context.hpp"
#include "codegen/traced_function.hpp"
#include "mbgen/model.hpp"

namespace mbgen::codegen {

/// The source file of forward_dynamics_derivatives from its trace (trace_forward_dynamics_derivatives:
/// the work outputs factor_entries and inverse_pivot last) for the tree it was traced on.
std::string emit_forward_dynamics_derivatives_definition(const TracedFunction& f, const Model& tree, const EmitContext& ctx);

}  // namespace mbgen::codegen
