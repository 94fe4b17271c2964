#pragma once
// One point of the study (docs/study.md): a scenario run with one backend, integrator and step,
// sampled at fixed times so that two runs compare sample by sample, and timed (the stepping
// alone, in CPU seconds).
#include <chrono>
#include <cmath>
#include <ctime>
#include <vector>

#include "examples/sim/run_scenario.hpp"

namespace mbgen::study {

/// What a run produced: q at t = k * sample_period (k = 0 .. as far as it got), its status and
/// cost.
struct Trajectory {
  std::vector<VecX<double>> q;
  sim::StepStatus status = sim::StepStatus::ok;
  double end_time = 0;
  double cpu_seconds = 0;          ///< process CPU time spent in the simulator's steps
  double energy_balance = 0;       ///< J at the end: energy - energy(0) - work of the forces
  sim::SimulationStatistics statistics;
  /// Ran to its end: ok, or continued through dead points (the continuation's spans).
  bool finished(double duration) const { return sim::advanced(status) && end_time >= duration - 1e-9; }
};

inline double cpu_now() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

/// Runs the scenario of `o` for `duration` s with `backend` (the controller on
/// `controller_backend`), sampling q every `sample_period` s.
template <typename Backend>
Trajectory run_trajectory(Backend backend, Backend controller_backend, const gen::Description& d, const simulate::ScenarioOptions& o,
                          double duration, double sample_period) {
  Trajectory out;
  sim::SimulatorOptions so = o.simulator;
  so.contact = o.scenario != simulate::Scenario::swing;
  sim::Simulator<Backend> sim(std::move(backend), so);
  if (!simulate::prepare_scenario(sim, std::move(controller_backend), d, o)) {
    out.status = sim::StepStatus::closure_lost;
    return out;
  }
  out.q.push_back(sim.q().template cast<double>());
  const long samples = std::lround(duration / sample_period);
  bool continued = false;
  for (long k = 1; k <= samples; ++k) {
    const double start = cpu_now();
    out.status = sim.run_until(static_cast<double>(k) * sample_period);
    out.cpu_seconds += cpu_now() - start;
    if (!sim::advanced(out.status)) break;
    continued = continued || out.status == sim::StepStatus::continued;
    out.q.push_back(sim.q().template cast<double>());
  }
  if (continued && out.status == sim::StepStatus::ok) out.status = sim::StepStatus::continued;
  out.end_time = sim.time();
  out.energy_balance = static_cast<double>(sim.energy_balance());
  out.statistics = sim.statistics();
  return out;
}

/// The largest deviation of one trajectory from another over their common samples: the base's
/// position (m) and orientation (rad, the angle between the two attitudes), and the joints (rad
/// or m, the largest over every tree joint, loops' dependent coordinates included).
struct Deviation {
  double base_position = 0, base_orientation = 0, joints = 0;
  int worst_joint_q = -1;  ///< the q index of the joint entry that deviated most (-1: none)
  double largest() const { return std::max({base_position, base_orientation, joints}); }
};

inline Deviation deviation(const Trajectory& a, const Trajectory& b, bool floating_base) {
  Deviation dev;
  const std::size_t n = std::min(a.q.size(), b.q.size());
  for (std::size_t k = 0; k < n; ++k) {
    const VecX<double>& p = a.q[k];
    const VecX<double>& r = b.q[k];
    int first_joint = 0;
    if (floating_base) {
      dev.base_position = std::max(dev.base_position, (p.head<3>() - r.head<3>()).norm());
      // Unit quaternions a rotation angle theta apart are 2 sin(theta / 4) apart (q or -q):
      // exact for small angles, where 2 acos(q . r) loses half the digits.
      const double chord = std::min((p.segment<4>(3) - r.segment<4>(3)).norm(), (p.segment<4>(3) + r.segment<4>(3)).norm());
      dev.base_orientation = std::max(dev.base_orientation, 4 * std::asin(std::min(1.0, chord / 2)));
      first_joint = 7;
    }
    if (p.size() > first_joint) {
      Eigen::Index worst = 0;
      const double d = (p.tail(p.size() - first_joint) - r.tail(r.size() - first_joint)).cwiseAbs().maxCoeff(&worst);
      if (d > dev.joints) dev.joints = d, dev.worst_joint_q = first_joint + static_cast<int>(worst);
    }
  }
  return dev;
}

}  // namespace mbgen::study
