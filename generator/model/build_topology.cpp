// Closures as given (ClosureSpec) as the Model's (LoopClosure), and the topology stage composed.
#include <fmt/format.h>

#include <cmath>
#include <utility>

#include "mbgen/algorithm/closure.hpp"
#include "load/load_error.hpp"
#include "model/topology.hpp"

namespace mbgen::gen {

namespace {

ClosureType closure_type(const Description& d, const ClosureSpec& spec) {
  if (spec.type == "weld" || spec.type == "6d") return ClosureType::Weld;
  if (spec.type == "spherical" || spec.type == "3d") return ClosureType::Point;
  if (spec.type == "revolute") return ClosureType::Revolute;
  if (spec.type == "prismatic") return ClosureType::Prismatic;
  if (spec.type == "universal") return ClosureType::Universal;
  if (spec.type == "coupling") return ClosureType::Coupling;
  throw LoadError(d.extras_file, spec.source_line, fmt::format("closure '{}'", spec.name),
                  fmt::format("has type '{}', which the loop builder does not know", spec.type),
                  "use revolute, prismatic, universal, spherical or weld (6d / 3d in robot.yaml)");
}

/// A coupling relates two 1-DoF joints with one position coordinate each, named as joints.
void check_coupling(const Description& d, const ClosureSpec& spec, const LoopClosure& c) {
  const Model& model = d.model;
  for (const auto& [name, body] : {std::pair{spec.frame_a, c.body_a}, std::pair{spec.frame_b, c.body_b}}) {
    const Joint& joint = model.joint(model.body(body).joint);
    if (joint.name != name || joint.nv != 1 || joint.nq != 1)
      throw LoadError(d.extras_file, spec.source_line, fmt::format("coupling '{}'", spec.name),
                      fmt::format("'{}' is not a moving 1-DoF joint of the tree (a coupling relates two joints' positions)", name),
                      "name a revolute or prismatic joint");
  }
  if (c.body_a == c.body_b)
    throw LoadError(d.extras_file, spec.source_line, fmt::format("coupling '{}'", spec.name),
                    fmt::format("couples '{}' to itself", spec.frame_a), "name two different joints");
  if (!(std::isfinite(spec.ratio) && std::isfinite(spec.offset)) || spec.ratio == 0)
    throw LoadError(d.extras_file, spec.source_line, fmt::format("coupling '{}'", spec.name),
                    fmt::format("has ratio {} and offset {}: the ratio must be finite and non-zero, the offset finite", spec.ratio,
                                spec.offset),
                    "a joint held at a constant value is a lock (scene: lock), not a coupling");
}

}  // namespace

std::vector<LoopClosure> closures_of(const Description& d) {
  const Model& model = d.model;
  std::vector<LoopClosure> closures;
  int offset = 0;
  for (const ClosureSpec& spec : d.closures) {
    LoopClosure c;
    c.name = spec.name;
    c.type = closure_type(d, spec);
    const Frame& fa = model.frame(spec.resolved_a);
    const Frame& fb = model.frame(spec.resolved_b);
    c.body_a = fa.body;
    c.body_b = fb.body;
    c.X_ACa = fa.X_BF * spec.X_AC;
    c.X_BCb = fb.X_BF * spec.X_BC;
    c.axis = spec.axis.normalized();
    c.axis_b = closure_axis_basis(c.axis).col(0);
    c.ratio = spec.ratio;
    c.offset = spec.offset;
    if (c.type == ClosureType::Coupling) check_coupling(d, spec, c);
    c.row_offset = offset;
    offset += c.rows();
    closures.push_back(c);
  }
  return closures;
}

std::vector<BodyIndex> cycle_path(const Model& model, const LoopClosure& closure) {
  const BodyIndex top = closure_top(model, closure);
  std::vector<BodyIndex> path, down;
  for (BodyIndex b = closure.body_a; b != top; b = model.body(b).parent) path.push_back(b);
  path.push_back(top);
  for (BodyIndex b = closure.body_b; b != top; b = model.body(b).parent) down.push_back(b);
  path.insert(path.end(), down.rbegin(), down.rend());
  return path;
}

Model spanning_tree(const Model& closed) {
  Model tree = closed;
  tree.closures.clear();
  tree.subsystems.clear();
  tree.update_structure();
  return tree;
}

std::string coordinate_name(const Model& model, int v_index) {
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    if (v_index < joint.idx_v || v_index >= joint.idx_v + joint.nv) continue;
    return joint.nv == 1 ? joint.name : fmt::format("{}[{}]", joint.name, v_index - joint.idx_v);
  }
  return fmt::format("v[{}]", v_index);
}

Description build_topology(Description d) {
  d.closed_dof = d.model.nv();
  if (d.closures.empty()) return d;
  d.model.closures = closures_of(d);
  d.model.update_structure();
  const Assembled assembled = assemble_closures(d);
  d.assembly = assembled.report;
  d.warnings.insert(d.warnings.end(), assembled.warnings.begin(), assembled.warnings.end());
  SubSystemChoice choice = choose_subsystems(d, d.assembly.q);
  d.model.subsystems = std::move(choice.subsystems);
  d.model.update_structure();
  d.warnings.insert(d.warnings.end(), choice.warnings.begin(), choice.warnings.end());
  d.closed_dof = d.model.nv() - choice.total_rank;
  return d;
}

}  // namespace mbgen::gen
