#pragma once
// What the SDFormat loader's files share (load_sdf.cpp, sdf_collision.cpp): libsdformat's poses
// as mbgen's, and the line of an element for error messages.
#include <sdf/sdf.hh>

#include <string>

#include "load/description.hpp"

namespace mbgen::gen::sdformat {

inline SE3<double> to_se3(const ignition::math::Pose3d& pose) {
  SE3<double> X;
  const auto& q = pose.Rot();
  X.rotation = Eigen::Quaterniond(q.W(), q.X(), q.Y(), q.Z()).normalized().toRotationMatrix();
  X.translation = Vec3<double>(pose.Pos().X(), pose.Pos().Y(), pose.Pos().Z());
  return X;
}

inline Vec3<double> to_vec3(const ignition::math::Vector3d& v) { return {v.X(), v.Y(), v.Z()}; }

inline int line_of(const sdf::ElementPtr& e) { return e ? e->LineNumber().value_or(0) : 0; }

/// The pose of `what` (a link, joint, collision or frame) in the frame `in`, as libsdformat
/// resolves it (relative_to, use_parent_model_frame and the version's defaults); a LoadError
/// naming the element when it cannot.
SE3<double> resolve(const std::string& path, const sdf::SemanticPose& pose, const std::string& in, const std::string& element,
                    int line);

/// The links' collision geometry as SSVs (sphere -> point, cylinder and capsule -> line, as
/// URDF's), boxes and meshes kept for fitting; a link without <collision> gives its <visual>
/// meshes (sdf_collision.cpp).
void add_sdf_collisions(const std::string& path, const sdf::Model& model, Description& d);

}  // namespace mbgen::gen::sdformat
