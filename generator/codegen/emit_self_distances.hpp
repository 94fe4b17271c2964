#pragma once
// Emits `self_distances`: the distance, normal, witness points and distance-Jacobian row of every
// pair a collision scene keeps (DESIGN.md, "Swept-sphere volumes"; generic twin:
// collision::compute_distances + compute_distance_jacobians).
//
// Two parts, as DESIGN.md's "One implementation of the math" asks:
//  - branch-free: the shapes' points (and bounding-sphere centres) placed in the world by the body
//    poses, and the world joint-Jacobian columns that support the bodies with shapes, traced with
//    the symbolic scalar from forward_kinematics / compute_joint_jacobians and printed
//    straight-line into local arrays P and J;
//  - data-dependent: per pair, the shape pairs unrolled as calls into the runtime's SSV
//    primitives (ssv_distance) through ClosestShapes (closest_shapes.hpp: the bounding-sphere skip
//    of compound_distance, same order), then the Jacobian row over the supporting columns only.
#include <string>

#include "codegen/emit_cpp.hpp"
#include "mbgen/collision/collision_model.hpp"
#include "mbgen/model.hpp"

namespace mbgen::codegen {

struct SelfDistanceCode {
  /// header.fmt's num_distance_pairs, distance_pair_rows, distance_pair_names and
  /// distance_declarations (distance_declarations.fmt rendered).
  TemplateFields header_fields;
  std::string source;  ///< self_distances_source.fmt rendered: the source file
};

/// Always emits the function, with num_distance_pairs = 0 and an empty body when the scene keeps
/// no pair (so that the generated file set does not depend on the description).
SelfDistanceCode emit_self_distances(const Model& model, const collision::CollisionModel& scene, const EmitContext& ctx);

}  // namespace mbgen::codegen
