// The closed-loop convention of shared/robots/parallel_legs (a robot.yaml beside the URDF):
//   closed_loop: [[A, B], ...]   frame pairs that must coincide (link names, or joint names:
//                                a moving joint's child frame)
//   type: [6d | 3d, ...]         one per pair, either case: pose or position constraint
//   name_mot: [joint, ...]       actuated joints
//   joint_name / joint_type      URDF revolute joints standing for SPHERICAL or UJOINT_XY joints
// Users already have models in this form, so it is read as is (see docs/extras.md).
#include <fmt/format.h>

#include <algorithm>
#include <cctype>

#include "load/extras_support.hpp"
#include "load/load_error.hpp"
#include "load/name_match.hpp"

namespace mbgen::gen {

namespace {

using namespace yaml;

const std::vector<std::string> kJointTypes = {"SPHERICAL", "UJOINT_XY"};

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}
std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

void read_closed_loops(const ExtrasFile& x, Description& d) {
  const YAML::Node& loops = x.root["closed_loop"];
  const YAML::Node& types = x.root["type"];
  if (!loops) {
    if (types) fail(x.path, types, "type", "is given without closed_loop", "add `closed_loop: [[A, B], ...]` or remove `type`");
    return;
  }
  require_sequence(x.path, loops, "closed_loop", "[[closedloop1_A, closedloop1_B]]");
  if (!types)
    fail(x.path, loops, "closed_loop", "has no `type` list", fmt::format("add `type:` with one of 6d or 3d per pair ({} pairs)", loops.size()));
  require_sequence(x.path, types, "type", "['6d', '3d']");
  if (types.size() != loops.size())
    fail(x.path, types, "type", fmt::format("has {} entries for {} closed_loop pairs", types.size(), loops.size()),
         "give one type (6d or 3d) per pair, in the same order");
  for (std::size_t i = 0; i < loops.size(); ++i) {
    const YAML::Node& pair = loops[i];
    const std::string element = fmt::format("closed_loop[{}]", i);
    if (!pair.IsSequence() || pair.size() != 2)
      fail(x.path, pair, element, "must be a pair of frame names", "write e.g. [closedloop1_A, closedloop1_B]");
    ClosureSpec spec;
    spec.name = fmt::format("closed_loop_{}", i + 1);
    spec.type = lower(to_string(x.path, types[i], fmt::format("type[{}]", i)));
    if (spec.type != "6d" && spec.type != "3d")
      fail(x.path, types[i], fmt::format("type[{}]", i), fmt::format("'{}' is not 6d or 3d", types[i].Scalar()),
           "write 6d (the two frames coincide) or 3d (their origins coincide)");
    spec.frame_a = to_string(x.path, pair[0], element);
    spec.frame_b = to_string(x.path, pair[1], element);
    // Unknown frame names are errors: a closure on a guessed frame would be silently wrong.
    spec.resolved_a = resolve_frame(x.path, pair[0], element, d.model);
    spec.resolved_b = resolve_frame(x.path, pair[1], element, d.model);
    spec.source_line = line_of(pair);
    spec.source = fmt::format("{}:{}", x.path, spec.source_line);
    d.closures.push_back(spec);
  }
}

void read_motors(const ExtrasFile& x, Description& d) {
  const YAML::Node& motors = x.root["name_mot"];
  if (!motors) return;
  require_sequence(x.path, motors, "name_mot", "[mot1, mot2]");
  for (std::size_t i = 0; i < motors.size(); ++i) {
    resolve_moving_joint(x.path, motors[i], fmt::format("name_mot[{}]", i), d.model);
    d.actuated_joints.push_back(motors[i].Scalar());
  }
}

void read_joint_types(const ExtrasFile& x, Description& d) {
  const YAML::Node& names = x.root["joint_name"];
  const YAML::Node& types = x.root["joint_type"];
  if (!names && !types) return;
  if (!names || !types)
    fail(x.path, names ? names : types, names ? "joint_name" : "joint_type", "is given without its partner list",
         "give joint_name and joint_type together, one type per joint");
  require_sequence(x.path, names, "joint_name", "[spherical_free_hip]");
  require_sequence(x.path, types, "joint_type", "[SPHERICAL]");
  if (names.size() != types.size())
    fail(x.path, types, "joint_type", fmt::format("has {} entries for {} joint_name entries", types.size(), names.size()),
         "give one joint_type per joint_name, in the same order");
  const std::vector<std::string> joints = moving_joint_names(d.model);
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string element = fmt::format("joint_name[{}]", i);
    const std::string type = upper(to_string(x.path, types[i], fmt::format("joint_type[{}]", i)));
    if (std::find(kJointTypes.begin(), kJointTypes.end(), type) == kJointTypes.end())
      fail(x.path, types[i], fmt::format("joint_type[{}]", i), fmt::format("'{}' is not a known joint type", types[i].Scalar()),
           "write SPHERICAL or UJOINT_XY");
    const std::string name = to_string(x.path, names[i], element);
    auto joint = d.model.find_joint(name);
    if (!joint) {
      // An error: the override changes the mechanism (a ball instead of a hinge), so skipping it
      // would load another robot. disney_robot ships with such a misspelling (LOOPS.md).
      const std::string hint = did_you_mean(name, joints);
      fail(x.path, names[i], element,
           fmt::format("names '{}', which is no moving joint of the URDF, so its joint_type {} cannot be applied", name, type),
           hint.empty() ? "name a revolute joint of the URDF" : hint + " (correct the name in joint_name)");
    }
    if (d.model.joint(*joint).type != JointType::Revolute)
      fail(x.path, names[i], element, fmt::format("names '{}', which is not a revolute joint", name),
           "joint_type replaces a revolute joint of the URDF; name one");
    d.joint_type_overrides[name] = type;
  }
}

}  // namespace

void apply_parallel_legs(const ExtrasFile& x, Description& d) {
  try {
    read_closed_loops(x, d);
    read_motors(x, d);
    read_joint_types(x, d);
  } catch (const YAML::Exception& e) {
    throw LoadError(x.path, e.mark.is_null() ? 0 : e.mark.line + 1, "", fmt::format("unexpected YAML: {}", e.msg),
                    "compare with the parallel_legs schema in docs/extras.md");
  }
}

}  // namespace mbgen::gen
