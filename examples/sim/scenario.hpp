#pragma once
// The simulation scenarios of `mbgen_sim` (docs/simulation.md): what each one sets up, and the
// options the command line gives them.
#include <string>
#include <vector>

#include "load/description.hpp"
#include "mbgen/sim/simulator.hpp"

namespace mbgen::simulate {

enum class Scenario {
  drop,   ///< dropped from `height` above the ground, PD + gravity holding the start pose
  push,   ///< standing (settled for `settle` s), then pushed at the base by `impulse` N s along +x
  swing,  ///< a mechanism swinging freely from its assembled pose, no contact, no control
};

struct ScenarioOptions {
  Scenario scenario = Scenario::drop;
  std::string backend = "generated";  ///< generated, generic, kkt, independent
  sim::SimulatorOptions simulator;
  double duration = 2.0;     ///< s of simulated time (after settling, for push)
  double height = 0.05;      ///< m: drop height of the lowest contact sphere
  double impulse = 4.0;      ///< N s: push
  double push_time = 0.05;   ///< s: the push's duration (a constant force impulse / push_time)
  double settle = 1.0;       ///< s: push, standing time before the push
  double swing_speed = 3.0;  ///< rad/s (or m/s): swing, the independent coordinates' start velocity
  double bandwidth = 40;      ///< Hz: the PD gains' natural frequency per joint (kp = w^2 m, kd = 2 zeta w m)
  double damping_ratio = 1;   ///< zeta
  double baumgarte = 20;     ///< kkt backend: alpha = beta (1/s)
  double sample_period = 1e-3;  ///< s: CSV rows
  /// Stop a contact scenario when the CoM sinks below half its start height (when only the feet
  /// touch the ground the rest of the robot would sink through it); false: run to the end.
  bool stop_when_fallen = true;
  std::string csv;           ///< output file
  /// The poses and each contact sphere's normal force, one row per sample, for `mbgen view`
  /// (mbgen/sim/trajectory_csv.hpp); empty: not written.
  std::string poses_csv;
};

/// What a run ended with, for the summary line.
struct ScenarioResult {
  sim::StepStatus status = sim::StepStatus::ok;
  double end_time = 0;
  double cpu_seconds = 0;      ///< of the simulation itself (sampling excluded)
  sim::SimulationStatistics statistics;
  double max_closure_drift = 0;  ///< max |Phi| (m, rad) over the samples: the loops' violation
  double max_penetration = 0;    ///< m
  double final_energy_balance = 0;  ///< J
  double final_base_height = 0;     ///< m
  double final_normal_force = 0;    ///< N, summed over the contacts
  double final_com_height = 0;     ///< m
  bool fell = false;                ///< the CoM fell below half its start height: stopped there
  double start_com_height = 0;      ///< m
  double final_kinetic_energy = 0;  ///< J: near 0 when the robot lies at rest
  int stops = 0, stops_touched = 0; ///< end stops, and how many were ever entered
  std::string deepest_stop;         ///< the joint whose stop was entered deepest
  int closure_status = 0;           ///< the last closure_positions status (1 not converged, 2 singular)
  std::string closure_subsystem;    ///< the loop closures of the sub-system it failed in
  std::vector<sim::ContinuationSpan> spans;  ///< the continuation spans (--continue-through-dead-points)
  std::vector<std::string> subsystem_names;  ///< the backend's sub-systems' names, for the spans
};

/// The loop closures of the sub-system a span began in ("a diverged step" when it began so).
inline std::string span_subsystem(const sim::ContinuationSpan& span, const ScenarioResult& r) {
  if (span.subsystem < 0 || span.subsystem >= static_cast<int>(r.subsystem_names.size())) return "a diverged step";
  return r.subsystem_names[static_cast<std::size_t>(span.subsystem)];
}

}  // namespace mbgen::simulate
