// URDF <mimic joint multiplier offset>: the joint carrying it follows the named one,
// q_follower = multiplier q_leader + offset. Pinocchio 3 models it as a joint without a
// coordinate of its own; here it is a coupling closure (loop_closure.hpp), one row through the
// loop machinery, so the follower is the dependent coordinate of a sub-system and the closed
// system has one degree of freedom fewer, the coupled inertia and forces entering through it.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "load/description.hpp"
#include "load/load_error.hpp"
#include "load/parse_urdf.hpp"

namespace mbgen::gen {

FrameIndex moved_body_frame(const Model& model, const std::string& joint_name) {
  const auto joint = model.find_joint(joint_name);
  if (!joint) return FrameIndex();
  const BodyIndex child = model.joint(*joint).child;
  for (int f = 0; f < model.num_frames(); ++f)
    if (model.frame(FrameIndex(f)).kind == FrameKind::Body && model.frame(FrameIndex(f)).body == child) return FrameIndex(f);
  return FrameIndex();
}

namespace {

/// The frame of the body that a moving 1-DoF joint moves (the closure's side), or an error
/// naming the <joint> that needs it.
FrameIndex checked_body_frame(const std::string& path, int line, const std::string& element, const Model& model,
                              const std::string& joint_name) {
  const auto joint = model.find_joint(joint_name);
  if (!joint)
    throw LoadError(path, line, element,
                    fmt::format("couples '{}', which is no moving joint of the tree (a fixed joint, or none)", joint_name),
                    "mimic a revolute, continuous or prismatic joint");
  if (model.joint(*joint).nv != 1)
    throw LoadError(path, line, element, fmt::format("couples '{}', a joint with {} coordinates", joint_name, model.joint(*joint).nv),
                    "mimic a revolute, continuous or prismatic joint");
  const FrameIndex frame = moved_body_frame(model, joint_name);
  if (!frame.valid()) throw LoadError(path, line, element, fmt::format("the body moved by '{}' has no frame", joint_name), "report this model");
  return frame;
}

}  // namespace

void add_urdf_mimics(const std::string& path, Description& d, bool couple) {
  const urdf::ModelInterfaceSharedPtr urdf = parse_urdf_file(path);
  // Document order (the joints' lines), so that the closures and their rows are deterministic.
  std::vector<std::pair<int, urdf::JointSharedPtr>> mimics;
  for (const auto& [name, joint] : urdf->joints_)
    if (joint->mimic) mimics.emplace_back(d.urdf_lines.line_of_joint(name), joint);
  std::sort(mimics.begin(), mimics.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [line, joint] : mimics) {
    if (!d.model.find_joint(joint->name)) {  // a fixed joint follows nothing: Pinocchio skips it too
      d.warnings.push_back(fmt::format("joint '{}' (line {}) is fixed: its <mimic> of '{}' couples nothing and is skipped",
                                       joint->name, line, joint->mimic->joint_name));
      continue;
    }
    if (!couple) {
      d.warnings.push_back(fmt::format("joint '{}' mimics '{}' (line {}): loaded as an independent joint, as Pinocchio's "
                                       "buildModel and MuJoCo's URDF import do by default; `mimic: couple` in the extras "
                                       "(or --mimic couple) makes it follow '{}' through a coupling",
                                       joint->name, joint->mimic->joint_name, line, joint->mimic->joint_name));
      continue;
    }
    const std::string element = fmt::format("joint '{}': <mimic joint=\"{}\">", joint->name, joint->mimic->joint_name);
    ClosureSpec c;
    c.name = fmt::format("mimic_{}", joint->name);
    c.type = "coupling";
    c.frame_a = joint->mimic->joint_name;
    c.frame_b = joint->name;
    c.ratio = joint->mimic->multiplier;
    c.offset = joint->mimic->offset;
    if (c.ratio == 0 || !std::isfinite(c.ratio) || !std::isfinite(c.offset))
      throw LoadError(path, line, element, fmt::format("has multiplier {} and offset {}", c.ratio, c.offset),
                      "give a finite, non-zero multiplier (a joint held at a constant value is a fixed joint)");
    if (c.frame_a == c.frame_b) throw LoadError(path, line, element, "mimics itself", "name another joint");
    c.resolved_a = checked_body_frame(path, line, element, d.model, c.frame_a);
    c.resolved_b = checked_body_frame(path, line, element, d.model, c.frame_b);
    c.source_line = line;
    c.source = fmt::format("{}:{}: <mimic>", path, line);
    d.closures.push_back(c);
  }
}

}  // namespace mbgen::gen
