#include "codegen/function_catalog.hpp"

#include <algorithm>
#include <numeric>
#include <set>
#include <stdexcept>

#include "codegen/emit_cpp.hpp"
#include "codegen/emit_derivatives.hpp"
#include "codegen/trace_derivatives.hpp"
#include "codegen/trace_dynamics.hpp"
#include "codegen/trace_loop_maps.hpp"
#include "mbgen/algorithm/loop_dynamics_derivatives.hpp"

namespace mbgen::codegen {

const TracedFunction& DefinitionInputs::other(const std::string& name) const {
  const auto it = std::find_if(traced.begin(), traced.end(), [&](const TracedFunction& g) { return g.name == name; });
  if (it == traced.end()) throw std::logic_error("function catalogue: " + function.name + " needs " + name + ", which was not traced");
  return *it;
}

namespace {

// One copy of the unrolled dynamics: with loops, forward_dynamics is full_accelerations read at
// the independent coordinates; without, full_accelerations is forward_dynamics whole.
std::string forward_dynamics_source(const DefinitionInputs& in) {
  if (in.model.subsystems.empty()) return emit_definition(in.function, in.ctx);
  return emit_selection_definition(in.function, in.other("full_accelerations"), in.independent, in.ctx);
}

std::string full_accelerations_source(const DefinitionInputs& in) {
  if (!in.model.subsystems.empty()) return emit_definition(in.function, in.ctx);
  std::vector<int> all(static_cast<std::size_t>(in.model.nv()));
  std::iota(all.begin(), all.end(), 0);
  return emit_selection_definition(in.function, in.other("forward_dynamics"), all, in.ctx);
}

// full_velocities is velocity_map's product with vy: one copy of the unrolled maps.
std::string full_velocities_source(const DefinitionInputs& in) {
  return emit_product_definition(in.function, in.other("velocity_map"), in.ctx);
}

// Each velocity index's parent in the tree (-1: none): the mass matrix factor's structure.
std::vector<int> tree_parents(const Model& tree) {
  std::vector<int> parent;
  for (int k = 0; k < tree.nv(); ++k) parent.push_back(tree.velocity_parent(k));
  return parent;
}

// Without contact spheres, contact_accelerations is a call of full_accelerations.
std::string contact_accelerations_source(const DefinitionInputs& in) {
  if (in.has_contacts) return emit_definition(in.function, in.ctx);
  return emit_contact_free_definition(in.function, in.other("full_accelerations"), in.independent, in.ctx);
}

}  // namespace

// Each row begins `row("name", Batch::...`: cmake/mbgen_function_catalog.cmake reads those two
// fields from this file, so keep them on the row's first line.
const std::vector<GeneratedFunction>& function_catalog() {
  static const std::vector<GeneratedFunction> rows = [] {
    std::vector<GeneratedFunction> r;
    const auto row = [&r](const char* name, Batch batch, const char* summary, std::vector<std::string> outputs,
                          std::vector<std::string> needs = {}, std::vector<std::string> with_all_of = {}) {
      GeneratedFunction f;
      f.name = name, f.batch = batch, f.summary = summary;
      f.outputs = std::move(outputs), f.needs = std::move(needs), f.with_all_of = std::move(with_all_of);
      r.push_back(std::move(f));
    };
    // clang-format off
    row("forward_dynamics", Batch::yes,
         "accelerations of the closed system's independent coordinates (articulated-body algorithm, loops as sub-systems)",
         {"forward_dynamics"}, {"full_accelerations"});
    r.back().trace = [](const TraceInputs& in) { return trace_generated_forward_dynamics(in.model); };
    r.back().definition = forward_dynamics_source;
    row("full_accelerations", Batch::no, "accelerations of every tree joint of the closed system",
         {"forward_dynamics", kSimulationOutput}, {"forward_dynamics"});
    r.back().trace = [](const TraceInputs& in) { return trace_full_accelerations(in.model); };
    r.back().definition = full_accelerations_source;
    row("velocity_map", Batch::no, "the map T with v = T vy from the independent velocities to every tree joint's",
         {"forward_dynamics", kSimulationOutput});
    r.back().trace = [](const TraceInputs& in) { return trace_velocity_map(in.model); };
    row("full_velocities", Batch::no, "every tree joint's velocity v = T vy",
         {"forward_dynamics", kSimulationOutput}, {"velocity_map"});
    r.back().trace = [](const TraceInputs& in) { return trace_full_velocities(in.model); };
    r.back().definition = full_velocities_source;
    row("acceleration_bias", Batch::no, "the bias g with qdd = T ydd + g", {"forward_dynamics"});
    r.back().trace = [](const TraceInputs& in) { return trace_acceleration_bias(in.model); };
    row("inverse_dynamics", Batch::yes, "the spanning tree's joint forces (recursive Newton-Euler)",
         {"inverse_dynamics", kSimulationOutput});
    r.back().trace = [](const TraceInputs& in) { return trace_inverse_dynamics(in.tree); };
    row("actuator_forces", Batch::yes, "the closed system's inverse dynamics for its actuators",
         {"inverse_dynamics", kSimulationOutput});
    r.back().trace = [](const TraceInputs& in) { return trace_actuator_forces(in.model, in.actuation); };
    row("mass_matrix", Batch::yes, "the spanning tree's mass matrix (composite-rigid-body algorithm)",
         {"mass_matrix", kSimulationOutput});
    r.back().trace = [](const TraceInputs& in) { return trace_mass_matrix(in.tree); };
    r.back().pack_output_stores = false;
    row("mass_matrix_factor", Batch::yes, "the sparse factor M = L^T D L of mass_matrix's output", {"mass_matrix"});
    r.back().trace = [](const TraceInputs& in) { return trace_mass_matrix_factor(in.tree); };
    row("mass_matrix_solve", Batch::yes, "x = M^-1 b from mass_matrix_factor's factor", {"mass_matrix"});
    r.back().trace = [](const TraceInputs& in) { return trace_mass_matrix_solve(in.tree); };
    row("forward_kinematics", Batch::yes, "every body's pose in the world", {"forward_kinematics"});
    r.back().trace = [](const TraceInputs& in) { return trace_forward_kinematics(in.tree); };
    row("frame_poses", Batch::yes, "the frames' poses in the world", {"forward_kinematics", "jacobians"});
    r.back().per_frame = true;
    r.back().trace = [](const TraceInputs& in) { return trace_frame_poses(in.tree, in.frames); };
    row("frame_jacobians", Batch::yes, "the frames' Jacobians (local world-aligned)", {"jacobians"});
    r.back().per_frame = true;
    r.back().trace = [](const TraceInputs& in) { return trace_frame_jacobians(in.tree, in.frames); };
    row("center_of_mass", Batch::yes, "the centre of mass in the world", {"center_of_mass", kSimulationOutput});
    r.back().trace = [](const TraceInputs& in) { return trace_center_of_mass(in.tree); };
    row("centroidal_momentum_matrix", Batch::yes, "the centroidal momentum matrix A_G(q)", {"centroidal_momentum"});
    r.back().trace = [](const TraceInputs& in) { return trace_centroidal_momentum_matrix(in.tree); };
    r.back().pack_output_stores = false;
    // A scene with the four parts of a controller's kinematics gets them in one pass too.
    row("task_kinematics", Batch::no, "frame_poses, frame_jacobians, center_of_mass and centroidal_momentum_matrix in one pass",
         {}, {}, {"frame_poses", "frame_jacobians", "center_of_mass", "centroidal_momentum_matrix"});
    r.back().per_frame = true;
    r.back().trace = [](const TraceInputs& in) { return trace_task_kinematics(in.tree, in.frames); };
    // The position level of the loops, which every function of a closed system presumes (it
    // returns at once without loops).
    row("closure_positions", Batch::no, "closes the loops: the dependent coordinates from the independent ones (Newton)", {});
    r.back().always = true;
    r.back().writer = Writer::closure_positions;
    // The loops in full coordinates, for a solver that keeps them by multipliers: the simulator's
    // soft span through a dead point (docs/simulation.md). No rows without loops.
    row("closure_constraints", Batch::no, "the kept closure rows in full coordinates: residual, Jacobian and bias",
         {kSimulationOutput});
    r.back().trace = [](const TraceInputs& in) { return trace_closure_constraints(in.model); };
    row("self_distances", Batch::no, "distances, witness points and Jacobians of the scene's SSV pairs", {"distances"});
    r.back().writer = Writer::self_distances;
    row("contact_points", Batch::no, "centres and Jacobians of the ground-contact spheres", {kSimulationOutput});
    r.back().trace = [](const TraceInputs& in) { return trace_contact_points(in.tree, in.contacts); };
    row("contact_accelerations", Batch::no, "the closed system's accelerations under the ground's forces",
         {kSimulationOutput}, {"full_accelerations"});
    r.back().trace = [](const TraceInputs& in) { return trace_contact_accelerations(in.model, in.contacts, in.contact_exponent); };
    r.back().definition = contact_accelerations_source;
    // The derivatives (docs/derivatives.md), of the spanning tree: on request only.
    row("inverse_dynamics_derivatives", Batch::yes, "inverse_dynamics and its derivatives dtau/dq, dtau/dv (analytic)",
         {"id_derivatives"});
    r.back().on_request = true;
    r.back().trace = [](const TraceInputs& in) { return trace_inverse_dynamics_derivatives(in.tree, in.derivative_blocks); };
    row("forward_dynamics_derivatives", Batch::yes, "the forward dynamics and its derivatives dqdd/dq, dqdd/dv, dqdd/dtau",
         {"fd_derivatives"});
    r.back().on_request = true;
    r.back().trace = [](const TraceInputs& in) {
      if (!in.model.subsystems.empty()) return trace_loop_forward_dynamics_derivatives(in.model, in.derivative_blocks);
      return trace_forward_dynamics_derivatives(in.tree, in.derivative_blocks);
    };
    // The solves with M (a tree: dqdd/dq, dqdd/dv) or M_y (a closed system: and dydd/dtau) run as
    // row loops (emit_derivatives.hpp), of the blocks the function has.
    r.back().definition = [](const DefinitionInputs& in) {
      if (!in.model.subsystems.empty())
        return emit_forward_dynamics_derivatives_definition(
            in.function, closed_mass_matrix_elimination_tree(in.model),
            solved_outputs(in.function, {"dqdd_dq", "dqdd_dv", "dqdd_dtau"}), in.ctx);
      return emit_forward_dynamics_derivatives_definition(in.function, tree_parents(in.model),
                                                          solved_outputs(in.function, {"dqdd_dq", "dqdd_dv"}), in.ctx);
    };
    r.back().batch_definition = [](const DefinitionInputs& in, int lanes) {
      if (!in.model.subsystems.empty())
        return emit_forward_dynamics_derivatives_batch_definition(
            in.function, closed_mass_matrix_elimination_tree(in.model),
            solved_outputs(in.function, {"dqdd_dq", "dqdd_dv", "dqdd_dtau"}), lanes, in.ctx);
      return emit_forward_dynamics_derivatives_batch_definition(
          in.function, tree_parents(in.model), solved_outputs(in.function, {"dqdd_dq", "dqdd_dv"}), lanes, in.ctx);
    };
    row("contact_forward_dynamics_derivatives", Batch::no,
         "the forward dynamics under the compliant ground and its derivatives dqdd/dq, dqdd/dv, dqdd/dtau (trees)",
         {"contact_fd_derivatives"});
    r.back().on_request = true;
    r.back().trace = [](const TraceInputs& in) {
      return trace_contact_forward_dynamics_derivatives(in.model, in.contacts, in.contact_exponent, in.derivative_blocks);
    };
    r.back().definition = [](const DefinitionInputs& in) {
      return emit_forward_dynamics_derivatives_definition(in.function, tree_parents(in.model),
                                                          solved_outputs(in.function, {"dqdd_dq", "dqdd_dv"}), in.ctx);
    };
    row("rigid_contact_forward_dynamics_derivatives", Batch::no,
         "the forward dynamics with the scene's rigid contacts held, the contact forces, and their derivatives (trees)",
         {"rigid_contact_fd_derivatives"});
    r.back().on_request = true;
    r.back().trace = [](const TraceInputs& in) {
      return trace_rigid_contact_forward_dynamics_derivatives(in.model, in.rigid_contacts, in.derivative_blocks);
    };
    r.back().definition = [](const DefinitionInputs& in) {
      return emit_rigid_contact_derivatives_definition(in.function, tree_parents(in.model),
                                                       solved_outputs(in.function, {"dqdd_dq", "dqdd_dv"}), in.ctx);
    };
    // clang-format on
    return r;
  }();
  return rows;
}

const GeneratedFunction* find_function(const std::string& name) {
  for (const GeneratedFunction& f : function_catalog())
    if (name == f.name) return &f;
  return nullptr;
}

std::vector<std::string> all_functions() {
  std::vector<std::string> names;
  for (const GeneratedFunction& f : function_catalog()) names.push_back(f.name);
  return names;
}

std::vector<std::string> batched_functions() {
  std::vector<std::string> names;
  for (const GeneratedFunction& f : function_catalog())
    if (f.batch == Batch::yes) names.push_back(f.name);
  return names;
}

std::vector<std::string> scene_outputs() {
  std::set<std::string> outputs;
  for (const GeneratedFunction& f : function_catalog()) outputs.insert(f.outputs.begin(), f.outputs.end());
  return {outputs.begin(), outputs.end()};
}

}  // namespace mbgen::codegen
