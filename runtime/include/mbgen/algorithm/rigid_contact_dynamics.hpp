#pragma once
// Forward dynamics with rigid contacts held: the feet (or any named frames) do not move, and the
// joint accelerations a and the contact forces lambda solve
//     M a + h = tau + J^T lambda,    J a + gamma = 0,
// with M the mass matrix, h = C v + g, and J (m x nv) and gamma (m) the contacts' Jacobian and
// acceleration drift (the contacts' accelerations at a = 0). What Pinocchio's
// constraintDynamics computes for its rigid constraint models (without its proximal iterations:
// the contacts' rows must be independent), and what a planner under a fixed stance linearises
// (rigid_contact_derivatives.hpp).
//
// A contact is a model frame (Model::frames: a link's, a fixed joint's or a user's) and a kind:
//   Point: 3 rows, the classical acceleration of the frame's origin, in the frame's own axes;
//   Frame: 6 rows, that and the frame's angular acceleration, in the frame's axes (a flat foot).
// Both are the second time derivatives of what the contact holds (the origin's position, the
// frame's orientation), so a state that satisfies them keeps the contact exactly; the forces are
// in the same axes: lambda = [force on the body at the origin; moment] (Pinocchio's LOCAL).
//
// The solve goes through the operational-space inverse J M^-1 J^T, factored without pivoting
// (small_ldlt.hpp, a symbolic scalar can record it), and the mass matrix's sparse factor
// (mass_matrix_factor.hpp): m + 1 sparse solves with M and one m x m factor, m <= 6 per contact.
// Contacts that constrain the same motion twice (four points of one flat foot: 12 rows of rank 6)
// make J M^-1 J^T singular; the status says so instead of returning forces that are not unique.
// Spanning trees only: a model with closed loops is refused (its closure rows would join the
// contact rows; forward_dynamics_kkt solves that system for the closures alone).
#include <stdexcept>
#include <string>
#include <vector>

#include "mbgen/algorithm/jacobian.hpp"
#include "mbgen/algorithm/mass_matrix_factor.hpp"
#include "mbgen/algorithm/rnea.hpp"
#include "mbgen/algorithm/small_ldlt.hpp"

namespace mbgen {

enum class RigidContactKind { Point, Frame };

/// A contact held rigidly: the frame's origin (Point) or the whole frame (Frame) does not move.
struct RigidContact {
  FrameIndex frame;
  RigidContactKind kind = RigidContactKind::Frame;
  int rows() const { return kind == RigidContactKind::Point ? 3 : 6; }
};

enum class RigidContactStatus {
  Solved,
  /// J M^-1 J^T has a pivot below `singular_tolerance` times its largest diagonal entry (or one
  /// that is not finite): the contacts' rows are dependent (redundant contacts, or a posture that
  /// loses rank). The outputs are then not meaningful.
  Singular,
  /// The accelerations or forces are not finite: the state or tau holds a NaN or an infinity.
  NotFinite,
};

inline const char* to_string(RigidContactStatus s) {
  switch (s) {
    case RigidContactStatus::Solved: return "solved";
    case RigidContactStatus::Singular: return "singular";
    case RigidContactStatus::NotFinite: return "not_finite";
  }
  return "unknown";
}

/// Work memory and results of rigid_contact_dynamics. Making it checks the model and the contacts
/// (std::invalid_argument naming what is wrong) and allocates; the algorithms then do not.
template <typename S> struct RigidContactWorkspace {
  RigidContactWorkspace(const Model& model, std::vector<RigidContact> contacts);

  std::vector<RigidContact> contacts;
  std::vector<int> first_row;  ///< per contact: its first row in J, gamma and lambda
  int m = 0;                   ///< rows of all contacts
  double singular_tolerance = 1e-12;

  // Results.
  VecX<S> a;         ///< nv: joint accelerations
  VecX<S> lambda;    ///< m: contact forces (per contact [force; moment], the frame's axes)
  RigidContactStatus status = RigidContactStatus::Solved;

  // What the solve leaves, read by the derivatives: M's factor is in data.M.
  MatX<S> J;         ///< m x nv, rows in the contact frames' axes
  VecX<S> gamma;     ///< m: the contacts' accelerations at a = 0
  VecX<S> free_a;    ///< nv: M^-1 (tau - h), the accelerations without contact
  MatX<S> Y;         ///< nv x m: M^-1 J^T
  MatX<S> JY_factor; ///< m x m: ldlt_factor of J M^-1 J^T
  VecX<S> operator_diagonal;  ///< m: the diagonal of J M^-1 J^T before its factoring (the status' scale)
  Mat6X<S> frame_J;  ///< 6 x nv scratch: one frame's Jacobian
};

template <typename S>
RigidContactWorkspace<S>::RigidContactWorkspace(const Model& model, std::vector<RigidContact> contacts_)
    : contacts(std::move(contacts_)) {
  if (!model.closures.empty())
    throw std::invalid_argument("rigid contacts: model '" + model.name + "' has " + std::to_string(model.closures.size()) +
                                " loop closure(s); rigid_contact_dynamics handles spanning trees only (fix: a tree "
                                "model, or the closures' own forward_dynamics_kkt without contacts)");
  for (const RigidContact& c : contacts) {
    if (c.frame.value() < 0 || c.frame.value() >= model.num_frames())
      throw std::invalid_argument("rigid contacts: frame index " + std::to_string(c.frame.value()) + " is not a frame of '" +
                                  model.name + "' (it has " + std::to_string(model.num_frames()) + ")");
    if (model.frame(c.frame).body == kWorldBody)
      throw std::invalid_argument("rigid contacts: frame '" + model.frame(c.frame).name +
                                  "' is fixed in the world; a contact must be on a moving body");
    first_row.push_back(m);
    m += c.rows();
  }
  const int nv = model.nv();
  a = VecX<S>::Zero(nv);
  lambda = VecX<S>::Zero(m);
  J = MatX<S>::Zero(m, nv);
  gamma = VecX<S>::Zero(m);
  free_a = VecX<S>::Zero(nv);
  Y = MatX<S>::Zero(nv, m);
  JY_factor = MatX<S>::Zero(m, m);
  operator_diagonal = VecX<S>::Zero(m);
  frame_J = Mat6X<S>::Zero(6, nv);
}

namespace detail {
/// J and gamma of the contacts at (q, v): the frames' Jacobians in their own axes and their
/// accelerations at a = 0 (classical for the origin: the spatial acceleration's linear part plus
/// omega x v). Leaves the world poses (data.X_WB, data.X_WF) and data.J at q.
template <typename S>
void rigid_contact_kinematics(const Model& model, Data<S>& data, RigidContactWorkspace<S>& ws, const ConstVecRef<S>& q,
                              const ConstVecRef<S>& v) {
  data.ddq.setZero();
  forward_kinematics<S>(model, data, q, v, data.ddq);  // body velocities and accelerations at a = 0
  compute_joint_jacobians<S>(model, data, q);          // poses again, and the columns data.J
  for (std::size_t k = 0; k < ws.contacts.size(); ++k) {
    const RigidContact& c = ws.contacts[k];
    const Frame& frame = model.frame(c.frame);
    const int r0 = ws.first_row[k], rows = c.rows();
    const SE3<S> X_BF = frame.X_BF.template cast<S>();
    const Motion<S> v_F = X_BF.act_inv(data.v[frame.body]), a_F = X_BF.act_inv(data.a[frame.body]);
    ws.gamma.template segment<3>(r0) = a_F.linear + v_F.angular.cross(v_F.linear);
    if (rows == 6) ws.gamma.template segment<3>(r0 + 3) = a_F.angular;
    const SE3<S>& X_WF = data.X_WF[c.frame];
    detail::point_frame_jacobian<S>(model, data, frame.body, X_WF.translation, X_WF.rotation, ReferenceFrame::Local, ws.frame_J);
    ws.J.middleRows(r0, rows) = ws.frame_J.topRows(rows);
  }
}

/// The solve of rigid_contact_dynamics without its checks, which a symbolic scalar cannot record
/// (it has no comparisons): what the generator traces. ws.a, ws.lambda, and what the derivatives
/// read (ws.J, ws.Y, ws.JY_factor, ws.operator_diagonal, M's factor in data.M).
template <typename S>
void rigid_contact_solve(const Model& model, Data<S>& data, RigidContactWorkspace<S>& ws, const ConstVecRef<S>& q,
                         const ConstVecRef<S>& v, const ConstVecRef<S>& tau) {
  const int m = ws.m;
  rigid_contact_kinematics<S>(model, data, ws, q, v);
  ws.free_a = tau - nonlinear_effects<S>(model, data, q, v);
  mass_matrix_factor<S>(model, data, q);
  mass_matrix_solve_in_place<S>(model, data.M, ws.free_a);
  ws.Y = ws.J.transpose();
  for (int i = 0; i < m; ++i) {
    auto column = ws.Y.col(i);
    mass_matrix_solve_in_place<S>(model, data.M, column);
  }
  // J M^-1 J^T lambda = -gamma - J M^-1 (tau - h), then a = M^-1 (tau - h) + M^-1 J^T lambda.
  for (int i = 0; i < m; ++i)
    for (int j = 0; j <= i; ++j) ws.JY_factor(i, j) = ws.JY_factor(j, i) = ws.J.row(i).dot(ws.Y.col(j));
  ws.operator_diagonal = ws.JY_factor.diagonal();
  ldlt_factor<S>(ws.JY_factor, m, ws.JY_factor);
  ws.lambda = -ws.gamma;
  ws.lambda.noalias() -= ws.J * ws.free_a;
  ldlt_solve<S>(ws.JY_factor, m, ws.lambda.data());
  ws.a = ws.free_a;
  ws.a.noalias() += ws.Y * ws.lambda;
}
}  // namespace detail

/// Whether J M^-1 J^T was regular: Singular when a pivot d_i of its L D L^T factor is not above
/// `tolerance` times the largest diagonal entry (or is not finite). `diagonal` the operator's
/// diagonal, `pivots` the d_i. The rule rigid_contact_dynamics applies, and a caller of the
/// generated rigid_contact_fd_derivatives applies to its `operator_pivots` output.
template <typename S, typename Diagonal, typename Pivots>
RigidContactStatus rigid_contact_operator_status(const Diagonal& diagonal, const Pivots& pivots, int m, double tolerance) {
  S largest = S(0);
  for (int i = 0; i < m; ++i) largest = std::max(largest, S(diagonal[i]));
  for (int i = 0; i < m; ++i)  // NaN fails the comparison too
    if (!(S(pivots[i]) > S(tolerance) * largest)) return RigidContactStatus::Singular;
  return RigidContactStatus::Solved;
}

namespace detail {
/// The status of the last rigid_contact_solve: the operator's (its factor holds F(i, i) = 1 / d_i),
/// then whether a and lambda are finite.
template <typename S> RigidContactStatus rigid_contact_status(const RigidContactWorkspace<S>& ws) {
  const RigidContactStatus status = rigid_contact_operator_status<S>(
      ws.operator_diagonal, ws.JY_factor.diagonal().cwiseInverse(), ws.m, ws.singular_tolerance);
  if (status == RigidContactStatus::Solved && !(ws.a.allFinite() && ws.lambda.allFinite())) return RigidContactStatus::NotFinite;
  return status;
}
}  // namespace detail

/// Joint accelerations (ws.a, also returned) and contact forces (ws.lambda) with the contacts
/// held, at (q, v) under joint forces tau; ws.status says whether the contacts' system was
/// regular and the results finite. Leaves the mass matrix's factor in data.M. No allocation.
template <typename S>
const VecX<S>& rigid_contact_dynamics(const Model& model, Data<S>& data, RigidContactWorkspace<S>& ws, const ConstVecRef<S>& q,
                                      const ConstVecRef<S>& v, const ConstVecRef<S>& tau) {
  detail::rigid_contact_solve<S>(model, data, ws, q, v, tau);
  ws.status = detail::rigid_contact_status<S>(ws);
  return ws.a;
}

}  // namespace mbgen
