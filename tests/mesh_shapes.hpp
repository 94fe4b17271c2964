#pragma once
// Meshes the SSV-fitting tests build themselves (closed, outward-facing triangles): a box, a
// cylinder, an L-shaped prism, a thin plate, a sphere; and random points on a mesh's surface.
#include <cmath>
#include <cstdint>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "mesh/triangle_mesh.hpp"

namespace mbgen::test {

/// A prism: the polygon `outline` (x, y; counter-clockwise) extruded over z in [0, height],
/// side walls and both caps (caps fanned from the first corner: a convex or star-shaped outline
/// from it, which the L-shape is).
inline mesh::TriangleMesh prism(const std::vector<std::pair<double, double>>& outline, double height) {
  mesh::TriangleMesh m;
  const int n = static_cast<int>(outline.size());
  for (double z : {0.0, height})
    for (const auto& [x, y] : outline) m.vertices.emplace_back(x, y, z);
  for (int i = 0; i < n; ++i) {
    const int j = (i + 1) % n;
    m.triangles.push_back({i, j, n + j});
    m.triangles.push_back({i, n + j, n + i});
  }
  for (int i = 1; i + 1 < n; ++i) {
    m.triangles.push_back({0, i + 1, i});
    m.triangles.push_back({n, n + i, n + i + 1});
  }
  return m;
}

inline mesh::TriangleMesh cylinder_mesh(double radius, double length, int sides) {
  std::vector<std::pair<double, double>> outline;
  for (int k = 0; k < sides; ++k)
    outline.emplace_back(radius * std::cos(2 * M_PI * k / sides), radius * std::sin(2 * M_PI * k / sides));
  mesh::TriangleMesh m = prism(outline, length);
  for (auto& v : m.vertices) v.z() -= length / 2;
  return m;
}

/// An L: a 0.3 x 0.06 bar along x and a 0.06 x 0.25 bar along y sharing the corner, 0.05 thick.
inline mesh::TriangleMesh l_shape() {
  return prism({{0, 0}, {0.3, 0}, {0.3, 0.06}, {0.06, 0.06}, {0.06, 0.25}, {0, 0.25}}, 0.05);
}

/// A UV sphere of the given radius (its vertices on the sphere).
inline mesh::TriangleMesh sphere_mesh(double radius, int rings, int sectors) {
  mesh::TriangleMesh m;
  m.vertices.emplace_back(0, 0, radius);
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < sectors; ++j) {
      const double th = M_PI * i / rings, ph = 2 * M_PI * j / sectors;
      m.vertices.emplace_back(radius * std::sin(th) * std::cos(ph), radius * std::sin(th) * std::sin(ph), radius * std::cos(th));
    }
  m.vertices.emplace_back(0, 0, -radius);
  const int south = static_cast<int>(m.vertices.size()) - 1;
  auto at = [&](int i, int j) { return 1 + (i - 1) * sectors + (j % sectors); };
  for (int j = 0; j < sectors; ++j) {
    m.triangles.push_back({0, at(1, j), at(1, j + 1)});
    m.triangles.push_back({south, at(rings - 1, j + 1), at(rings - 1, j)});
    for (int i = 1; i + 1 < rings; ++i) {
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  }
  return m;
}

/// `count` points uniformly on the mesh's surface (area-weighted triangles), seeded.
inline std::vector<Vec3<double>> surface_samples(const mesh::TriangleMesh& m, int count, unsigned seed) {
  std::vector<double> areas;
  for (const auto& t : m.triangles)
    areas.push_back(0.5 * (m.vertices[t[1]] - m.vertices[t[0]]).cross(m.vertices[t[2]] - m.vertices[t[0]]).norm());
  std::mt19937 rng(seed);
  std::discrete_distribution<int> pick(areas.begin(), areas.end());
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3<double>> points;
  for (int k = 0; k < count; ++k) {
    const auto& t = m.triangles[pick(rng)];
    double a = u(rng), b = u(rng);
    if (a + b > 1) a = 1 - a, b = 1 - b;
    points.push_back(m.vertices[t[0]] + a * (m.vertices[t[1]] - m.vertices[t[0]]) + b * (m.vertices[t[2]] - m.vertices[t[0]]));
  }
  return points;
}

/// Writes `m` as a binary STL (80-byte header, count, per triangle a zero normal, three float
/// corners and a zero attribute). `poison` is added to the first corner's x of every triangle: a
/// NaN makes a file with non-finite vertices.
inline void write_binary_stl(const std::string& path, const mesh::TriangleMesh& m, float poison = 0) {
  std::ofstream out(path, std::ios::binary);
  char header[80] = "binary STL written by mbgen's tests";
  out.write(header, 80);
  const auto n = static_cast<std::uint32_t>(m.triangles.size());
  out.write(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : m.triangles) {
    float values[12] = {0, 0, 0};
    for (int k = 0; k < 3; ++k)
      for (int i = 0; i < 3; ++i) values[3 + 3 * k + i] = static_cast<float>(m.vertices[t[k]][i]);
    values[3] += poison;
    out.write(reinterpret_cast<const char*>(values), sizeof values);
    const std::uint16_t attribute = 0;
    out.write(reinterpret_cast<const char*>(&attribute), 2);
  }
}

}  // namespace mbgen::test
