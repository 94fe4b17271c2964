// The YAML extras file, mbgen's own schema (docs/extras.md): what URDF cannot say.
//   robot, base, snap_quarter_turns, closures, independent, assembly, drives, ssv, scene
// Also reads any extras file and tells the two schemas apart by their top-level keys.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "load/extras_support.hpp"
#include "load/load_error.hpp"
#include "load/name_match.hpp"

namespace mbgen::gen {

namespace {

using namespace yaml;

const std::vector<std::string> kMbgenKeys = {"assembly", "base", "closure_joints", "closures", "drives", "independent", "mimic", "robot", "scene", "snap_quarter_turns", "ssv"};
const std::vector<std::string> kParallelLegsKeys = {"closed_loop", "joint_name", "joint_type", "name_mot", "type"};
const std::vector<std::string> kClosureTypes = {"coupling", "prismatic", "revolute", "spherical", "universal", "weld"};
bool has_any(const YAML::Node& root, const std::vector<std::string>& keys) {
  return std::any_of(keys.begin(), keys.end(), [&](const std::string& k) { return static_cast<bool>(root[k]); });
}

/// A value from a fixed set, else a LoadError suggesting the closest.
std::string one_of(const std::string& file, const YAML::Node& node, const std::string& element,
                   const std::vector<std::string>& allowed) {
  const std::string value = to_string(file, node, element);
  if (std::find(allowed.begin(), allowed.end(), value) != allowed.end()) return value;
  const std::string hint = did_you_mean(value, allowed);
  fail(file, node, element, fmt::format("'{}' is not one of {}", value, fmt::join(allowed, ", ")),
       hint.empty() ? fmt::format("write one of {}", fmt::join(allowed, ", ")) : hint);
}

/// [[a, b], ...] of frame names, e.g. collision exclude lists.
std::vector<std::pair<std::string, std::string>> frame_pairs(const std::string& file, const YAML::Node& node,
                                                             const std::string& element, const Model& model) {
  require_sequence(file, node, element, "[[torso, pelvis]]");
  std::vector<std::pair<std::string, std::string>> pairs;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string item = fmt::format("{}[{}]", element, i);
    if (!node[i].IsSequence() || node[i].size() != 2) fail(file, node[i], item, "must be a pair of link names", "write e.g. [torso, pelvis]");
    resolve_frame(file, node[i][0], item, model);
    resolve_frame(file, node[i][1], item, model);
    pairs.emplace_back(node[i][0].Scalar(), node[i][1].Scalar());
  }
  return pairs;
}

/// `type: coupling`: q_child = ratio q_parent + offset, parent and child moving 1-DoF joints (a
/// gear pair or belt the URDF cannot say; docs/extras.md, "Coupled joints").
void read_coupling(const ExtrasFile& x, const YAML::Node& c, const std::string& element, Description& d, ClosureSpec& spec) {
  for (const char* key : {"axis", "parent_origin", "child_origin"})
    if (c[key]) fail(x.path, c[key], element + ": " + key, "does not apply to a coupling (it relates joint positions, not frames)",
                     "remove it");
  for (const char* side : {"parent", "child"}) {
    const JointIndex j = resolve_moving_joint(x.path, c[side], element + ": " + side, d.model);
    if (d.model.joint(j).nv != 1)
      fail(x.path, c[side], element + ": " + side, fmt::format("names '{}', a joint with {} coordinates", d.model.joint(j).name, d.model.joint(j).nv),
           "couple revolute, continuous or prismatic joints");
  }
  spec.resolved_a = moved_body_frame(d.model, spec.frame_a);
  spec.resolved_b = moved_body_frame(d.model, spec.frame_b);
  if (c["ratio"]) spec.ratio = to_number(x.path, c["ratio"], element + ": ratio");
  if (c["offset"]) spec.offset = to_number(x.path, c["offset"], element + ": offset");
  if (spec.ratio == 0)
    fail(x.path, c["ratio"], element + ": ratio", "is 0: the child would be held constant, not coupled",
         "give a non-zero ratio, or lock the joint (`scene: lock`)");
  spec.source_line = line_of(c);
  spec.source = fmt::format("{}:{}", x.path, spec.source_line);
  d.closures.push_back(spec);
}

void read_closures(const ExtrasFile& x, const YAML::Node& node, Description& d) {
  require_sequence(x.path, node, "closures", "[{name: rod, type: revolute, parent: crank, child: shank}]");
  std::set<std::string> names;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node& c = node[i];
    std::string element = fmt::format("closures[{}]", i);
    require_map(x.path, c, element, "{name: rod, type: revolute, parent: crank, child: shank, axis: [0, 1, 0]}");
    reject_unknown_keys(x.path, c, element,
                        {"axis", "child", "child_origin", "name", "offset", "parent", "parent_origin", "ratio", "type"});
    ClosureSpec spec;
    spec.name = c["name"] ? to_string(x.path, c["name"], element + ".name") : fmt::format("closure_{}", i + 1);
    element = fmt::format("closure '{}'", spec.name);
    if (!names.insert(spec.name).second)
      fail(x.path, c["name"], element, "is defined twice", "give each closure its own name");
    if (!c["type"]) fail(x.path, c, element, "has no type", fmt::format("add `type:` one of {}", fmt::join(kClosureTypes, ", ")));
    spec.type = one_of(x.path, c["type"], element + ": type", kClosureTypes);
    for (const char* side : {"parent", "child"})
      if (!c[side]) fail(x.path, c, element, fmt::format("has no {}", side), fmt::format("add `{}:` a link or joint name", side));
    spec.frame_a = to_string(x.path, c["parent"], element + ": parent");
    spec.frame_b = to_string(x.path, c["child"], element + ": child");
    if (spec.type == "coupling") {  // child = ratio parent + offset, both moving 1-DoF joints
      read_coupling(x, c, element, d, spec);
      continue;
    }
    for (const char* key : {"ratio", "offset"})
      if (c[key]) fail(x.path, c[key], element + ": " + key, "applies to a coupling", "remove it, or make the closure `type: coupling`");
    spec.resolved_a = resolve_frame(x.path, c["parent"], element + ": parent", d.model);
    spec.resolved_b = resolve_frame(x.path, c["child"], element + ": child", d.model);
    if (c["parent_origin"]) spec.X_AC = to_origin(x.path, c["parent_origin"], element + ": parent_origin");
    if (c["child_origin"]) spec.X_BC = to_origin(x.path, c["child_origin"], element + ": child_origin");
    if (c["axis"]) {
      spec.axis = to_vec3(x.path, c["axis"], element + ": axis");
      if (spec.axis.norm() < 1e-12) fail(x.path, c["axis"], element + ": axis", "is zero", "give a non-zero axis, e.g. [0, 1, 0]");
      spec.axis.normalize();
    }
    spec.source_line = line_of(c);
    spec.source = fmt::format("{}:{}", x.path, spec.source_line);
    d.closures.push_back(spec);
  }
}

void read_independent(const ExtrasFile& x, const YAML::Node& node, Description& d) {
  require_sequence(x.path, node, "independent", "[knee_motor, hip_motor]");
  for (std::size_t i = 0; i < node.size(); ++i) {
    resolve_moving_joint(x.path, node[i], fmt::format("independent[{}]", i), d.model);
    d.actuated_joints.push_back(node[i].Scalar());
  }
}

/// assembly: {joint: value}: where the loops' assembly starts (rad or m; joints not named at 0);
/// over an MJCF keyframe's values where both give a joint.
void read_assembly(const ExtrasFile& x, const YAML::Node& node, Description& d) {
  require_map(x.path, node, "assembly", "{knee: -0.8, ankle_pitch: 0.3}");
  for (const auto& entry : node) {
    const std::string element = fmt::format("assembly: {}", entry.first.Scalar());
    const JointIndex j = resolve_moving_joint(x.path, entry.first, element, d.model);
    if (d.model.joint(j).nq != 1)
      fail(x.path, entry.first, element, "is not a one-coordinate joint", "seed revolute and prismatic joints only");
    const double value = to_number(x.path, entry.second, element);
    if (!std::isfinite(value)) fail(x.path, entry.second, element, "is not finite", "give a number (rad or m)");
    d.assembly_seed[entry.first.Scalar()] = value;
  }
  const std::string here = fmt::format("{}:{}", x.path, line_of(node));
  d.assembly_seed_source = d.assembly_seed_source.empty() ? here : d.assembly_seed_source + " and " + here;
}

void read_drives(const ExtrasFile& x, const YAML::Node& node, Description& d) {
  require_sequence(x.path, node, "drives", "[{joint: hip_yaw_l, gear_ratio: 100, rotor_inertia: 1.2e-4, model: armature}]");
  std::set<std::string> seen;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YAML::Node& n = node[i];
    std::string element = fmt::format("drives[{}]", i);
    require_map(x.path, n, element, "{joint: hip_yaw_l, gear_ratio: 100, rotor_inertia: 1.2e-4, model: armature}");
    reject_unknown_keys(x.path, n, element, {"gear_ratio", "joint", "model", "rotor_inertia"});
    if (!n["joint"]) fail(x.path, n, element, "has no joint", "add `joint:` a moving joint's name");
    DriveSpec drive;
    const JointIndex joint = resolve_moving_joint(x.path, n["joint"], element + ": joint", d.model);
    drive.joint = n["joint"].Scalar();
    if (d.model.joint(joint).nv != 1)
      fail(x.path, n["joint"], element + ": joint", fmt::format("names '{}', a {} joint", drive.joint, to_string(d.model.joint(joint).type)),
           "a drive turns one revolute or prismatic joint");
    element = fmt::format("drive of joint '{}'", drive.joint);
    if (!seen.insert(drive.joint).second) fail(x.path, n, element, "is given twice", "keep one drive per joint");
    if (n["gear_ratio"]) drive.gear_ratio = to_number(x.path, n["gear_ratio"], element + ": gear_ratio");
    if (n["rotor_inertia"]) drive.rotor_inertia = to_number(x.path, n["rotor_inertia"], element + ": rotor_inertia");
    if (n["model"]) drive.model = one_of(x.path, n["model"], element + ": model", {"armature", "body"});
    if (drive.gear_ratio == 0)
      fail(x.path, n["gear_ratio"], element + ": gear_ratio", "is zero", "give the reduction, e.g. 100 (negative reverses the rotor)");
    if (drive.rotor_inertia < 0)
      fail(x.path, n["rotor_inertia"], element + ": rotor_inertia", "is negative", "give the rotor's inertia about its spin axis, >= 0 kg m^2");
    d.drives.push_back(drive);
  }
}

/// Puts the drives into the model (rotor.hpp): reflected inertia on the diagonal, or a rotor
/// body; `scene: rotors` overrides each drive's own `model`, and `rotors: none` leaves every rotor
/// out (a model reduction: the drives are not modelled). Drives sit on 1-DoF joints only
/// (resolve_moving_joint saw to that: floating joints are not named in extras).
void apply_drives(Description& d) {
  if (d.scene && d.scene->rotors == "none") {
    if (!d.drives.empty())
      d.reductions.push_back(fmt::format("rotors: none: the {} drive(s) not modelled (no armature, no rotor body)", d.drives.size()));
    return;
  }
  for (DriveSpec& drive : d.drives) {
    if (d.scene && !d.scene->rotors.empty()) drive.model = d.scene->rotors;
    Joint& joint = d.model.mutable_joint(*d.model.find_joint(drive.joint));
    if (drive.model == "body") {
      joint.rotor_gear_ratio = drive.gear_ratio;
      joint.rotor_inertia = drive.rotor_inertia;
    } else {
      joint.armature = drive.gear_ratio * drive.gear_ratio * drive.rotor_inertia;
    }
  }
}

SsvPrimitive read_primitive(const std::string& file, const YAML::Node& n, const std::string& element) {
  require_map(file, n, element, "{line: [[0, 0, 0.1], [0, 0, 0.5]], radius: 0.15}");
  reject_unknown_keys(file, n, element, {"line", "point", "radius", "triangle"});
  SsvPrimitive p;
  int kinds = 0;
  if (n["point"]) {
    ++kinds;
    p.kind = SsvPrimitive::Kind::Point;
    p.points = {to_vec3(file, n["point"], element + ": point")};
  }
  for (auto [key, kind, count] : {std::tuple{"line", SsvPrimitive::Kind::Line, 2}, std::tuple{"triangle", SsvPrimitive::Kind::Triangle, 3}}) {
    if (!n[key]) continue;
    ++kinds;
    const YAML::Node& pts = n[key];
    if (!pts.IsSequence() || static_cast<int>(pts.size()) != count)
      fail(file, pts, fmt::format("{}: {}", element, key), fmt::format("must be a list of {} points", count),
           count == 2 ? "write e.g. [[0, 0, 0.1], [0, 0, 0.5]]" : "write e.g. [[0, 0, 0], [0.1, 0, 0], [0, 0.1, 0]]");
    p.kind = kind;
    p.points.clear();
    for (int k = 0; k < count; ++k) p.points.push_back(to_vec3(file, pts[k], fmt::format("{}: {}", element, key)));
  }
  if (kinds != 1)
    fail(file, n, element, "must have exactly one of point, line, triangle", "write e.g. {point: [0, 0, 0], radius: 0.06}");
  if (!n["radius"]) fail(file, n, element, "has no radius", "add `radius:` in metres (0 for a bare point, segment or triangle)");
  p.radius = to_number(file, n["radius"], element + ": radius");
  if (p.radius < 0) fail(file, n["radius"], element + ": radius", "is negative", "give a radius >= 0 in metres");
  return p;
}

void read_ssv(const ExtrasFile& x, const YAML::Node& node, Description& d) {
  require_map(x.path, node, "ssv", "{torso: [{line: [[0, 0, 0.1], [0, 0, 0.5]], radius: 0.15}]}");
  for (const auto& entry : node) {
    const std::string link = entry.first.Scalar();
    const std::string element = fmt::format("ssv of '{}'", link);
    resolve_frame(x.path, entry.first, "ssv", d.model);
    require_sequence(x.path, entry.second, element, "[{point: [0, 0, 0], radius: 0.06}]");
    std::vector<SsvPrimitive>& compound = d.ssv[link];
    compound.clear();  // the extras' compound replaces what the URDF's <collision> elements gave
    d.ssv_from_extras.insert(link);
    for (std::size_t i = 0; i < entry.second.size(); ++i) {
      compound.push_back(read_primitive(x.path, entry.second[i], fmt::format("{}[{}]", element, i)));
      compound.back().source = fmt::format("{}:{}", x.path, line_of(entry.second[i]));
    }
  }
}

void read_outputs(const ExtrasFile& x, const YAML::Node& node, Description& d, SceneSpec& scene) {
  require_sequence(x.path, node, "scene: outputs", "[forward_dynamics, mass_matrix, jacobians: [foot_l]]");
  for (std::size_t i = 0; i < node.size(); ++i) {
    const std::string element = fmt::format("scene: outputs[{}]", i);
    const YAML::Node& n = node[i];
    if (n.IsMap()) {  // `jacobians: [frame, ...]`
      reject_unknown_keys(x.path, n, element, {"jacobians"});
      require_sequence(x.path, n["jacobians"], element + ": jacobians", "[foot_l, foot_r]");
      for (std::size_t k = 0; k < n["jacobians"].size(); ++k) {
        resolve_frame(x.path, n["jacobians"][k], element + ": jacobians", d.model);
        scene.jacobian_frames.push_back(n["jacobians"][k].Scalar());
      }
      scene.outputs.push_back("jacobians");
    } else {
      // The name is checked against the generator's catalogue of functions when they are
      // selected (codegen/scene_functions.cpp), with this line in the message.
      scene.outputs.push_back(to_string(x.path, n, element));
    }
    scene.output_lines.push_back(line_of(n));
  }
}

/// A number of the extras with its lower bound (> lowest when strict, else >=) and the fix to
/// print when it is out of range.
struct BoundedNumber {
  const char* key;
  double* value;
  double lowest;
  bool strict;
  const char* fix;
};

/// Reads each of `numbers` that `map` gives into its value, refusing one out of its range.
void read_bounded_numbers(const ExtrasFile& x, const YAML::Node& map, const std::string& element,
                          std::initializer_list<BoundedNumber> numbers) {
  for (const BoundedNumber& k : numbers) {
    if (!map[k.key]) continue;
    *k.value = to_number(x.path, map[k.key], element + ": " + k.key);
    if (k.strict ? !(*k.value > k.lowest) : !(*k.value >= k.lowest)) fail(x.path, map[k.key], element + ": " + k.key, "is out of range", k.fix);
  }
}

/// `scene: contact`: the links must exist and carry SSVs (their vertex spheres touch the ground).
ContactSpec read_contact(const ExtrasFile& x, const YAML::Node& c, const Description& d) {
  const std::string element = "scene: contact";
  require_map(x.path, c, element, "{links: [foot_l, foot_r], stiffness: 2e7, damping: 2, friction: 0.8}");
  reject_unknown_keys(x.path, c, element,
                      {"damping", "exponent", "friction", "ground", "links", "stiction_velocity", "stiffness"});
  ContactSpec contact;
  if (!c["links"]) fail(x.path, c, element, "has no links", "list the links that touch the ground, e.g. links: [foot_l, foot_r]");
  require_sequence(x.path, c["links"], element + ": links", "[foot_l, foot_r]");
  for (std::size_t i = 0; i < c["links"].size(); ++i) {
    const YAML::Node& n = c["links"][i];
    resolve_frame(x.path, n, element + ": links", d.model);
    const std::string link = n.Scalar();
    auto it = d.ssv.find(link);
    if (it == d.ssv.end() || it->second.empty())
      fail(x.path, n, element + ": links", fmt::format("'{}' has no swept-sphere volume to touch the ground with", link),
           fmt::format("give it one under `ssv:`, e.g. {}: [{{line: [[-0.05, 0, -0.05], [0.1, 0, -0.05]], radius: 0.02}}]", link));
    contact.links.push_back(link);
  }
  ContactParameters& p = contact.parameters;
  read_bounded_numbers(x, c, element,
                       {BoundedNumber{"stiffness", &p.stiffness, 0, true, "give k > 0 in N/m^exponent, e.g. 2e7"},
                        BoundedNumber{"damping", &p.damping, 0, false, "give d >= 0 in s/m, e.g. 2"},
                        BoundedNumber{"exponent", &p.exponent, 1, false, "give e >= 1: 1 is a linear spring, 1.5 Hertz's sphere"},
                        BoundedNumber{"friction", &p.friction, 0, false, "give mu >= 0, e.g. 0.8"},
                        BoundedNumber{"stiction_velocity", &p.stiction_velocity, 0, true, "give v_s > 0 in m/s, e.g. 1e-3"}});
  if (const YAML::Node& g = c["ground"]) {
    require_map(x.path, g, element + ": ground", "{normal: [0, 0, 1], offset: 0}");
    reject_unknown_keys(x.path, g, element + ": ground", {"normal", "offset"});
    if (g["normal"]) {
      const Vec3<double> n = to_vec3(x.path, g["normal"], element + ": ground: normal");
      if (!(n.norm() > 1e-9))
        fail(x.path, g["normal"], element + ": ground: normal", "is zero", "give the plane's upward normal, e.g. [0, 0, 1]");
      contact.ground.normal = n.normalized();
    }
    if (g["offset"]) contact.ground.offset = to_number(x.path, g["offset"], element + ": ground: offset");
  }
  return contact;
}

/// `scene: joint_limits`: false (no end stops in a simulation of the scene), true, or a map of the
/// stops' law and per-joint exceptions (JointStopParameters); each joint named must have a range.
JointStopParameters read_joint_limits(const ExtrasFile& x, const YAML::Node& node, const Description& d) {
  const std::string element = "scene: joint_limits";
  JointStopParameters p;
  if (node.IsScalar() && (node.Scalar() == "true" || node.Scalar() == "false")) {
    p.enabled = node.Scalar() == "true";
    return p;
  }
  require_map(x.path, node, element, "false, or {frequency: 100, damping: 3, free: [toe_l], joints: {knee_l: {stiffness: 2e4}}}");
  reject_unknown_keys(x.path, node, element, {"damping", "exponent", "free", "frequency", "joints", "max_damping_ratio"});
  read_bounded_numbers(x, node, element,
               {BoundedNumber{"frequency", &p.frequency, 0, true, "give f > 0 in Hz, e.g. 100 (each stop's default stiffness rings at f)"},
                BoundedNumber{"damping", &p.damping, 0, false, "give d >= 0 in s/rad, e.g. 3"},
                BoundedNumber{"exponent", &p.exponent, 1, false, "give e >= 1: 1 is a linear spring"},
                BoundedNumber{"max_damping_ratio", &p.max_damping_ratio, 0, false, "give zeta >= 0, e.g. 1 (0: Hunt-Crossley's damping uncapped)"}});
  // A joint named must have a range for its stop to act at.
  const auto limited_joint = [&](const YAML::Node& name, const std::string& where) {
    const Joint& joint = d.model.joint(resolve_moving_joint(x.path, name, where, d.model));
    if (!joint.bounded || joint.nv != 1 || !(joint.lower < joint.upper))
      fail(x.path, name, where, fmt::format("names '{}', which has no position range", joint.name),
           "name a revolute or prismatic joint with <limit lower upper> (its stop is where its range ends)");
    for (const JointStopSetting& s : p.joints)
      if (s.joint == joint.name) fail(x.path, name, where, fmt::format("names '{}' twice", joint.name), "keep one entry");
    return joint.name;
  };
  if (const YAML::Node& f = node["free"]) {
    require_sequence(x.path, f, element + ": free", "[toe_l, toe_r]");
    for (std::size_t i = 0; i < f.size(); ++i) {
      JointStopSetting s;
      s.joint = limited_joint(f[i], element + ": free");
      s.free = true;
      p.joints.push_back(s);
    }
  }
  if (const YAML::Node& j = node["joints"]) {
    require_map(x.path, j, element + ": joints", "{knee_l: {stiffness: 2e4, damping: 3}}");
    for (const auto& entry : j) {
      const std::string where = element + ": joints: " + entry.first.Scalar();
      JointStopSetting s;
      s.joint = limited_joint(entry.first, element + ": joints");
      require_map(x.path, entry.second, where, "{stiffness: 2e4, damping: 3}");
      reject_unknown_keys(x.path, entry.second, where, {"damping", "stiffness"});
      read_bounded_numbers(x, entry.second, where,
                   {BoundedNumber{"stiffness", &s.stiffness, 0, true, "give k > 0 in N m/rad (N/m for a prismatic joint)"},
                    BoundedNumber{"damping", &s.damping, 0, false, "give d >= 0 in s/rad"}});
      p.joints.push_back(s);
    }
  }
  return p;
}

/// `lock: [joint, ...]` (each at 0) or `lock: {joint: value, ...}`: moving 1-DoF joints, each
/// once, a finite value within the joint's limits.
void read_lock(const ExtrasFile& x, const YAML::Node& node, const Description& d, SceneSpec& scene) {
  if (!node.IsSequence() && !node.IsMap())
    fail(x.path, node, "scene: lock", "must be a list of joints or a map joint: value", "write e.g. [head_pan, head_tilt] or {elbow_l: -0.5}");
  scene.lock_line = line_of(node);
  std::set<std::string> seen;
  const auto add = [&](const YAML::Node& name, double value, const YAML::Node& where) {
    const std::string element = "scene: lock";
    const JointIndex j = resolve_moving_joint(x.path, name, element, d.model);
    const Joint& joint = d.model.joint(j);
    if (joint.nv != 1)
      fail(x.path, name, element, fmt::format("names '{}', a {} joint", joint.name, to_string(joint.type)),
           "lock revolute or prismatic joints (a floating base is fixed with `base: fixed`)");
    if (!seen.insert(joint.name).second) fail(x.path, name, element, fmt::format("names '{}' twice", joint.name), "keep one entry");
    if (!std::isfinite(value)) fail(x.path, where, element, fmt::format("gives '{}' a non-finite value", joint.name), "give a number");
    if (joint.bounded && (value < joint.lower || value > joint.upper))
      fail(x.path, where, element, fmt::format("locks '{}' at {:g}, outside its limits [{:g}, {:g}]", joint.name, value, joint.lower, joint.upper),
           "give a value within the joint's limits");
    scene.lock.emplace_back(joint.name, value);
  };
  if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i) add(node[i], 0.0, node[i]);
  } else {
    for (const auto& entry : node) add(entry.first, to_number(x.path, entry.second, "scene: lock: " + entry.first.Scalar()), entry.second);
  }
}

/// `rigid_contacts: [{frame: l_sole, kind: frame}, {frame: toe, kind: point}]` (kind: frame when
/// left out). Each frame a frame of the robot on a moving body, named once.
void read_rigid_contacts(const ExtrasFile& x, const YAML::Node& node, Description& d, SceneSpec& scene) {
  require_sequence(x.path, node, "scene: rigid_contacts", "[{frame: l_sole, kind: frame}, {frame: r_sole, kind: frame}]");
  if (node.size() == 0)
    fail(x.path, node, "scene: rigid_contacts", "is empty", "name the frames held, e.g. [{frame: l_sole}], or leave the key out");
  for (std::size_t k = 0; k < node.size(); ++k) {
    const std::string element = fmt::format("scene: rigid_contacts[{}]", k);
    const YAML::Node& n = node[k];
    require_map(x.path, n, element, "{frame: l_sole, kind: frame}");
    reject_unknown_keys(x.path, n, element, {"frame", "kind"});
    if (!n["frame"]) fail(x.path, n, element, "has no frame", "name the frame held: {frame: l_sole}");
    RigidContactSpec c;
    const FrameIndex f = resolve_frame(x.path, n["frame"], element + ": frame", d.model);
    c.frame = d.model.frame(f).name;  // a moving joint named: its child body's frame
    if (d.model.frame(f).body == kWorldBody)
      fail(x.path, n["frame"], element + ": frame", fmt::format("'{}' is fixed in the world", c.frame),
           "name a frame on a moving body (a foot's sole)");
    if (n["kind"]) c.kind = one_of(x.path, n["kind"], element + ": kind", {"frame", "point"});
    for (const RigidContactSpec& other : scene.rigid_contacts)
      if (other.frame == c.frame)
        fail(x.path, n["frame"], element + ": frame", fmt::format("names '{}' twice", c.frame),
             "hold each frame once (kind: frame holds its origin and its axes)");
    c.line = line_of(n);
    scene.rigid_contacts.push_back(c);
  }
}

void read_scene(const ExtrasFile& x, const YAML::Node& node, Description& d) {
  require_map(x.path, node, "scene", "{outputs: [forward_dynamics], scalar: double}");
  reject_unknown_keys(x.path, node, "scene",
                      {"collision", "contact", "derivatives_wrt", "joint_limits", "lock", "loops", "merge_below", "outputs",
                       "rigid_contacts", "rotors", "scalar"});
  SceneSpec scene;
  if (node["lock"]) read_lock(x, node["lock"], d, scene);
  if (node["merge_below"]) {
    scene.merge_below = to_number(x.path, node["merge_below"], "scene: merge_below");
    if (!(scene.merge_below >= 0))
      fail(x.path, node["merge_below"], "scene: merge_below", "is negative", "give a mass in kg, e.g. 0.5 (0: merge nothing)");
  }
  if (node["contact"]) scene.contact = read_contact(x, node["contact"], d);
  if (node["joint_limits"]) scene.joint_limits = read_joint_limits(x, node["joint_limits"], d);
  if (node["outputs"]) read_outputs(x, node["outputs"], d, scene);
  if (const YAML::Node& wrt = node["derivatives_wrt"]) {
    require_sequence(x.path, wrt, "scene: derivatives_wrt", "[q, tau]");
    if (wrt.size() == 0)
      fail(x.path, wrt, "scene: derivatives_wrt", "is empty",
           "name the inputs the derivatives are taken with respect to, e.g. [q, tau], or leave the key out for all of q, v, tau");
    for (std::size_t k = 0; k < wrt.size(); ++k) {
      const std::string input = one_of(x.path, wrt[k], "scene: derivatives_wrt", {"q", "v", "tau"});
      if (std::find(scene.derivatives_wrt.begin(), scene.derivatives_wrt.end(), input) != scene.derivatives_wrt.end())
        fail(x.path, wrt[k], "scene: derivatives_wrt", fmt::format("names {} twice", input), "name each input once");
      scene.derivatives_wrt.push_back(input);
    }
  }
  if (node["rigid_contacts"]) read_rigid_contacts(x, node["rigid_contacts"], d, scene);
  if (node["scalar"]) scene.scalar = one_of(x.path, node["scalar"], "scene: scalar", {"double", "float"});
  if (node["rotors"]) scene.rotors = one_of(x.path, node["rotors"], "scene: rotors", {"armature", "body", "none"});
  if (node["loops"]) {
    scene.loops = one_of(x.path, node["loops"], "scene: loops", {"exact", "transmission"});
    scene.loops_line = line_of(node["loops"]);
  }
  if (const YAML::Node& c = node["collision"]) {
    require_map(x.path, c, "scene: collision", "{margin: 0.05, exclude: [[torso, pelvis]]}");
    reject_unknown_keys(x.path, c, "scene: collision", {"exclude", "fit", "fit_budget", "include", "margin", "prune_samples"});
    if (c["fit"]) {
      if (!c["fit"].IsScalar() || (c["fit"].Scalar() != "true" && c["fit"].Scalar() != "false"))
        fail(x.path, c["fit"], "scene: collision: fit", "must be true or false", "write `fit: true` to fit SSVs to the links' meshes");
      scene.collision_fit = c["fit"].Scalar() == "true";
    }
    if (c["fit_budget"]) {
      const double n = to_number(x.path, c["fit_budget"], "scene: collision: fit_budget");
      if (!(n >= 1) || n != std::floor(n) || n > 64)
        fail(x.path, c["fit_budget"], "scene: collision: fit_budget", "must be a whole number from 1 to 64",
             "write e.g. `fit_budget: 4` (SSV primitives per link)");
      scene.collision_fit_budget = static_cast<int>(n);
    }
    if (c["margin"]) scene.collision_margin = to_number(x.path, c["margin"], "scene: collision: margin");
    if (scene.collision_margin < 0) fail(x.path, c["margin"], "scene: collision: margin", "is negative", "give a distance >= 0 in metres");
    if (c["exclude"]) scene.collision_exclude = frame_pairs(x.path, c["exclude"], "scene: collision: exclude", d.model);
    if (c["include"]) scene.collision_include = frame_pairs(x.path, c["include"], "scene: collision: include", d.model);
    if (c["prune_samples"]) {
      const double n = to_number(x.path, c["prune_samples"], "scene: collision: prune_samples");
      if (n < 0 || n != static_cast<int>(n))
        fail(x.path, c["prune_samples"], "scene: collision: prune_samples", "must be a whole number >= 0", "write e.g. 20000");
      scene.prune_samples = static_cast<int>(n);
    }
  }
  d.scene = scene;
}

}  // namespace

ExtrasFile read_extras(const std::string& path) {
  ExtrasFile x;
  x.path = path;
  try {
    x.root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw LoadError(path, 0, "", "cannot open the extras file", "check the path given to --extras");
  } catch (const YAML::Exception& e) {
    throw LoadError(path, e.mark.is_null() ? 0 : e.mark.line + 1, "", fmt::format("malformed YAML: {}", e.msg),
                    "repair the YAML (indentation, an unclosed bracket or quote, a missing ': ' are the usual causes)");
  }
  if (x.root.IsNull()) return x;  // an empty file says nothing
  require_map(path, x.root, "", "`base: floating` on its own line");
  const bool mbgen = has_any(x.root, kMbgenKeys), legs = has_any(x.root, kParallelLegsKeys);
  if (mbgen && legs)
    fail(path, x.root, "", "mixes the keys of the two schemas (robot/base/closures/... and closed_loop/type/name_mot/...)",
         "write one schema per file (see docs/extras.md)");
  x.schema = legs ? ExtrasFile::Schema::ParallelLegs : ExtrasFile::Schema::Mbgen;
  // Unknown keys are caught here, against the schema chosen (and suggested from both).
  const std::vector<std::string>& keys = legs ? kParallelLegsKeys : kMbgenKeys;
  std::set<std::string> seen;
  for (const auto& entry : x.root) {
    const std::string key = entry.first.Scalar();
    // yaml-cpp keeps one of two equal keys silently; a second `base:` is a mistake to report.
    if (!seen.insert(key).second)
      fail(path, entry.first, fmt::format("key '{}'", key), "is given twice", "keep one of them");
    if (std::find(keys.begin(), keys.end(), key) != keys.end()) continue;
    std::vector<std::string> all = kMbgenKeys;
    all.insert(all.end(), kParallelLegsKeys.begin(), kParallelLegsKeys.end());
    const std::string hint = did_you_mean(key, all);
    fail(path, entry.first, fmt::format("key '{}'", key), "is not a known top-level key",
         (hint.empty() ? "" : hint + " ") + fmt::format("(known keys: {})", fmt::join(keys, ", ")));
  }
  return x;
}

double extras_quarter_turns(const ExtrasFile& x, const std::string& description) {
  if (x.schema != ExtrasFile::Schema::Mbgen || x.root.IsNull() || !x.root["snap_quarter_turns"]) return 0;
  const YAML::Node n = x.root["snap_quarter_turns"];
  const DescriptionFormat format = description_format(description);
  if (format == DescriptionFormat::Sdf)
    fail(x.path, n, "snap_quarter_turns", "applies to a URDF's origins, and " + description + " is an SDFormat file",
         "remove it: libsdformat resolves the file's poses");
  if (format == DescriptionFormat::Mjcf)
    fail(x.path, n, "snap_quarter_turns", "applies to a URDF's origins, and " + description + " is an MJCF",
         "remove it: MJCF orientations snap entries within 1e-14 of 0 or +-1 (euler=\"0 0 90\" is exact)");
  const double tolerance = to_number(x.path, n, "snap_quarter_turns");
  // A rotation 1e-6 off a quarter turn is no decimal rounding of one: refuse to move the robot.
  if (!(tolerance >= 0 && tolerance <= 1e-6))
    fail(x.path, n, "snap_quarter_turns", fmt::format("{} is outside [0, 1e-6]", tolerance),
         "give the rounding of the URDF's quarter turns, e.g. 1e-9 for rpy written as 1.57079632679");
  return tolerance;
}

bool extras_couples_mimics(const ExtrasFile& x, const std::string& description) {
  if (x.schema != ExtrasFile::Schema::Mbgen || x.root.IsNull() || !x.root["mimic"]) return false;
  const YAML::Node n = x.root["mimic"];
  const DescriptionFormat format = description_format(description);
  if (format == DescriptionFormat::Sdf)
    fail(x.path, n, "mimic", "applies to a URDF's <mimic> elements, and " + description + " is an SDFormat file",
         "remove it: write a coupling as a `closures:` entry of type coupling");
  if (format == DescriptionFormat::Mjcf)
    fail(x.path, n, "mimic", "applies to a URDF's <mimic> elements, and " + description + " is an MJCF",
         "remove it: an MJCF couples joints with <equality><joint> or a fixed <tendon>, which are always read");
  return one_of(x.path, n, "mimic", {"couple", "independent"}) == "couple";
}

std::vector<std::string> extras_closure_joints(const ExtrasFile& x, const std::string& description) {
  if (x.schema != ExtrasFile::Schema::Mbgen || x.root.IsNull() || !x.root["closure_joints"]) return {};
  const YAML::Node n = x.root["closure_joints"];
  if (description_format(description) != DescriptionFormat::Sdf)
    fail(x.path, n, "closure_joints", "chooses the spanning tree of an SDFormat file, and " + description + " is not one",
         "remove it: give a URDF's loops as `closures:`, an MJCF's as <equality> elements");
  require_sequence(x.path, n, "closure_joints", "[left-pitch-rod-joint, right-pitch-rod-joint]");
  std::vector<std::string> names;
  for (std::size_t i = 0; i < n.size(); ++i) names.push_back(to_string(x.path, n[i], fmt::format("closure_joints[{}]", i)));
  return names;
}

std::optional<BaseType> extras_base(const ExtrasFile& x) {
  if (x.schema != ExtrasFile::Schema::Mbgen || x.root.IsNull() || !x.root["base"]) return std::nullopt;
  return one_of(x.path, x.root["base"], "base", {"fixed", "floating"}) == "floating" ? BaseType::Floating : BaseType::Fixed;
}

void apply_mbgen_extras(const ExtrasFile& x, Description& d) {
  if (x.root.IsNull()) return;
  try {
    const YAML::Node& root = x.root;
    if (root["robot"]) d.robot_name = to_string(x.path, root["robot"], "robot");
    if (root["closures"]) read_closures(x, root["closures"], d);
    if (root["independent"]) read_independent(x, root["independent"], d);
    if (root["assembly"]) read_assembly(x, root["assembly"], d);
    if (root["drives"]) read_drives(x, root["drives"], d);
    if (root["ssv"]) read_ssv(x, root["ssv"], d);
    if (root["scene"]) read_scene(x, root["scene"], d);
    apply_drives(d);
  } catch (const YAML::Exception& e) {  // what a typed read above missed
    throw LoadError(x.path, e.mark.is_null() ? 0 : e.mark.line + 1, "", fmt::format("unexpected YAML: {}", e.msg),
                    "compare with the schema in docs/extras.md");
  }
}

}  // namespace mbgen::gen
