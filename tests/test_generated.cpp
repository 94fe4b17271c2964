// Generated code equals the generic runtime it was traced from. Compiled once and linked into
// every test_generated_<robot> with that robot's table of generated functions
// (generated_robot.hpp; tests/CMakeLists.txt).
//
// Tolerances. double: 1e-12 relative. The generated code performs the generic code's operations
// minus exact ones (x*0, x*1, x+0, constant folding) and in places another summation order, so
// the two differ by round-off only; forward dynamics is compared by its normwise backward error,
// which does not grow with the conditioning of M.
// float: the same quantities in single precision (unit round-off u = 6e-8). For a recursion of
// depth d over n bodies, backward errors grow like c * d * u with small c; d <= 40 here, so we
// allow 1e-4 (~ 40 * 40 u) for dynamics and kinematics alike, relative to the size of the terms.
//
// Robots with loops: every function but forward_dynamics and full_accelerations is the spanning
// tree's (compared with the generic runtime on the tree); those two are the closed system's,
// compared with forward_dynamics_loops_independent at seeded consistent states (loops closed by
// Newton, independent velocities), by the same normwise backward error on the tree joints'
// accelerations; float: the loop maps add a QR of Phi_z (condition <= 1e3 at the assembled
// poses, test_topology) to the recursion, so 1e-2 relative (1e3 * 1e-5 of the tree bound).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <type_traits>

#include "generated_robot.hpp"
#include "malloc_guard.hpp"
#include "model/actuated_coordinates.hpp"
#include "model/topology.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

class GeneratedTest : public ::testing::Test {
 protected:
  GeneratedTest()
      : description(load_with_extras()), closed(description.model), model(tree_of(closed)), data(model),
        closed_data(closed), frames(frame_indices(model)) {}

  static gen::Description load_with_extras() {
    gen::LoadOptions options;
    const generated::Robot& robot = generated::robot();
    options.base = robot.load_floating ? gen::BaseType::Floating : gen::BaseType::Fixed;
    if (std::string(robot.extras).size() > 0) options.extras_file = robot.extras;
    return gen::load_description(robot.description, options);
  }
  static Model tree_of(Model m) {
    m.closures.clear();
    m.subsystems.clear();
    m.update_structure();
    return m;
  }
  static std::vector<FrameIndex> frame_indices(const Model& model) {
    const generated::Robot& robot = generated::robot();
    std::vector<FrameIndex> out;
    for (const char* name : robot.frame_names) out.push_back(model.frame_index(name));
    return out;
  }
  template <typename T> static VecX<double> widen(const std::vector<T>& x) {
    VecX<double> out(static_cast<int>(x.size()));
    for (int i = 0; i < out.size(); ++i) out[i] = static_cast<double>(x[static_cast<std::size_t>(i)]);
    return out;
  }
  template <typename T> static std::vector<T> narrow(const VecX<double>& x) {
    std::vector<T> out(static_cast<std::size_t>(x.size()));
    for (int i = 0; i < x.size(); ++i) out[static_cast<std::size_t>(i)] = static_cast<T>(x[i]);
    return out;
  }
  /// The generic reference of every function, flattened as the generated code lays it out.
  struct Reference {
    VecX<double> qdd, tau, M, X_WB, X_WF, J, com, Ag, bias;
    MatX<double> M_matrix;
  };
  Reference reference(const VecX<double>& q, const VecX<double>& v, const VecX<double>& tau, const VecX<double>& a) {
    Reference r;
    r.qdd = aba<double>(model, data, q, v, tau);
    r.bias = nonlinear_effects<double>(model, data, q, v);
    r.tau = rnea<double>(model, data, q, v, a);
    r.M_matrix = crba<double>(model, data, q);
    r.M = Eigen::Map<const VecX<double>>(MatX<double>(r.M_matrix.transpose()).data(), model.nv() * model.nv());
    compute_joint_jacobians<double>(model, data, q);
    r.X_WB.resize(12 * (model.num_bodies() - 1));
    for (int k = 1; k < model.num_bodies(); ++k) flatten_pose(data.X_WB[BodyIndex(k)], r.X_WB.data() + 12 * (k - 1));
    r.X_WF.resize(12 * static_cast<int>(frames.size()));
    r.J.resize(6 * model.nv() * static_cast<int>(frames.size()));
    Mat6X<double> J(6, model.nv());
    for (std::size_t f = 0; f < frames.size(); ++f) {
      flatten_pose(data.X_WF[frames[f]], r.X_WF.data() + 12 * f);
      frame_jacobian<double>(model, data, frames[f], ReferenceFrame::LocalWorldAligned, J);
      const Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor> Jr = J;
      r.J.segment(static_cast<int>(6 * model.nv() * f), 6 * model.nv()) = Eigen::Map<const VecX<double>>(Jr.data(), 6 * model.nv());
    }
    r.com = center_of_mass<double>(model, data, q);
    const Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor> Ag = centroidal_momentum_matrix<double>(model, data, q);
    r.Ag = Eigen::Map<const VecX<double>>(Ag.data(), 6 * model.nv());
    return r;
  }
  static void flatten_pose(const SE3<double>& X, double* out) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) out[4 * r + c] = X.rotation(r, c);
      out[4 * r + 3] = X.translation[r];
    }
  }

  /// Runs every generated function for scalar T and compares with the reference.
  template <typename T> void compare(double tolerance, int trials) {
    std::mt19937_64 rng(2024);
    const int nv = model.nv(), nb = model.num_bodies() - 1, nf = static_cast<int>(frames.size());
    std::vector<T> qdd(nv), tau_out(nv), M(nv * nv), X_WB(12 * nb), X_WF(12 * nf), J(6 * nv * nf), com(3), Ag(6 * nv);
    std::vector<T> X_WF_task(X_WF.size()), J_task(J.size()), com_task(3), Ag_task(Ag.size());  // task_kinematics' four
    double worst[12] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0};
    for (int trial = 0; trial < trials; ++trial) {
      const VecX<double> q = random_configuration<double>(model, rng);
      const VecX<double> v = random_vector<double>(nv, rng, 2.0);
      const VecX<double> tau = random_vector<double>(nv, rng, 10.0);
      const VecX<double> a = random_vector<double>(nv, rng, 5.0);
      const Reference r = reference(q, v, tau, a);
      const std::vector<T> qt = narrow<T>(q), vt = narrow<T>(v), taut = narrow<T>(tau), at = narrow<T>(a);
      if (!robot.has_loops) generated::forward_dynamics(qt.data(), vt.data(), taut.data(), qdd.data());
      generated::inverse_dynamics(qt.data(), vt.data(), at.data(), tau_out.data());
      generated::mass_matrix(qt.data(), M.data());
      generated::forward_kinematics(qt.data(), X_WB.data());
      generated::frame_poses(qt.data(), X_WF.data());
      generated::frame_jacobians(qt.data(), J.data());
      generated::center_of_mass(qt.data(), com.data());
      generated::centroidal_momentum_matrix(qt.data(), Ag.data());
      generated::task_kinematics(qt.data(), X_WF_task.data(), J_task.data(), com_task.data(), Ag_task.data());
      // Forward dynamics: normwise backward error, as in test_aba.cpp.
      const double scale = r.M_matrix.norm() * r.qdd.norm() + tau.norm() + r.bias.norm();
      if (!robot.has_loops) worst[0] = std::max(worst[0], (r.M_matrix * (widen(qdd) - r.qdd)).norm() / scale);
      // Inverse dynamics: relative to the size of its terms.
      const double id_scale = r.M_matrix.norm() * a.norm() + r.bias.norm() + r.tau.norm();
      worst[1] = std::max(worst[1], (widen(tau_out) - r.tau).norm() / std::max(1.0, id_scale));
      worst[2] = std::max(worst[2], relative_error(widen(M), r.M));
      worst[3] = std::max(worst[3], relative_error(widen(X_WB), r.X_WB));
      worst[4] = std::max(worst[4], relative_error(widen(X_WF), r.X_WF));
      worst[5] = std::max(worst[5], relative_error(widen(J), r.J));
      worst[6] = std::max(worst[6], relative_error(widen(com), r.com));
      worst[7] = std::max(worst[7], relative_error(widen(Ag), r.Ag));
      worst[8] = std::max(worst[8], relative_error(widen(X_WF_task), r.X_WF));
      worst[9] = std::max(worst[9], relative_error(widen(J_task), r.J));
      worst[10] = std::max(worst[10], relative_error(widen(com_task), r.com));
      worst[11] = std::max(worst[11], relative_error(widen(Ag_task), r.Ag));
    }
    const char* names[12] = {"forward_dynamics", "inverse_dynamics", "mass_matrix", "forward_kinematics",
                             "frame_poses", "frame_jacobians", "center_of_mass", "centroidal_momentum_matrix",
                             "task_kinematics X_WF", "task_kinematics J", "task_kinematics com", "task_kinematics Ag"};
    for (int k = 0; k < 12; ++k) {
      EXPECT_LT(worst[k], tolerance) << names[k];
      RecordProperty(names[k], std::to_string(worst[k]));
    }
  }

  /// forward_dynamics and full_accelerations: against the generic O(n) recursion, on the tree
  /// for a robot without loops, on the closed system (consistent states) for one with loops.
  /// A seeded state of the closed system (consistent: loops closed, v = T vy) or, for a tree,
  /// of the tree; false when Newton does not reach one (then drawn again).
  template <typename Rng> bool draw_state(Rng& rng, VecX<double>& q, VecX<double>& v) {
    if (robot.has_loops) return consistent_state(closed, description.assembly.q, rng, 0.05, q, v);
    q = random_configuration<double>(closed, rng);
    v = random_vector<double>(closed.nv(), rng, 2.0);
    return true;
  }

  template <typename T> void compare_closed(double tolerance, int trials) {
    std::mt19937_64 rng(2025);
    const int nv = closed.nv(), ny = robot.ny;
    ASSERT_EQ(ny, static_cast<int>(closed.structure().independent_v.size()));
    std::vector<T> ydd(ny), qdd(nv);
    double worst_y = 0, worst_full = 0;
    int states = 0;
    for (int trial = 0; trial < 4 * trials && states < trials; ++trial) {
      VecX<double> q, v;
      if (!draw_state(rng, q, v)) continue;
      ++states;
      VecX<double> vy(ny);
      for (int i = 0; i < ny; ++i) vy[i] = v[closed.structure().independent_v[static_cast<std::size_t>(i)]];
      const VecX<double> tau = random_vector<double>(nv, rng, 10.0);
      forward_dynamics_loops_independent<double>(closed, closed_data, q, vy, tau);
      const VecX<double> expected = closed_data.ddq;
      const std::vector<T> qt = narrow<T>(q), vt = narrow<T>(vy), taut = narrow<T>(tau);
      generated::forward_dynamics(qt.data(), vt.data(), taut.data(), ydd.data());
      generated::full_accelerations(qt.data(), vt.data(), taut.data(), qdd.data());
      // Backward error on the tree joints: M (qdd - expected) against the terms of the equation.
      const MatX<double> M = crba<double>(model, data, q);
      const double scale = M.norm() * expected.norm() + tau.norm() + nonlinear_effects<double>(model, data, q, v).norm();
      worst_full = std::max(worst_full, (M * (widen(qdd) - expected)).norm() / scale);
      VecX<double> expected_y(ny);
      for (int i = 0; i < ny; ++i) expected_y[i] = expected[closed.structure().independent_v[static_cast<std::size_t>(i)]];
      worst_y = std::max(worst_y, (widen(ydd) - expected_y).norm() / std::max(1.0, expected.norm()));
    }
    EXPECT_GE(states, trials / 2);
    EXPECT_LT(worst_full, tolerance) << "full_accelerations";
    compare_maps<T>(tolerance, trials);
    EXPECT_LT(worst_y, robot.has_loops ? tolerance : tolerance) << "forward_dynamics (independent accelerations)";
    RecordProperty("full_accelerations", std::to_string(worst_full));
  }

  /// The maps between the coordinate sets against the generic runtime at consistent states:
  /// velocity_map, full_velocities, acceleration_bias (relative to their size, at `tolerance`),
  /// independent_velocities (exact), and closure_positions from a pose whose dependent
  /// coordinates were moved by up to 1e-3: back to the closed pose, converged, in the generic
  /// Newton's number of steps (double) and within its tolerance's reach (float: 1e-3 of the move).
  template <typename T> void compare_maps(double tolerance, int trials) {
    std::mt19937_64 rng(2026);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    const int nv = closed.nv(), ny = robot.ny;
    std::vector<T> Tmap(static_cast<std::size_t>(nv * ny)), v_out(nv), g_out(nv), vy_back(ny);
    double worst[5] = {0, 0, 0, 0, 0};
    int states = 0;
    for (int trial = 0; trial < 4 * trials && states < trials; ++trial) {
      VecX<double> q, v;
      if (!draw_state(rng, q, v)) continue;
      ++states;
      VecX<double> vy(ny), g(nv), v_full(nv);
      for (int i = 0; i < ny; ++i) vy[i] = v[closed.structure().independent_v[static_cast<std::size_t>(i)]];
      MatX<double> T_expected(nv, ny);
      velocity_map<double>(closed, closed_data, q, T_expected);
      full_velocities<double>(closed, closed_data, q, vy, v_full);
      acceleration_bias<double>(closed, closed_data, q, vy, g);
      const std::vector<T> qt = narrow<T>(q), vyt = narrow<T>(vy);
      generated::velocity_map(qt.data(), Tmap.data());
      generated::full_velocities(qt.data(), vyt.data(), v_out.data());
      generated::acceleration_bias(qt.data(), vyt.data(), g_out.data());
      MatX<double> T_generated(nv, ny);
      for (int r = 0; r < nv; ++r)
        for (int c = 0; c < ny; ++c) T_generated(r, c) = static_cast<double>(Tmap[static_cast<std::size_t>(r * ny + c)]);
      worst[0] = std::max(worst[0], relative_error(T_generated, T_expected));
      // The contract BasicDifferentialIk's gather relies on: the row of independent coordinate i
      // is the unit row e_i exactly, in both maps (y = v[independent_v_index] for v = T y).
      for (int i = 0; i < ny; ++i)
        for (int c = 0; c < ny; ++c) {
          const int r = robot.independent_v_index[i];
          ASSERT_EQ(T_generated(r, c), i == c ? 1.0 : 0.0) << "generated T(" << r << ", " << c << ")";
          ASSERT_EQ(T_expected(r, c), i == c ? 1.0 : 0.0) << "generic T(" << r << ", " << c << ")";
        }
      worst[1] = std::max(worst[1], relative_error(widen(v_out), v_full));
      worst[2] = std::max(worst[2], (widen(g_out) - g).norm() / std::max(1.0, g.norm()));
      generated::independent_velocities(v_out.data(), vy_back.data());
      for (int i = 0; i < ny; ++i) EXPECT_EQ(vy_back[static_cast<std::size_t>(i)], vyt[static_cast<std::size_t>(i)]);

      // closure_positions: dependent coordinates moved off the closed pose, then closed again.
      VecX<double> moved = q;
      for (const SubSystem& s : closed.subsystems)
        for (int z : s.dependent) moved[closed.q_index_of_v(z)] += 1e-3 * unit(rng);
      std::vector<T> closing = narrow<T>(moved);
      const auto result = generated::closure_positions(closing.data());
      EXPECT_EQ(result.status, generated::ClosureStatus::converged) << "closure_positions, residual " << result.residual << " pivot ratio " << result.pivot_ratio << " iterations " << result.iterations;
      worst[3] = std::max(worst[3], (widen(closing) - q).cwiseAbs().maxCoeff());
      if (std::is_same_v<T, double>) {
        VecX<double> generic = moved;
        const ClosureResult<double> expected = closure_positions<double>(closed, closed_data, generic);
        EXPECT_EQ(result.iterations, expected.iterations);
        EXPECT_EQ(result.worst_subsystem, expected.worst_subsystem);  // the sub-system nearest a dead point
        EXPECT_LT((widen(closing) - generic).cwiseAbs().maxCoeff(), 1e-12);
      }
      if (!robot.has_loops) {
        EXPECT_EQ(result.iterations, 0);
        EXPECT_EQ(result.worst_subsystem, -1);
      } else {
        EXPECT_GE(result.worst_subsystem, 0);
        EXPECT_LT(result.worst_subsystem, static_cast<int>(closed.subsystems.size()));
      }
      // close_loops: q closed as closure_positions' is (not the same bits: closure_positions may end
      // with a simplified step, close_loops always with Newton's), in at most one step more or fewer;
      // v's dependent entries full_velocities' at its q (independent kept).
      std::vector<T> closing_both = narrow<T>(moved), v_both(static_cast<std::size_t>(nv), T(7)), v_expected(static_cast<std::size_t>(nv));
      for (int i = 0; i < ny; ++i) v_both[static_cast<std::size_t>(robot.independent_v_index[i])] = vyt[static_cast<std::size_t>(i)];
      const auto both = generated::close_loops(closing_both.data(), v_both.data());
      EXPECT_EQ(both.status, result.status);
      EXPECT_LE(std::abs(both.iterations - result.iterations), 1);
      worst[3] = std::max(worst[3], (widen(closing_both) - q).cwiseAbs().maxCoeff());
      generated::full_velocities(closing_both.data(), vyt.data(), v_expected.data());
      worst[1] = std::max(worst[1], relative_error(widen(v_both), widen(v_expected)));

      // closure_constraints at the moved (open) pose and any velocities, as the simulator's soft
      // span reads them: the generic rows SubSystem::rows picks, sub-system by sub-system.
      const int rows = nv - ny;
      const VecX<double> v_any = VecX<double>::NullaryExpr(nv, [&] { return unit(rng); });
      closure_constraints<double>(closed, closed_data, moved, v_any);
      VecX<double> Phi_expected(rows), gamma_expected(rows);
      MatX<double> J_expected(rows, nv);
      int r = 0;
      for (const SubSystem& s : closed.subsystems)
        for (int row : s.rows) {
          Phi_expected[r] = closed_data.Phi[row], gamma_expected[r] = closed_data.gamma[row];
          J_expected.row(r++) = closed_data.Phi_q.row(row);
        }
      ASSERT_EQ(r, rows);
      std::vector<T> Phi_out(static_cast<std::size_t>(rows) + 1), J_out(static_cast<std::size_t>(rows * nv) + 1),
          gamma_out(static_cast<std::size_t>(rows) + 1);
      const std::vector<T> moved_t = narrow<T>(moved), v_any_t = narrow<T>(v_any);
      generated::closure_constraints(moved_t.data(), v_any_t.data(), Phi_out.data(), J_out.data(), gamma_out.data());
      VecX<double> Phi_generated(rows), gamma_generated(rows);
      MatX<double> J_generated(rows, nv);
      for (int i = 0; i < rows; ++i) {
        Phi_generated[i] = static_cast<double>(Phi_out[static_cast<std::size_t>(i)]);
        gamma_generated[i] = static_cast<double>(gamma_out[static_cast<std::size_t>(i)]);
        for (int c = 0; c < nv; ++c) J_generated(i, c) = static_cast<double>(J_out[static_cast<std::size_t>(i * nv + c)]);
      }
      if (rows > 0) {
        // The residual is ~1e-3 (the move): relative to the scale of the poses' terms (1 m).
        worst[4] = std::max(worst[4], (Phi_generated - Phi_expected).cwiseAbs().maxCoeff());
        worst[4] = std::max(worst[4], relative_error(J_generated, J_expected));
        worst[4] = std::max(worst[4], (gamma_generated - gamma_expected).norm() / std::max(1.0, gamma_expected.norm()));
      }
    }
    EXPECT_GE(states, trials / 2);
    EXPECT_LT(worst[0], tolerance) << "velocity_map";
    EXPECT_LT(worst[1], tolerance) << "full_velocities";
    EXPECT_LT(worst[2], tolerance) << "acceleration_bias";
    // Newton's tolerance 1e-12 (double) bounds |q - closed pose| by ~cond(Phi_z) 1e-12 <= 1e-9;
    // float stops at 2e-6 m of residual: 1e-3 (condition <= 1e3 at these poses, test_topology).
    EXPECT_LT(worst[3], (std::is_same_v<T, double> ? 1e-9 : 1e-3)) << "closure_positions";
    EXPECT_LT(worst[4], tolerance) << "closure_constraints";
    RecordProperty("velocity_map", std::to_string(worst[0]));
    RecordProperty("closure_positions", std::to_string(worst[3]));
    RecordProperty("closure_constraints", std::to_string(worst[4]));
  }

  const generated::Robot& robot = generated::robot();
  gen::Description description;
  Model closed;  ///< with the loops (forward_dynamics, full_accelerations)
  Model model;   ///< the spanning tree (every other function)
  Data<double> data, closed_data;
  std::vector<FrameIndex> frames;
};

TEST_F(GeneratedTest, SizesAndNamesMatchTheModel) {
  EXPECT_EQ(robot.nq, model.nq());
  EXPECT_EQ(robot.nv, model.nv());
  EXPECT_EQ(robot.num_bodies, model.num_bodies() - 1);
  EXPECT_EQ(robot.floating_base, model.floating_base());
  const std::vector<std::string> names = model.joint_names();
  ASSERT_EQ(robot.joint_names.size, names.size());
  for (std::size_t j = 0; j < names.size(); ++j) EXPECT_EQ(names[j], robot.joint_names[j]);
  for (int k = 1; k < model.num_bodies(); ++k) EXPECT_EQ(model.body(BodyIndex(k)).name, robot.body_names[k - 1]);
  ASSERT_EQ(robot.joint_names_full.size, names.size());
  ASSERT_EQ(robot.independent_v_index.size, static_cast<std::size_t>(robot.ny));
  for (int i = 0; i < robot.ny; ++i) EXPECT_EQ(robot.independent_v_index[i], closed.structure().independent_v[static_cast<std::size_t>(i)]);
}

// The header's joint ranges are the description's, as the runtime reads them from the Model
// (joint_position_limits): the same joints, indices and limits to the bit.
TEST_F(GeneratedTest, JointLimitsAreTheDescriptions) {
  const std::vector<JointLimit> expected = joint_position_limits(model);
  ASSERT_EQ(robot.limits.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(robot.limits[i].joint, expected[i].joint);
    EXPECT_EQ(robot.limits[i].q_index, expected[i].q_index) << expected[i].joint;
    EXPECT_EQ(robot.limits[i].v_index, expected[i].v_index) << expected[i].joint;
    EXPECT_EQ(robot.limits[i].lower, expected[i].lower) << expected[i].joint;
    EXPECT_EQ(robot.limits[i].upper, expected[i].upper) << expected[i].joint;
  }
}

TEST_F(GeneratedTest, DoubleEqualsGeneric) { compare<double>(1e-12, 100); }

TEST_F(GeneratedTest, FloatWithinDerivedBound) { compare<float>(1e-4, 100); }

TEST_F(GeneratedTest, ClosedSystemDoubleEqualsGeneric) { compare_closed<double>(1e-12, 20); }

TEST_F(GeneratedTest, ClosedSystemFloatWithinDerivedBound) { compare_closed<float>(robot.has_loops ? 1e-2 : 1e-4, 20); }

// actuator_forces: the description's actuated set, the generic function's values (1e-12 relative
// to the forces' size), and forward dynamics with them giving back the accelerations (normwise
// backward error 1e-12).
TEST_F(GeneratedTest, ActuatorForcesEqualGenericAndGiveBackTheAccelerations) {
  const Actuation act = gen::description_actuation(description);
  ASSERT_EQ(robot.na, act.num_actuators());
  for (int i = 0; i < robot.na; ++i) {
    EXPECT_EQ(robot.actuated_v_index[i], act.actuated_v[static_cast<std::size_t>(i)]);
    EXPECT_EQ(robot.actuated_joint_names[i], gen::coordinate_name(closed, act.actuated_v[static_cast<std::size_t>(i)]));
  }
  std::mt19937_64 rng(2027);
  const int ny = robot.ny, na = robot.na;
  std::vector<double> f(static_cast<std::size_t>(std::max(na, 1))), r(static_cast<std::size_t>(ny)), ydd_back(static_cast<std::size_t>(ny));
  double worst_generic = 0, worst_round_trip = 0;
  int states = 0;
  for (int trial = 0; trial < 80 && states < 20; ++trial) {
    VecX<double> q, v;
    if (!draw_state(rng, q, v)) continue;
    ++states;
    VecX<double> vy(ny);
    for (int i = 0; i < ny; ++i) vy[i] = v[closed.structure().independent_v[static_cast<std::size_t>(i)]];
    const VecX<double> ydd = random_vector<double>(ny, rng, 5.0);
    VecX<double> f_expected(na), r_expected(ny);
    actuator_forces<double>(closed, closed_data, act, q, vy, ydd, f_expected, r_expected);
    generated::actuator_forces(q.data(), vy.data(), ydd.data(), f.data(), r.data());
    VecX<double> both(na + ny), both_expected(na + ny);
    for (int i = 0; i < na; ++i) both[i] = f[static_cast<std::size_t>(i)];
    for (int i = 0; i < ny; ++i) both[na + i] = r[static_cast<std::size_t>(i)];
    both_expected << f_expected, r_expected;
    worst_generic = std::max(worst_generic, relative_error(both, both_expected));
    VecX<double> tau = VecX<double>::Zero(closed.nv());
    for (int i = 0; i < na; ++i) tau[robot.actuated_v_index[i]] += f[static_cast<std::size_t>(i)];
    for (int i = 0; i < ny; ++i) tau[robot.independent_v_index[i]] += r[static_cast<std::size_t>(i)];
    generated::forward_dynamics(q.data(), vy.data(), tau.data(), ydd_back.data());
    // Normwise backward error, as for forward dynamics above: M_y (ydd' - ydd) against the terms
    // of the equation (wl16_like's ill-conditioned loops amplify the forward error to 2e-10).
    const MatX<double> My = mass_matrix_loops<double>(closed, closed_data, q);
    const VecX<double> gap = Eigen::Map<const VecX<double>>(ydd_back.data(), ny) - ydd;
    worst_round_trip = std::max(worst_round_trip, (My * gap).norm() / (My.norm() * ydd.norm() + both.norm()));
  }
  EXPECT_GE(states, 10);
  EXPECT_LT(worst_generic, 1e-12) << "actuator_forces vs generic";
  EXPECT_LT(worst_round_trip, 1e-12) << "forward_dynamics(actuator_forces) vs ydd, backward error";
  RecordProperty("actuator_forces", std::to_string(worst_generic));
}

// The mass matrix's L^T D L factor and the solve with it. The factor is checked by what it must
// rebuild, L^T D L = M (generic M; 1e-12 relative in double, 1e-4 in float): entry by entry
// against the generic factor would measure M's conditioning (cassie's massless bodies amplify
// round-off in L). The solve: on the same factor, generated equals generic to 1e-12, and M x = b
// to 1e-10 normwise backward error with the generated mass matrix.
template <typename T> MatX<double> rebuilt_mass_matrix(const std::vector<T>& LD, int nv) {
  MatX<double> L = MatX<double>::Identity(nv, nv), D = MatX<double>::Zero(nv, nv);
  for (int r = 0; r < nv; ++r)
    for (int c = 0; c < nv; ++c) {
      const double x = static_cast<double>(LD[static_cast<std::size_t>(r * nv + c)]);
      if (c < r) L(r, c) = x;
      if (c == r) D(r, r) = x;
    }
  return L.transpose() * D * L;
}

TEST_F(GeneratedTest, MassMatrixFactorRebuildsMAndSolveEqualsGeneric) {
  std::mt19937_64 rng(77);
  const int nv = model.nv();
  std::vector<double> LD(static_cast<std::size_t>(nv * nv)), M(LD.size()), x(static_cast<std::size_t>(nv));
  std::vector<float> LDf(LD.size()), Mf(LD.size());
  double worst_factor = 0, worst_factor_f = 0, worst_solve = 0, worst_backward = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    const VecX<double> b = random_vector<double>(nv, rng, 10.0);
    generated::mass_matrix(q.data(), M.data());
    generated::mass_matrix_factor(M.data(), LD.data());
    generated::mass_matrix_solve(LD.data(), b.data(), x.data());
    const std::vector<float> qf = narrow<float>(q);
    generated::mass_matrix(qf.data(), Mf.data());
    generated::mass_matrix_factor(Mf.data(), LDf.data());
    const MatX<double> M_generic = crba<double>(model, data, q);
    worst_factor = std::max(worst_factor, relative_error(rebuilt_mass_matrix(LD, nv), M_generic));
    worst_factor_f = std::max(worst_factor_f, relative_error(rebuilt_mass_matrix(LDf, nv), M_generic));
    // The generic solve on the generated factor (row-major, as generated code writes it).
    MatX<double> factor(nv, nv);
    for (int r = 0; r < nv; ++r)
      for (int c = 0; c < nv; ++c) factor(r, c) = LD[static_cast<std::size_t>(r * nv + c)];
    VecX<double> x_generic = b;
    mass_matrix_solve_in_place<double>(model, factor, x_generic);
    worst_solve = std::max(worst_solve, relative_error(widen(x), x_generic));
    const Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> Mg(M.data(), nv, nv);
    const VecX<double> xv = widen(x);
    worst_backward = std::max(worst_backward, (Mg * xv - b).norm() / (Mg.norm() * xv.norm() + b.norm()));
  }
  EXPECT_LT(worst_factor, 1e-12);
  EXPECT_LT(worst_factor_f, 1e-4);
  EXPECT_LT(worst_solve, 1e-12);
  EXPECT_LT(worst_backward, 1e-10);
  RecordProperty("mass_matrix_factor", std::to_string(worst_factor));
  RecordProperty("mass_matrix_solve", std::to_string(worst_solve));
}

// Non-finite input gives non-finite output where the output depends on it, and the closure
// says not_converged: a NaN never turns into a plausible number (docs/reliability.md).
TEST_F(GeneratedTest, NonFiniteInputsGiveNonFiniteOutputs) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (const double bad : {nan, std::numeric_limits<double>::infinity()}) {
    // The assembled pose (a closed one) with loops; q = 0 (a unit quaternion) without.
    std::vector<double> q(robot.nq, 0.0), v(robot.ny, 0.1), tau(robot.nv, 0.2), qdd(robot.ny);
    if (robot.has_loops) q.assign(description.assembly.q.data(), description.assembly.q.data() + robot.nq);
    if (robot.floating_base && !robot.has_loops) q[6] = 1;
    ASSERT_EQ(generated::closure_positions(q.data()).status, generated::ClosureStatus::converged);
    // A joint force: the joint's own acceleration depends on it (M^-1 has a positive diagonal).
    for (int i = 0; i < robot.ny; ++i) {
      std::vector<double> t = tau;
      t[static_cast<std::size_t>(robot.independent_v_index[i])] = bad;
      generated::forward_dynamics(q.data(), v.data(), t.data(), qdd.data());
      EXPECT_FALSE(std::isfinite(qdd[static_cast<std::size_t>(i)])) << "tau of " << robot.independent_joint_names[i];
    }
    // A position: the pose of the first body depends on its joint's first coordinate.
    std::vector<double> X(12 * robot.num_bodies), q_bad = q;
    q_bad[0] = bad;
    generated::forward_kinematics(q_bad.data(), X.data());
    EXPECT_FALSE(std::all_of(X.begin(), X.begin() + 12, [](double x) { return std::isfinite(x); }));
    // The closure: a non-finite coordinate is no closed pose (loops), or nothing to close.
    const auto result = generated::closure_positions(q_bad.data());
    EXPECT_EQ(result.status, robot.has_loops ? generated::ClosureStatus::not_converged : generated::ClosureStatus::converged);
  }
}

TEST_F(GeneratedTest, NoAllocation) {
  std::vector<double> q(robot.nq, 0.1), v(robot.nv, 0.2), out(36 * robot.nv * (robot.num_bodies + robot.num_frames + 1));
  if (robot.floating_base) q[6] = 1, q[3] = q[4] = q[5] = 0;
  std::vector<float> qf(q.begin(), q.end()), vf(v.begin(), v.end()), outf(out.size());
  MallocGuard guard;
  generated::forward_dynamics(q.data(), v.data(), v.data(), out.data());
  generated::full_accelerations(q.data(), v.data(), v.data(), out.data());
  generated::inverse_dynamics(q.data(), v.data(), v.data(), out.data());
  generated::actuator_forces(q.data(), v.data(), v.data(), out.data(), out.data() + robot.nv);
  generated::mass_matrix(q.data(), out.data());
  generated::mass_matrix_factor(out.data(), out.data() + robot.nv * robot.nv);
  generated::mass_matrix_solve(out.data() + robot.nv * robot.nv, v.data(), out.data());
  generated::forward_kinematics(q.data(), out.data());
  generated::frame_poses(q.data(), out.data());
  generated::frame_jacobians(q.data(), out.data());
  generated::center_of_mass(q.data(), out.data());
  generated::centroidal_momentum_matrix(q.data(), out.data());
  generated::task_kinematics(q.data(), out.data(), out.data() + 12 * robot.num_frames, out.data() + 18 * robot.num_frames * robot.nv,
                          out.data() + 24 * robot.num_frames * robot.nv);
  generated::velocity_map(q.data(), out.data());
  generated::full_velocities(q.data(), v.data(), out.data());
  generated::acceleration_bias(q.data(), v.data(), out.data());
  generated::closure_positions(q.data());
  generated::closure_positions(qf.data());
  generated::forward_dynamics(qf.data(), vf.data(), vf.data(), outf.data());
  generated::mass_matrix(qf.data(), outf.data());
  EXPECT_EQ(guard.count(), 0u);
}

}  // namespace
}  // namespace mbgen::test
