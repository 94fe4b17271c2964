#pragma once
// Traces the runtime's analytic dynamics derivatives (algorithm/rnea_derivatives.hpp,
// aba_derivatives.hpp) with the symbolic scalar. Matrices are emitted row-major, nv x nv; the
// derivative with respect to q is along q (+) delta (configuration.hpp's integrate).
#include "codegen/traced_function.hpp"
#include <vector>

#include "mbgen/contact_model.hpp"
#include "mbgen/model.hpp"

namespace mbgen::codegen {

/// tau, dtau/dq and dtau/dv of the spanning tree's inverse dynamics at (q, v, qdd).
TracedFunction trace_inverse_dynamics_derivatives(const Model& tree);
/// qdd, dqdd/dq, dqdd/dv and M^-1 of the spanning tree's forward dynamics at (q, v, tau).
TracedFunction trace_forward_dynamics_derivatives(const Model& tree);
/// qdd, dqdd/dq, dqdd/dv and M^-1 of the spanning tree's forward dynamics under the compliant
/// ground at the spheres (contact_dynamics_derivatives.hpp), and what the law gave per sphere.
/// Trees only: a closed system is refused (std::invalid_argument saying so).
TracedFunction trace_contact_forward_dynamics_derivatives(const Model& model, const std::vector<ContactSphere>& spheres,
                                                          double exponent);
/// A closed system's: ydd, dydd/dy (along the closed set), dydd/dyd and dydd/dtau in its
/// independent coordinates (loop_dynamics_derivatives.hpp), every matrix row-major.
TracedFunction trace_loop_forward_dynamics_derivatives(const Model& model);

}  // namespace mbgen::codegen
