#pragma once
// The generated forward_dynamics_derivatives: its traced part (the forward dynamics, the inverse
// dynamics' derivatives at its accelerations, the mass matrix's factor: aba_derivatives.hpp's
// forward_dynamics_derivatives_before_solves) printed as straight-line code, and the solves with
// that factor printed here as loops over the rows of dqdd/dq and dqdd/dv, each row gathered a block
// of columns at a time (M^-1 is traced: Z^T D^-1 Z, aba_derivatives.hpp). Unrolled, the 3 nv solves
// were two thirds of the function's operations and made its code too large for the instruction
// caches (talos: 150k statements, twice Pinocchio's time); as loops they are short and vectorise. A closed system's
// (loop_dynamics_derivatives.hpp) the same: M_y's factor along its elimination tree, and its
// three matrices solved (dydd/dtau = M_y^-1 T^T too: T^T has few entries, its solve fills them).
// contact_forward_dynamics_derivatives (contact_dynamics_derivatives.hpp) is the tree's with the
// ground's joint forces' derivatives added before the same two solves.
#include <string>
#include <vector>

#include "codegen/emit_context.hpp"
#include "codegen/traced_function.hpp"
#include "mbgen/model.hpp"

namespace mbgen::codegen {

/// The source file of a forward-dynamics derivative function from its trace
/// (trace_forward_dynamics_derivatives, trace_loop_forward_dynamics_derivatives,
/// trace_contact_forward_dynamics_derivatives: the work outputs factor_entries and inverse_pivot
/// last), with the factor's structure, each row's parent (a tree's velocity parents; a closed
/// system's LoopDynamicsDerivatives::y_parent), and the outputs (by position) that leave the trace
/// to be solved in place.
std::string emit_forward_dynamics_derivatives_definition(const TracedFunction& f, const std::vector<int>& parent,
                                                        const std::vector<std::size_t>& solved, const EmitContext& ctx);

/// Its batch form over `lanes` states (emit_batch.hpp): the trace on GCC vectors, then the same
/// solves on the lanes, each state's sums those of the one-state function term by term, so that
/// each state equals it bit for bit.
std::string emit_forward_dynamics_derivatives_batch_definition(const TracedFunction& f, const std::vector<int>& parent,
                                                              const std::vector<std::size_t>& solved, int lanes,
                                                              const EmitContext& ctx);

/// The source file of rigid_contact_forward_dynamics_derivatives from its trace
/// (trace_rigid_contact_forward_dynamics_derivatives: work outputs J, contact_factor, Y,
/// factor_entries and inverse_pivot last): the tree's solves of dqdd/dq and dqdd/dv with M's factor
/// (each row's parent: the tree's velocity parents; `solved` those two outputs' positions), then
/// the products with J and Y and the solves with J M^-1 J^T's factor that finish them and the tau
/// block (rigid_contact_derivatives.hpp's rigid_contact_derivatives_solves).
std::string emit_rigid_contact_derivatives_definition(const TracedFunction& f, const std::vector<int>& parent,
                                                      const std::vector<std::size_t>& solved, const EmitContext& ctx);

}  // namespace mbgen::codegen
