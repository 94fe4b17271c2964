#include "codegen/trace_derivatives.hpp"

#include <fmt/format.h>

#include "codegen/trace_support.hpp"
#include <algorithm>
#include <stdexcept>
#include <utility>

#include "mbgen/algorithm/aba_derivatives.hpp"
#include "mbgen/algorithm/contact_dynamics_derivatives.hpp"
#include "mbgen/algorithm/loop_dynamics_derivatives.hpp"
#include "mbgen/algorithm/rigid_contact_derivatives.hpp"

namespace mbgen::codegen {

using namespace tracing;

namespace {
ArraySpec square_spec(const Model& m, const char* name, const char* what) {
  return {name, m.nv() * m.nv(), fmt::format("[{0} x {0}, row-major] {1}", m.nv(), what), {m.nv(), m.nv()}};
}

/// Appends a matrix output and its trace's ids when its block is asked for.
void add_block(TracedFunction& f, bool wanted, ArraySpec spec, std::vector<int> ids) {
  if (!wanted) return;
  f.outputs.push_back(std::move(spec));
  f.output_ids.push_back(std::move(ids));
}

/// The doc's last sentence when blocks are left out: which ones, and why the signature lacks them.
void note_blocks(TracedFunction& f, DerivativeBlocks blocks) {
  if (blocks.all()) return;
  f.doc += fmt::format(" Generated with respect to {} only (derivatives_wrt): the other inputs' blocks are left out.", blocks.names());
}

/// The entries L(k, i) of a tree's mass matrix factor, i an ancestor of k: the work array's size.
int factor_entry_count(const Model& tree) {
  int entries = 0;
  for (int k = 0; k < tree.nv(); ++k)
    for (int i = tree.velocity_parent(k); i >= 0; i = tree.velocity_parent(i)) ++entries;
  return entries;
}
}  // namespace

DerivativeBlocks DerivativeBlocks::from_names(const std::vector<std::string>& names) {
  if (names.empty()) return {};
  DerivativeBlocks b{false, false, false};
  for (const std::string& n : names) {
    if (n == "q") b.q = true;
    else if (n == "v") b.v = true;
    else if (n == "tau") b.tau = true;
    else throw std::invalid_argument(fmt::format("derivatives with respect to '{}': the inputs are q, v and tau", n));
  }
  return b;
}

std::string DerivativeBlocks::names() const {
  std::string out;
  for (const auto& [wanted, name] : {std::pair{q, "q"}, std::pair{v, "v"}, std::pair{tau, "tau"}})
    if (wanted) out += (out.empty() ? "" : ", ") + std::string(name);
  return out;
}

std::vector<std::size_t> solved_outputs(const TracedFunction& f, const std::vector<std::string>& names) {
  std::vector<std::size_t> solved;
  for (std::size_t k = 0; k < f.outputs.size(); ++k)
    if (std::find(names.begin(), names.end(), f.outputs[k].name) != names.end()) solved.push_back(k);
  return solved;
}

TracedFunction trace_inverse_dynamics_derivatives(const Model& tree, DerivativeBlocks blocks) {
  if (!blocks.q && !blocks.v)
    throw std::invalid_argument(fmt::format(
        "id_derivatives with respect to {} only: nothing to compute (dtau/dqdd is mass_matrix's M); take q or v in "
        "derivatives_wrt, or generate mass_matrix",
        blocks.names()));
  TracedFunction f;
  f.name = "inverse_dynamics_derivatives";
  f.doc = "The inverse dynamics tau = M(q) qdd + C(q, v) v + g(q) and its derivatives dtau/dq and dtau/dv (dtau/dqdd is "
          "mass_matrix's M). d/dq is taken along q (+) delta with delta in v-space (integrate: a floating base moves by the "
          "exponential of its body twist), so dtau/dq is nv x nv. Analytic recursion (rnea_derivatives.hpp).";
  f.inputs = {q_spec(tree), v_spec(tree, "v", "joint velocities"), v_spec(tree, "qdd", "joint accelerations")};
  Recording rec(f.graph);
  Data<Sym> data(tree);
  DynamicsDerivatives<Sym> d(tree);
  const SymVec q = inputs(0, tree.nq()), v = inputs(1, tree.nv()), a = inputs(2, tree.nv());
  inverse_dynamics_derivatives<Sym>(tree, data, d, q, v, a);
  f.outputs = {v_spec(tree, "tau", "joint forces")};
  f.output_ids = {ids_of(d.tau)};
  add_block(f, blocks.q, square_spec(tree, "dtau_dq", "dtau/dq along q (+) delta"), ids_of(d.dtau_dq));
  add_block(f, blocks.v, square_spec(tree, "dtau_dv", "dtau/dv"), ids_of(d.dtau_dv));
  note_blocks(f, blocks);
  return f;
}

TracedFunction trace_forward_dynamics_derivatives(const Model& tree, DerivativeBlocks blocks) {
  const int entries = factor_entry_count(tree);
  TracedFunction f;
  f.name = "forward_dynamics_derivatives";
  f.doc = "The forward dynamics qdd = M(q)^-1 (tau - C(q, v) v - g(q)) and its derivatives dqdd/dq, dqdd/dv and "
          "dqdd/dtau = M^-1: the inverse dynamics' derivatives at the qdd found, times -M^-1 (aba_derivatives.hpp). d/dq is "
          "taken along q (+) delta with delta in v-space, as inverse_dynamics_derivatives. Unrolled up to the solves with "
          "M, which run as loops over the rows of dqdd/dq and dqdd/dv (the same sparse L^T D L solve, a block of columns at a time).";
  f.inputs = {q_spec(tree), v_spec(tree, "v", "joint velocities"), v_spec(tree, "tau", "joint forces")};
  Recording rec(f.graph);
  Data<Sym> data(tree);
  DynamicsDerivatives<Sym> d(tree);
  const SymVec q = inputs(0, tree.nq()), v = inputs(1, tree.nv()), tau = inputs(2, tree.nv());
  forward_dynamics_derivatives_before_solves<Sym>(tree, data, d, q, v, tau);
  // The solves run in place: dqdd_dq and dqdd_dv leave the trace as -dtau/dq and -dtau/dv.
  f.outputs = {v_spec(tree, "qdd", "joint accelerations")};
  f.output_ids = {ids_of(d.ddq)};
  add_block(f, blocks.q, square_spec(tree, "dqdd_dq", "dqdd/dq along q (+) delta"), ids_of(d.dddq_dq));
  add_block(f, blocks.v, square_spec(tree, "dqdd_dv", "dqdd/dv"), ids_of(d.dddq_dv));
  add_block(f, blocks.tau, square_spec(tree, "Minv", "dqdd/dtau = M^-1"), ids_of(d.Minv));
  add_block(f, true, {"factor_entries", entries, fmt::format("[{}] L(k, i) of M's factor, k's ancestors i from the nearest", entries)},
            ids_of(d.factor_entries));
  add_block(f, true, v_spec(tree, "inverse_pivot", "1 / D of M's factor"), ids_of(d.inverse_pivot));
  f.work_outputs = 2;
  note_blocks(f, blocks);
  return f;
}

TracedFunction trace_contact_forward_dynamics_derivatives(const Model& model, const std::vector<ContactSphere>& spheres,
                                                          double exponent, DerivativeBlocks blocks) {
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
      "speed) the slope of the side the value takes. Unrolled up to the solves with M, which run as loops over the rows.",
      exponent);
  f.inputs = {q_spec(model), v_spec(model, "v", "joint velocities"), v_spec(model, "tau", "joint forces"),
              {"ground", kGroundInputs, "[4] the ground n . x <= offset: n_x, n_y, n_z (unit, world), offset (m)"},
              {"law", kLawInputs, "[4] stiffness (N/m^exponent), damping (s/m), friction coefficient, stiction velocity (m/s)"}};
  const int entries = factor_entry_count(model);
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
  f.outputs = {v_spec(model, "qdd", "joint accelerations")};
  f.output_ids = {ids_of(d.fd.ddq)};
  add_block(f, blocks.q, square_spec(model, "dqdd_dq", "dqdd/dq along q (+) delta"), ids_of(d.fd.dddq_dq));
  add_block(f, blocks.v, square_spec(model, "dqdd_dv", "dqdd/dv"), ids_of(d.fd.dddq_dv));
  add_block(f, blocks.tau, square_spec(model, "Minv", "dqdd/dtau = M^-1"), ids_of(d.fd.Minv));
  add_block(f, true,
            {"contacts", kContactOutputs * spheres_count,
             fmt::format("[{} x 10] per sphere: penetration (m, <= 0 apart), witness point (3, world), force on the robot "
                         "there (3, N, world), slip velocity (3, m/s)",
                         spheres_count),
             {spheres_count, kContactOutputs}},
            contact_ids);
  add_block(f, true, {"factor_entries", entries, fmt::format("[{}] L(k, i) of M's factor, k's ancestors i from the nearest", entries)},
            ids_of(d.fd.factor_entries));
  add_block(f, true, v_spec(model, "inverse_pivot", "1 / D of M's factor"), ids_of(d.fd.inverse_pivot));
  f.work_outputs = 2;
  note_blocks(f, blocks);
  return f;
}

TracedFunction trace_rigid_contact_forward_dynamics_derivatives(const Model& model, const std::vector<RigidContact>& contacts,
                                                                DerivativeBlocks blocks) {
  if (!model.closures.empty())
    throw std::invalid_argument(fmt::format(
        "rigid_contact_fd_derivatives: the derivatives with rigid contacts are built for trees only, and this robot has {} "
        "loop closure(s): request fd_derivatives (the closed system's, without contacts) or describe the robot without its "
        "loops",
        model.closures.size()));
  if (contacts.empty())
    throw std::invalid_argument(
        "rigid_contact_fd_derivatives: the scene holds no rigid contact: name the frames held in the extras, "
        "scene: rigid_contacts: [{frame: l_sole, kind: frame}, {frame: r_sole, kind: frame}]");
  const int n = model.nv();
  TracedFunction f;
  f.name = "rigid_contact_forward_dynamics_derivatives";
  std::string held;
  for (const RigidContact& c : contacts)
    held += fmt::format("{}{} ({})", held.empty() ? "" : ", ", model.frame(c.frame).name,
                        c.kind == RigidContactKind::Point ? "point: 3 rows" : "frame: 6 rows");
  f.doc = fmt::format(
      "The forward dynamics with rigid contacts held, M qdd + h = tau + J^T lambda and J qdd + gamma = 0 "
      "(rigid_contact_dynamics.hpp), at {}; and the derivatives of qdd and lambda with respect to q (along q (+) delta, "
      "delta in v-space, as forward_dynamics_derivatives), v and tau (rigid_contact_derivatives.hpp). lambda per contact "
      "[force; moment] in the contact frame's axes (Pinocchio's LOCAL), the moment for a frame only. The results mean "
      "something only when J M^-1 J^T is regular: operator_pivots holds, per row, its diagonal entry and its pivot d_i, "
      "and the contacts are dependent (rigid_contact_dynamics' Singular) when a pivot is not above 1e-12 times the "
      "largest diagonal entry (mbgen::rigid_contact_operator_status applies that rule). Unrolled up to the solves with "
      "M, which run as loops over the rows, with the products by (J M^-1 J^T)^-1 J and M^-1 J^T after them.",
      held);
  f.inputs = {q_spec(model), v_spec(model, "v", "joint velocities"), v_spec(model, "tau", "joint forces")};
  const int entries = factor_entry_count(model);
  Recording rec(f.graph);
  Data<Sym> data(model);
  RigidContactWorkspace<Sym> ws(model, contacts);
  RigidContactDerivatives<Sym> d(model, ws);
  const int m = ws.m;
  const SymVec q = inputs(0, model.nq()), v = inputs(1, n), tau = inputs(2, n);
  rigid_contact_derivatives_before_solves<Sym>(model, data, ws, d, q, v, tau);
  MatX<Sym> pivots(m, 2);
  for (int i = 0; i < m; ++i) {
    pivots(i, 0) = ws.operator_diagonal[i];
    pivots(i, 1) = Sym(1.0) / ws.JY_factor(i, i);  // the factor holds 1 / d_i
  }
  const auto rows_spec = [&](const char* name, const char* what) {
    return ArraySpec{name, m * n, fmt::format("[{} x {}, row-major] {}", m, n, what), {m, n}};
  };
  // The solves and products run in place after the trace (emit_derivatives.cpp): dqdd_dq and
  // dqdd_dv leave it as -dr1/dq and -dr1/dv, dlambda_dq and dlambda_dv as dr2, dqdd_dtau as M^-1
  // and dlambda_dtau as Y^T (rigid_contact_derivatives_before_solves).
  f.outputs = {v_spec(model, "qdd", "joint accelerations"),
               {"lambda", m, fmt::format("[{}] contact forces, per contact [force; moment] in its frame's axes", m)}};
  f.output_ids = {ids_of(ws.a), ids_of(ws.lambda)};
  add_block(f, blocks.q, square_spec(model, "dqdd_dq", "dqdd/dq along q (+) delta"), ids_of(d.da_dq));
  add_block(f, blocks.q, rows_spec("dlambda_dq", "dlambda/dq along q (+) delta"), ids_of(d.dlambda_dq));
  add_block(f, blocks.v, square_spec(model, "dqdd_dv", "dqdd/dv"), ids_of(d.da_dv));
  add_block(f, blocks.v, rows_spec("dlambda_dv", "dlambda/dv"), ids_of(d.dlambda_dv));
  add_block(f, blocks.tau, square_spec(model, "dqdd_dtau", "dqdd/dtau"), ids_of(d.da_dtau));
  add_block(f, blocks.tau, rows_spec("dlambda_dtau", "dlambda/dtau"), ids_of(d.dlambda_dtau));
  add_block(f, true,
            {"operator_pivots", 2 * m,
             fmt::format("[{} x 2, row-major] per row of J M^-1 J^T: its diagonal entry, its pivot d_i (singular: a pivot "
                         "<= 1e-12 x the largest diagonal entry)",
                         m),
             {m, 2}},
            ids_of(pivots));
  add_block(f, true, {"J", m * n, fmt::format("[{} x {}, row-major] the contacts' Jacobian", m, n), {m, n}}, ids_of(ws.J));
  add_block(f, true,
            {"contact_factor", m * m, fmt::format("[{0} x {0}, row-major] ldlt_factor of J M^-1 J^T", m), {m, m}},
            ids_of(ws.JY_factor));
  add_block(f, true, {"Y", n * m, fmt::format("[{} x {}, row-major] M^-1 J^T", n, m), {n, m}}, ids_of(ws.Y));
  add_block(f, true, {"factor_entries", entries, fmt::format("[{}] L(k, i) of M's factor, k's ancestors i from the nearest", entries)},
            ids_of(d.id.factor_entries));
  add_block(f, true, v_spec(model, "inverse_pivot", "1 / D of M's factor"), ids_of(d.id.inverse_pivot));
  f.work_outputs = 5;
  note_blocks(f, blocks);
  return f;
}

TracedFunction trace_loop_forward_dynamics_derivatives(const Model& model, DerivativeBlocks blocks) {
  const int ny = num_independent(model), nv = model.nv();
  TracedFunction f;
  f.name = "forward_dynamics_derivatives";
  f.doc = "The closed system's forward dynamics in its independent coordinates (forward_dynamics) and its derivatives "
          "dydd/dy, dydd/dyd and dydd/dtau = M_y^-1 T^T, the loops held closed: d/dy moves q along the closed set (the "
          "dependent coordinates follow, a floating base by integrate). The tree's analytic derivatives projected by the "
          "velocity map, with the closure's own dependence on y by the implicit-function theorem through Phi_z "
          "(loop_dynamics_derivatives.hpp). Unrolled up to the solves with M_y, which run as loops over the rows "
          "(its L^T D L factor along its elimination tree). q must close the loops.";
  f.inputs = {closed_q_spec(model), y_spec(model, "v", "independent velocities"),
              v_spec(model, "tau", "joint forces of every tree joint (those of dependent joints act through T^T)")};
  Recording rec(f.graph);
  Data<Sym> data(model);
  LoopDynamicsDerivatives<Sym> ld(model);
  const int entries = static_cast<int>(ld.factor_entries.size());
  const SymVec q = inputs(0, model.nq()), vy = inputs(1, ny), tau = inputs(2, nv);
  forward_dynamics_loops_derivatives_before_solves<Sym>(model, data, ld, q, vy, tau);
  // The solves run in place (emit_derivatives.cpp): the matrices leave the trace as -R_q, -R_v, T^T.
  f.outputs = {y_spec(model, "qdd", "independent accelerations")};
  f.output_ids = {ids_of(ld.ydd)};
  add_block(f, blocks.q, {"dqdd_dq", ny * ny, fmt::format("[{0} x {0}, row-major] dydd/dy along the closed set", ny), {ny, ny}},
            ids_of(ld.dydd_dy));
  add_block(f, blocks.v, {"dqdd_dv", ny * ny, fmt::format("[{0} x {0}, row-major] dydd/dyd", ny), {ny, ny}}, ids_of(ld.dydd_dyd));
  add_block(f, blocks.tau, {"dqdd_dtau", ny * nv, fmt::format("[{} x {}, row-major] dydd/dtau = M_y^-1 T^T", ny, nv), {ny, nv}},
            ids_of(ld.dydd_dtau));
  add_block(f, true, {"factor_entries", entries, fmt::format("[{}] L(k, i) of M_y's factor along its elimination tree", entries)},
            ids_of(ld.factor_entries));
  add_block(f, true, y_spec(model, "inverse_pivot", "1 / D of M_y's factor"), ids_of(ld.inverse_pivot));
  f.work_outputs = 2;
  note_blocks(f, blocks);
  return f;
}

}  // namespace mbgen::codegen
