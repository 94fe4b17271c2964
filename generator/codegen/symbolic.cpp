#include "codegen/symbolic.hpp"

#include <stdexcept>

namespace mbgen::codegen {

namespace {
thread_local ExpressionGraph* g_current = nullptr;
}

Recording::Recording(ExpressionGraph& graph) : previous_(g_current) { g_current = &graph; }
Recording::~Recording() { g_current = previous_; }

ExpressionGraph& Recording::graph() {
  if (!g_current) throw std::logic_error("mbgen::codegen::Sym used outside a Recording");
  return *g_current;
}

}  // namespace mbgen::codegen
