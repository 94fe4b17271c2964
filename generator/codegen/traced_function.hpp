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
};

struct TracedFunction {
  std::string name;
  std::string doc;
  std::vector<ArraySpec> inputs;
  std::vector<ArraySpec> outputs;
  std::vector<std::vector<int>> output_ids;  ///< per output, one node id per element
  ExpressionGraph graph;
};

/// Operation count of the nodes that the outputs depend on.
OpCount count_operations(const TracedFunction& f);

}  // namespace mbgen::codegen
