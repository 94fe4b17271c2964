#pragma once
// Description: everything the loader read about a robot: the tree Model, plus what URDF cannot
// say (closures, actuated joints, drives) from the YAML extras, and the warnings raised.
#include <optional>
#include <string>
#include <vector>

#include "mbgen/model.hpp"

namespace mbgen::gen {

enum class BaseType { Fixed, Floating };

/// A loop closure as given by the user (loop detection and sub-systems come later).
struct ClosureSpec {
  std::string name;
  std::string type;     ///< revolute, spherical, universal, weld, prismatic (extras) or 6d / 3d (robot.yaml)
  std::string frame_a;  ///< frame (link, joint or user frame) on one side
  std::string frame_b;  ///< frame on the other side
  SE3<double> X_AC;     ///< closure frame in frame_a (identity unless the extras give an origin)
  SE3<double> X_BC;     ///< closure frame in frame_b
  Vec3<double> axis = Vec3<double>::UnitZ();  ///< closure joint axis in the closure frame, where it has one
  std::string source;   ///< file and line it came from
};

/// A harmonic-drive (or other geared) actuator on a joint.
struct DriveSpec {
  std::string joint;
  double gear_ratio = 1.0;
  double rotor_inertia = 0.0;  ///< rotor inertia about its spin axis, kg m^2
  std::string model = "armature";  ///< armature (reflected inertia) or body (rotor body with gyroscopic terms)
};

struct Description {
  Model model;
  std::string description_file;       ///< as given on the command line
  std::string extras_file;            ///< empty when there is none
  BaseType base = BaseType::Fixed;
  std::vector<ClosureSpec> closures;
  std::vector<std::string> actuated_joints;  ///< name_mot of robot.yaml, or `independent` hints
  std::vector<DriveSpec> drives;
  std::vector<std::string> warnings;
};

struct LoadOptions {
  std::optional<std::string> extras_file;  ///< YAML extras; if absent, a robot.yaml beside the URDF is used
  std::optional<BaseType> base;            ///< overrides the extras' `base`
  bool pick_up_robot_yaml = true;
};

/// Loads a URDF (and extras). Throws LoadError with file, line, element and fix on bad input.
Description load_description(const std::string& path, const LoadOptions& options = {});

/// Builds the tree Model from a URDF file alone (fixed joints merged). Warnings are appended.
Model load_urdf_model(const std::string& path, BaseType base, std::vector<std::string>& warnings);

}  // namespace mbgen::gen
