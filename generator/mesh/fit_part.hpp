#pragma once
// One part of a fitted compound (fit_ssv.hpp): a sphere, a capsule or a plate enclosing a point
// set, and the geometry the fitter shares between its files.
#include <vector>

#include "mesh/fit_ssv.hpp"

namespace mbgen::mesh {

/// Principal axes of a piece of surface: columns of `axes`, largest spread first.
struct PrincipalFrame {
  Vec3<double> centre;
  Mat3<double> axes;
};

/// Area-weighted principal axes of a triangle soup (the corners' if its area is zero). Each
/// axis's largest component is made positive, so the frame does not depend on the solver's signs.
PrincipalFrame principal_frame(const std::vector<Triangle>& soup);

/// Primitives that share a radius and enclose a point set together: a sphere or a capsule (one
/// primitive) or a plate (two triangles forming a rectangle).
struct Part {
  std::vector<FittedPrimitive> primitives;
  double volume = 0;  ///< swept volume of the part (the plate's union, not the sum of its triangles)
};

/// The smallest of the candidates (sphere, capsules, plates) enclosing `points` in at most
/// `max_primitives` primitives; a two-primitive plate must save `min_gain` of the best single
/// primitive's volume. The radius is at least what every point needs (core distance).
Part fit_part(const std::vector<Vec3<double>>& points, const PrincipalFrame& frame, int max_primitives, double min_gain);

/// max over `points` of min over the part's cores of the core distance: the radius they need.
double needed_radius(const std::vector<Vec3<double>>& points, const std::vector<FittedPrimitive>& part);

/// The part's volume from its cores and radius (sphere, capsule, or a rectangle's two triangles).
double part_volume(const std::vector<FittedPrimitive>& part);

}  // namespace mbgen::mesh
