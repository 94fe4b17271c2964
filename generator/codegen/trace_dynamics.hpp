#pragma once
// Traces the runtime's generic algorithms with the symbolic scalar: one TracedFunction per
// emitted function (forward and inverse dynamics, mass matrix, kinematics, Jacobians, CoM,
// centroidal momentum matrix).
#include <vector>

#include "codegen/traced_function.hpp"
#include "mbgen/algorithm/actuator_forces.hpp"
#include "mbgen/model.hpp"
#include "mbgen/contact_model.hpp"

namespace mbgen::codegen {

TracedFunction trace_forward_dynamics(const Model& model);
TracedFunction trace_inverse_dynamics(const Model& model);
/// A model with loops: forward dynamics in independent coordinates (O(n), sub-systems as
/// aggregate bodies) and the accelerations of every tree joint.
TracedFunction trace_forward_dynamics_loops(const Model& model);
/// The forward_dynamics the generator emits for `model`: trace_forward_dynamics_loops with loops,
/// else trace_forward_dynamics of the tree (inspect and mbgen_study count its operations).
TracedFunction trace_generated_forward_dynamics(const Model& model);
TracedFunction trace_full_accelerations(const Model& model);
/// The closed system's inverse dynamics for the actuators (algorithm/actuator_forces.hpp): the
/// actuated coordinates' forces and the residual on the independent ones, from (q, vy, ydd).
TracedFunction trace_actuator_forces(const Model& model, const Actuation& actuation);
TracedFunction trace_mass_matrix(const Model& model);
/// The L^T D L factor of a mass matrix given as input (algorithm/mass_matrix_factor.hpp) and x = M^-1 b from it.
TracedFunction trace_mass_matrix_factor(const Model& model);
TracedFunction trace_mass_matrix_solve(const Model& model);
/// All body poses, 12 numbers each: the 3x4 matrix [R_WB | p_WB], row-major.
TracedFunction trace_forward_kinematics(const Model& model);
/// Poses (12 numbers each, as above) of the given frames.
TracedFunction trace_frame_poses(const Model& model, const std::vector<FrameIndex>& frames);
/// Jacobians (6 x nv row-major each, LocalWorldAligned) of the given frames.
TracedFunction trace_frame_jacobians(const Model& model, const std::vector<FrameIndex>& frames);
/// Centres and body Jacobians (6 x nv, LocalWorldAligned) of the ground-contact spheres.
TracedFunction trace_contact_points(const Model& model, const std::vector<ContactSphere>& spheres);
/// The closed system's accelerations (as full_accelerations) under tau plus the ground's joint
/// forces through the contact spheres (algorithm/contact_points.hpp: contact_joint_forces, the
/// law of sim/contact.hpp for `exponent`), and per sphere what the law gave. Nothing stored in
/// between: the kinematics of the contacts and of the dynamics are one graph.
TracedFunction trace_contact_accelerations(const Model& model, const std::vector<ContactSphere>& spheres, double exponent);
TracedFunction trace_center_of_mass(const Model& model);
TracedFunction trace_centroidal_momentum_matrix(const Model& model);
/// The frames' poses and Jacobians (as the two functions above), the centre of mass and the
/// centroidal momentum matrix in one trace: GenericBackend::task_kinematics' pass of the
/// kinematics, its terms computed once.
TracedFunction trace_task_kinematics(const Model& model, const std::vector<FrameIndex>& frames);

}  // namespace mbgen::codegen
