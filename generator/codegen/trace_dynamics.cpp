#include "codegen/trace_dynamics.hpp"

#include <fmt/format.h>

#include "codegen/trace_support.hpp"
#include "model/topology.hpp"

namespace mbgen::codegen {

using namespace tracing;

namespace {

void append_pose(std::vector<int>& ids, const SE3<Sym>& X) {
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) ids.push_back(X.rotation(r, c).id());
    ids.push_back(X.translation[r].id());
  }
}

/// The frames' Jacobians (LOCAL_WORLD_ALIGNED, 6 x nv row-major each, one after the other) from
/// data's joint Jacobians (compute_joint_jacobians first).
std::vector<int> frame_jacobian_ids(const Model& model, Data<Sym>& data, const std::vector<FrameIndex>& frames) {
  std::vector<int> ids;
  Mat6X<Sym> J(6, model.nv());
  for (FrameIndex fr : frames) {
    frame_jacobian<Sym>(model, data, fr, ReferenceFrame::LocalWorldAligned, J);
    for (int id : ids_of(J)) ids.push_back(id);
  }
  return ids;
}

}  // namespace

TracedFunction trace_forward_dynamics(const Model& model) {
  TracedFunction f;
  f.name = "forward_dynamics";
  f.doc = "Joint accelerations qdd = M(q)^-1 (tau - C(q, v) v - g(q)) (articulated-body algorithm).";
  f.inputs = {q_spec(model), v_spec(model, "v", "joint velocities"), v_spec(model, "tau", "joint forces")};
  f.outputs = {v_spec(model, "qdd", "joint accelerations")};
  Recording rec(f.graph);
  Data<Sym> data(model);
  const SymVec q = inputs(0, model.nq()), v = inputs(1, model.nv()), tau = inputs(2, model.nv());
  f.output_ids = {ids_of(aba<Sym>(model, data, q, v, tau))};
  return f;
}

namespace {
/// Symbolic inputs and the O(n) recursion with sub-systems, shared by the two loop functions.
void trace_loop_recursion(const Model& model, Data<Sym>& data) {
  const SymVec q = inputs(0, model.nq()), vy = inputs(1, model.structure().num_independent()), tau = inputs(2, model.nv());
  forward_dynamics_loops_independent<Sym>(model, data, q, vy, tau);
}
}  // namespace

TracedFunction trace_generated_forward_dynamics(const Model& model) {
  if (!model.subsystems.empty()) return trace_forward_dynamics_loops(model);
  return trace_forward_dynamics(gen::spanning_tree(model));
}

TracedFunction trace_forward_dynamics_loops(const Model& model) {
  TracedFunction f;
  f.name = "forward_dynamics";
  f.doc = "Accelerations of the independent coordinates of the closed system: O(n) articulated-body algorithm with "
          "each sub-system of loops as one aggregate body (its velocity and acceleration maps from a Givens QR of the "
          "closure Jacobian's dependent block). q must close the loops and v be the independent velocities.";
  f.inputs = {closed_q_spec(model), y_spec(model, "v", "independent velocities"),
              v_spec(model, "tau", "joint forces of every tree joint (those of dependent joints act through G^T)")};
  f.outputs = {y_spec(model, "qdd", "independent accelerations")};
  Recording rec(f.graph);
  Data<Sym> data(model);
  trace_loop_recursion(model, data);
  std::vector<int> ids;
  for (int i : model.structure().independent_v) ids.push_back(data.ddq[i].id());
  f.output_ids = {ids};
  return f;
}

TracedFunction trace_full_accelerations(const Model& model) {
  TracedFunction f;
  f.name = "full_accelerations";
  f.doc = "Accelerations of every tree joint of the closed system (the dependent ones from the loops), as "
          "forward_dynamics computes them.";
  f.inputs = {closed_q_spec(model), y_spec(model, "v", "independent velocities"),
              v_spec(model, "tau", "joint forces of every tree joint (those of dependent joints act through G^T)")};
  f.outputs = {v_spec(model, "qdd", "accelerations of every tree joint, joint_names order")};
  Recording rec(f.graph);
  Data<Sym> data(model);
  trace_loop_recursion(model, data);
  f.output_ids = {ids_of(data.ddq)};
  return f;
}

TracedFunction trace_actuator_forces(const Model& model, const Actuation& actuation) {
  const int na = actuation.num_actuators(), ny = num_independent(model);
  TracedFunction f;
  f.name = "actuator_forces";
  f.doc = "Inverse dynamics of the closed system for its actuators: the forces of the actuated joints "
          "(actuated_joint_names) that give the independent accelerations ydd at (q, vy), the loops closed and every "
          "other joint passive, and the residual: the generalized forces on the independent coordinates no actuator "
          "reaches (a floating base's six: what the contacts must supply). Joint forces tau_a on actuated_v_index plus "
          "the residual on independent_v_index make forward_dynamics return ydd. An actuator that is a dependent "
          "coordinate of its loops is solved for through them; at its dead point the result is not finite.";
  f.inputs = {closed_q_spec(model), y_spec(model, "vy", "independent velocities"), y_spec(model, "ydd", "independent accelerations")};
  f.outputs = {{"tau_a", na, fmt::format("[{}] actuator forces (N m or N), actuated_joint_names order", na)},
               y_spec(model, "residual", "generalized forces no actuator supplies (zero where the actuators reach)")};
  Recording rec(f.graph);
  Data<Sym> data(model);
  const SymVec q = inputs(0, model.nq()), vy = inputs(1, ny), ydd = inputs(2, ny);
  SymVec tau_a(na), residual(ny);
  actuator_forces<Sym>(model, data, actuation, q, vy, ydd, tau_a, residual);
  f.output_ids = {ids_of(tau_a), ids_of(residual)};
  return f;
}

TracedFunction trace_inverse_dynamics(const Model& model) {
  TracedFunction f;
  f.name = "inverse_dynamics";
  f.doc = "Joint forces tau = M(q) qdd + C(q, v) v + g(q) (recursive Newton-Euler).";
  f.inputs = {q_spec(model), v_spec(model, "v", "joint velocities"), v_spec(model, "qdd", "joint accelerations")};
  f.outputs = {v_spec(model, "tau", "joint forces")};
  Recording rec(f.graph);
  Data<Sym> data(model);
  const SymVec q = inputs(0, model.nq()), v = inputs(1, model.nv()), a = inputs(2, model.nv());
  f.output_ids = {ids_of(rnea<Sym>(model, data, q, v, a))};
  return f;
}

TracedFunction trace_mass_matrix(const Model& model) {
  TracedFunction f;
  f.name = "mass_matrix";
  f.doc = "Joint-space mass matrix M(q) (composite-rigid-body algorithm).";
  f.inputs = {q_spec(model)};
  f.outputs = {{"M", model.nv() * model.nv(), fmt::format("[{0} x {0}, row-major] mass matrix", model.nv()), {model.nv(), model.nv()}}};
  Recording rec(f.graph);
  Data<Sym> data(model);
  const SymVec q = inputs(0, model.nq());
  f.output_ids = {ids_of(crba<Sym>(model, data, q))};
  return f;
}

TracedFunction trace_mass_matrix_factor(const Model& model) {
  const int n = model.nv();
  TracedFunction f;
  f.name = "mass_matrix_factor";
  f.doc = "The mass matrix's sparse factor M = L^T D L (Featherstone's LTDL: L unit lower triangular, nonzero only where "
          "the column's coordinate is an ancestor of the row's, so no fill-in). Takes mass_matrix's output, so that a "
          "controller needing M and M^-1 computes M once; only the entries of ancestor pairs are read.";
  f.inputs = {{"M", n * n, fmt::format("[{0} x {0}, row-major] mass_matrix's output", n), {n, n}}};
  f.outputs = {{"LD", n * n,
                fmt::format("[{0} x {0}, row-major] D on the diagonal, L strictly below it, zeros above (mass_matrix_solve "
                            "takes it)",
                            n),
                {n, n}}};
  Recording rec(f.graph);
  MatX<Sym> LD = square_input(0, n);
  factor_mass_matrix_in_place<Sym>(model, LD);
  f.output_ids = {ids_of(LD)};
  return f;
}

TracedFunction trace_mass_matrix_solve(const Model& model) {
  const int n = model.nv();
  TracedFunction f;
  f.name = "mass_matrix_solve";
  f.doc = "x = M^-1 b from mass_matrix_factor's L^T D L (two sparse triangular sweeps and the diagonal): the joint "
          "accelerations of joint forces b, or an operational-space controller's M^-1 J^T column by column.";
  f.inputs = {{"LD", n * n, fmt::format("[{0} x {0}, row-major] mass_matrix_factor's output", n), {n, n}},
              v_spec(model, "b", "right-hand side (joint forces)")};
  f.outputs = {v_spec(model, "x", "M^-1 b")};
  Recording rec(f.graph);
  const MatX<Sym> factor = square_input(0, n);
  SymVec x = inputs(1, n);
  mass_matrix_solve_in_place<Sym>(model, factor, x);
  f.output_ids = {ids_of(x)};
  return f;
}

TracedFunction trace_forward_kinematics(const Model& model) {
  const int nb = model.num_bodies() - 1;
  TracedFunction f;
  f.name = "forward_kinematics";
  f.doc = "Pose of every body in the world, in body_names order.";
  f.inputs = {q_spec(model)};
  f.outputs = {{"X_WB", 12 * nb, fmt::format("[{} x 12] per body the 3x4 matrix [R_WB | p_WB], row-major", nb), {nb, 3, 4}}};
  Recording rec(f.graph);
  Data<Sym> data(model);
  forward_kinematics<Sym>(model, data, inputs(0, model.nq()));
  std::vector<int> ids;
  for (int k = 1; k < model.num_bodies(); ++k) append_pose(ids, data.X_WB[BodyIndex(k)]);
  f.output_ids = {ids};
  return f;
}

TracedFunction trace_frame_poses(const Model& model, const std::vector<FrameIndex>& frames) {
  const int n = static_cast<int>(frames.size());
  TracedFunction f;
  f.name = "frame_poses";
  f.doc = "Pose of each frame in frame_names, in the world.";
  f.inputs = {q_spec(model)};
  f.outputs = {{"X_WF", 12 * n, fmt::format("[{} x 12] per frame the 3x4 matrix [R_WF | p_WF], row-major", n), {n, 3, 4}}};
  Recording rec(f.graph);
  Data<Sym> data(model);
  forward_kinematics<Sym>(model, data, inputs(0, model.nq()));
  update_frame_placements<Sym>(model, data);
  std::vector<int> ids;
  for (FrameIndex fr : frames) append_pose(ids, data.X_WF[fr]);
  f.output_ids = {ids};
  return f;
}

TracedFunction trace_frame_jacobians(const Model& model, const std::vector<FrameIndex>& frames) {
  const int n = static_cast<int>(frames.size());
  TracedFunction f;
  f.name = "frame_jacobians";
  f.doc = "Jacobian of each frame in frame_names: rows [linear velocity of the frame origin; angular "
          "velocity], both in world axes (LOCAL_WORLD_ALIGNED).";
  f.inputs = {q_spec(model)};
  f.outputs = {{"J", 6 * model.nv() * n, fmt::format("[{} x 6 x {}] per frame a row-major 6 x nv matrix", n, model.nv()), {n, 6, model.nv()}}};
  Recording rec(f.graph);
  Data<Sym> data(model);
  compute_joint_jacobians<Sym>(model, data, inputs(0, model.nq()));
  f.output_ids = {frame_jacobian_ids(model, data, frames)};
  return f;
}

TracedFunction trace_contact_points(const Model& model, const std::vector<ContactSphere>& spheres) {
  const int n = static_cast<int>(spheres.size());
  TracedFunction f;
  f.name = "contact_points";
  f.doc = "Centre of each contact sphere (contact_sphere_names; the vertices of the SSVs of the scene's contact "
          "links) in the world, and the Jacobian of its body at the centre: rows [linear velocity of the centre; "
          "angular velocity], world axes. The simulator's ground contact (mbgen/sim/contact.hpp) reads both.";
  f.inputs = {q_spec(model)};
  f.outputs = {{"p", 3 * n, fmt::format("[{} x 3] centres, world", n), {n, 3}},
               {"J", 6 * model.nv() * n, fmt::format("[{} x 6 x {}] per sphere a row-major 6 x nv matrix", n, model.nv()), {n, 6, model.nv()}}};
  Recording rec(f.graph);
  Data<Sym> data(model);
  std::vector<Sym> p(static_cast<std::size_t>(3 * n)), J(static_cast<std::size_t>(6 * model.nv() * n));
  contact_points<Sym>(model, data, spheres, inputs(0, model.nq()), p.data(), J.data());
  std::vector<int> p_ids, J_ids;
  for (const Sym& x : p) p_ids.push_back(x.id());
  for (const Sym& x : J) J_ids.push_back(x.id());
  f.output_ids = {p_ids, J_ids};
  return f;
}

TracedFunction trace_contact_accelerations(const Model& model, const std::vector<ContactSphere>& spheres, double exponent) {
  const int n = static_cast<int>(spheres.size());
  TracedFunction f;
  f.name = "contact_accelerations";
  f.doc = fmt::format(
      "Accelerations of every tree joint of the closed system (as full_accelerations) under tau and the ground: the "
      "compliant law of mbgen/sim/contact.hpp (Hunt-Crossley, exponent {} built in; regularised Coulomb) at each "
      "contact sphere, its wrench an external force on its body in the articulated-body algorithm. Also writes, per "
      "sphere, what the law gave. The simulator's step (NAME::Backend::accelerations_with_contact).",
      exponent);
  f.inputs = {closed_q_spec(model), v_spec(model, "v", "velocities of every tree joint (only the independent ones are read: the dependent ones are T vy)"),
              v_spec(model, "tau", "joint forces of every tree joint (those of dependent joints act through G^T)"),
              {"ground", kGroundInputs, "[4] the ground n . x <= offset: n_x, n_y, n_z (unit, world), offset (m)"},
              {"law", kLawInputs, "[4] stiffness (N/m^exponent), damping (s/m), friction coefficient, stiction velocity (m/s)"}};
  f.outputs = {v_spec(model, "qdd", "accelerations of every tree joint, joint_names order"),
               {"contacts", kContactOutputs * n,
                fmt::format("[{} x 10] per sphere: penetration (m, <= 0 apart), witness point (3, world), force on the robot "
                            "there (3, N, world), slip velocity (3, m/s)",
                            n),
                {n, kContactOutputs}}};
  Recording rec(f.graph);
  Data<Sym> data(model);
  const SymVec q = inputs(0, model.nq()), v = inputs(1, model.nv()), tau = inputs(2, model.nv()),
               ground = inputs(3, kGroundInputs), law = inputs(4, kLawInputs);
  std::vector<Sym> contacts(static_cast<std::size_t>(kContactOutputs * n));
  const std::vector<int> qdd =
      ids_of(contact_forward_dynamics<Sym>(model, data, spheres, exponent, q, v, tau, ground.data(), law.data(), contacts.data()));
  std::vector<int> contact_ids;
  for (const Sym& x : contacts) contact_ids.push_back(x.id());
  f.output_ids = {qdd, contact_ids};
  return f;
}

TracedFunction trace_center_of_mass(const Model& model) {
  TracedFunction f;
  f.name = "center_of_mass";
  f.doc = "Centre of mass of the robot in the world.";
  f.inputs = {q_spec(model)};
  f.outputs = {{"com", 3, "[3] centre of mass, world"}};
  Recording rec(f.graph);
  Data<Sym> data(model);
  f.output_ids = {ids_of(center_of_mass<Sym>(model, data, inputs(0, model.nq())))};
  return f;
}

TracedFunction trace_centroidal_momentum_matrix(const Model& model) {
  TracedFunction f;
  f.name = "centroidal_momentum_matrix";
  f.doc = "Centroidal momentum matrix A_G(q): h_G = A_G v is [linear momentum; angular momentum about "
          "the centre of mass], world axes.";
  f.inputs = {q_spec(model)};
  f.outputs = {{"Ag", 6 * model.nv(), fmt::format("[6 x {}, row-major] centroidal momentum matrix", model.nv()), {6, model.nv()}}};
  Recording rec(f.graph);
  Data<Sym> data(model);
  f.output_ids = {ids_of(centroidal_momentum_matrix<Sym>(model, data, inputs(0, model.nq())))};
  return f;
}

TracedFunction trace_task_kinematics(const Model& model, const std::vector<FrameIndex>& frames) {
  const int n = static_cast<int>(frames.size()), nv = model.nv();
  TracedFunction f;
  f.name = "task_kinematics";
  f.doc = "frame_poses, frame_jacobians, center_of_mass and centroidal_momentum_matrix in one pass of the kinematics "
          "(a controller step's reads: Backend::task_kinematics), each term computed once; the centre of mass is the "
          "momentum matrix's (from the composite bodies), equal to center_of_mass's to round-off.";
  f.inputs = {q_spec(model)};
  f.outputs = {{"X_WF", 12 * n, fmt::format("[{} x 12] per frame the 3x4 matrix [R_WF | p_WF], row-major", n), {n, 3, 4}},
               {"J", 6 * nv * n, fmt::format("[{} x 6 x {}] per frame a row-major 6 x nv matrix, LOCAL_WORLD_ALIGNED", n, nv), {n, 6, nv}},
               {"com", 3, "[3] centre of mass, world"},
               {"Ag", 6 * nv, fmt::format("[6 x {}, row-major] centroidal momentum matrix", nv), {6, nv}}};
  Recording rec(f.graph);
  Data<Sym> data(model);
  // GenericBackend::task_kinematics' calls: the joint Jacobians (poses and frames with them), then
  // the momentum matrix from those poses.
  compute_joint_jacobians<Sym>(model, data, inputs(0, model.nq()));
  const Mat6X<Sym>& A = detail::centroidal_momentum_matrix_from_poses<Sym>(model, data);
  std::vector<int> poses;
  for (FrameIndex fr : frames) append_pose(poses, data.X_WF[fr]);
  f.output_ids = {poses, frame_jacobian_ids(model, data, frames), ids_of(data.com), ids_of(A)};
  return f;
}

}  // namespace mbgen::codegen
