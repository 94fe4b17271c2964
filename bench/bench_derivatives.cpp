// The dynamics' derivatives (docs/derivatives.md):
//   derivatives/<robot>/generated           NAME_derivatives::forward_dynamics_derivatives: qdd, dqdd/dq, dqdd/dv, M^-1
//   derivatives/<robot>/generic             forward_dynamics_derivatives<double> of the runtime, same outputs
//   derivatives/<robot>/finite_differences  central differences of the generated NAME::forward_dynamics (2 nv calls
//                                           for dqdd/dq, each after the runtime's integrate, 2 nv for dqdd/dv, 2 nv for
//                                           dqdd/dtau: what an MPC user without derivatives writes)
//   id_derivatives/<robot>/{generated,generic}  tau, dtau/dq, dtau/dv
// and for the closed-loop robots lola (floating) and cassie_like (fixed), in the independent
// coordinates y along the closed set (loop_dynamics_derivatives.hpp):
//   derivatives/<robot>/generated           NAME::forward_dynamics_derivatives: ydd, dydd/dy, dydd/dyd, dydd/dtau
//   derivatives/<robot>/generic             forward_dynamics_loops_derivatives<double>, same outputs
//   derivatives/<robot>/finite_differences  central differences of the generated forward_dynamics: per y, the
//                                           runtime's integrate then the generated closure_positions (Newton,
//                                           warm-started at the state) on each side; 2 ny calls for dydd/dyd,
//                                           2 nv for dydd/dtau
// and with both feet of talos held flat (rigid_contact_derivatives.hpp; examples/data/talos_stance.yaml):
//   contact_derivatives/talos/generated           NAME::rigid_contact_forward_dynamics_derivatives: the same outputs
//   contact_derivatives/talos/generic             rigid_contact_dynamics_derivatives<double>: a, lambda and their
//                                                 derivatives wrt q, v, tau
//   contact_derivatives/talos/finite_differences  central differences of rigid_contact_dynamics<double> (6 nv calls)
// and hyq on its four feet under the compliant ground (examples/data/hyq_sim.yaml; contact_dynamics_derivatives.hpp;
// the pool's states against the plane z = 0, some feet pressing and some not, which costs the same: no branch):
//   compliant_derivatives/hyq/generated           NAME::contact_forward_dynamics_derivatives: qdd, dqdd/dq, dqdd/dv, M^-1
//   compliant_derivatives/hyq/generic             contact_forward_dynamics_derivatives<double>, same outputs
//   compliant_derivatives/hyq/finite_differences  central differences of the generated contact_accelerations (6 nv calls)
//   compliant_derivatives/hyq/value               one generated contact_accelerations (what the derivatives cost against)
// and one simulator step (RK4, 1e-4 s) of hyq standing on its four feet, neutral joints, the ground 1 mm above the
// lowest foot, the scene's law (sim/step_derivatives.hpp):
//   step_derivatives/hyq/generic    sim::StepDerivatives<sim::GenericBackend<double>>::compute
//   step_derivatives/hyq/generated  sim::StepDerivatives<hyq_contact::Backend>::compute: the stages call the generated
//                                   contact_forward_dynamics_derivatives
// and one simulator step of talos standing on 8 sole spheres pressed 1 mm into the ground (RK4, 1e-4 s,
// sim/step_derivatives.hpp):
//   step_derivatives/talos/generic             sim::StepDerivatives<sim::GenericBackend<double>>::compute: q+, v+, dx+/dx, dx+/du
//   step_derivatives/talos/finite_differences  central differences of the simulator's step (6 nv steps, each
//                                               after set_state)
#include "bench_derivatives.hpp"

#include <memory>
#include <utility>

#include "hyq.hpp"
#include "collision/contact_spheres.hpp"
#include "hyq_contact.hpp"
#include "hyq_derivatives.hpp"
#include "iiwa14.hpp"
#include "iiwa14_derivatives.hpp"
#include "lola.hpp"
#include "lola_derivatives.hpp"
#include "mbgen/algorithm/aba_derivatives.hpp"
#include "mbgen/algorithm/contact_dynamics_derivatives.hpp"
#include "mbgen/algorithm/loop_dynamics_derivatives.hpp"
#include "mbgen/algorithm/rigid_contact_derivatives.hpp"
#include "mbgen/sim/step_derivatives.hpp"
#include "pl_cassie_like.hpp"
#include "pl_cassie_like_derivatives.hpp"
#include "talos.hpp"
#include "talos_derivatives.hpp"
#include "talos_stance.hpp"

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

/// Central differences of accelerations(q, v, tau, out), q moved by the runtime's integrate: da/dq,
/// da/dv, da/dtau side by side (nv x 3 nv), the fallback without derivatives (6 nv calls).
template <typename Accelerations> struct CentralDifferences {
  CentralDifferences(const Model& model, Accelerations accelerations)
      : model(&model), accelerations(std::move(accelerations)), nv(model.nv()), q(model.nq()), v(nv), tau(nv), plus(nv),
        minus(nv), e(VecX<double>::Zero(nv)), da(nv, 3 * nv) {}
  const double* run(const Sample& s) {
    const double h = 1e-6;
    for (int k = 0; k < nv; ++k) {
      for (int side : {1, -1}) {
        e[k] = side * h;
        integrate<double>(*model, s.q, e, q);
        accelerations(q, s.v, s.tau, side > 0 ? plus : minus);
      }
      e[k] = 0;
      da.col(k) = (plus - minus) / (2 * h);
      v = s.v;
      v[k] += h;
      accelerations(s.q, v, s.tau, plus);
      v[k] -= 2 * h;
      accelerations(s.q, v, s.tau, minus);
      da.col(nv + k) = (plus - minus) / (2 * h);
      tau = s.tau;
      tau[k] += h;
      accelerations(s.q, s.v, tau, plus);
      tau[k] -= 2 * h;
      accelerations(s.q, s.v, tau, minus);
      da.col(2 * nv + k) = (plus - minus) / (2 * h);
    }
    return da.data();
  }
  const Model* model;
  Accelerations accelerations;
  int nv;
  VecX<double> q, v, tau, plus, minus, e;
  MatX<double> da;
};

template <typename Accelerations> std::shared_ptr<CentralDifferences<Accelerations>> central_differences(const Model& model,
                                                                                                        Accelerations f) {
  return std::make_shared<CentralDifferences<Accelerations>>(model, std::move(f));
}

/// contact_derivatives/talos/{generated,generic,finite_differences}: both feet held flat (6-D
/// contacts at the sole frames, examples/data/talos_stance.yaml), the generated and the generic
/// rigid_contact_dynamics_derivatives against central differences of rigid_contact_dynamics (6 nv
/// calls).
void add_contacts(const Robot& robot, const std::vector<std::string>& feet) {
  std::vector<RigidContact> contacts;
  for (const std::string& foot : feet) contacts.push_back({robot.model.frame_index(foot), RigidContactKind::Frame});
  struct Generated {
    Generated(int nv, int m)
        : a(static_cast<std::size_t>(nv)), lambda(static_cast<std::size_t>(m)), dq(static_cast<std::size_t>(nv * nv)), dv(dq),
          dtau(dq), lq(static_cast<std::size_t>(m * nv)), lv(lq), ltau(lq), pivots(static_cast<std::size_t>(2 * m)) {}
    std::vector<double> a, lambda, dq, dv, dtau, lq, lv, ltau, pivots;
  };
  const int m = 6 * static_cast<int>(feet.size());
  add_benchmark("contact_derivatives", robot, "generated", [w = std::make_shared<Generated>(robot.model.nv(), m)](const Sample& s) {
    talos_stance::rigid_contact_forward_dynamics_derivatives(s.q.data(), s.v.data(), s.tau.data(), w->a.data(), w->lambda.data(),
                                                             w->dq.data(), w->lq.data(), w->dv.data(), w->lv.data(),
                                                             w->dtau.data(), w->ltau.data(), w->pivots.data());
    return w->dq.data();
  });
  struct Generic {
    Generic(const Model& m, const std::vector<RigidContact>& c) : data(m), ws(m, c), d(m, ws) {}
    Data<double> data;
    RigidContactWorkspace<double> ws;
    RigidContactDerivatives<double> d;
  };
  add_benchmark("contact_derivatives", robot, "generic", [&robot, w = std::make_shared<Generic>(robot.model, contacts)](const Sample& s) {
    rigid_contact_dynamics_derivatives<double>(robot.model, w->data, w->ws, w->d, s.q, s.v, s.tau);
    return w->d.da_dq.data();
  });
  // The rigid contacts' accelerations (generic: the generated function is the derivatives' only).
  struct Dynamics {
    Dynamics(const Model& m, const std::vector<RigidContact>& c) : data(m), ws(m, c) {}
    Data<double> data;
    RigidContactWorkspace<double> ws;
  };
  auto rigid = [&model = robot.model, w = std::make_shared<Dynamics>(robot.model, contacts)](
                   const VecX<double>& q, const VecX<double>& v, const VecX<double>& tau, VecX<double>& out) {
    out = rigid_contact_dynamics<double>(model, w->data, w->ws, q, v, tau);
  };
  add_benchmark("contact_derivatives", robot, "finite_differences",
                [w = central_differences(robot.model, rigid)](const Sample& s) { return w->run(s); });
}

/// hyq's scene on the ground (examples/data/hyq_sim.yaml): its model, spheres, law and the plane z = 0.
struct CompliantGround {
  CompliantGround() {
    gen::LoadOptions options;
    options.extras_file = std::string(MBGEN_SOURCE_DIR) + "/examples/data/hyq_sim.yaml";
    const gen::Description d = gen::load_description(std::string(MBGEN_SHARED_ROBOTS) + "/hyq/hyq_no_sensors.urdf", options);
    model = d.model;
    spheres = gen::contact_spheres(d);
    exponent = d.scene->contact->parameters.exponent;
    contact_inputs(GroundPlane{}, d.scene->contact->parameters, ground, law);
  }
  Model model;
  std::vector<ContactSphere> spheres;
  double exponent = 1.5, ground[kGroundInputs] = {}, law[kLawInputs] = {};
};

/// compliant_derivatives/hyq/{generated,generic,finite_differences,value} (header comment).
void add_compliant(const Robot& robot) {
  const auto scene = std::make_shared<const CompliantGround>();
  const int nv = robot.model.nv(), m = hyq_contact::num_contact_spheres;
  struct Buffers {
    Buffers(int nv, int m) : out(nv), contacts(static_cast<std::size_t>(kContactOutputs * m)) {}
    Outputs out;
    std::vector<double> contacts;
  };
  add_benchmark("compliant_derivatives", robot, "generated", [scene, w = std::make_shared<Buffers>(nv, m)](const Sample& s) {
    hyq_contact::contact_forward_dynamics_derivatives(s.q.data(), s.v.data(), s.tau.data(), scene->ground, scene->law,
                                                      w->out.x.data(), w->out.a.data(), w->out.b.data(), w->out.c.data(),
                                                      w->contacts.data());
    return w->out.a.data();
  });
  struct Generic {
    explicit Generic(const Model& model, int m) : data(model), d(model), contacts(static_cast<std::size_t>(kContactOutputs * m)) {}
    Data<double> data;
    ContactDynamicsDerivatives<double> d;
    std::vector<double> contacts;
  };
  add_benchmark("compliant_derivatives", robot, "generic", [scene, w = std::make_shared<Generic>(scene->model, m)](const Sample& s) {
    contact_forward_dynamics_derivatives<double>(scene->model, w->data, w->d, scene->spheres, scene->exponent, s.q, s.v, s.tau,
                                                 scene->ground, scene->law, w->contacts.data());
    return w->d.fd.dddq_dq.data();
  });
  auto compliant = [scene, contacts = std::vector<double>(static_cast<std::size_t>(kContactOutputs * m))](
                       const VecX<double>& q, const VecX<double>& v, const VecX<double>& tau, VecX<double>& out) mutable {
    hyq_contact::contact_accelerations(q.data(), v.data(), tau.data(), scene->ground, scene->law, out.data(), contacts.data());
  };
  add_benchmark("compliant_derivatives", robot, "finite_differences",
                [w = central_differences(scene->model, compliant)](const Sample& s) { return w->run(s); });
  add_benchmark("compliant_derivatives", robot, "value", [scene, w = std::make_shared<Buffers>(nv, m)](const Sample& s) {
    hyq_contact::contact_accelerations(s.q.data(), s.v.data(), s.tau.data(), scene->ground, scene->law, w->out.x.data(),
                                       w->contacts.data());
    return w->out.x.data();
  });
}

/// step_derivatives/hyq/{generic,generated} (header comment).
void add_step_derivatives_hyq() {
  struct Standing {
    Standing() : q(neutral_configuration<double>(scene.model)), v(VecX<double>::Zero(scene.model.nv())), tau(v) {
      Data<double> data(scene.model);
      const int m = static_cast<int>(scene.spheres.size());
      VecX<double> c(3 * m), J(6 * scene.model.nv() * m);
      contact_points<double>(scene.model, data, scene.spheres, q, c.data(), J.data());
      double lowest = 1e9;
      for (int k = 0; k < m; ++k) lowest = std::min(lowest, c[3 * k + 2] - scene.spheres[static_cast<std::size_t>(k)].radius);
      options.ground.offset = lowest + 1e-3;
      options.contact_parameters.exponent = scene.exponent;
      options.energy_check_interval = 0;
    }
    CompliantGround scene;
    VecX<double> q, v, tau;
    sim::SimulatorOptions options;
  };
  const auto standing = std::make_shared<const Standing>();
  benchmark::RegisterBenchmark("step_derivatives/hyq/generic", [standing](benchmark::State& state) {
    sim::Simulator<sim::GenericBackend<double>> simulator(sim::GenericBackend<double>(standing->scene.model, standing->scene.spheres),
                                                          standing->options);
    simulator.set_state(standing->q.data(), standing->v.data());
    sim::StepDerivatives<sim::GenericBackend<double>> d(simulator);
    for (auto _ : state) {
      d.compute(standing->q.data(), standing->v.data(), standing->tau.data());
      benchmark::DoNotOptimize(d.dx_dx().data());
    }
  })->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark("step_derivatives/hyq/generated", [standing](benchmark::State& state) {
    sim::Simulator<hyq_contact::Backend> simulator(hyq_contact::Backend{}, standing->options);
    simulator.set_state(standing->q.data(), standing->v.data());
    sim::StepDerivatives<hyq_contact::Backend> d(simulator);
    for (auto _ : state) {
      d.compute(standing->q.data(), standing->v.data(), standing->tau.data());
      benchmark::DoNotOptimize(d.dx_dx().data());
    }
  })->Unit(benchmark::kMicrosecond);
}

/// talos standing: neutral joints, four spheres (r 1 cm) at each sole's corners, the ground 1 mm
/// above the lowest sphere; a simulator (RK4, 1e-4 s) at rest there.
struct StandingOnSpheres {
  explicit StandingOnSpheres(const Model& model) : q(neutral_configuration<double>(model)), v(VecX<double>::Zero(model.nv())),
                                                   tau(VecX<double>::Zero(model.nv())) {
    for (const char* foot : {"left_sole_link", "right_sole_link"}) {
      const Frame& f = model.frame(model.frame_index(foot));
      for (double x : {-0.1, 0.1})
        for (double y : {-0.05, 0.05}) spheres.push_back({f.body, f.X_BF.act(Vec3<double>(x, y, 0.01)), 0.01, foot});
    }
    Data<double> data(model);
    VecX<double> c(3 * static_cast<int>(spheres.size())), J(6 * model.nv() * static_cast<int>(spheres.size()));
    contact_points<double>(model, data, spheres, q, c.data(), J.data());
    double lowest = 1e9;
    for (std::size_t k = 0; k < spheres.size(); ++k) lowest = std::min(lowest, c[3 * static_cast<int>(k) + 2] - spheres[k].radius);
    sim::SimulatorOptions o;
    o.ground.offset = lowest + 1e-3;
    o.energy_check_interval = 0;
    simulator = std::make_unique<sim::Simulator<sim::GenericBackend<double>>>(sim::GenericBackend<double>(model, spheres), o);
    simulator->set_controller([this](double, const double*, const double*, double* t) {
      for (int i = 0; i < this->tau.size(); ++i) t[i] = this->tau[i];
    });
    simulator->set_state(q.data(), v.data());
  }
  std::vector<ContactSphere> spheres;
  VecX<double> q, v, tau;
  std::unique_ptr<sim::Simulator<sim::GenericBackend<double>>> simulator;
};

/// Central differences of the simulator's step: the fallback without StepDerivatives.
struct StepFiniteDifferences {
  explicit StepFiniteDifferences(const Model& model)
      : model(&model), scene(model), nv(model.nv()), q(model.nq()), e(VecX<double>::Zero(nv)), dq(nv), dq_minus(nv),
        center(model.nq()), jacobian(2 * nv, 3 * nv) {
    sim::StepDerivatives<sim::GenericBackend<double>> d(*scene.simulator);
    d.compute(scene.q.data(), scene.v.data(), scene.tau.data());
    center = d.q_next();
  }
  /// The state one step after (qx, vx) under ux: its tangent from `center` in dq, its v in v_out.
  void step(const VecX<double>& qx, const VecX<double>& vx, const VecX<double>& ux, VecX<double>& out_dq, VecX<double>& v_out) {
    scene.tau = ux;
    scene.simulator->set_state(qx.data(), vx.data());
    scene.simulator->step();
    difference<double>(*model, center, scene.simulator->q(), out_dq);
    v_out = scene.simulator->v();
  }
  const double* run() {
    const double h = 1e-6;
    const VecX<double> q0 = scene.q, v0 = scene.v, u0 = scene.tau;
    VecX<double> v_plus(nv), v_minus(nv), x(nv);
    for (int k = 0; k < 3 * nv; ++k) {
      for (int side : {1, -1}) {
        VecX<double> vx = v0, ux = u0;
        if (k < nv) {
          e[k] = side * h;
          integrate<double>(*model, q0, e, q);
          e[k] = 0;
        } else {
          q = q0;
          (k < 2 * nv ? vx[k - nv] : ux[k - 2 * nv]) += side * h;
        }
        step(q, vx, ux, side > 0 ? dq : dq_minus, side > 0 ? v_plus : v_minus);
      }
      jacobian.col(k) << (dq - dq_minus) / (2 * h), (v_plus - v_minus) / (2 * h);
    }
    scene.tau = u0;
    return jacobian.data();
  }
  const Model* model;
  StandingOnSpheres scene;
  int nv;
  VecX<double> q, e, dq, dq_minus, center;
  MatX<double> jacobian;
};

/// step_derivatives/<robot>/{generic,finite_differences} (header comment).
void add_step_derivatives(const Robot& robot) {
  const Model* model = &robot.model;
  const std::string prefix = "step_derivatives/" + robot.name + "/";
  benchmark::RegisterBenchmark((prefix + "generic").c_str(), [model](benchmark::State& state) {
    StandingOnSpheres scene(*model);
    sim::StepDerivatives<sim::GenericBackend<double>> d(*scene.simulator);
    for (auto _ : state) {
      d.compute(scene.q.data(), scene.v.data(), scene.tau.data());
      benchmark::DoNotOptimize(d.dx_dx().data());
    }
  })->Unit(benchmark::kMicrosecond);
  benchmark::RegisterBenchmark((prefix + "finite_differences").c_str(), [model](benchmark::State& state) {
    StepFiniteDifferences fd(*model);
    for (auto _ : state) benchmark::DoNotOptimize(fd.run());
  })->Unit(benchmark::kMicrosecond);
}

/// The generated functions of a closed-loop robot the loop benchmarks call.
struct LoopDerivativeApi {
  void (*forward_dynamics_derivatives)(const double*, const double*, const double*, double*, double*, double*, double*);
  void (*forward_dynamics)(const double*, const double*, const double*, double*);
  void (*closure_positions)(double*);
};

/// One state in independent velocities.
struct LoopSample {
  VecX<double> q, vy, tau;
};

/// Central differences of the generated closed-system forward dynamics: the user's fallback.
struct LoopFiniteDifferences {
  LoopFiniteDifferences(const Model& model, const LoopDerivativeApi& api)
      : model(&model), api(api), ny(model.structure().num_independent()), nv(model.nv()), q(model.nq()), vy(ny), tau(nv), plus(ny),
        minus(ny), e(VecX<double>::Zero(nv)), a(static_cast<std::size_t>(ny * ny)), b(a), c(static_cast<std::size_t>(ny * nv)) {}
  const double* run(const LoopSample& s) {
    const double h = 1e-6;
    const auto column = [&](std::vector<double>& out, int cols, int k) {
      for (int r = 0; r < ny; ++r) out[static_cast<std::size_t>(r * cols + k)] = (plus[r] - minus[r]) / (2 * h);
    };
    for (int k = 0; k < ny; ++k) {
      const int i = model->structure().independent_v[static_cast<std::size_t>(k)];
      for (int side : {1, -1}) {
        e[i] = side * h;
        integrate<double>(*model, s.q, e, q);
        api.closure_positions(q.data());
        api.forward_dynamics(q.data(), s.vy.data(), s.tau.data(), side > 0 ? plus.data() : minus.data());
      }
      e[i] = 0;
      column(a, ny, k);
      vy = s.vy;
      vy[k] += h;
      api.forward_dynamics(s.q.data(), vy.data(), s.tau.data(), plus.data());
      vy[k] -= 2 * h;
      api.forward_dynamics(s.q.data(), vy.data(), s.tau.data(), minus.data());
      column(b, ny, k);
    }
    for (int k = 0; k < nv; ++k) {
      tau = s.tau;
      tau[k] += h;
      api.forward_dynamics(s.q.data(), s.vy.data(), tau.data(), plus.data());
      tau[k] -= 2 * h;
      api.forward_dynamics(s.q.data(), s.vy.data(), tau.data(), minus.data());
      column(c, nv, k);
    }
    return a.data();
  }
  const Model* model;
  LoopDerivativeApi api;
  int ny, nv;
  VecX<double> q, vy, tau, plus, minus, e;
  std::vector<double> a, b, c;
};

void add_loops(const std::string& name, const std::string& urdf, const std::string& extras, const LoopDerivativeApi& api) {
  static std::vector<std::unique_ptr<Model>> models;  // live as long as the benchmarks
  gen::LoadOptions options;
  if (!extras.empty()) options.extras_file = extras;
  const gen::Description d = gen::load_description(urdf, options);
  models.push_back(std::make_unique<Model>(d.model));
  const Model* model = models.back().get();
  const int ny = model->structure().num_independent(), nv = model->nv();
  auto pool = std::make_shared<std::vector<LoopSample>>();
  const auto states = consistent_pool(*model, d.assembly.q);  // (held: a range-for over *f() would outlive it)
  for (const Sample& sample : *states) {
    LoopSample x{sample.q, VecX<double>(ny), sample.tau};
    for (int i = 0; i < ny; ++i) x.vy[i] = sample.v[model->structure().independent_v[static_cast<std::size_t>(i)]];
    pool->push_back(std::move(x));
  }
  struct Out {
    Out(int ny, int nv) : x(static_cast<std::size_t>(ny)), a(static_cast<std::size_t>(ny * ny)), b(a), c(static_cast<std::size_t>(ny * nv)) {}
    std::vector<double> x, a, b, c;
  };
  add_benchmark<LoopSample>("derivatives", name, "generated", pool, [api, out = std::make_shared<Out>(ny, nv)](const LoopSample& s) {
    api.forward_dynamics_derivatives(s.q.data(), s.vy.data(), s.tau.data(), out->x.data(), out->a.data(), out->b.data(), out->c.data());
    return out->a.data();
  });
  struct Generic {
    explicit Generic(const Model& m) : data(m), ld(m) {}
    Data<double> data;
    LoopDynamicsDerivatives<double> ld;
  };
  add_benchmark<LoopSample>("derivatives", name, "generic", pool, [model, w = std::make_shared<Generic>(*model)](const LoopSample& s) {
    forward_dynamics_loops_derivatives<double>(*model, w->data, w->ld, s.q, s.vy, s.tau);
    return w->ld.dydd_dy.data();
  });
  add_benchmark<LoopSample>("derivatives", name, "finite_differences", pool,
                            [w = std::make_shared<LoopFiniteDifferences>(*model, api)](const LoopSample& s) { return w->run(s); });
}

}  // namespace

void add_loop_derivative_benchmarks() {
  const std::string source = MBGEN_SOURCE_DIR, shared = MBGEN_SHARED_ROBOTS;
  add_loops("lola", source + "/robots/lola/lola.urdf", source + "/robots/lola/lola.yaml",
            {&lola_derivatives::forward_dynamics_derivatives, &lola::forward_dynamics, [](double* q) { lola::closure_positions(q); }});
  add_loops("cassie_like", shared + "/parallel_legs/cassie_like/robot.urdf", "",
            {&pl_cassie_like_derivatives::forward_dynamics_derivatives, &pl_cassie_like::forward_dynamics,
             [](double* q) { pl_cassie_like::closure_positions(q); }});
}

void add_derivative_benchmarks(const Robot& robot) {
  if (robot.name == "iiwa14") add(robot, MBGEN_DERIVATIVE_API(iiwa14));
  if (robot.name == "hyq") {
    add(robot, MBGEN_DERIVATIVE_API(hyq));
    add_compliant(robot);
    add_step_derivatives_hyq();
  }
  if (robot.name == "talos") {
    add(robot, MBGEN_DERIVATIVE_API(talos));
    add_contacts(robot, {"left_sole_link", "right_sole_link"});
    add_step_derivatives(robot);
  }
}

}  // namespace mbgen::bench
