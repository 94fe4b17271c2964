#pragma once
// What follows from a model's structure alone — its tree, closures, sub-systems and drives — and
// from no state: the closed system's coordinates, the bodies the loops' rows read, and each
// sub-system's layout for the O(n) recursion. The Model computes it (Model::update_structure,
// after every change of its bodies or loops) and owns it; the algorithms, the generator and the
// controllers read it from there, and Data<S> holds only the scalar workspace.
#include <vector>

#include "mbgen/index.hpp"

namespace mbgen {

/// A sub-system's bodies as the O(n) recursion walks them (algorithm/subsystem_aba.hpp).
struct SubSystemLayout {
  std::vector<int> parent_local;  ///< per body: its parent's position in SubSystem::bodies, or -1 (the root)
  /// Per body: 1 when nothing but rigid bodies of this sub-system hangs below it (no tree
  /// subtree, no other sub-system, no rotor body), so that its gathered inertia is a rigid body's
  /// and moves to the parent as mass moments (subsystem_backward).
  std::vector<char> rigid;
  /// Per coordinate: its column among the independent coordinates (>= 0), or -1 - its row among
  /// the dependent ones.
  std::vector<int> coordinate_role;
  bool operator==(const SubSystemLayout& o) const {
    return parent_local == o.parent_local && rigid == o.rigid && coordinate_role == o.coordinate_role;
  }
};

struct ModelStructure {
  /// v indices of the closed system's coordinates y: every coordinate not dependent in a
  /// sub-system, ascending (all of them for a tree). The order of independent velocities.
  std::vector<int> independent_v;
  std::vector<int> column_of_v;  ///< v index -> its place in independent_v, or -1 (dependent)
  IndexedVector<BodyIndex, int> subsystem_of_body;  ///< index into Model::subsystems, or -1 for a tree body
  /// The bodies strictly below a closure's top (the common ancestor of its two bodies) on its
  /// cycle, ascending: all the loops' rows read (algorithm/closure.hpp, detail::cycle_placements).
  std::vector<BodyIndex> cycle_bodies;
  std::vector<SubSystemLayout> subsystems;  ///< one per Model::subsystems entry
  int num_independent() const { return static_cast<int>(independent_v.size()); }
  bool operator==(const ModelStructure& o) const {
    return independent_v == o.independent_v && column_of_v == o.column_of_v && subsystem_of_body == o.subsystem_of_body &&
           cycle_bodies == o.cycle_bodies && subsystems == o.subsystems;
  }
};

}  // namespace mbgen
