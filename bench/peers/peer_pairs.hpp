#pragma once
// The robots timed against Pinocchio (bench_peers.cpp) and checked against it first
// (peer_check.cpp): each one's generated functions, Pinocchio's model of the same URDF, and
// kPoolSize states in both libraries' layouts, so that no conversion is timed.
#include <Eigen/Core>

#include <memory>
#include <string>
#include <vector>

#include "joint_map.hpp"
#include "pinocchio_peer.hpp"

namespace mbgen::peers {

/// A tree robot's generated functions (the bench's generated libraries).
struct GeneratedTree {
  std::string robot;
  std::string urdf;  ///< relative to ../shared/robots
  bool floating = false;
  int nq = 0, nv = 0;
  std::vector<std::string> joint_names;
  void (*forward_dynamics)(const double*, const double*, const double*, double*);
  void (*inverse_dynamics)(const double*, const double*, const double*, double*);
  void (*mass_matrix)(const double*, double*);
  void (*forward_dynamics_derivatives)(const double*, const double*, const double*, double*, double*, double*, double*);
  void (*inverse_dynamics_derivatives)(const double*, const double*, const double*, double*, double*, double*);
};

/// A closed-loop robot's generated functions (fixed base; the loops in its robot.yaml).
struct GeneratedLoops {
  std::string robot;
  std::string urdf;  ///< relative to ../shared/robots; its robot.yaml beside it names the closures
  int nq = 0, nv = 0, ny = 0;
  std::vector<std::string> joint_names;
  std::vector<int> independent_v_index;
  void (*forward_dynamics)(const double*, const double*, const double*, double*);
  void (*full_accelerations)(const double*, const double*, const double*, double*);
  /// closure_positions in place: its status (0 when Newton converged), the steps it took in *iterations.
  int (*closure_positions)(double* q, int* iterations);
};

struct TreeState {
  Eigen::VectorXd q, v, a, tau;                                      // mbgen's layout
  Eigen::VectorXd pinocchio_q, pinocchio_v, pinocchio_a, pinocchio_tau;  // Pinocchio's
};

struct LoopState {
  Eigen::VectorXd q, v, vy, tau;  // mbgen's: loops closed, every velocity (v = T vy) and the independent ones
  Eigen::VectorXd warm_q;  // q with the independent coordinates moved by kStep vy, the dependent ones held: loops open
  Eigen::VectorXd pinocchio_q, pinocchio_v, pinocchio_tau;
};

struct TreePair {
  GeneratedTree generated;
  std::unique_ptr<PinocchioRobot> pinocchio;
  std::unique_ptr<JointMap> map;
  std::shared_ptr<const std::vector<TreeState>> states;
};

struct LoopPair {
  GeneratedLoops generated;
  std::unique_ptr<PinocchioRobot> pinocchio;
  std::unique_ptr<JointMap> map;
  std::shared_ptr<const std::vector<LoopState>> states;
};

/// iiwa14 (fixed), hyq and talos_reduced (floating), with their states.
std::vector<TreePair> tree_pairs();
/// cassie_like, talos_like and digit_like_2legs (parallel_legs; digit's ball and universal
/// joints as mbgen's revolute chains on both sides), with closed states.
std::vector<LoopPair> loop_pairs();

/// The largest relative error over the states of each quantity (generated against Pinocchio).
struct TreeAgreement {
  double forward_dynamics = 0, inverse_dynamics = 0, mass_matrix = 0;
  double fd_derivatives = 0;  ///< ddq, d ddq/dq, d ddq/dv and M^-1, the worst
  double id_derivatives = 0;  ///< dtau/dq and dtau/dv, the worst
};
TreeAgreement check(TreePair& pair);

struct LoopAgreement {
  double full_accelerations = 0;  ///< against constraintDynamics with the tight settings
  double forward_dynamics = 0;    ///< the independent entries of full_accelerations against forward_dynamics
  double pinocchio_closure = 0;   ///< Pinocchio's |log6| of the closures at mbgen's closed states
  int warm_closures_converged = 0;       ///< from warm_q
  int predicted_closures_converged = 0;  ///< from q + kStep v (predicted_start)
  int warm_iterations = 0, predicted_iterations = 0;  ///< closure_positions' steps, summed over the states
};
LoopAgreement check(LoopPair& pair);

/// The step of a closed-loop simulator that the closed step stands for (1 ms).
inline constexpr double kStep = 1e-3;

/// Where a simulator's step leaves q before it closes the loops: every coordinate moved by its
/// velocity, kStep v (a fixed base: nq = nv), the explicit Euler predictor. The loops are open
/// by O(kStep^2) (their curvature times v^2), against O(kStep) for warm_q.
inline void predicted_start(const LoopState& s, Eigen::VectorXd& q) { q = s.q + kStep * s.v; }

/// The check's tolerances (README.md here): round-off of either library, times the conditioning
/// of M (the derivatives, M^-1) or of the proximal solve (the loops).
inline constexpr double kTreeTolerance = 1e-12;
inline constexpr double kDerivativeTolerance = 1e-10;
inline constexpr double kLoopTolerance = 1e-9;

}  // namespace mbgen::peers
