#include "mesh/convex_hull.hpp"

#include <algorithm>
#include <cstdio>
#include <numeric>

extern "C" {
#include <libqhull_r/qhull_ra.h>
}

namespace mbgen::mesh {

ConvexHull convex_hull(const std::vector<Vec3<double>>& points) {
  ConvexHull hull;
  const auto every_point = [&] {
    hull.vertices.resize(points.size());
    std::iota(hull.vertices.begin(), hull.vertices.end(), 0);
    return hull;
  };
  if (points.size() < 4) return every_point();
  std::vector<coordT> coordinates;
  coordinates.reserve(3 * points.size());
  for (const Vec3<double>& p : points) coordinates.insert(coordinates.end(), {p.x(), p.y(), p.z()});
  // Qhull reports errors to a stream; a flat input (QH6154) is an answer here, not a failure.
  FILE* quiet = std::fopen("/dev/null", "w");
  qhT qh_storage;
  qhT* qh = &qh_storage;
  qh_zero(qh, quiet);
  char flags[] = "qhull Qt";
  const int status = qh_new_qhull(qh, 3, static_cast<int>(points.size()), coordinates.data(), False, flags, nullptr, quiet);
  if (status == 0) {
    qh_getarea(qh, qh->facet_list);
    hull.volume = qh->totvol;
    hull.solid = true;
    vertexT* vertex;
    FORALLvertices hull.vertices.push_back(qh_pointid(qh, vertex->point));
    std::sort(hull.vertices.begin(), hull.vertices.end());
  }
  qh_freeqhull(qh, !qh_ALL);
  int long_bytes = 0, total_bytes = 0;
  qh_memfreeshort(qh, &long_bytes, &total_bytes);
  if (quiet) std::fclose(quiet);
  if (status != 0) return every_point();
  return hull;
}

}  // namespace mbgen::mesh
