#pragma once
// A triangle mesh as the SSV fitting sees it: corner coordinates in one frame (metres) and
// triangles as index triples. No normals, no materials: only the surface to enclose.
#include <array>
#include <vector>

#include "mbgen/spatial/se3.hpp"

namespace mbgen::mesh {

struct TriangleMesh {
  std::vector<Vec3<double>> vertices;
  std::vector<std::array<int, 3>> triangles;  ///< indices into vertices
};

/// A triangle by its corners (what the fitter splits and clips: no shared indices needed).
using Triangle = std::array<Vec3<double>, 3>;

/// The mesh's triangles as corner triples.
std::vector<Triangle> triangle_soup(const TriangleMesh& mesh);

/// Appends `mesh` with every vertex mapped by x -> X * (scale .* x) (a URDF <mesh>'s scale, then
/// its <origin>): the meshes of one link gathered in the link's frame.
void append_transformed(const TriangleMesh& mesh, const Vec3<double>& scale, const SE3<double>& X, TriangleMesh& out);

/// The 12 triangles of a box with the given full side lengths, centred at the origin.
TriangleMesh box_mesh(const Vec3<double>& size);

}  // namespace mbgen::mesh
