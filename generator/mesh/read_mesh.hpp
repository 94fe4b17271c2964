#pragma once
// Reading a mesh file (STL binary and ASCII, OBJ, COLLADA/DAE, and whatever else assimp reads)
// into one TriangleMesh in the file's own coordinates.
#include <stdexcept>
#include <string>

#include "mesh/triangle_mesh.hpp"

namespace mbgen::mesh {

/// A mesh file that cannot be used: missing, unreadable, empty, or with non-finite coordinates.
/// The message names the file and says what is wrong; the caller adds the link.
struct MeshError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Reads every mesh of the file's scene, node transforms applied (a DAE's nodes and its <unit>),
/// polygons triangulated, points and lines dropped. COLLADA's <up_axis> is ignored, as ROS tools
/// do: a URDF's <origin> is meant for the file's own axes. Throws MeshError.
TriangleMesh read_mesh(const std::string& path);

}  // namespace mbgen::mesh
