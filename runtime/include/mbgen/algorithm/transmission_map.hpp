#pragma once
// The kinematic map of a transmission (docs/extras.md, `scene: loops: transmission`): a model
// reduced that way moves its output joints (Lola's knee; the foot's pitch and roll), and the
// actuators that drive them through the linkage (the knee's nut, the ankle's two rods) are gone
// from it. This map gives them back: for the reduced model's q, the actuators' positions a(q)
// and the Jacobian J = da/dq (na x the reduced model's nv; zero outside the outputs), which is
// also the force transmission: actuator forces f act on the reduced model as tau = J^T f
// (virtual work; exact when the linkage is massless).
//
// It closes the loops of the whole robot (the generator's Description::transmission_model,
// whose sub-systems take the outputs as independent coordinates) by Newton, warm-started from
// the last call, and reads the actuators' rows of its velocity map T. Allocates when made,
// never after.
#include <stdexcept>
#include <string>
#include <vector>

#include "mbgen/algorithm/closure_positions.hpp"
#include "mbgen/algorithm/subsystem_maps.hpp"
#include "mbgen/data.hpp"

namespace mbgen {

template <typename S> class TransmissionMap {
 public:
  /// `linkage`: the whole robot with its loops, partitioned with the outputs independent;
  /// `reduced`: the reduced model; `actuators`: joints of `linkage` (not in `reduced`), in the
  /// order of a and of J's rows; `warm_start`: a closed configuration of `linkage` (nq), whose
  /// entries for joints absent from `reduced` (welded or locked) stay as given outside the loops.
  TransmissionMap(Model linkage, const Model& reduced, const std::vector<std::string>& actuators, VecX<S> warm_start)
      : linkage_(std::move(linkage)), data_(linkage_), q_(std::move(warm_start)), reduced_nv_(reduced.nv()) {
    if (q_.size() != linkage_.nq()) throw std::invalid_argument("TransmissionMap: warm start of the wrong size");
    for (int k = 1; k < reduced.num_joints(); ++k) {
      const Joint& r = reduced.joint(JointIndex(k));
      const auto w = linkage_.find_joint(r.name);
      if (!w) throw std::invalid_argument("TransmissionMap: joint '" + r.name + "' of the reduced model is not in the linkage model");
      for (int i = 0; i < r.nq; ++i) q_from_.emplace_back(linkage_.joint(*w).idx_q + i, r.idx_q + i);
      for (int i = 0; i < r.nv; ++i) v_of_linkage_.emplace_back(linkage_.joint(*w).idx_v + i, r.idx_v + i);
    }
    for (const std::string& name : actuators) {
      const auto j = linkage_.find_joint(name);
      if (!j || linkage_.joint(*j).nv != 1) throw std::invalid_argument("TransmissionMap: no 1-DoF joint '" + name + "' in the linkage model");
      if (reduced.find_joint(name)) throw std::invalid_argument("TransmissionMap: '" + name + "' is a joint of the reduced model, not an actuator it lost");
      actuator_q_.push_back(linkage_.joint(*j).idx_q);
      actuator_v_.push_back(linkage_.joint(*j).idx_v);
    }
    T_ = MatX<S>::Zero(linkage_.nv(), static_cast<Eigen::Index>(linkage_.structure().independent_v.size()));
  }

  /// Actuator positions a (na) for the reduced model's q (and J, na x reduced nv row-major, when
  /// not null). The status is the closure's: at a dead point of a linkage (Singular) or where it
  /// cannot close (NotConverged) a and J are not defined and must not be used.
  ClosureStatus evaluate(const S* q_reduced, S* a, S* J = nullptr, const ClosureOptions& options = {}) {
    for (const auto& [w, r] : q_from_) q_[w] = q_reduced[r];
    const ClosureResult<S> closed = closure_positions<S>(linkage_, data_, q_, options);
    if (closed.status != ClosureStatus::Converged) return closed.status;
    for (std::size_t i = 0; i < actuator_q_.size(); ++i) a[i] = q_[actuator_q_[i]];
    if (J) {
      velocity_map<S>(linkage_, data_, q_, T_);
      for (std::size_t i = 0; i < actuator_v_.size() * static_cast<std::size_t>(reduced_nv_); ++i) J[i] = S(0);
      for (std::size_t k = 0; k < linkage_.structure().independent_v.size(); ++k) {
        const int w = linkage_.structure().independent_v[k];
        for (const auto& [lw, r] : v_of_linkage_)
          if (lw == w)
            for (std::size_t i = 0; i < actuator_v_.size(); ++i) J[i * static_cast<std::size_t>(reduced_nv_) + static_cast<std::size_t>(r)] = T_(actuator_v_[i], static_cast<Eigen::Index>(k));
      }
    }
    return ClosureStatus::Converged;
  }

  /// The whole robot's configuration of the last evaluate() (loops closed): the linkage's joints
  /// where the reduced model has none, for comparisons with the exact model.
  const VecX<S>& linkage_q() const { return q_; }
  const Model& linkage_model() const { return linkage_; }
  int num_actuators() const { return static_cast<int>(actuator_q_.size()); }

 private:
  Model linkage_;
  Data<S> data_;
  VecX<S> q_;
  MatX<S> T_;
  int reduced_nv_;
  std::vector<std::pair<int, int>> q_from_, v_of_linkage_;  // (linkage index, reduced index)
  std::vector<int> actuator_q_, actuator_v_;
};

}  // namespace mbgen
