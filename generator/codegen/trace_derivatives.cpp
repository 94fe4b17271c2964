#include "codegen/trace_derivatives.hpp"

#include <fmt/format.h>

#include "codegen/trace_support.hpp"
#include <stdexcept>

#include "mbgen/algorithm/aba_derivatives.hpp"
#include "mbgen/algorithm/contact_dynamics_derivatives.hpp"
#include "mbgen/algorithm/loop_dynamics_derivatives.hpp"

namespace mbgen::codegen {

using namespace tracing;

namespace {
ArraySpec square_spec(const Model& m, const char* name, const char* what) {
  return {name, m.nv() * m.nv(), fmt::format("[{0} x {0}, row-major] {1}", m.nv(), what), {m.nv(), m.nv()}};
}

/// The entries L(k, i) of a tree's mass matrix factor, i an ancestor of k: the work array's size.
int factor_entry_count(const Model& tree) {
  int entries = 0;
  for (int k = 0; k < tree.nv(); ++k)
    for (int i = tree.velocity_parent(k); i >= 0; i = tree.velocity_parent(i)) ++entries;
  return entries;
}
}  // namespace

TracedFunction trace_inverse_dynamics_derivatives(const Model& tree) {
  TracedFunction f;
  f.name = "inverse_dynamics_derivatives";
  f.doc = "The inverse dynamics tau = M(q) qdd + C(q, v) v + g(q) and its derivatives dtau/dq and dtau/dv (dtau/dqdd is "
          "mass_matrix's M). d/dq is taken along q (+) delta with delta in v-space (integrate: a floating base moves by the "
          "exponential of its body twist), so dtau/dq is nv x nv. Analytic recursion (rnea_derivatives.hpp).";
  f.inputs = {q_spec(tree), v_spec(tree, "v", "joint velocities"), v_spec(tree, "qdd", "joint accelerations")};
  f.outputs = {v_spec(tree, "tau", "joint forces"), square_spec(tree, "dtau_dq", "dtau/dq along q (+) delta"),
               square_spec(tree, "dtau_dv", "dtau/dv")};
  Recording rec(f.graph);
  Data<Sym> data(tree);
  DynamicsDerivatives<Sym> d(tree);
  const SymVec q = inputs(0, tree.nq()), v = inputs(1, tree.nv()), a = inputs(2, tree.nv());
  inverse_dynamics_derivatives<Sym>(tree, data, d, q, v, a);
  f.output_ids = {ids_of(d.tau), ids_of(d.dtau_dq), ids_of(d.dtau_dv)};
  return f;
}

TracedFunction trace_forward_dynamics_derivatives(const Model& tree) {
  const int entries = factor_entry_count(tree);
  TracedFunction f;
  f.name = "forward_dynamics_derivatives";
  f.doc = "The forward dynamics qdd = M(q)^-1 (tau - C(q, v) v - g(q)) and its derivatives dqdd/dq, dqdd/dv and "
          "dqdd/dtau = M^-1: the inverse dynamics' derivatives at the qdd found, times -M^-1 (aba_derivatives.hpp). d/dq is "
          "taken along q (+) delta with delta in v-space, as inverse_dynamics_derivatives. Unrolled up to the solves with "
          "M, which run as loops over whole rows of dqdd/dq and dqdd/dv (the same sparse L^T D L solve, vectorisable).";
  f.inputs = {q_spec(tree), v_spec(tree, "v", "joint velocities"), v_spec(tree, "tau", "joint forces")};
  f.outputs = {v_spec(tree, "qdd", "joint accelerations"), square_spec(tree, "dqdd_dq", "dqdd/dq along q (+) delta"),
               square_spec(tree, "dqdd_dv", "dqdd/dv"), square_spec(tree, "Minv", "dqdd/dtau = M^-1"),
               {"factor_entries", entries, fmt::format("[{}] L(k, i) of M's factor, k's ancestors i from the nearest", entries)},
               v_spec(tree, "inverse_pivot", "1 / D of M's factor")};
  f.work_outputs = 2;
  Recording rec(f.graph);
  Data<Sym> data(tree);
  DynamicsDerivatives<Sym> d(tree);
  const SymVec q = inputs(0, tree.nq()), v = inputs(1, tree.nv()), tau = inputs(2, tree.nv());
  forward_dynamics_derivatives_before_solves<Sym>(tree, data, d, q, v, tau);
  // The solves run in place: dqdd_dq and dqdd_dv leave the trace as -dtau/dq and -dtau/dv.
  f.output_ids = {ids_of(d.ddq), ids_of(d.dddq_dq), ids_of(d.dddq_dv), ids_of(d.Minv), ids_of(d.factor_entries),
                  ids_of(d.inverse_pivot)};
  return f;
}

TracedFunction trace_contact_forward_dynamics_derivatives(const Model& model, const std::vector<ContactSphere>& spheres,
                                                          double exponent) {
  if (!model.subsystems.empty())
    throw std::invalid_argument(fmt::format(
        "contact_fd_derivatives: the derivatives under the compliant ground are built for trees only, and this "
        "robot has {} closed loops: request fd_derivatives (the closed system's, without the ground) or describe the "
        "robot without its loops",
        model.closures.size()));
  const int n = model.nv(), spheres_count = static_cast<int>(spheres.size());
  TracedFunction f;
  f.name = "contact_forward_dynamics_derivatives";
  f.doc = fmt::format(
      "The forward dynamics under tau and the compliant ground (as contact_accelerations: the law of "
      "mbgen/algorithm/contact_law.hpp, exponent {} built in, at each contact sphere) and its derivatives dqdd/dq, "
      "dqdd/dv and dqdd/dtau = M^-1: the inverse dynamics' derivatives minus the ground's joint forces' at the qdd "
      "found, times -M^-1 (contact_dynamics_derivatives.hpp). d/dq is taken along q (+) delta with delta in v-space, "
      "as forward_dynamics_derivatives. Where the law switches (touch-down, the normal force's clamp, the stiction "
      "speed) the slope of the side the value takes. Unrolled up to the solves with M, which run as loops over whole rows.",
      exponent);
  f.inputs = {q_spec(model), v_spec(model, "v", "joint velocities"), v_spec(model, "tau", "joint forces"),
              {"ground", kGroundInputs, "[4] the ground n . x <= offset: n_x, n_y, n_z (unit, world), offset (m)"},
              {"law", kLawInputs, "[4] stiffness (N/m^exponent), damping (s/m), friction coefficient, stiction velocity (m/s)"}};
  f.outputs = {v_spec(model, "qdd", "joint accelerations"), square_spec(model, "dqdd_dq", "dqdd/dq along q (+) delta"),
               square_spec(model, "dqdd_dv", "dqdd/dv"), square_spec(model, "Minv", "dqdd/dtau = M^-1"),
               {"contacts", kContactOutputs * spheres_count,
                fmt::format("[{} x 10] per sphere: penetration (m, <= 0 apart), witness point (3, world), force on the robot "
                            "there (3, N, world), slip velocity (3, m/s)",
                            spheres_count),
                {spheres_count, kContactOutputs}}};
  const int entries = factor_entry_count(model);
  f.outputs.push_back({"factor_entries", entries, fmt::format("[{}] L(k, i) of M's factor, k's ancestors i from the nearest", entries)});
  f.outputs.push_back(v_spec(model, "inverse_pivot", "1 / D of M's factor"));
  f.work_outputs = 2;
  Recording rec(f.graph);
  Data<Sym> data(model);
  ContactDynamicsDerivatives<Sym> d(model);
  const SymVec q = inputs(0, model.nq()), v = inputs(1, n), tau = inputs(2, n), ground = inputs(3, kGroundInputs),
               law = inputs(4, kLawInputs);
  std::vector<Sym> contacts(static_cast<std::size_t>(kContactOutputs * spheres_count));
  contact_forward_dynamics_derivatives_before_solves<Sym>(model, data, d, spheres, exponent, q, v, tau, ground.data(), law.data(),
                                                         contacts.data());
  std::vector<int> contact_ids;
  for (const Sym& x : contacts) contact_ids.push_back(x.id());
  // The solves run in place: dqdd_dq and dqdd_dv leave the trace as dtau_c - dtau.
  f.output_ids = {ids_of(d.fd.ddq), ids_of(d.fd.dddq_dq),     ids_of(d.fd.dddq_dv),
                  ids_of(d.fd.Minv), contact_ids,             ids_of(d.fd.factor_entries),
                  ids_of(d.fd.inverse_pivot)};
  return f;
}

TracedFunction trace_loop_forward_dynamics_derivatives(const Model& model) {
  const int ny = num_independent(model), nv = model.nv();
  TracedFunction f;
  f.name = "forward_dynamics_derivatives";
  f.doc = "The closed system's forward dynamics in its independent coordinates (forward_dynamics) and its derivatives "
          "dydd/dy, dydd/dyd and dydd/dtau = M_y^-1 T^T, the loops held closed: d/dy moves q along the closed set (the "
          "dependent coordinates follow, a floating base by integrate). The tree's analytic derivatives projected by the "
          "velocity map, with the closure's own dependence on y by the implicit-function theorem through Phi_z "
          "(loop_dynamics_derivatives.hpp). Unrolled up to the solves with M_y, which run as loops over whole rows "
          "(its L^T D L factor along its elimination tree). q must close the loops.";
  f.inputs = {closed_q_spec(model), y_spec(model, "v", "independent velocities"),
              v_spec(model, "tau", "joint forces of every tree joint (those of dependent joints act through T^T)")};
  f.outputs = {y_spec(model, "qdd", "independent accelerations"),
               {"dqdd_dq", ny * ny, fmt::format("[{0} x {0}, row-major] dydd/dy along the closed set", ny), {ny, ny}},
               {"dqdd_dv", ny * ny, fmt::format("[{0} x {0}, row-major] dydd/dyd", ny), {ny, ny}},
               {"dqdd_dtau", ny * nv, fmt::format("[{} x {}, row-major] dydd/dtau = M_y^-1 T^T", ny, nv), {ny, nv}}};
  Recording rec(f.graph);
  Data<Sym> data(model);
  LoopDynamicsDerivatives<Sym> ld(model);
  const int entries = static_cast<int>(ld.factor_entries.size());
  f.outputs.push_back({"factor_entries", entries, fmt::format("[{}] L(k, i) of M_y's factor along its elimination tree", entries)});
  f.outputs.push_back(y_spec(model, "inverse_pivot", "1 / D of M_y's factor"));
  f.work_outputs = 2;
  const SymVec q = inputs(0, model.nq()), vy = inputs(1, ny), tau = inputs(2, nv);
  forward_dynamics_loops_derivatives_before_solves<Sym>(model, data, ld, q, vy, tau);
  // The solves run in place (emit_derivatives.cpp): the matrices leave the trace as -R_q, -R_v, T^T.
  f.output_ids = {ids_of(ld.ydd),         ids_of(ld.dydd_dy),        ids_of(ld.dydd_dyd),
                  ids_of(ld.dydd_dtau),   ids_of(ld.factor_entries), ids_of(ld.inverse_pivot)};
  return f;
}

}  // namespace mbgen::codegen
