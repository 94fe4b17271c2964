// Typed YAML reads with 1-based line numbers, and name resolution with suggestions.
#include "load/extras_support.hpp"

#include <Eigen/Geometry>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "load/load_error.hpp"
#include "load/name_match.hpp"
#include "load/parse_numbers.hpp"

namespace mbgen::gen {

namespace {
/// A plain number (parse_numbers): yaml-cpp would also read "1e", "0x10" or ".nan".
bool parse_number(const std::string& text, double& value) {
  const ParsedNumbers parsed = parse_numbers(text);
  if (!parsed.problem.empty() || parsed.values.size() != 1) return false;
  value = parsed.values[0];
  return true;
}

std::string with_suggestion(const std::string& fix, const std::string& suggestion) {
  return suggestion.empty() ? fix : fmt::format("{} ({})", suggestion, fix);
}
}  // namespace

namespace yaml {

int line_of(const YAML::Node& node) {
  if (!node.IsDefined()) return 0;
  const YAML::Mark mark = node.Mark();
  return mark.is_null() ? 0 : mark.line + 1;  // yaml-cpp counts lines from 0
}

void fail(const std::string& file, const YAML::Node& node, const std::string& element, const std::string& problem,
          const std::string& fix) {
  throw LoadError(file, line_of(node), element, problem, fix);
}

std::string to_string(const std::string& file, const YAML::Node& node, const std::string& element) {
  if (!node.IsDefined() || node.IsNull()) fail(file, node, element, "is missing", "give a name");
  if (!node.IsScalar()) fail(file, node, element, "must be a single name, not a list or map", "write e.g. `name: knee`");
  return node.Scalar();
}

double to_number(const std::string& file, const YAML::Node& node, const std::string& element) {
  double value = 0;
  if (!node.IsScalar() || !parse_number(node.Scalar(), value))
    fail(file, node, element, node.IsScalar() ? fmt::format("'{}' is not a number", node.Scalar()) : "must be a number",
         "write a finite decimal number, e.g. 0.05 or 1.2e-4");
  return value;
}

Vec3<double> to_vec3(const std::string& file, const YAML::Node& node, const std::string& element) {
  if (!node.IsSequence() || node.size() != 3)
    fail(file, node, element, "must be a list of three numbers", "write e.g. [0, 0, 0.05]");
  return Vec3<double>(to_number(file, node[0], element), to_number(file, node[1], element),
                      to_number(file, node[2], element));
}

SE3<double> to_origin(const std::string& file, const YAML::Node& node, const std::string& element) {
  require_map(file, node, element, "{xyz: [0, 0, 0.05], rpy: [0, 0, 0]}");
  reject_unknown_keys(file, node, element, {"rpy", "xyz"});
  SE3<double> X;
  if (node["xyz"]) X.translation = to_vec3(file, node["xyz"], element + ".xyz");
  if (node["rpy"]) {
    const Vec3<double> rpy = to_vec3(file, node["rpy"], element + ".rpy");
    X.rotation = (Eigen::AngleAxisd(rpy.z(), Vec3<double>::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3<double>::UnitY()) *
                  Eigen::AngleAxisd(rpy.x(), Vec3<double>::UnitX()))
                     .toRotationMatrix();
  }
  return X;
}

void require_sequence(const std::string& file, const YAML::Node& node, const std::string& element,
                      const std::string& example) {
  if (!node.IsSequence()) fail(file, node, element, "must be a list", fmt::format("write e.g. {}", example));
}

void require_map(const std::string& file, const YAML::Node& node, const std::string& element,
                 const std::string& example) {
  if (!node.IsMap()) fail(file, node, element, "must be a map of keys to values", fmt::format("write e.g. {}", example));
}

void reject_unknown_keys(const std::string& file, const YAML::Node& map, const std::string& element,
                         const std::vector<std::string>& allowed) {
  std::vector<std::string> seen;
  for (const auto& entry : map) {
    const std::string key = entry.first.Scalar();
    if (std::find(seen.begin(), seen.end(), key) != seen.end())
      fail(file, entry.first, element.empty() ? fmt::format("key '{}'", key) : fmt::format("{}: key '{}'", element, key),
           "is given twice", "keep one of them");
    seen.push_back(key);
    if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
    const std::string where = element.empty() ? fmt::format("key '{}'", key) : fmt::format("{}: key '{}'", element, key);
    fail(file, entry.first, where, "is not a known key",
         with_suggestion(fmt::format("known keys: {}", fmt::join(allowed, ", ")), did_you_mean(key, allowed)));
  }
}

std::vector<std::string> frame_candidates(const Model& model) {
  std::vector<std::string> names;
  for (int f = 0; f < model.num_frames(); ++f) names.push_back(model.frame(FrameIndex(f)).name);
  for (const std::string& joint : model.joint_names()) names.push_back(joint);
  std::sort(names.begin(), names.end());
  names.erase(std::unique(names.begin(), names.end()), names.end());
  return names;
}

std::vector<std::string> moving_joint_names(const Model& model) {
  std::vector<std::string> names = model.joint_names();
  std::sort(names.begin(), names.end());
  return names;
}

FrameIndex resolve_frame(const std::string& file, const YAML::Node& node, const std::string& element,
                         const Model& model) {
  const std::string name = to_string(file, node, element);
  if (auto frame = model.find_frame(name)) return *frame;
  // A moving joint's child frame is its child body's frame (they coincide at q = 0).
  if (const FrameIndex moved = moved_body_frame(model, name); moved.valid()) return moved;
  fail(file, node, element, fmt::format("names '{}', which is no link or joint of the URDF", name),
       with_suggestion("use a <link> or <joint> name of the URDF", did_you_mean(name, frame_candidates(model))));
}

JointIndex resolve_moving_joint(const std::string& file, const YAML::Node& node, const std::string& element,
                                const Model& model) {
  const std::string name = to_string(file, node, element);
  if (auto joint = model.find_joint(name)) return *joint;
  if (auto frame = model.find_frame(name); frame && model.frame(*frame).kind == FrameKind::Joint)
    fail(file, node, element, fmt::format("names '{}', a fixed joint (merged into its parent body)", name),
         "name a revolute, continuous or prismatic joint");
  fail(file, node, element, fmt::format("names '{}', which is no moving joint of the URDF", name),
       with_suggestion("use a revolute, continuous or prismatic <joint> name of the URDF",
                       did_you_mean(name, moving_joint_names(model))));
}

}  // namespace yaml
}  // namespace mbgen::gen
