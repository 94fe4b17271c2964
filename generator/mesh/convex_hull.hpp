#pragma once
// Convex hulls of point sets through Qhull (Debian's libqhull-dev): the points an enclosing
// convex volume must contain, and the volume the fitted SSVs are measured against.
#include <vector>

#include "mbgen/spatial/types.hpp"

namespace mbgen::mesh {

struct ConvexHull {
  std::vector<int> vertices;  ///< indices of the input points on the hull, increasing
  double volume = 0;          ///< 0 for flat or degenerate input
  bool solid = false;         ///< false: the points are (nearly) coplanar, collinear or too few;
                              ///< then `vertices` is every point (a hull in fewer dimensions)
};

/// The convex hull of `points`. Deterministic: same points, same result.
ConvexHull convex_hull(const std::vector<Vec3<double>>& points);

}  // namespace mbgen::mesh
