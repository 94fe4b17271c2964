#pragma once
// Traces the runtime's analytic dynamics derivatives (algorithm/rnea_derivatives.hpp,
// aba_derivatives.hpp) with the symbolic scalar. Matrices are emitted row-major, nv x nv; the
// derivative with respect to q is along q (+) delta (configuration.hpp's integrate).
#include "codegen/traced_function.hpp"
#include <string>
#include <vector>

#include "mbgen/algorithm/rigid_contact_dynamics.hpp"
#include "mbgen/contact_model.hpp"
#include "mbgen/model.hpp"

namespace mbgen::codegen {

/// The inputs the derivatives are taken with respect to (the scene's `derivatives_wrt`,
/// --derivatives-wrt): a block left out is neither an output nor computed (what only it needs
/// drops out of the trace). The values (tau, qdd) are always returned.
struct DerivativeBlocks {
  bool q = true, v = true, tau = true;
  /// From the names q, v, tau (empty: all three); std::invalid_argument for any other.
  static DerivativeBlocks from_names(const std::vector<std::string>& names);
  bool all() const { return q && v && tau; }
  std::string names() const;  ///< "q, v, tau" or the part chosen
};

/// tau, dtau/dq and dtau/dv of the spanning tree's inverse dynamics at (q, v, qdd); of the two
/// matrices those `blocks` asks for (tau: none, dtau/dqdd being mass_matrix's M; a choice of
/// neither q nor v is refused, std::invalid_argument).
TracedFunction trace_inverse_dynamics_derivatives(const Model& tree, DerivativeBlocks blocks = {});
/// qdd, dqdd/dq, dqdd/dv and M^-1 of the spanning tree's forward dynamics at (q, v, tau) (the
/// matrices `blocks` asks for).
TracedFunction trace_forward_dynamics_derivatives(const Model& tree, DerivativeBlocks blocks = {});
/// qdd, dqdd/dq, dqdd/dv and M^-1 of the spanning tree's forward dynamics under the compliant
/// ground at the spheres (contact_dynamics_derivatives.hpp), and what the law gave per sphere.
/// Trees only: a closed system is refused (std::invalid_argument saying so).
TracedFunction trace_contact_forward_dynamics_derivatives(const Model& model, const std::vector<ContactSphere>& spheres,
                                                          double exponent, DerivativeBlocks blocks = {});
/// qdd and the contact forces lambda with the scene's rigid contacts held, and their derivatives
/// with respect to q, v and tau (rigid_contact_derivatives.hpp): traced up to the solves with M,
/// which emit_rigid_contact_derivatives_definition prints as loops with the two products after
/// them. Trees only, and at least one contact: std::invalid_argument otherwise.
TracedFunction trace_rigid_contact_forward_dynamics_derivatives(const Model& model, const std::vector<RigidContact>& contacts,
                                                                DerivativeBlocks blocks = {});
/// A closed system's: ydd, dydd/dy (along the closed set), dydd/dyd and dydd/dtau in its
/// independent coordinates (loop_dynamics_derivatives.hpp), every matrix row-major.
TracedFunction trace_loop_forward_dynamics_derivatives(const Model& model, DerivativeBlocks blocks = {});

/// The outputs of a derivatives trace that the generated code solves in place after the trace
/// (emit_derivatives.hpp): those of `names` the function has, by index.
std::vector<std::size_t> solved_outputs(const TracedFunction& f, const std::vector<std::string>& names);

}  // namespace mbgen::codegen
