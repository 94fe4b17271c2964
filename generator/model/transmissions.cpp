#include "model/transmissions.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <set>

#include "load/load_error.hpp"
#include "mbgen/algorithm/closure.hpp"
#include "model/topology.hpp"

namespace mbgen::gen {

namespace {

/// Bodies from b up to the cycle's root r (b included, r not).
std::vector<BodyIndex> path_below(const Model& m, BodyIndex b, BodyIndex r) {
  std::vector<BodyIndex> path;
  for (; b != r; b = m.body(b).parent) path.push_back(b);
  return path;
}

std::vector<std::string> joint_names(const Model& m, const std::set<int>& bodies) {
  std::vector<std::string> names;
  for (int b : bodies) names.push_back(m.joint(Model::joint_of(BodyIndex(b))).name);
  return names;
}

}  // namespace

std::map<std::string, double> plan_transmissions(Description& d) {
  const auto refuse = [&](const std::string& problem, const std::string& fix) -> LoadError {
    return LoadError(d.extras_file, d.scene->loops_line, "scene: loops: transmission", problem, fix);
  };
  // The exact loops as read, assembled and partitioned (the same stages load_description runs).
  const Description whole = build_topology(d);
  const Model& m = whole.model;
  std::map<std::string, double> weld;
  std::set<std::string> actuators, outputs, replaced;
  for (const SubSystem& sub : m.subsystems) {
    // Coupled joints (a gripper's mimic, a gear pair) are no linkage to replace: they stay loops
    // of the reduced model. Mixed into a linkage's loops they leave no clear actuator side.
    const auto coupling = [&](int c) { return m.closures[static_cast<std::size_t>(c)].type == ClosureType::Coupling; };
    if (std::all_of(sub.closures.begin(), sub.closures.end(), coupling)) continue;
    if (std::any_of(sub.closures.begin(), sub.closures.end(), coupling))
      throw refuse(fmt::format("the loops of closure '{}' mix joint couplings with a linkage: the transmission would weld "
                               "coupled joints",
                               m.closures[static_cast<std::size_t>(sub.closures[0])].name),
                   "keep `loops: exact` for this robot");
    std::set<int> independent;  // bodies whose joint is an independent coordinate of the exact model
    for (int v : sub.independent) independent.insert(m.joint_of_v(v).value());
    std::set<int> linkage, output;
    TransmissionSpec t;
    for (int c : sub.closures) {
      const LoopClosure& closure = m.closures[static_cast<std::size_t>(c)];
      t.closures.push_back(closure.name);
      const BodyIndex root = closure_top(m, closure);
      const std::vector<BodyIndex> a = path_below(m, closure.body_a, root), b = path_below(m, closure.body_b, root);
      const auto driven = [&](const std::vector<BodyIndex>& path) {
        return std::any_of(path.begin(), path.end(), [&](BodyIndex x) { return independent.count(x.value()) > 0; });
      };
      const bool driven_a = driven(a), driven_b = driven(b);
      if (driven_a == driven_b)
        throw refuse(fmt::format("loop '{}' has {} on both of its sides ({} and {}): a transmission needs the actuators on one "
                                 "side (the linkage) and the output joints on the other",
                                 closure.name, driven_a ? "independent coordinates" : "no independent coordinate",
                                 m.body(closure.body_a).name, m.body(closure.body_b).name),
                     "name the actuators of the loop in `independent:` (one side of each loop), or keep `loops: exact`");
      for (BodyIndex x : driven_a ? a : b) linkage.insert(x.value());
      for (BodyIndex x : driven_a ? b : a) output.insert(x.value());
    }
    for (int x : linkage) {
      if (output.count(x))
        throw refuse(fmt::format("body '{}' is on the actuator side of one loop and on the output side of another", m.body(BodyIndex(x)).name),
                     "keep `loops: exact` for this robot");
      for (BodyIndex child : m.body(BodyIndex(x)).children)
        if (!linkage.count(child.value()))
          throw refuse(fmt::format("the linkage body '{}' carries '{}', which is not part of the linkage: it cannot be lumped",
                                   m.body(BodyIndex(x)).name, m.body(child).name),
                       "keep `loops: exact` for this robot");
    }
    for (int x : independent) t.actuators.push_back(m.joint(Model::joint_of(BodyIndex(x))).name);
    t.outputs = joint_names(m, output);
    if (t.outputs.size() != t.actuators.size())
      throw refuse(fmt::format("the loops {} drive {} output joint(s) ({}) with {} actuator(s) ({}): a transmission maps as many of "
                               "each",
                               fmt::join(t.closures, ", "), t.outputs.size(), fmt::join(t.outputs, ", "), t.actuators.size(),
                               fmt::join(t.actuators, ", ")),
                   "keep `loops: exact` for this robot");
    double mass = 0;
    for (int x : linkage) {
      const Body& body = m.body(BodyIndex(x));
      t.linkage.push_back(body.name);
      mass += body.inertia.mass;
      const Joint& joint = m.joint(body.joint);
      if (joint.nv != 1)
        throw refuse(fmt::format("the linkage joint '{}' is {}: only 1-DoF joints can be welded", joint.name, to_string(joint.type)),
                     "keep `loops: exact` for this robot");
      weld.emplace(joint.name, whole.assembly.q[joint.idx_q]);
    }
    d.reductions.push_back(fmt::format("loops: transmission: {}: {} -> {}; linkage {} ({:.3g} kg) lumped into its parents",
                                       fmt::join(t.closures, ", "), fmt::join(t.actuators, ", "), fmt::join(t.outputs, ", "),
                                       fmt::join(t.linkage, ", "), mass));
    actuators.insert(t.actuators.begin(), t.actuators.end());
    outputs.insert(t.outputs.begin(), t.outputs.end());
    replaced.insert(t.closures.begin(), t.closures.end());
    d.transmissions.push_back(std::move(t));
  }
  if (d.transmissions.empty()) return weld;

  // The map's model: the same loops, the outputs as the hinted coordinates in place of the
  // actuators. The sub-systems must take them: outputs that do not determine the linkage (Phi_z
  // singular or ill-conditioned at every closed pose) cannot stand for it.
  std::vector<std::string> hints;
  for (const std::string& j : d.actuated_joints)
    if (!actuators.count(j)) hints.push_back(j);
  for (const TransmissionSpec& t : d.transmissions)
    for (const std::string& j : t.outputs)
      if (std::find(hints.begin(), hints.end(), j) == hints.end()) hints.push_back(j);
  Description mapped = d;
  mapped.actuated_joints = hints;
  mapped.reductions.clear();
  mapped.transmissions.clear();
  mapped = build_topology(std::move(mapped));
  std::set<std::string> mapped_independent;
  for (const SubSystem& sub : mapped.model.subsystems)
    for (int v : sub.independent) mapped_independent.insert(mapped.model.joint(mapped.model.joint_of_v(v)).name);
  for (const std::string& j : outputs)
    if (!mapped_independent.count(j))
      throw refuse(fmt::format("the output joint '{}' cannot be an independent coordinate of its loops (the loops' Jacobian in the "
                               "other coordinates is singular or ill-conditioned at the reference pose): it does not determine "
                               "the linkage",
                               j),
                   "keep `loops: exact` for this robot");
  d.transmission_model = mapped.model;
  d.actuated_joints = hints;
  d.closures.erase(std::remove_if(d.closures.begin(), d.closures.end(), [&](const ClosureSpec& c) { return replaced.count(c.name) > 0; }),
                   d.closures.end());
  return weld;
}

}  // namespace mbgen::gen
