#pragma once
// Kinematic loops on top of the spanning tree: loop closures (what the tree cannot say) and
// the sub-systems they form (DESIGN.md, "Kinematic loops and sub-systems").
//
// A closure joins a frame Ca fixed in body A to a frame Cb fixed in body B. Its constraint rows
// are components of the motion of Cb relative to Ca, expressed in Ca, [linear; angular]:
//   weld       3 linear + 3 angular                         (6 rows)
//   point      3 linear (a ball joint / spherical closure)  (3 rows)
//   revolute   3 linear + 2 angular (perpendicular to axis) (5 rows)
//   prismatic  2 linear (perpendicular to axis) + 3 angular (5 rows)
//   universal  3 linear + 1 angular (about axis x axis_b)   (4 rows)
//   coupling   q_b - ratio q_a - offset                     (1 row)
// A coupling is not a joint between two frames but a linear relation between the positions of
// the 1-DoF joints that move body_a (the leader) and body_b (the follower): URDF <mimic>, MJCF
// joint equalities and fixed tendons. Its frames are unused; its cycle is the tree path between
// the two joints (closure_top), so both joints are coordinates of its sub-system and the
// follower, solved from the leader, has no coordinate of its own in the closed system.
// The residual rows and the exact definitions are in algorithm/closure.hpp.
// The stacked rows of all closures, in closure order, are the system's constraint rows;
// `row_offset` is where a closure's rows start. Rows may be redundant (a 6d closure of a planar
// loop has rank 3): sub-systems keep an independent subset.
#include <string>
#include <vector>

#include "mbgen/index.hpp"
#include "mbgen/spatial/se3.hpp"

namespace mbgen {

enum class ClosureType { Weld, Point, Revolute, Prismatic, Universal, Coupling };

inline const char* to_string(ClosureType type) {
  switch (type) {
    case ClosureType::Weld: return "weld";
    case ClosureType::Point: return "point";
    case ClosureType::Revolute: return "revolute";
    case ClosureType::Prismatic: return "prismatic";
    case ClosureType::Universal: return "universal";
    case ClosureType::Coupling: return "coupling";
  }
  return "unknown";
}

/// Number of constraint rows of a closure type.
inline int closure_rows(ClosureType type) {
  switch (type) {
    case ClosureType::Weld: return 6;
    case ClosureType::Point: return 3;
    case ClosureType::Revolute: return 5;
    case ClosureType::Prismatic: return 5;
    case ClosureType::Universal: return 4;
    case ClosureType::Coupling: return 1;
  }
  return 0;
}

struct LoopClosure {
  std::string name;
  ClosureType type = ClosureType::Weld;
  BodyIndex body_a, body_b;  ///< the two bodies joined (either may be the world)
  SE3<double> X_ACa;         ///< closure frame Ca in body A
  SE3<double> X_BCb;         ///< closure frame Cb in body B (coincides with Ca when closed, up to the free motion)
  Vec3<double> axis = Vec3<double>::UnitZ();    ///< revolute/prismatic: free axis, in Ca; universal: first axis, fixed in Ca
  Vec3<double> axis_b = Vec3<double>::UnitY();  ///< universal: second axis, fixed in Cb (perpendicular to `axis` when closed)
  double ratio = 1.0, offset = 0.0;  ///< coupling: q_b = ratio q_a + offset (the joints of body_a and body_b)
  int row_offset = 0;        ///< first row of this closure in the stacked constraint vector
  int rows() const { return closure_rows(type); }
};

/// Bodies that must be solved together: the union of the fundamental cycles (tree path body_a ->
/// common ancestor -> body_b) that share a moving joint, i.e. a body other than their roots.
/// Loops that only meet at a body stay apart: their coordinates are disjoint and their rows
/// decouple (generator/model/topology.hpp). Coordinates are velocity indices; the
/// rows of Phi_q outside `coordinates` are exact zeros, so Phi_z = Phi_q(rows, dependent) and
/// Phi_y = Phi_q(rows, independent) are all a sub-system needs (algorithm/closure_positions.hpp, algorithm/subsystem_maps.hpp).
struct SubSystem {
  std::vector<int> closures;        ///< indices into Model::closures
  std::vector<BodyIndex> bodies;    ///< bodies on its cycles, ascending (parents first); not the root
  BodyIndex root;                   ///< deepest common ancestor of its bodies (may be the world)
  std::vector<int> coordinates;     ///< v indices of the joints moving `bodies`, ascending
  std::vector<int> independent;     ///< subset of `coordinates`: the sub-system's own coordinates y
  /// The rest: z, solved from the closures, in the order of Phi_z's columns in its factorisation
  /// (ascending, unless loops share joints: then each loop's own first; find_subsystems.cpp).
  std::vector<int> dependent;
  std::vector<int> rows;            ///< kept (independent) constraint rows, global indices; size = rank
  /// Smallest / largest |R_ii| of Phi_z (Givens QR, rows ascending, columns as `dependent`) at the
  /// assembled pose, rounded to two significant digits (a scale, and the same constant in the
  /// generated code): what closure_positions measures this sub-system's pivot ratio against to
  /// tell a dead point in float (algorithm/closure_positions.hpp). 1 unless the loader set it.
  double nominal_pivot_ratio = 1.0;
  int rank() const { return static_cast<int>(rows.size()); }
};

}  // namespace mbgen
