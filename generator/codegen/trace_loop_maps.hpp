#pragma once
// Traces the maps between the closed system's coordinate sets (runtime: closure_positions.hpp,
// subsystem_maps.hpp): one Newton step of the closure (the generated closure_positions loops
// over it), the velocity map T, full velocities T vy and the acceleration bias g.
#include <vector>

#include "codegen/traced_function.hpp"
#include "mbgen/model.hpp"

namespace mbgen::codegen {

/// Total rank of the sub-systems: the number of dependent coordinates (0 without loops).
int num_dependent(const Model& model);

/// Where each sub-system's part of closure_newton_step's factor begins (one entry more than the
/// sub-systems; the last is the factor's length): per sub-system of rank n, n (n - 1) / 2 cosines,
/// as many sines and R's n (n + 1) / 2 upper entries.
std::vector<int> closure_factor_begin(const Model& model);

/// closure_newton_step(q, residual, pivots, step, factor): at q (nq), per sub-system in order,
/// the kept closure rows (residual), the diagonal of Phi_z's Givens R factor (pivots) and the
/// Newton step Phi_z^-1 Phi (step, to subtract from the dependent coordinates in
/// SubSystem::dependent order), each num_dependent(model) long; and the factor itself (factor,
/// closure_factor_begin(model).back() long), for the loop's simplified steps. Needs a model with loops.
/// with_velocities: closure_newton_step_velocities(q, v, residual, pivots, step, vz), also the
/// dependent velocities from v's independent ones at q (vz, the same order), for close_loops; no
/// factor (close_loops takes no simplified step).
TracedFunction trace_closure_newton_step(const Model& model, bool with_velocities = false);
/// closure_residual(q, residual): the kept closure rows at q alone (the step's residual output,
/// the same expressions): the generated closure_positions checks a predicted final iterate with it.
TracedFunction trace_closure_residual(const Model& model);
/// closure_constraints(q, v, Phi, J, gamma): the kept closure rows (num_dependent(model), no
/// rows without loops) in full coordinates: residual, Jacobian (rows x nv, row-major), bias.
TracedFunction trace_closure_constraints(const Model& model);
/// velocity_map(q, T): T (nv x ny, row-major) with v = T vy.
TracedFunction trace_velocity_map(const Model& model);
/// full_velocities(q, vy, v): v = T vy.
TracedFunction trace_full_velocities(const Model& model);
/// acceleration_bias(q, vy, g): qdd = T ydd + g.
TracedFunction trace_acceleration_bias(const Model& model);

}  // namespace mbgen::codegen
