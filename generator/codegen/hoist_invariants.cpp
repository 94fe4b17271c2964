#include "codegen/hoist_invariants.hpp"

#include <stdexcept>
#include <string>

namespace mbgen::codegen {

namespace {

bool is_leaf(const Node& n) { return n.op == Op::Constant || n.op == Op::Input; }

/// Marks `needed` for every node that `roots` reach, not looking past the nodes `stop` marks
/// (themselves marked).
void mark_reachable(const ExpressionGraph& g, const std::vector<int>& roots, const std::vector<bool>& stop,
                    std::vector<bool>& needed) {
  std::vector<int> pending(roots);
  while (!pending.empty()) {
    const int id = pending.back();
    pending.pop_back();
    if (needed[static_cast<std::size_t>(id)]) continue;
    needed[static_cast<std::size_t>(id)] = true;
    if (stop[static_cast<std::size_t>(id)]) continue;
    const Node& n = g.node(id);
    if (n.a >= 0) pending.push_back(n.a);
    if (n.b >= 0) pending.push_back(n.b);
  }
}

/// Copies the `needed` nodes of `from` into `to` in ascending id order, so that the relative
/// order of any two copies is theirs (ExpressionGraph puts commutative operands in id order: a
/// max of a NaN depends on the side). `replace(id)`, when it returns a node of `to`, stands for id.
/// The graph builders simplify; `from` is already simplified, so each copy keeps its operation.
template <typename Replace>
std::vector<int> copy_nodes(const ExpressionGraph& from, const std::vector<bool>& needed, ExpressionGraph& to, Replace replace) {
  std::vector<int> id_in_to(static_cast<std::size_t>(from.size()), -1);
  for (int id = 0; id < from.size(); ++id) {
    if (!needed[static_cast<std::size_t>(id)]) continue;
    int copy = replace(id);
    if (copy < 0) {
      const Node& n = from.node(id);
      auto operand = [&](int x) { return id_in_to[static_cast<std::size_t>(x)]; };
      switch (n.op) {
        case Op::Constant: copy = to.constant(n.value); break;
        case Op::Input: copy = to.input(n.input, n.index); break;
        case Op::Neg:
        case Op::Sin:
        case Op::Cos:
        case Op::Sqrt:
        case Op::Step: copy = to.unary(n.op, operand(n.a)); break;
        default: copy = to.binary(n.op, operand(n.a), operand(n.b)); break;
      }
      if (to.node(copy).op != n.op) throw std::logic_error("hoist_invariants: a copied node changed its operation");
    }
    id_in_to[static_cast<std::size_t>(id)] = copy;
  }
  return id_in_to;
}

}  // namespace

HoistedFunction hoist_invariants(const TracedFunction& f, const std::function<bool(int argument, int index)>& varies) {
  const ExpressionGraph& g = f.graph;
  const std::size_t size = static_cast<std::size_t>(g.size());
  std::vector<int> outputs;
  for (const auto& ids : f.output_ids) outputs.insert(outputs.end(), ids.begin(), ids.end());
  std::vector<bool> nothing(size, false), used(size, false);
  mark_reachable(g, outputs, nothing, used);

  // Operands have smaller ids than their node: one ascending pass settles invariance.
  std::vector<bool> invariant(size, false);
  for (std::size_t id = 0; id < size; ++id) {
    const Node& n = g.node(static_cast<int>(id));
    if (n.op == Op::Constant) invariant[id] = true;
    else if (n.op == Op::Input) invariant[id] = !varies(n.input, n.index);
    else invariant[id] = invariant[static_cast<std::size_t>(n.a)] && (n.b < 0 || invariant[static_cast<std::size_t>(n.b)]);
  }
  // The boundary: invariant statements that a varying statement or an output reads.
  std::vector<bool> boundary(size, false);
  for (std::size_t id = 0; id < size; ++id) {
    const Node& n = g.node(static_cast<int>(id));
    if (!used[id] || invariant[id] || is_leaf(n)) continue;
    for (int operand : {n.a, n.b})
      if (operand >= 0 && invariant[static_cast<std::size_t>(operand)] && !is_leaf(g.node(operand)))
        boundary[static_cast<std::size_t>(operand)] = true;
  }
  for (int id : outputs)
    if (invariant[static_cast<std::size_t>(id)] && !is_leaf(g.node(id))) boundary[static_cast<std::size_t>(id)] = true;
  std::vector<int> slot(size, -1), boundary_ids;
  for (std::size_t id = 0; id < size; ++id)
    if (boundary[id]) slot[id] = static_cast<int>(boundary_ids.size()), boundary_ids.push_back(static_cast<int>(id));
  const int w_size = static_cast<int>(boundary_ids.size());
  const ArraySpec w{"invariants", w_size, std::to_string(w_size) + " values computed by " + f.name + "_setup"};

  HoistedFunction out;
  TracedFunction& setup = out.setup;
  setup.name = f.name + "_setup";
  setup.doc = "The values of " + f.name + " that depend only on inputs the loop does not change, computed once before it.";
  setup.inputs = f.inputs;
  setup.outputs = {w};
  std::vector<bool> setup_needed(size, false);
  mark_reachable(g, boundary_ids, nothing, setup_needed);
  const std::vector<int> in_setup = copy_nodes(g, setup_needed, setup.graph, [](int) { return -1; });
  setup.output_ids.emplace_back();
  for (int id : boundary_ids) setup.output_ids.back().push_back(in_setup[static_cast<std::size_t>(id)]);

  TracedFunction& body = out.body;
  body.name = f.name;
  body.doc = f.doc;
  body.inputs = f.inputs;
  body.inputs.push_back(w);
  body.outputs = f.outputs;
  std::vector<bool> body_needed(size, false);
  mark_reachable(g, outputs, boundary, body_needed);
  const int w_argument = static_cast<int>(f.inputs.size());
  const std::vector<int> in_body = copy_nodes(g, body_needed, body.graph, [&](int id) {
    return boundary[static_cast<std::size_t>(id)] ? body.graph.input(w_argument, slot[static_cast<std::size_t>(id)]) : -1;
  });
  for (const auto& ids : f.output_ids) {
    body.output_ids.emplace_back();
    for (int id : ids) body.output_ids.back().push_back(in_body[static_cast<std::size_t>(id)]);
  }
  return out;
}

}  // namespace mbgen::codegen
