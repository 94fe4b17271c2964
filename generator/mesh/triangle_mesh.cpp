#include "mesh/triangle_mesh.hpp"

namespace mbgen::mesh {

std::vector<Triangle> triangle_soup(const TriangleMesh& mesh) {
  std::vector<Triangle> soup;
  soup.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) soup.push_back({mesh.vertices[t[0]], mesh.vertices[t[1]], mesh.vertices[t[2]]});
  return soup;
}

void append_transformed(const TriangleMesh& mesh, const Vec3<double>& scale, const SE3<double>& X, TriangleMesh& out) {
  const int offset = static_cast<int>(out.vertices.size());
  for (const Vec3<double>& v : mesh.vertices) out.vertices.push_back(X.act(scale.cwiseProduct(v)));
  for (const auto& t : mesh.triangles) out.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
}

TriangleMesh box_mesh(const Vec3<double>& size) {
  TriangleMesh box;
  for (int i = 0; i < 8; ++i)
    box.vertices.push_back(0.5 * Vec3<double>((i & 1 ? 1 : -1) * size.x(), (i & 2 ? 1 : -1) * size.y(), (i & 4 ? 1 : -1) * size.z()));
  // Two triangles per face, corners by bit pattern (bit 0: x, bit 1: y, bit 2: z).
  box.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                   {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return box;
}

}  // namespace mbgen::mesh
