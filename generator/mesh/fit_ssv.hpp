#pragma once
// Fitting a compound of swept-sphere volumes to a link's mesh (issue 16, item 2; docs/ssv.md,
// "Fitting SSVs to meshes"). The compound encloses the whole surface, not only the vertices:
// each part encloses the convex hull of its piece of the mesh, and the pieces cover the mesh.
//
// Method: one part per piece, the smallest of three candidates, each enclosing by construction
// and sized on the piece's convex-hull vertices:
//   - a sphere (point-SSV): a near-minimal enclosing sphere (Badoiu-Clarkson iterations);
//   - a capsule (line-SSV) along each principal axis: the axis through the centre of the
//     smallest circle around the points' projections, and for each radius the shortest segment
//     within reach of every point, the radius chosen for the least volume;
//   - a plate (two triangle-SSVs forming a rectangle) normal to each principal axis: the
//     rectangle shrunk as far as the radius lets every point stay within reach.
// Then greedy splitting: while the budget allows, the piece whose best cut saves most volume (at
// least `min_gain` of it) is cut in two by a plane normal to one of its principal axes, and each
// half fitted; and, when two cuts would pay where one does not, cutting first (single primitives,
// the largest part cut until the budget is spent) wins if it saves `min_gain` more. A cut clips
// the triangles it crosses, so both halves contain the cut's points.
// Why this and not an optimisation over all primitives at once: every step is a closed form or
// a 1-D search, so the result is deterministic and takes seconds for a humanoid (TALOS's 48
// links: 9 s, the gap measurement included), and enclosure never depends on a solver's convergence.
#include <vector>

#include "mesh/triangle_mesh.hpp"

namespace mbgen::mesh {

/// One SSV primitive: its core's 1 (point), 2 (segment) or 3 (triangle) points and its radius.
struct FittedPrimitive {
  std::vector<Vec3<double>> points;
  double radius = 0;
};

struct FitOptions {
  int budget = 4;          ///< most primitives in the compound (a plate counts 2); >= 1
  double min_gain = 0.05;  ///< a split or a second primitive must save this fraction of the volume
};

/// What the fit achieved, for the report and the tests.
struct FitReport {
  int vertices = 0, triangles = 0;
  double hull_volume = 0;   ///< the mesh's convex hull (0 for a flat mesh)
  /// Swept volume of the compound: the sum over its parts (a sphere, a capsule, or a plate's two
  /// triangles together), so an upper bound of the union's volume.
  double volume = 0;
  /// Largest distance from the compound's surface to the mesh, over points sampled on the part
  /// surfaces that lie on the compound's surface: how conservative the model is.
  double largest_gap = 0;
  /// Largest distance of a mesh vertex outside the compound (core distance - radius, maximised):
  /// <= 0 for an enclosing compound, which fit_ssv_compound checks before returning.
  double largest_outside = 0;
};

struct FittedCompound {
  std::vector<FittedPrimitive> primitives;
  FitReport report;
};

/// Fits a compound to `mesh` (metres, the link's frame). Coordinates are rounded to 1 um and
/// radii rounded up so that the enclosure survives writing them with six decimals. Throws
/// std::invalid_argument for a budget below 1 or a mesh without triangles.
FittedCompound fit_ssv_compound(const TriangleMesh& mesh, const FitOptions& options = {});

/// Distance from p to the primitive's core (point, segment or triangle).
double core_distance(const Vec3<double>& p, const FittedPrimitive& primitive);

/// min over the compound of (core distance - radius): <= 0 inside, the distance outside.
double distance_to_compound(const Vec3<double>& p, const std::vector<FittedPrimitive>& compound);

/// Volume of one primitive alone (sphere, capsule or swept triangle; Steiner's formula).
double primitive_volume(const FittedPrimitive& primitive);

}  // namespace mbgen::mesh
