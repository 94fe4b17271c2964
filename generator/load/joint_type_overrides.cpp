// parallel_legs joint_type overrides made real: a revolute joint that stands for a ball
// (SPHERICAL) or universal (UJOINT_XY) joint becomes a chain of revolute joints with massless
// links between them. The Model is rebuilt because bodies are numbered parents first.
#include <fmt/format.h>

#include "load/joint_type_overrides.hpp"

namespace mbgen::gen {

namespace {

/// Axes (of the joint frame) of the chain standing for a joint type, in order.
std::vector<int> chain_axes(const std::string& type) {
  return type == "SPHERICAL" ? std::vector<int>{0, 1, 2} : std::vector<int>{0, 1};
}

const char* kAxisName[3] = {"x", "y", "z"};

Joint chain_joint(const Joint& original, int axis, bool first) {
  Joint j;
  j.name = fmt::format("{}_{}", original.name, kAxisName[axis]);
  j.type = JointType::Revolute;
  j.axis = Vec3<double>::Unit(axis);
  j.X_PJ = first ? original.X_PJ : SE3<double>::Identity();
  j.bounded = false;  // a ball or cardan joint's limits are not those of the revolute it replaces
  j.velocity_limit = original.velocity_limit;
  j.effort_limit = original.effort_limit;
  return j;
}

}  // namespace

void apply_joint_type_overrides(Description& d) {
  if (d.joint_type_overrides.empty()) return;
  const Model& old = d.model;
  Model rebuilt;
  rebuilt.name = old.name;
  rebuilt.gravity = old.gravity;
  std::vector<BodyIndex> new_index(old.num_bodies(), kWorldBody);
  std::vector<Frame> added_frames;
  for (int k = 1; k < old.num_bodies(); ++k) {
    const Body& body = old.body(BodyIndex(k));
    const Joint& joint = old.joint(body.joint);
    BodyIndex parent = new_index[body.parent.value()];
    auto it = d.joint_type_overrides.find(joint.name);
    if (it == d.joint_type_overrides.end()) {
      new_index[k] = rebuilt.add_body(parent, joint, body.name, body.inertia);
      continue;
    }
    const std::vector<int> axes = chain_axes(it->second);
    for (std::size_t i = 0; i + 1 < axes.size(); ++i) {
      const std::string link = fmt::format("{}_{}_link", joint.name, kAxisName[axes[i]]);
      parent = rebuilt.add_body(parent, chain_joint(joint, axes[i], i == 0), link, Inertia<double>{});
      added_frames.push_back(Frame{link, FrameKind::Body, parent, SE3<double>::Identity()});
    }
    new_index[k] = rebuilt.add_body(parent, chain_joint(joint, axes.back(), false), body.name, body.inertia);
  }
  for (int f = 0; f < old.num_frames(); ++f) {
    Frame frame = old.frame(FrameIndex(f));
    frame.body = new_index[frame.body.value()];
    rebuilt.add_frame(frame);
  }
  for (Frame& frame : added_frames) rebuilt.add_frame(frame);
  d.model = std::move(rebuilt);
}

}  // namespace mbgen::gen
