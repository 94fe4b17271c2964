// One simulator step (bench/README.md): sim_step/<robot>/<backend>/<integrator>, Lola standing on
// its 12 foot spheres (every one pressing the ground, friction acting) under PD + gravity
// control at 1 kHz, h = 1e-4 s, the loops re-closed and the velocities projected after each
// step, the default energy check (every 10 steps) included: what a simulation pays per step.
// Backends: generated (lola::Backend), generic (the O(n) recursion interpreted), kkt and
// independent (the O(n^3) references). Compare with fd/lola/generated (one forward dynamics).
#include "bench_sim.hpp"

#include <algorithm>
#include <chrono>
#include <memory>
#include <vector>

#include "collision/contact_spheres.hpp"
#include "lola.hpp"
#include "mbgen/sim/pd_gravity.hpp"
#include "mbgen/sim/simulator.hpp"
#include "model/load_description.hpp"

namespace mbgen::bench {

namespace {

/// PD + gravity holding q_ref: a 40 Hz loop on each joint's apparent inertia, as mbgen_sim's.
template <typename Backend> sim::PdGravityController<Backend> controller(Backend backend, const VecX<double>& q_ref) {
  return sim::PdGravityController<Backend>::from_bandwidth(std::move(backend), q_ref, 40.0);
}

struct StandingLola {
  gen::Description description;
  std::vector<ContactSphere> spheres;
  VecX<double> q, v;  ///< settled: 0.5 s after being set down 0.3 mm deep
};

const StandingLola& standing_lola() {
  static const StandingLola lola = [] {
    StandingLola s;
    gen::LoadOptions options;
    options.extras_file = MBGEN_SOURCE_DIR "/robots/lola/lola.yaml";
    s.description = gen::load_description(MBGEN_SOURCE_DIR "/robots/lola/lola.urdf", options);
    s.spheres = gen::contact_spheres(s.description);
    s.q = s.description.assembly.q;
    VecX<double> p(3 * lola::num_contact_spheres), J(6 * lola::nv * lola::num_contact_spheres);
    lola::contact_points(s.q.data(), p.data(), J.data());
    double lowest = 1e9;
    for (int k = 0; k < lola::num_contact_spheres; ++k) lowest = std::min(lowest, p[3 * k + 2] - lola::contact_sphere_radius[k]);
    s.q[2] -= lowest + 3e-4;
    s.v = VecX<double>::Zero(lola::nv);
    sim::Simulator<lola::Backend> settle(lola::Backend{});
    settle.set_controller(controller(lola::Backend{}, s.q));
    settle.set_state(s.q.data(), s.v.data());
    if (settle.run_until(0.5) != sim::StepStatus::ok) throw std::runtime_error("bench: Lola does not settle");
    s.q = settle.q(), s.v = settle.v();
    return s;
  }();
  return lola;
}

template <typename Backend>
void add_step(const std::string& backend_name, sim::Integrator integrator, std::function<Backend()> make) {
  const std::string name = "sim_step/lola/" + backend_name + "/" + sim::to_string(integrator);
  benchmark::RegisterBenchmark(name.c_str(), [integrator, make](benchmark::State& state) {
    const StandingLola& s = standing_lola();
    sim::SimulatorOptions o;
    o.integrator = integrator;
    sim::Simulator<Backend> sim(make(), o);
    sim.set_controller(controller(make(), s.q));
    sim.set_state(s.q.data(), s.v.data());
    long steps = 0;
    for (auto _ : state) {
      // Back to the settled state every 1000 steps (0.1 s): the measured steps stay standing ones.
      if (++steps % 1000 == 0) {
        state.PauseTiming();
        sim.set_state(s.q.data(), s.v.data());
        state.ResumeTiming();
      }
      benchmark::DoNotOptimize(sim.step());
    }
    state.SetItemsProcessed(state.iterations());
  });
}

}  // namespace

/// One evaluation of the step's dynamics at the standing state: the generated
/// contact_accelerations (12 pressing spheres, the law, their wrenches as body forces of the
/// closed-system forward dynamics), to set against fd/lola/generated.
void add_contact_accelerations() {
  benchmark::RegisterBenchmark("contact_accelerations/lola/generated", [](benchmark::State& state) {
    const StandingLola& s = standing_lola();
    const lola::Backend backend;
    double ground[kGroundInputs], law[kLawInputs];
    ContactParameters p;
    p.stiffness = lola::contact_stiffness, p.damping = lola::contact_damping, p.friction = lola::contact_friction;
    p.stiction_velocity = lola::contact_stiction_velocity;
    contact_inputs(GroundPlane{}, p, ground, law);
    VecX<double> tau = VecX<double>::Zero(lola::nv), qdd(lola::nv), out(kContactOutputs * lola::num_contact_spheres);
    for (auto _ : state) {
      backend.accelerations_with_contact(s.q.data(), s.v.data(), tau.data(), ground, law, qdd.data(), out.data());
      benchmark::DoNotOptimize(qdd.data());
      benchmark::ClobberMemory();
    }
  });
}

/// The step's cost in forward dynamics calls, measured so that the VM's speed drifts cancel: blocks
/// of 50 generated forward_dynamics calls (at the standing state) and 10 RK4 steps alternate, and
/// the counter step_per_fd is the median over blocks of (step time) / (fd time), adjacent blocks
/// sharing the machine's speed of the moment. (Separate benchmarks of the same run are minutes
/// apart on this 2-core VM, whose speed changes by 2x in that time.)
void add_step_per_fd() {
  benchmark::RegisterBenchmark("sim_step_per_fd/lola/generated/rk4", [](benchmark::State& state) {
    const StandingLola& s = standing_lola();
    sim::Simulator<lola::Backend> sim(lola::Backend{});
    sim.set_controller(controller(lola::Backend{}, s.q));
    sim.set_state(s.q.data(), s.v.data());
    VecX<double> vy(lola::ny), tau = VecX<double>::Zero(lola::nv), qdd(lola::ny);
    lola::independent_velocities(s.v.data(), vy.data());
    std::vector<double> ratios;
    long blocks = 0;
    using Clock = std::chrono::steady_clock;
    for (auto _ : state) {
      if (++blocks % 100 == 0) {  // back to the settled state every 1000 steps, untimed
        state.PauseTiming();
        sim.set_state(s.q.data(), s.v.data());
        state.ResumeTiming();
      }
      const auto t0 = Clock::now();
      for (int k = 0; k < 50; ++k) {
        lola::forward_dynamics(s.q.data(), vy.data(), tau.data(), qdd.data());
        benchmark::DoNotOptimize(qdd.data());
        benchmark::ClobberMemory();
      }
      const auto t1 = Clock::now();
      for (int k = 0; k < 10; ++k) benchmark::DoNotOptimize(sim.step());
      const auto t2 = Clock::now();
      ratios.push_back(std::chrono::duration<double>(t2 - t1).count() / 10 / (std::chrono::duration<double>(t1 - t0).count() / 50));
    }
    std::nth_element(ratios.begin(), ratios.begin() + static_cast<long>(ratios.size() / 2), ratios.end());
    state.counters["step_per_fd"] = ratios.empty() ? 0.0 : ratios[ratios.size() / 2];
  });
}

void add_sim_benchmarks() {
  add_contact_accelerations();
  add_step_per_fd();
  const StandingLola& s = standing_lola();
  const Model* model = &s.description.model;
  const std::vector<ContactSphere>* spheres = &s.spheres;
  using sim::Integrator;
  for (Integrator i : {Integrator::explicit_euler, Integrator::symplectic_euler, Integrator::rk4, Integrator::dormand_prince45,
                       Integrator::linearly_implicit_euler})
    add_step<lola::Backend>("generated", i, [] { return lola::Backend{}; });
  for (Integrator i : {Integrator::rk4, Integrator::linearly_implicit_euler})
    add_step<sim::GenericBackend<double>>("generic", i, [model, spheres] { return sim::GenericBackend<double>(*model, *spheres); });
  add_step<sim::KktBackend<double>>("kkt", Integrator::rk4,
                                    [model, spheres] { return sim::KktBackend<double>(*model, {20, 20}, *spheres); });
  add_step<sim::IndependentBackend<double>>("independent", Integrator::rk4,
                                            [model, spheres] { return sim::IndependentBackend<double>(*model, *spheres); });
}

}  // namespace mbgen::bench
