#include "cli/ssv_picture.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "mbgen/algorithm/configuration.hpp"
#include "mbgen/algorithm/kinematics.hpp"

namespace mbgen::cli {

namespace {

using V2 = Eigen::Vector2d;

/// Convex hull of 2-D points (Andrew's monotone chain), counter-clockwise, closed.
std::vector<V2> hull_2d(std::vector<V2> p) {
  std::sort(p.begin(), p.end(), [](const V2& a, const V2& b) { return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y()); });
  const auto cross = [](const V2& o, const V2& a, const V2& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<V2> h(2 * p.size());
  std::size_t k = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 0) --k;
    h[k++] = p[i];
  }
  for (std::size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i - 1]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k);  // the last point repeats the first: closed
  return h;
}

V2 project(const Vec3<double>& x, int view) {
  switch (view) {
    case 0: return {x.y(), x.z()};  // front (the script reverses y: seen from +x)
    case 1: return {x.x(), x.z()};  // side
    default: return {x.x(), x.y()}; // top
  }
}

}  // namespace

void write_ssv_picture_data(const std::string& directory, const gen::Description& d, const std::vector<gen::LinkFit>& fits) {
  std::filesystem::create_directories(directory);
  const Model& model = d.model;
  Data<double> data(model);
  const VecX<double> q = d.assembly.q.size() == model.nq() ? d.assembly.q : neutral_configuration<double>(model);
  forward_kinematics<double>(model, data, q);
  update_frame_placements<double>(model, data);

  std::ofstream mesh_out(std::filesystem::path(directory) / "mesh.dat");
  mesh_out << "# world x y z of each mesh triangle at the nominal pose, one closed block each\n";
  std::ofstream ssv_out(std::filesystem::path(directory) / "ssv.dat");
  ssv_out << "# silhouettes of the SSV primitives: index 0 front (y z), 1 side (x z), 2 top (x y)\n";
  std::vector<std::vector<std::vector<V2>>> outlines(3);
  for (const gen::LinkFit& fit : fits) {
    const auto frame = model.find_frame(fit.link);
    if (!frame) continue;
    const SE3<double>& X_WL = data.X_WF[*frame];
    // The meshes as the fit read them, placed in the world.
    for (const auto& t : fit.mesh.triangles) {
      for (int k : {0, 1, 2, 0}) {
        const Vec3<double> x = X_WL.act(fit.mesh.vertices[t[k]]);
        mesh_out << fmt::format("{:.5f} {:.5f} {:.5f}\n", x.x(), x.y(), x.z());
      }
      mesh_out << "\n";
    }
    // Each part's silhouette: its projected cores swept by a disc of its radius. A plate's two
    // triangles (the fitter's (a, b, c), (a, c, d)) are drawn as one rectangle.
    const auto& primitives = fit.compound.primitives;
    for (std::size_t i = 0; i < primitives.size(); ++i) {
      std::vector<Vec3<double>> cores = primitives[i].points;
      const double radius = primitives[i].radius;
      if (i + 1 < primitives.size() && cores.size() == 3 && primitives[i + 1].points.size() == 3 &&
          primitives[i + 1].radius == radius && primitives[i + 1].points[0] == cores[0] && primitives[i + 1].points[1] == cores[2])
        cores.push_back(primitives[++i].points[2]);
      for (int view = 0; view < 3; ++view) {
        std::vector<V2> samples;
        for (const Vec3<double>& c : cores)
          for (int k = 0; k < 72; ++k) {
            const double a = 2 * 3.14159265358979323846 * k / 72;
            samples.push_back(project(X_WL.act(c), view) + radius * V2(std::cos(a), std::sin(a)));
          }
        outlines[view].push_back(hull_2d(samples));
      }
    }
  }
  for (int view = 0; view < 3; ++view) {
    if (view) ssv_out << "\n\n";
    for (const auto& outline : outlines[view]) {
      for (const V2& x : outline) ssv_out << fmt::format("{:.5f} {:.5f}\n", x.x(), x.y());
      ssv_out << "\n";
    }
  }
  if (!mesh_out || !ssv_out) throw std::runtime_error(fmt::format("{}: cannot write the picture's data", directory));
}

}  // namespace mbgen::cli
