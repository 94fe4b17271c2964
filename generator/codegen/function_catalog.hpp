#pragma once
// The catalogue of generated functions: one row per function mbgen can emit, and everything
// else about the set derived from it — the scene outputs the extras accept (docs/extras.md), which
// functions an output brings and what they need in turn (scene_functions.hpp), the batch forms
// (emit_batch.hpp), the files mbgen_add_robot declares (cmake/mbgen_function_catalog.cmake reads
// the rows' first two fields from this file's .cpp), and the order the header declares them in.
// Adding a function is one row here, its tracer and its tests.
#include <string>
#include <vector>

#include "codegen/emit_context.hpp"
#include "codegen/trace_derivatives.hpp"
#include "codegen/traced_function.hpp"
#include "mbgen/algorithm/actuator_forces.hpp"
#include "mbgen/contact_model.hpp"
#include "mbgen/model.hpp"

namespace mbgen::codegen {

/// What a tracer may read: the closed system and its spanning tree (tree functions are traced on
/// the tree: the tree's inverse dynamics and mass matrix), the frames of frame_poses and
/// frame_jacobians, the description's actuation, its contact spheres and its rigid contacts.
struct TraceInputs {
  const Model& model;
  const Model& tree;
  const std::vector<FrameIndex>& frames;
  const Actuation& actuation;
  const std::vector<ContactSphere>& contacts;
  double contact_exponent;
  DerivativeBlocks derivative_blocks;  ///< the derivatives' inputs (trace_derivatives.hpp)
  const std::vector<RigidContact>& rigid_contacts;  ///< the scene's `rigid_contacts`, resolved
};

struct GeneratedFunction;

/// What a row's source writer may read: its own trace, the traces of the other emitted
/// functions (by name), and the closed system's independent coordinates.
struct DefinitionInputs {
  const TracedFunction& function;
  const std::vector<TracedFunction>& traced;
  const Model& model;
  const std::vector<int>& independent;  ///< v indices of the closed system's coordinates
  bool has_contacts;                    ///< the scene has contact spheres
  const EmitContext& ctx;
  /// The trace of another emitted function (the row's `needs` guarantee it is there).
  const TracedFunction& other(const std::string& name) const;
};

enum class Batch { no, yes };

/// Who writes a row's source file: its trace through `definition`, or a writer of its own
/// (closure_positions: a Newton loop around traced steps; self_distances: the collision scene's
/// pairs), which generate_robot calls by this kind.
enum class Writer { traced, closure_positions, self_distances };

struct GeneratedFunction {
  const char* name;  ///< the C++ name and the file's: <robot>_<name>.cpp
  Batch batch;       ///< also emitted over W states per call with --batch (<name>_batch)
  const char* summary;
  /// The scene outputs (extras `scene: outputs`) that bring this function.
  std::vector<std::string> outputs;
  /// Other functions emitted whenever this one is (its source reads their traces, or a user
  /// cannot use it without them).
  std::vector<std::string> needs;
  /// Emitted as well when all of these are (task_kinematics: the four in one pass).
  std::vector<std::string> with_all_of;
  bool per_frame = false;  ///< of the frames: not emitted when the robot has none
  bool always = false;     ///< emitted whatever the scene says
  /// Emitted only when one of its outputs is named (scene outputs or --outputs): not by default,
  /// nor by `all` (the derivatives: several times the dynamics' code, which few scenes need).
  bool on_request = false;
  /// false: the one-state statements are compiled without g++'s straight-line vectoriser, which
  /// packs adjacent output entries into one store (TracedFunction::pack_output_stores says why).
  bool pack_output_stores = true;
  Writer writer = Writer::traced;
  /// The trace (Writer::traced rows).
  TracedFunction (*trace)(const TraceInputs&) = nullptr;
  /// The source file from the trace; null: emit_definition of the function's own trace.
  std::string (*definition)(const DefinitionInputs&) = nullptr;
  /// The batch form's source file over `lanes` states (a Batch::yes row whose trace has work
  /// outputs); null: emit_batch_definition of the trace.
  std::string (*batch_definition)(const DefinitionInputs&, int lanes) = nullptr;
};

/// Every function mbgen emits, in the order the header declares them.
const std::vector<GeneratedFunction>& function_catalog();

/// The row named `name`, or null.
const GeneratedFunction* find_function(const std::string& name);

/// The names of the rows, in catalogue order.
std::vector<std::string> all_functions();

/// The rows with a batch form, in catalogue order.
std::vector<std::string> batched_functions();

/// The scene outputs: every output some row names, sorted.
std::vector<std::string> scene_outputs();

/// The scene output that asks for the simulator (NAME::Backend and what it calls); implied by a
/// scene with `contact:`.
inline constexpr const char* kSimulationOutput = "simulation";

}  // namespace mbgen::codegen
