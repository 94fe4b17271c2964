#pragma once
// A function of arrays traced into an expression graph: what the emitter prints.
#include <string>
#include <vector>

#include "codegen/expression_graph.hpp"

namespace mbgen::codegen {

struct ArraySpec {
  std::string name;
  int size = 0;
  std::string doc;  ///< size and layout, for the header comment
  /// Its shape as an array of the bindings (a generated Python module's NumPy shape: rows, cols
  /// of a row-major matrix; per frame a 3 x 4 pose): empty for a vector of `size`.
  std::vector<int> shape = {};
};

struct TracedFunction {
  std::string name;
  std::string doc;
  std::vector<ArraySpec> inputs;
  std::vector<ArraySpec> outputs;
  std::vector<std::vector<int>> output_ids;  ///< per output, one node id per element
  /// The last `work_outputs` outputs are work arrays, not results: the impl writes them, the row's
  /// own source (its catalogue `definition`) keeps them local, and the public signature, the
  /// header's declaration, leaves them out (forward_dynamics_derivatives: the factor of M its
  /// solves read).
  int work_outputs = 0;
  /// false: its statements function carries MBGEN_GENERATED_SCALAR_STORES (scalar_stores_macro.fmt),
  /// which keeps g++ from packing adjacent output entries into one vector store. Set from the
  /// catalogue for the functions of hundreds of output entries whose neighbours come from distant
  /// statements (the mass matrix's columns run down different chains): packing holds the early
  /// values in registers or on the stack until their neighbours exist (bench/README.md).
  bool pack_output_stores = true;
  ExpressionGraph graph;
};

/// Operation count of the nodes that the outputs depend on.
OpCount count_operations(const TracedFunction& f);

}  // namespace mbgen::codegen
