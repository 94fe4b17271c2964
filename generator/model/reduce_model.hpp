#pragma once
// Model reductions (docs/extras.md, "Model reductions"): a scene that needs less than the whole
// robot asks for a smaller model, and the generated code shrinks with it.
//  - `lock`: welds joints at given values: the child body becomes part of its parent (its
//    inertia lumped in, its frames and children re-attached with the joint's pose at that value),
//    its coordinate is gone;
//  - `merge_below: m`: every limb (a body with everything below it) lighter than m kg, moving no
//    loop and hanging from a moving body, is welded at the reference pose (joint values 0) into
//    its parent;
//  - `loops: transmission`: every sub-system of loops replaced by the map from its actuators to
//    its output joints, the linkage welded at the reference pose (model/transmissions.hpp).
// A joint that a loop closure needs (one on a loop's path) cannot be welded: the loop would lose
// its freedom; that is a LoadError naming the loop. Mass and centre of mass are conserved at the
// welded pose (welding to the world removes that body from the dynamics, as a fixed base does).
#include <map>
#include <string>

#include "load/description.hpp"

namespace mbgen::gen {

/// The model with the joints of `values` (name -> value) welded. Bodies keep their order; each
/// welded joint's name stays as a frame (kind Joint) at its child body's frame, and frame indices
/// of the input stay valid. Throws std::invalid_argument for an unknown or multi-DoF joint.
Model weld_joints(const Model& model, const std::map<std::string, double>& values);

/// The description with the scene's `lock`, `merge_below` and `loops` applied (model, drives,
/// hints, closures), and what each removed recorded in its `reductions`. The same description
/// when its scene asks for none.
Description reduce_model(Description description);

}  // namespace mbgen::gen
