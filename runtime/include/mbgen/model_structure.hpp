#pragma once
// What follows from a model's structure alone — its tree, closures and sub-systems — and not from
// any state: the closed system's coordinates and the bodies the loops' rows read. Data<S> keeps
// these tables for the algorithms; the generator and the loaders read them from here, without a
// workspace.
#include <vector>

#include "mbgen/model.hpp"

namespace mbgen {

/// v indices of the closed system's coordinates y: every coordinate not dependent in a
/// sub-system, ascending (all of them for a tree). The order of independent velocities.
inline std::vector<int> independent_coordinates(const Model& model) {
  std::vector<bool> dependent(static_cast<std::size_t>(model.nv()), false);
  for (const SubSystem& s : model.subsystems)
    for (int z : s.dependent) dependent[static_cast<std::size_t>(z)] = true;
  std::vector<int> independent;
  for (int i = 0; i < model.nv(); ++i)
    if (!dependent[static_cast<std::size_t>(i)]) independent.push_back(i);
  return independent;
}

/// v index -> its place among independent_coordinates(model), or -1 (dependent).
inline std::vector<int> column_of_coordinates(const Model& model) {
  std::vector<int> column(static_cast<std::size_t>(model.nv()), -1);
  const std::vector<int> independent = independent_coordinates(model);
  for (std::size_t c = 0; c < independent.size(); ++c) column[static_cast<std::size_t>(independent[c])] = static_cast<int>(c);
  return column;
}

/// Body -> the index of the sub-system it belongs to, or -1 for a tree body.
inline IndexedVector<BodyIndex, int> subsystem_of_bodies(const Model& model) {
  IndexedVector<BodyIndex, int> of(model.num_bodies(), -1);
  for (std::size_t k = 0; k < model.subsystems.size(); ++k)
    for (BodyIndex b : model.subsystems[k].bodies) of[b] = static_cast<int>(k);
  return of;
}

/// The bodies strictly below a closure's top (the common ancestor of its two bodies) on its
/// cycle, ascending: all the loops' rows read (algorithm/closure.hpp, detail::cycle_placements).
inline std::vector<BodyIndex> cycle_bodies(const Model& model) {
  std::vector<bool> on_cycle(static_cast<std::size_t>(model.num_bodies()), false);
  for (const LoopClosure& c : model.closures) {
    const BodyIndex top = common_ancestor(model, c.body_a, c.body_b);
    for (BodyIndex b : {c.body_a, c.body_b})
      for (; b != top; b = model.body(b).parent) on_cycle[static_cast<std::size_t>(b.value())] = true;
  }
  std::vector<BodyIndex> bodies;
  for (int k = 1; k < model.num_bodies(); ++k)
    if (on_cycle[static_cast<std::size_t>(k)]) bodies.push_back(BodyIndex(k));
  return bodies;
}

}  // namespace mbgen
