#pragma once
// Pinocchio 3.7 behind an opaque interface (bench/peers/README.md): the peer benchmark and its
// agreement check see only Eigen vectors here, so that Pinocchio's headers (Boost, its own
// configuration) are compiled in this folder's translation units alone, at the build's flags.
// Pinocchio is not part of mbgen: it is built from a source tree the user names with
// -DMBGEN_PINOCCHIO_SOURCE=DIR, only when they ask for the comparison.
#include <Eigen/Core>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace mbgen::peers {

/// A joint's place in Pinocchio's q and v.
struct PinocchioJointSlot {
  int q = -1, v = -1, nq = 0, nv = 0;
};

/// A ball or universal joint of the URDF modelled, as mbgen does, as a chain of revolute joints
/// about x, y (and z) at the joint's origin, named <joint>_x, <joint>_y (, <joint>_z), with
/// massless bodies between them: so that both libraries solve the same equations.
struct RevoluteChain {
  std::string joint;
  int axes = 3;  ///< 2 (universal: x, y) or 3 (ball: x, y, z)
};

class PinocchioRobot {
 public:
  /// Pinocchio keeps its derivatives and M^-1 row-major (as mbgen's generated code does).
  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  /// Pinocchio's URDF parser; `floating` puts a JointModelFreeFlyer at the root
  /// (q = [x y z qx qy qz qw], v = [v_B w_B] in base coordinates, as mbgen's floating base).
  /// Throws std::runtime_error naming the file when Pinocchio cannot read it.
  PinocchioRobot(const std::string& urdf, bool floating, const std::vector<RevoluteChain>& chains = {});
  ~PinocchioRobot();
  PinocchioRobot(const PinocchioRobot&) = delete;
  PinocchioRobot& operator=(const PinocchioRobot&) = delete;

  int nq() const;
  int nv() const;
  /// The joint's slot, or nv == 0 when Pinocchio's model has no joint of that name.
  PinocchioJointSlot joint(const std::string& name) const;

  /// pinocchio::aba: the joint accelerations.
  const Eigen::VectorXd& aba(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& tau);
  /// pinocchio::rnea: the joint forces.
  const Eigen::VectorXd& rnea(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a);
  /// pinocchio::crba: the mass matrix (Pinocchio fills the upper triangle; both are returned).
  Eigen::MatrixXd crba(const Eigen::VectorXd& q);
  /// pinocchio::crba as it is: M's upper triangle (what the benchmark times).
  const Eigen::MatrixXd& crba_upper(const Eigen::VectorXd& q);
  /// pinocchio::computeABADerivatives: d ddq/dq, d ddq/dv, M^-1 (d/dq along integrate).
  void aba_derivatives(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& tau);
  /// pinocchio::computeRNEADerivatives: dtau/dq, dtau/dv.
  void rnea_derivatives(const Eigen::VectorXd& q, const Eigen::VectorXd& v, const Eigen::VectorXd& a);
  const Eigen::VectorXd& ddq() const;
  const RowMatrix& ddq_dq() const;
  const RowMatrix& ddq_dv() const;
  Eigen::MatrixXd minv() const;  ///< the full M^-1 of the last aba_derivatives (Pinocchio fills its upper triangle)
  const RowMatrix& dtau_dq() const;
  const RowMatrix& dtau_dv() const;

  /// Closes a loop between two frames of the URDF: a RigidConstraintModel(CONTACT_6D, LOCAL), the
  /// way Pinocchio's users model a closed chain. Throws naming a frame that does not exist.
  void add_closure(const std::string& frame_a, const std::string& frame_b);
  /// pinocchio::constraintDynamics with the closures: the joint accelerations. `tight` uses
  /// ProximalSettings(1e-12, 1e-8, 100) (the accuracy mbgen's closed systems keep), otherwise
  /// Pinocchio's defaults.
  const Eigen::VectorXd& constraint_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                             const Eigen::VectorXd& tau, bool tight);
  int last_proximal_iterations() const;
  /// The largest |log6| of the closures' relative placements at q (how closed Pinocchio sees q).
  double closure_error(const Eigen::VectorXd& q);

  struct Impl;

 private:
  std::unique_ptr<Impl> impl_;
};

}  // namespace mbgen::peers
