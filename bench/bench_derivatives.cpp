// The dynamics' derivatives (docs/derivatives.md):
//   derivatives/<robot>/generated           NAME_derivatives::forward_dynamics_derivatives: qdd, dqdd/dq, dqdd/dv, M^-1
//   derivatives/<robot>/generic             forward_dynamics_derivatives<double> of the runtime, same outputs
//   derivatives/<robot>/finite_differences  central differences of the generated NAME::forward_dynamics (2 nv calls
//                                           for dqdd/dq, each after the runtime's integrate, 2 nv for dqdd/dv, 2 nv for
//                                           dqdd/dtau: what an MPC user without derivatives writes)
//   id_derivatives/<robot>/{generated,generic}  tau, dtau/dq, dtau/dv
#include "bench_derivatives.hpp"

#include <memory>

#include "hyq.hpp"
#include "hyq_derivatives.hpp"
#include "iiwa14.hpp"
#include "iiwa14_derivatives.hpp"
#include "mbgen/algorithm/aba_derivatives.hpp"
#include "talos.hpp"
#include "talos_derivatives.hpp"

namespace mbgen::bench {

namespace {

struct DerivativeApi {
  void (*forward_dynamics_derivatives)(const double*, const double*, const double*, double*, double*, double*, double*);
  void (*inverse_dynamics_derivatives)(const double*, const double*, const double*, double*, double*, double*);
  void (*forward_dynamics)(const double*, const double*, const double*, double*);
};

#define MBGEN_DERIVATIVE_API(ns) \
  DerivativeApi { &ns##_derivatives::forward_dynamics_derivatives, &ns##_derivatives::inverse_dynamics_derivatives, &ns::forward_dynamics }

/// The outputs of one call: qdd (or tau) and three nv x nv matrices.
struct Outputs {
  explicit Outputs(int nv) : x(static_cast<std::size_t>(nv)), a(static_cast<std::size_t>(nv * nv)), b(a), c(a) {}
  std::vector<double> x, a, b, c;
};

/// Central differences of forward_dynamics at step h: the user's fallback without derivatives.
struct FiniteDifferences {
  FiniteDifferences(const Model& model, void (*fd)(const double*, const double*, const double*, double*))
      : model(&model), fd(fd), nv(model.nv()), q(model.nq()), v(nv), tau(nv), plus(nv), minus(nv), e(VecX<double>::Zero(nv)),
        out(nv) {}
  const double* run(const Sample& s) {
    const double h = 1e-6;
    for (int k = 0; k < nv; ++k) {
      e[k] = h;
      integrate<double>(*model, s.q, e, q);
      fd(q.data(), s.v.data(), s.tau.data(), plus.data());
      e[k] = -h;
      integrate<double>(*model, s.q, e, q);
      fd(q.data(), s.v.data(), s.tau.data(), minus.data());
      e[k] = 0;
      for (int r = 0; r < nv; ++r) out.a[static_cast<std::size_t>(r * nv + k)] = (plus[r] - minus[r]) / (2 * h);
      v = s.v;
      v[k] += h;
      fd(s.q.data(), v.data(), s.tau.data(), plus.data());
      v[k] -= 2 * h;
      fd(s.q.data(), v.data(), s.tau.data(), minus.data());
      for (int r = 0; r < nv; ++r) out.b[static_cast<std::size_t>(r * nv + k)] = (plus[r] - minus[r]) / (2 * h);
      tau = s.tau;
      tau[k] += h;
      fd(s.q.data(), s.v.data(), tau.data(), plus.data());
      tau[k] -= 2 * h;
      fd(s.q.data(), s.v.data(), tau.data(), minus.data());
      for (int r = 0; r < nv; ++r) out.c[static_cast<std::size_t>(r * nv + k)] = (plus[r] - minus[r]) / (2 * h);
    }
    return out.a.data();
  }
  const Model* model;
  void (*fd)(const double*, const double*, const double*, double*);
  int nv;
  VecX<double> q, v, tau, plus, minus, e;
  Outputs out;
};

void add(const Robot& robot, const DerivativeApi& api) {
  const int nv = robot.model.nv();
  add_benchmark("derivatives", robot, "generated", [api, out = std::make_shared<Outputs>(nv)](const Sample& s) {
    api.forward_dynamics_derivatives(s.q.data(), s.v.data(), s.tau.data(), out->x.data(), out->a.data(), out->b.data(),
                                     out->c.data());
    return out->a.data();
  });
  struct Generic {
    explicit Generic(const Model& m) : data(m), d(m) {}
    Data<double> data;
    DynamicsDerivatives<double> d;
  };
  add_benchmark("derivatives", robot, "generic", [&robot, w = std::make_shared<Generic>(robot.model)](const Sample& s) {
    forward_dynamics_derivatives<double>(robot.model, w->data, w->d, s.q, s.v, s.tau);
    return w->d.dddq_dq.data();
  });
  add_benchmark("derivatives", robot, "finite_differences",
                [w = std::make_shared<FiniteDifferences>(robot.model, api.forward_dynamics)](const Sample& s) { return w->run(s); });
  add_benchmark("id_derivatives", robot, "generated", [api, out = std::make_shared<Outputs>(nv)](const Sample& s) {
    api.inverse_dynamics_derivatives(s.q.data(), s.v.data(), s.a.data(), out->x.data(), out->a.data(), out->b.data());
    return out->a.data();
  });
  add_benchmark("id_derivatives", robot, "generic", [&robot, w = std::make_shared<Generic>(robot.model)](const Sample& s) {
    inverse_dynamics_derivatives<double>(robot.model, w->data, w->d, s.q, s.v, s.a);
    return w->d.dtau_dq.data();
  });
}

}  // namespace

void add_derivative_benchmarks(const Robot& robot) {
  if (robot.name == "iiwa14") add(robot, MBGEN_DERIVATIVE_API(iiwa14));
  if (robot.name == "hyq") add(robot, MBGEN_DERIVATIVE_API(hyq));
  if (robot.name == "talos") add(robot, MBGEN_DERIVATIVE_API(talos));
}

}  // namespace mbgen::bench
