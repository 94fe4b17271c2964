#pragma once
// Explicit integrators for the forward dynamics x' = f(x), x = (q, v). q is integrated in ambient
// coordinates (quaternion rates) and the quaternion renormalised after each step.
#include "mbgen/algorithm/aba.hpp"
#include "mbgen/algorithm/configuration.hpp"

namespace mbgen {

/// Work memory of rk4_step, sized once for a model (the step itself does not allocate).
template <typename S> struct Rk4Workspace {
  explicit Rk4Workspace(const Model& model)
      : q_stage(model.nq()), v_stage(model.nv()), dq{VecX<S>(model.nq()), VecX<S>(model.nq()), VecX<S>(model.nq()), VecX<S>(model.nq())},
        dv{VecX<S>(model.nv()), VecX<S>(model.nv()), VecX<S>(model.nv()), VecX<S>(model.nv())} {}
  VecX<S> q_stage, v_stage;
  VecX<S> dq[4], dv[4];
};

/// One classical Runge-Kutta step of size dt with constant joint forces tau, in place on (q, v).
/// Forward dynamics by ABA; damping and friction are not modelled (pass them in tau).
template <typename S>
void rk4_step(const Model& model, Data<S>& data, Rk4Workspace<S>& ws, Eigen::Ref<VecX<S>> q, Eigen::Ref<VecX<S>> v,
              const ConstVecRef<S>& tau, S dt) {
  const S weights[3] = {dt / S(2), dt / S(2), dt};
  for (int stage = 0; stage < 4; ++stage) {
    if (stage == 0) {
      ws.q_stage = q;
      ws.v_stage = v;
    } else {
      ws.q_stage = q + weights[stage - 1] * ws.dq[stage - 1];
      ws.v_stage = v + weights[stage - 1] * ws.dv[stage - 1];
    }
    configuration_derivative<S>(model, ws.q_stage, ws.v_stage, ws.dq[stage]);
    ws.dv[stage] = aba<S>(model, data, ws.q_stage, ws.v_stage, tau);
  }
  q += dt / S(6) * (ws.dq[0] + S(2) * ws.dq[1] + S(2) * ws.dq[2] + ws.dq[3]);
  v += dt / S(6) * (ws.dv[0] + S(2) * ws.dv[1] + S(2) * ws.dv[2] + ws.dv[3]);
  normalize_configuration<S>(model, q);
}

}  // namespace mbgen
