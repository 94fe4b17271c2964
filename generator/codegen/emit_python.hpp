#pragma once
// A generated robot's Python module (mbgen generate --python: <robot>_python.cpp): a pybind11
// module named after the robot that binds, for double, every function its header declares, with
// the same names and arguments, NumPy arrays in and out (mbgen/python/generated_module.hpp: shapes,
// batches, copies, the GIL), and the header's sizes and name tables as attributes. It calls the
// cpp flavour's API (namespace <robot>); docs/python.md.
#include <string>
#include <vector>

#include "codegen/emit_context.hpp"
#include "codegen/traced_function.hpp"

namespace mbgen::codegen {

/// What the module binds besides the traced functions.
struct PythonModuleContents {
  const std::vector<TracedFunction>& traced;  ///< the header's traced functions, in its order
  bool self_distances = false;                ///< self_distances and self_distances_near are declared
  bool contact = false;                       ///< the scene has contact spheres (their tables and law)
  bool frames = false;                        ///< frame_names is declared
  bool backend = false;                       ///< NAME::Backend is declared: the module binds a Simulator on it
  int nq = 0, nv = 0, num_distance_pairs = 0;
  /// --batch W: W, and the traced functions that have <name>_batch (a batched call runs W states
  /// at a time through it). 0: none.
  int batch_width = 0;
  std::vector<std::string> batched;
};

/// The file name of the module's source: <robot>_python.cpp.
std::string python_module_file(const EmitContext& ctx);

/// The module's source. The context's scalars must include double (Python's float).
std::string emit_python_module(const PythonModuleContents& contents, const EmitContext& ctx);

}  // namespace mbgen::codegen
