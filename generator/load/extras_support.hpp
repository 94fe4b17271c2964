#pragma once
// Helpers shared by the two YAML extras schemas: typed reads that fail with a LoadError naming
// the file and 1-based line (yaml-cpp's Mark is 0-based), and name resolution against the Model
// with close-match suggestions. Private to the generator library.
#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "load/description.hpp"

namespace mbgen::gen {

/// A parsed extras file and the schema its top-level keys say it follows.
struct ExtrasFile {
  enum class Schema { Mbgen, ParallelLegs };
  std::string path;
  YAML::Node root;  ///< a map, or null for an empty file
  Schema schema = Schema::Mbgen;
};

/// Parses the YAML and picks the schema from the keys; malformed YAML is a LoadError with its line.
ExtrasFile read_extras(const std::string& path);
/// `closure_joints:` of an mbgen-schema file: the SDFormat joints to leave out of the spanning
/// tree (each becomes a closure); empty when absent; a LoadError when the description it extends
/// is not SDFormat (URDF and MJCF write their loops as closures and equalities).
std::vector<std::string> extras_closure_joints(const ExtrasFile& extras, const std::string& description);
/// `base:` of an mbgen-schema file, if it says one.
std::optional<BaseType> extras_base(const ExtrasFile& extras);
/// `snap_quarter_turns:` of an mbgen-schema file (a tolerance in [0, 1e-6]), else 0; a LoadError
/// when the description it extends is an MJCF (the option is the URDF loader's).
double extras_quarter_turns(const ExtrasFile& extras, const std::string& description);
/// `mimic: couple` (true) or `independent` (false, also when absent) of an mbgen-schema file; a
/// LoadError when the description it extends is an MJCF (its couplings are <equality> elements).
bool extras_couples_mimics(const ExtrasFile& extras, const std::string& description);
/// Fills closures, independent, drives, ssv, scene, robot from an mbgen-schema file.
void apply_mbgen_extras(const ExtrasFile& extras, Description& d);
/// Fills closures, actuated joints and joint type overrides from a parallel_legs robot.yaml.
void apply_parallel_legs(const ExtrasFile& extras, Description& d);

namespace yaml {

int line_of(const YAML::Node& node);  ///< 1-based; 0 when the node has no position
[[noreturn]] void fail(const std::string& file, const YAML::Node& node, const std::string& element,
                       const std::string& problem, const std::string& fix);
std::string to_string(const std::string& file, const YAML::Node& node, const std::string& element);
double to_number(const std::string& file, const YAML::Node& node, const std::string& element);
Vec3<double> to_vec3(const std::string& file, const YAML::Node& node, const std::string& element);
/// {xyz: [..], rpy: [..]} (both optional; rpy as in URDF: roll about x, then pitch about y, then yaw about z, fixed axes).
SE3<double> to_origin(const std::string& file, const YAML::Node& node, const std::string& element);
/// A sequence (a single scalar is not accepted: lists are lists).
void require_sequence(const std::string& file, const YAML::Node& node, const std::string& element,
                      const std::string& example);
void require_map(const std::string& file, const YAML::Node& node, const std::string& element,
                 const std::string& example);
/// Every key of the map must be one of `allowed`; else a LoadError suggesting the closest.
void reject_unknown_keys(const std::string& file, const YAML::Node& map, const std::string& element,
                         const std::vector<std::string>& allowed);

/// A frame name (link, fixed joint, or a moving joint: its child body's frame), else a LoadError
/// with a close-match suggestion.
FrameIndex resolve_frame(const std::string& file, const YAML::Node& node, const std::string& element,
                         const Model& model);
/// A moving joint's name, else a LoadError (with a suggestion, or saying the joint is fixed).
JointIndex resolve_moving_joint(const std::string& file, const YAML::Node& node, const std::string& element,
                                const Model& model);
/// All names resolve_frame accepts, sorted (for suggestions).
std::vector<std::string> frame_candidates(const Model& model);
std::vector<std::string> moving_joint_names(const Model& model);

}  // namespace yaml
}  // namespace mbgen::gen
