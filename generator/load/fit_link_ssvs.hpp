#pragma once
// SSV compounds fitted to each link's meshes (issue 16): gathers a link's meshes and boxes in its
// frame (mesh files through mesh/read_mesh, package:// through the package paths), fits a
// compound (mesh/fit_ssv.hpp) and adds it to the description's `ssv`.
#include <string>
#include <vector>

#include "load/description.hpp"
#include "mesh/fit_ssv.hpp"

namespace mbgen::gen {

/// One link's fit: the compound, its report, and the files it came from.
struct LinkFit {
  std::string link;
  std::vector<std::string> sources;  ///< mesh paths as resolved ("box" for a box)
  mesh::TriangleMesh mesh;            ///< the link's meshes and boxes gathered in its frame, as fitted
  mesh::FittedCompound compound;
};

/// Fits a compound to every link of `d.link_meshes` whose compound the extras do not give, in
/// link-name order, and appends its primitives to d.ssv[link] (a URDF sphere or cylinder of the
/// same link stays). A mesh that cannot be used (not found, unreadable, no triangles, non-finite
/// vertices, a zero or non-finite scale) is a warning in d.warnings naming the link and the file,
/// and its link gets nothing fitted. A negative scale mirrors the mesh, as in ROS tools.
/// Throws std::invalid_argument for a budget below 1.
std::vector<LinkFit> fit_link_ssvs(Description& d, const std::map<std::string, std::string>& package_paths,
                                   const mesh::FitOptions& options);

/// The fitted primitive as the description's SSV (its kind from its number of points).
SsvPrimitive to_ssv_primitive(const mesh::FittedPrimitive& p, const std::string& source);

}  // namespace mbgen::gen
