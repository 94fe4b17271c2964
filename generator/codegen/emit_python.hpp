#pragma once
// A generated robot's Python module (mbgen generate --python: <robot>_python.cpp): a pybind11
// module named after the robot that binds, for double, every function its header declares, with
// the same names and arguments, NumPy arrays in and out (mbgen/python/generated_module.hpp: shapes,
// batches, copies, the GIL), and the header's sizes and name tables as attributes. It calls the
// cpp flavour's API (namespace <robot>); docs/python.md. Its text is templates/cpp/python's.
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

/// The module's templates (templates/cpp/python/*.fmt; docs/templates.md): the file's skeleton
/// and each binding's; codegen fills in the arrays, shapes, names and docstrings.
const std::vector<TemplateSpec>& python_template_catalog();

/// Where they are: the python/ folder of the cpp flavour's templates (the module binds that
/// flavour's API).
std::string python_templates_directory(const std::string& cpp_templates);

/// The file name of the module's source: <robot>_python.cpp.
std::string python_module_file(const EmitContext& ctx);

/// The module's source, from `templates` (a set of python_template_catalog()). The context's
/// scalars must include double (Python's float).
std::string emit_python_module(const PythonModuleContents& contents, const EmitContext& ctx, const TemplateSet& templates);

}  // namespace mbgen::codegen
