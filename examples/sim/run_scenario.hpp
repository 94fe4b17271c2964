#pragma once
// Runs one scenario with any backend and writes its trajectory as CSV (one row per sample): the
// same code path for the generated and the runtime backends.
#include <fmt/format.h>
#include <fmt/os.h>

#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "examples/sim/scenario.hpp"
#include "mbgen/algorithm/closure.hpp"
#include "mbgen/algorithm/configuration.hpp"
#include "mbgen/sim/pd_gravity.hpp"
#include "mbgen/sim/trajectory_csv.hpp"

namespace mbgen::simulate {

/// The scenario's start state: the description's assembled (closed) pose, or its neutral one;
/// for contact scenarios lowered or raised so that the lowest contact sphere is `height` above
/// the ground.
template <typename Backend>
VecX<typename Backend::Scalar> start_pose(Backend& backend, const gen::Description& d, double height) {
  using S = typename Backend::Scalar;
  VecX<S> q = d.assembly.q.size() ? d.assembly.q.cast<S>().eval() : mbgen::neutral_configuration<double>(d.model).cast<S>().eval();
  const int nc = backend.num_contacts();
  if (nc == 0 || !backend.floating_base()) return q;
  VecX<S> p(3 * nc), J(6 * backend.nv() * nc);
  backend.contact_points(q.data(), p.data(), J.data());
  S lowest = S(1e9);
  for (int k = 0; k < nc; ++k) lowest = std::min(lowest, p[3 * k + 2] - S(backend.contact_radius(k)));
  q[2] += S(height) - lowest;
  return q;
}

/// The loops' violation at q: max |Phi| over the sub-systems' kept rows (m, rad), by the generic
/// runtime in double whatever the backend (an independent check of a closed state); 0 without
/// loops.
inline double loop_violation(const Model& model, Data<double>& data, const VecX<double>& q) {
  if (model.closures.empty()) return 0;
  closure_residual<double>(model, data, q);
  double worst = 0;
  for (const SubSystem& sub : model.subsystems)
    for (int row : sub.rows) worst = std::max(worst, std::abs(data.Phi[row]));
  return worst;
}

/// Puts the scenario on `sim`: its start state (closed, projected) and, but for the swing, the
/// PD + gravity controller holding the start pose (on controller_backend), with the push's force
/// for the push. False if the start pose does not close. mbgen_sim and mbgen_study share it, so
/// that both run the same scenario.
template <typename Backend>
bool prepare_scenario(sim::Simulator<Backend>& sim, Backend controller_backend, const gen::Description& d, const ScenarioOptions& o) {
  using S = typename Backend::Scalar;
  Backend& b = sim.backend();
  const bool contact = o.scenario != Scenario::swing;
  const VecX<S> q0 = start_pose(b, d, contact ? o.height : 0.0);
  VecX<S> v0 = VecX<S>::Zero(b.nv());
  if (o.scenario == Scenario::swing) {
    VecX<S> vy = VecX<S>::Constant(b.ny(), S(o.swing_speed));
    b.full_velocities(q0.data(), vy.data(), v0.data());
  }
  if (sim.set_state(q0.data(), v0.data()) != 0) return false;
  // Control: PD + gravity on the actuated joints, holding the start pose (none for the swing);
  // the push adds a constant force on the base during push_time (its wrench entries of tau are in
  // base coordinates: the world force rotated into them).
  const double push_start = o.settle, push_end = o.settle + o.push_time;
  if (o.scenario != Scenario::swing) {
    // Gains of a o.bandwidth loop on each joint's apparent inertia (pd_gravity.hpp says why).
    auto pd = sim::PdGravityController<Backend>::from_bandwidth(std::move(controller_backend), q0, o.bandwidth, o.damping_ratio);
    const bool push = o.scenario == Scenario::push;
    const double force = o.impulse / o.push_time;
    sim.set_controller([pd, push, push_start, push_end, force](double t, const S* q, const S* v, S* tau) mutable {
      pd(t, q, v, tau);
      if (push && t >= push_start && t < push_end) {
        const S x = q[3], y = q[4], z = q[5], w = q[6];
        // R^T e_x: the world x axis in base coordinates (first row of R).
        tau[0] += S(force) * (S(1) - S(2) * (y * y + z * z));
        tau[1] += S(force) * S(2) * (x * y - z * w);
        tau[2] += S(force) * S(2) * (x * z + y * w);
      }
    });
  }
  return true;
}

template <typename Backend>
ScenarioResult run_scenario(Backend backend, Backend controller_backend, const gen::Description& d, const ScenarioOptions& o) {
  using S = typename Backend::Scalar;
  ScenarioResult result;
  const bool contact = o.scenario != Scenario::swing;
  sim::SimulatorOptions so = o.simulator;
  so.contact = contact;
  sim::Simulator<Backend> sim(std::move(backend), so);
  Backend& b = sim.backend();
  if (!prepare_scenario(sim, std::move(controller_backend), d, o)) {
    result.status = sim::StepStatus::closure_lost;
    return result;
  }

  // Contact links: the spheres are named link/ssv/vertex; one force column per link.
  std::vector<std::string> links;
  std::vector<int> link_of;
  for (int k = 0; k < b.num_contacts(); ++k) {
    std::string name = b.contact_name(k);
    name = name.substr(0, name.find('/'));
    auto it = std::find(links.begin(), links.end(), name);
    if (it == links.end()) links.push_back(name), it = links.end() - 1;
    link_of.push_back(static_cast<int>(it - links.begin()));
  }
  auto out = fmt::output_file(o.csv);
  out.print("t,base_x,base_y,base_z,com_x,com_y,com_z,energy,energy_balance,max_penetration,normal_force,closure_residual,weight,"
            "stop_penetration");
  for (const std::string& l : links) out.print(",force_{}", l);
  out.print("\n");
  std::vector<double> link_force(links.size());
  std::vector<std::string> sphere_names;
  for (int k = 0; k < b.num_contacts(); ++k) sphere_names.push_back(b.contact_name(k));
  std::unique_ptr<sim::TrajectoryCsvWriter> poses;
  if (!o.poses_csv.empty()) poses = std::make_unique<sim::TrajectoryCsvWriter>(o.poses_csv, d.model, contact ? sphere_names : std::vector<std::string>{});
  std::vector<double> q_row(static_cast<std::size_t>(d.model.nq())), sphere_force(sphere_names.size());
  Data<double> check(d.model);
  const double weight = d.model.total_mass() * d.model.gravity.norm();
  const double total = o.scenario == Scenario::push ? o.settle + o.duration : o.duration;
  const auto sample = [&] {
    const VecX<S>& q = sim.q();
    S com[3];
    b.center_of_mass(q.data(), com);
    double normal = 0, penetration = 0;
    std::fill(link_force.begin(), link_force.end(), 0.0);
    if (contact) {
      const auto& reports = sim.contacts();
      for (std::size_t k = 0; k < reports.size(); ++k) {
        normal += double(reports[k].normal_force);
        link_force[static_cast<std::size_t>(link_of[k])] += double(reports[k].normal_force);
        penetration = std::max(penetration, double(reports[k].penetration));
      }
    }
    const double drift = loop_violation(d.model, check, q.template cast<double>());
    result.max_closure_drift = std::max(result.max_closure_drift, drift);
    result.max_penetration = std::max(result.max_penetration, penetration);
    const bool floating = b.floating_base();
    double stop_penetration = 0;  // the deepest stop now
    for (const auto& r : sim.joint_stops()) stop_penetration = std::max(stop_penetration, double(r.penetration));
    out.print("{:.6f},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.6g},{:.9g},{:.3g},{:.6g},{:.6g}", sim.time(),
              floating ? double(q[0]) : 0.0, floating ? double(q[1]) : 0.0, floating ? double(q[2]) : 0.0, double(com[0]),
              double(com[1]), double(com[2]), double(sim.energy()), double(sim.energy_balance()), penetration, normal, drift, weight,
              stop_penetration);
    for (double f : link_force) out.print(",{:.6g}", f);
    out.print("\n");
    if (poses) {
      for (std::size_t i = 0; i < q_row.size(); ++i) q_row[i] = double(q[static_cast<int>(i)]);
      if (contact)
        for (std::size_t k = 0; k < sphere_force.size(); ++k) sphere_force[k] = double(sim.contacts()[k].normal_force);
      poses->write(double(sim.time()), q_row.data(), sphere_force.data());
    }
    result.final_energy_balance = double(sim.energy_balance());
    result.final_base_height = floating ? double(q[2]) : 0.0;
    result.final_normal_force = normal;
    result.final_com_height = double(com[2]);
  };
  sample();
  const double com_start = result.final_com_height;
  result.start_com_height = com_start;
  double cpu = 0;
  for (long k = 1;; ++k) {
    const double t_next = std::min(total, k * o.sample_period);
    const auto start = std::chrono::steady_clock::now();
    result.status = sim.run_until(t_next);
    cpu += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    sample();
    if (!sim::advanced(result.status) || t_next >= total) break;
    // A fall ends the scenario: the CoM below half its start height (only the contact links
    // touch the ground; the rest of the robot would sink through it).
    if (o.stop_when_fallen && contact && b.floating_base() && result.final_com_height < 0.5 * com_start) {
      result.fell = true;
      break;
    }
  }
  result.end_time = sim.time();
  result.cpu_seconds = cpu;
  {  // kinetic energy 1/2 v' M v, and the stops' record
    VecX<S> M(b.nv() * b.nv());
    b.mass_matrix(sim.q().data(), M.data());
    const Eigen::Map<const Eigen::Matrix<S, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> Mm(M.data(), b.nv(), b.nv());
    result.final_kinetic_energy = double(S(0.5) * sim.v().dot(Mm * sim.v()));
    double deepest = 0;
    for (const auto& r : sim.joint_stops()) {
      ++result.stops;
      if (r.time_active > 0 || r.max_penetration > S(0)) ++result.stops_touched;
      if (double(r.max_penetration) > deepest) deepest = double(r.max_penetration), result.deepest_stop = r.joint;
    }
  }
  result.statistics = sim.statistics();
  result.closure_status = sim.closure_status();
  if (sim.closure_subsystem() >= 0) result.closure_subsystem = sim.backend().subsystem_name(sim.closure_subsystem());
  result.spans = sim.continuation_spans();
  for (const sim::ContinuationSpan& span : result.spans)
    while (span.subsystem >= static_cast<int>(result.subsystem_names.size()))
      result.subsystem_names.push_back(sim.backend().subsystem_name(static_cast<int>(result.subsystem_names.size())));
  // The run's status: continued if any span was soft, though the last chunk ended exact.
  if (result.status == sim::StepStatus::ok && result.statistics.continuation_spans > 0) result.status = sim::StepStatus::continued;
  return result;
}

}  // namespace mbgen::simulate
