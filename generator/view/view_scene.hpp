#pragma once
// What a page of `mbgen view` shows, as the JSON the page reads (web/viewer/viewer.js; the schema
// is docs/view.md's): the bodies, their SSV compounds and meshes in the bodies' frames, the loop
// closures' two frames, the ground-contact spheres, the collision pairs, and per frame the pose
// of every body (mbgen's forward kinematics, the generic runtime's: the 3 x 4 [R | p] of the
// generated forward_kinematics, row-major, in body_names order), the pairs nearer than the
// threshold with their witness points, and the contact forces. The page computes no kinematics.
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "load/description.hpp"
#include "view/trajectory_csv.hpp"

namespace mbgen::view {

struct ViewOptions {
  double near_threshold = 0.03;  ///< m: pairs nearer than this are coloured, with their witness segment
  bool meshes = true;            ///< draw the links' meshes (when they resolve)
  std::map<std::string, std::string> package_paths;  ///< package:// and model:// folders, for the meshes
  double fps = 30;               ///< a trajectory's rows resampled to this rate (<= 0: every row)
};

/// The scene of description `d` at its assembled pose (the neutral one without loops), or along
/// `trajectory` when one is given. A mesh that cannot be read is a warning (its link is drawn
/// with its SSVs only), appended to `warnings`.
nlohmann::json view_scene(const gen::Description& d, const Trajectory* trajectory, const ViewOptions& options,
                          std::vector<std::string>& warnings);

/// The nominal pose `view_scene` shows without a trajectory.
VecX<double> nominal_pose(const gen::Description& d);

}  // namespace mbgen::view
