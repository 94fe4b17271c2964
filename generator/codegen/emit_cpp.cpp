#include "codegen/emit_cpp.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <functional>
#include <set>
#include <stdexcept>

namespace mbgen::codegen {

namespace {

/// Nodes that the outputs depend on.
std::vector<bool> reachable(const TracedFunction& f) {
  std::vector<bool> seen(static_cast<std::size_t>(f.graph.size()), false);
  std::vector<int> stack;
  for (const auto& ids : f.output_ids)
    for (int id : ids) stack.push_back(id);
  while (!stack.empty()) {
    const int id = stack.back();
    stack.pop_back();
    if (seen[static_cast<std::size_t>(id)]) continue;
    seen[static_cast<std::size_t>(id)] = true;
    const Node& n = f.graph.node(id);
    if (n.a >= 0) stack.push_back(n.a);
    if (n.b >= 0) stack.push_back(n.b);
  }
  return seen;
}

}  // namespace

std::string sincos_helper(const EmitContext& ctx, bool uses_trig) {
  // A rendered template ends without its last newline: a blank line parts the helpers from what follows.
  return ctx.inline_sincos || uses_trig ? ctx.templates.render("sincos", {}) + "\n\n" : std::string();
}

bool uses_trig(const TracedFunction& f) {
  const std::vector<bool> seen = reachable(f);
  for (int id = 0; id < f.graph.size(); ++id)
    if (seen[static_cast<std::size_t>(id)] && (f.graph.node(id).op == Op::Sin || f.graph.node(id).op == Op::Cos)) return true;
  return false;
}

std::string call_arguments(const TracedFunction& f) {
  std::string args;
  for (const ArraySpec& a : f.inputs) args += fmt::format("{}{}", args.empty() ? "" : ", ", a.name);
  for (const ArraySpec& a : f.outputs) args += fmt::format("{}{}", args.empty() ? "" : ", ", a.name);
  return args;
}

std::string literal(double value) {
  // fmt prints the shortest representation that reads back to the same double.
  return fmt::format("S({})", value);
}

OpCount count_operations(const TracedFunction& f) {
  const std::vector<bool> seen = reachable(f);
  OpCount c;
  for (int id = 0; id < f.graph.size(); ++id) {
    if (!seen[static_cast<std::size_t>(id)]) continue;
    switch (f.graph.node(id).op) {
      case Op::Add:
      case Op::Sub: ++c.add; break;
      case Op::Mul: ++c.mul; break;
      case Op::Div: ++c.div; break;
      case Op::Neg: ++c.neg; break;
      case Op::Sin:
      case Op::Cos: ++c.trig; break;
      case Op::Sqrt: ++c.sqrt; break;
      case Op::Max:
      case Op::Step: ++c.max; break;
      case Op::Pow: ++c.pow; break;
      default: break;
    }
  }
  return c;
}

std::vector<std::string> scalar_types(ScalarChoice choice) {
  switch (choice) {
    case ScalarChoice::Double: return {"double"};
    case ScalarChoice::Float: return {"float"};
    case ScalarChoice::Both: return {"double", "float"};
  }
  return {};
}

std::string describe_operations(const OpCount& c) {
  return fmt::format("{} operations: {} additions/subtractions, {} multiplications, {} divisions, {} negations, "
                     "{} sin/cos, {} square roots{}{}",
                     c.total(), c.add, c.mul, c.div, c.neg, c.trig, c.sqrt,
                     c.max > 0 ? fmt::format(", {} max (selects)", c.max) : std::string(),
                     c.pow > 0 ? fmt::format(", {} powers", c.pow) : std::string());
}

std::string parameters(const TracedFunction& f, const std::string& scalar) { return batch_parameters(f, scalar, 0); }

std::string public_parameters(const TracedFunction& f, const std::string& scalar) {
  std::string args;
  for (const ArraySpec& a : f.inputs) args += fmt::format("{}const {}* {}", args.empty() ? "" : ", ", scalar, a.name);
  for (std::size_t k = 0; k + static_cast<std::size_t>(f.work_outputs) < f.outputs.size(); ++k)
    args += fmt::format("{}{}* {}", args.empty() ? "" : ", ", scalar, f.outputs[k].name);
  return args;
}

std::string emit_declaration(const TracedFunction& f, const EmitContext& ctx) {
  std::string arguments, prototypes;
  for (const ArraySpec& a : f.inputs) arguments += ctx.templates.render("input_doc", {{"name", a.name}, {"doc", a.doc}});
  for (std::size_t k = 0; k + static_cast<std::size_t>(f.work_outputs) < f.outputs.size(); ++k)
    arguments += ctx.templates.render("output_doc", {{"name", f.outputs[k].name}, {"doc", f.outputs[k].doc}});
  for (const std::string& s : scalar_types(ctx.scalars))
    prototypes += ctx.templates.render("prototype", {{"public_name", ctx.public_name(f.name, s)},
                                                     {"parameters", public_parameters(f, s)},
                                                     {"scalar", s},
                                                     {"function", f.name},
                                                     {"robot", ctx.robot}});
  return ctx.templates.render("function_declaration", {{"doc", f.doc},
                                                       {"cost", describe_operations(count_operations(f))},
                                                       {"arguments", arguments},
                                                       {"prototypes", prototypes}});
}

std::string emit_entry_points(const std::string& function, const std::string& arguments,
                              const std::function<std::string(const std::string&)>& parameters_for, const EmitContext& ctx) {
  std::string out;
  for (const std::string& s : scalar_types(ctx.scalars))
    out += ctx.templates.render("entry_point", {{"public_name", ctx.public_name(function, s)},
                                                {"parameters", parameters_for(s)},
                                                {"function", function},
                                                {"scalar", s},
                                                {"arguments", arguments},
                                                {"robot", ctx.robot}});
  return out;
}

namespace {

bool is_statement(const Node& n) { return n.op != Op::Constant && n.op != Op::Input; }

/// An array parameter: `S* q` for one state, `S (*q)[lanes]` (q[i][w]: entry i of state w) for lanes.
std::string array_parameter(const std::string& name, const std::string& scalar, int lanes) {
  return lanes > 0 ? fmt::format("{} (*{})[{}]", scalar, name, lanes) : fmt::format("{}* {}", scalar, name);
}

std::string input_parameters(const TracedFunction& f, const std::string& scalar, int lanes) {
  std::string args;
  for (const ArraySpec& a : f.inputs) args += fmt::format("{}const {}", args.empty() ? "" : ", ", array_parameter(a.name, scalar, lanes));
  return args;
}

/// How statements are printed: for one state (`const S _t3 = _t1 * _t2;`) or for `lanes` states
/// at once (`const V _t3 = _t1 * _t2;`, V a GCC vector of S; batch_source.fmt defines the
/// lanes_* helpers). The operations and their order are the same, so that each lane computes
/// bit for bit what the one-state function computes.
class StatementPrinter {
 public:
  StatementPrinter(const TracedFunction& f, const std::vector<bool>& seen, StatementStyle style)
      : f_(f), seen_(seen), lanes_(style.lanes), inline_sincos_(style.inline_sincos || style.lanes > 0) {
    if (!batch()) gather_angles();
    if (style.angles_by_pointer) angle_bias_ = angle_pointer_bias();
    if (!inline_sincos_) return;
    // sin and cos of one argument are computed together (sincos_of gives both).
    std::vector<int> sin_of(static_cast<std::size_t>(f.graph.size()), -1), cos_of(sin_of);
    for (int id = 0; id < f.graph.size(); ++id) {
      if (!seen[static_cast<std::size_t>(id)]) continue;
      const Node& n = f.graph.node(id);
      if (n.op == Op::Sin) sin_of[static_cast<std::size_t>(n.a)] = id;
      if (n.op == Op::Cos) cos_of[static_cast<std::size_t>(n.a)] = id;
    }
    partner_.assign(static_cast<std::size_t>(f.graph.size()), -1);
    for (std::size_t x = 0; x < sin_of.size(); ++x)
      if (sin_of[x] >= 0 && cos_of[x] >= 0) {
        partner_[static_cast<std::size_t>(sin_of[x])] = cos_of[x];
        partner_[static_cast<std::size_t>(cos_of[x])] = sin_of[x];
      }
  }

  bool batch() const { return lanes_ > 0; }
  /// A sin or cos of an input, computed in the prologue (one state only).
  bool in_prologue(int id) const { return angle_slot_.empty() ? false : angle_slot_[static_cast<std::size_t>(id)] >= 0; }
  bool has_prologue() const { return !angles_.empty(); }

  /// One state: the sines and cosines of the inputs, all at once before any statement
  /// (sincos_all of sincos.fmt: one loop over sincos_of that g++ vectorises, 2 to 8 angles per
  /// instruction; libm calls, one by one, cost each function its fixed share: a third of talos'
  /// mass matrix). `_angle` is padded with zeros to a multiple of 4 lanes so that -O2, which
  /// vectorises only loops without a remainder, vectorises it too.
  std::string prologue() const {
    if (angles_.empty()) return std::string();
    const std::size_t padded = (angles_.size() + 3) / 4 * 4;
    std::string list;
    for (std::size_t k = 0; k < padded; ++k) {
      if (k > 0) list += ", ";
      list += k < angles_.size() ? input_name(angles_[k]) : std::string("S(0)");
    }
    return fmt::format("  const S _angle[{0}] = {{{1}}};\n  S _sin[{0}], _cos[{0}];\n  sincos_all(_angle, _sin, _cos);\n", padded, list);
  }
  const char* value_type() const { return batch() ? "V" : "S"; }

  /// Where the pointers handed to a function of the statements point: `_sin + bias`. The
  /// statements read `_sin[slot - bias]`, offsets -128 to 120 bytes for 32 doubles: x86-64
  /// addresses them with an 8-bit displacement from the pointer's register, where the arrays of
  /// a large function's own stack frame sit beyond it (a 32-bit displacement and a SIB byte:
  /// 9-byte instead of 5-byte instructions, a sixth of talos' mass matrix; bench/README.md).
  int angle_pointer_bias() const { return static_cast<int>(std::min<std::size_t>(16, (angles_.size() + 3) / 4 * 4)); }

  /// Constants and inputs are printed in place; statements get `_tN` (N their rank in id order).
  std::vector<std::string> leaf_and_temporary_names() const {
    std::vector<std::string> names(static_cast<std::size_t>(f_.graph.size()));
    int temporaries = 0;
    for (int id = 0; id < f_.graph.size(); ++id) {
      if (!seen_[static_cast<std::size_t>(id)]) continue;
      const Node& n = f_.graph.node(id);
      std::string& name = names[static_cast<std::size_t>(id)];
      if (n.op == Op::Constant) {
        name = literal(n.value);
      } else if (n.op == Op::Input) {
        const std::string element = input_name(id);
        name = batch() ? fmt::format("lanes_load<V>({})", element) : element;
      } else if (in_prologue(id)) {
        name = fmt::format("{}[{}]", n.op == Op::Sin ? "_sin" : "_cos", angle_slot_[static_cast<std::size_t>(id)] - angle_bias_);
      } else {
        name = fmt::format("_t{}", temporaries++);
      }
    }
    return names;
  }

  /// The order `run` (ids in topological order) is printed in: its own, except that in a batch
  /// the libm calls of inputs come first: every call spills the live vectors (no vector register
  /// survives a call), and at the top nothing is live yet. Their values do not change.
  std::vector<int> print_order(const std::vector<int>& run) const {
    std::vector<int> order = run;
    if (batch())
      std::stable_partition(order.begin(), order.end(), [&](int id) { return is_libm_call_of_leaves(f_.graph.node(id)); });
    return order;
  }

  /// The statements of `run` (ids in topological order) in print_order, their operands named by
  /// `name`, each declared `const <value_type> <name(id)> = ...;`, and after the k-th of them
  /// `after[k]` (when `after` is given: one entry per statement). A sin/cos pair within the run
  /// is printed once, at the first of the two, when they are inline.
  template <typename Name>
  std::string statements(const std::vector<int>& run, Name name, const std::vector<std::string>* after = nullptr) const {
    std::string out;
    std::vector<int> in_run;
    const std::vector<int> order = print_order(run);
    if (inline_sincos_) in_run = run;  // sorted: ids ascend
    for (std::size_t k = 0; k < order.size(); ++k) {
      if (after && k > 0) out += (*after)[k - 1];
      const int id = order[k];
      const Node& n = f_.graph.node(id);
      const int partner = inline_sincos_ && (n.op == Op::Sin || n.op == Op::Cos) ? partner_[static_cast<std::size_t>(id)] : -1;
      if (partner >= 0 && std::binary_search(in_run.begin(), in_run.end(), partner)) {
        if (partner < id) continue;  // printed with its partner (sin and cos keep their order: only sqrt and pow move up)
        const int s = n.op == Op::Sin ? id : partner, c = n.op == Op::Sin ? partner : id;
        out += fmt::format("  const auto [{}, {}] = sincos_of<S>({});\n", name(s), name(c), vector_operand(n.a, name));
        continue;
      }
      out += fmt::format("  const {} {} = {};\n", value_type(), name(id), expression(id, name));
    }
    if (after && !order.empty()) out += after->back();
    return out;
  }

  bool is_libm_call_of_leaves(const Node& n) const {
    const bool call = n.op == Op::Sqrt || n.op == Op::Pow;  // sin and cos are inline in a batch
    return call && !is_statement(f_.graph.node(n.a)) && (n.b < 0 || !is_statement(f_.graph.node(n.b)));
  }

  /// `target = value;` for an output element or a workspace slot.
  template <typename Name> std::string assignment(const std::string& target, int id, Name name) const {
    return batch() ? fmt::format("  lanes_store({}, {});\n", target, vector_operand(id, name))
                   : fmt::format("  {} = {};\n", target, name(id));
  }

 private:
  std::string input_name(int id) const {
    const Node& n = f_.graph.node(id);
    return fmt::format("{}[{}]", f_.inputs.at(static_cast<std::size_t>(n.input)).name, n.index);
  }

  /// angles_: the inputs whose sin or cos the function takes, in the order of their first sin
  /// or cos; angle_slot_[id]: a sin or cos node's index in it (else -1).
  void gather_angles() {
    angle_slot_.assign(static_cast<std::size_t>(f_.graph.size()), -1);
    std::vector<int> slot_of_input(static_cast<std::size_t>(f_.graph.size()), -1);
    for (int id = 0; id < f_.graph.size(); ++id) {
      const Node& n = f_.graph.node(id);
      if (!seen_[static_cast<std::size_t>(id)] || (n.op != Op::Sin && n.op != Op::Cos) || f_.graph.node(n.a).op != Op::Input) continue;
      int& slot = slot_of_input[static_cast<std::size_t>(n.a)];
      if (slot < 0) {
        slot = static_cast<int>(angles_.size());
        angles_.push_back(n.a);
      }
      angle_slot_[static_cast<std::size_t>(id)] = slot;
    }
  }

  /// An operand that must be a vector in a batch: a constant is broadcast.
  template <typename Name> std::string vector_operand(int id, Name name) const {
    return batch() && f_.graph.is_constant(id) ? fmt::format("lanes_broadcast<V>({})", name(id)) : std::string(name(id));
  }

  template <typename Name> std::string expression(int id, Name name) const {
    const Node& n = f_.graph.node(id);
    if (inline_sincos_ && (n.op == Op::Sin || n.op == Op::Cos))
      return fmt::format("sincos_of<S>({}).{}", vector_operand(n.a, name), n.op == Op::Sin ? "sin" : "cos");
    if (!batch()) {
      switch (n.op) {
        case Op::Sin: return fmt::format("std::sin({})", name(n.a));
        case Op::Cos: return fmt::format("std::cos({})", name(n.a));
        case Op::Sqrt: return fmt::format("std::sqrt({})", name(n.a));
        // A select, not std::fmax: no libm call on a microcontroller.
        case Op::Max: return fmt::format("{0} > {1} ? {0} : {1}", name(n.a), name(n.b));
        case Op::Step: return fmt::format("{} > S(0) ? S(1) : S(0)", name(n.a));
        case Op::Pow: return fmt::format("std::pow({}, {})", name(n.a), name(n.b));
        default: return arithmetic(n, name(n.a), n.b >= 0 ? std::string(name(n.b)) : std::string());
      }
    }
    switch (n.op) {
      case Op::Sqrt: return fmt::format("lanes_sqrt({})", vector_operand(n.a, name));
      case Op::Max: return fmt::format("lanes_max({}, {})", vector_operand(n.a, name), vector_operand(n.b, name));
      case Op::Step: return fmt::format("lanes_step({})", vector_operand(n.a, name));
      case Op::Pow: return fmt::format("lanes_pow({}, {})", vector_operand(n.a, name), vector_operand(n.b, name));
      default: {
        // Vector (op) scalar is a vector; scalar (op) scalar is not: then the first is broadcast.
        const bool all_constant = f_.graph.is_constant(n.a) && (n.b < 0 || f_.graph.is_constant(n.b));
        return arithmetic(n, all_constant ? vector_operand(n.a, name) : std::string(name(n.a)),
                          n.b >= 0 ? std::string(name(n.b)) : std::string());
      }
    }
  }

  static std::string arithmetic(const Node& n, const std::string& a, const std::string& b) {
    switch (n.op) {
      case Op::Add: return fmt::format("{} + {}", a, b);
      case Op::Sub: return fmt::format("{} - {}", a, b);
      case Op::Mul: return fmt::format("{} * {}", a, b);
      case Op::Div: return fmt::format("{} / {}", a, b);
      case Op::Neg: return fmt::format("-{}", a);
      default: break;
    }
    throw std::logic_error("expression: not a statement");
  }

  const TracedFunction& f_;
  const std::vector<bool>& seen_;
  int lanes_;
  bool inline_sincos_;
  std::vector<int> partner_;  ///< inline sin/cos: the cos of a sin's argument and vice versa, else -1
  std::vector<int> angles_;      ///< one state: the input nodes whose sin and cos the prologue computes
  int angle_bias_ = 0;           ///< statements reading the prologue's arrays through pointers: angle_pointer_bias
  std::vector<int> angle_slot_;  ///< one state: a prologue sin or cos node's index in angles_, else -1
};

/// Every output's assignments, or (with `only`) those of the outputs it marks.
std::string output_assignments(const TracedFunction& f, const StatementPrinter& printer, const std::vector<std::string>& names,
                               const std::vector<bool>* only = nullptr, bool skip_constants = false) {
  auto name = [&](int id) -> const std::string& { return names[static_cast<std::size_t>(id)]; };
  std::string body;
  for (std::size_t o = 0; o < f.outputs.size(); ++o)
    for (std::size_t i = 0; i < (only && !(*only)[o] ? 0 : f.output_ids[o].size()); ++i)
      if (!(skip_constants && f.graph.is_constant(f.output_ids[o][i])))
        body += printer.assignment(fmt::format("{}[{}]", f.outputs[o].name, i), f.output_ids[o][i], name);
  return body;
}

/// From this many constant output entries on, a one-state function writes them by a function of
/// their own, called last (see split_statements): large mass matrices, Jacobians, velocity maps,
/// contact Jacobians. Below it the separate pass costs what the packed stores save, or more
/// (hyq's mass matrix, 120 zeros: 2-5 % slower so).
constexpr int kConstantOutputsApart = 256;

/// f's constant output entries (structural zeros, a robot's total mass, the identity blocks of a
/// velocity map): how many, `<prefix>_constants<S>(outputs...)` writing them, and its call.
struct ConstantOutputs {
  int count = 0;
  std::string definition, call;
};
ConstantOutputs constant_outputs(const TracedFunction& f, const std::string& prefix) {
  ConstantOutputs c;
  std::string parameters, arguments, stores;
  for (std::size_t o = 0; o < f.outputs.size(); ++o) {
    const int before = c.count;
    for (std::size_t i = 0; i < f.output_ids[o].size(); ++i) {
      const int id = f.output_ids[o][i];
      if (!f.graph.is_constant(id)) continue;
      ++c.count;
      stores += fmt::format("  {}[{}] = {};\n", f.outputs[o].name, i, literal(f.graph.node(id).value));
    }
    if (c.count == before) continue;
    parameters += fmt::format("{}S* {}", parameters.empty() ? "" : ", ", f.outputs[o].name);
    arguments += (arguments.empty() ? "" : ", ") + f.outputs[o].name;
  }
  c.definition = fmt::format("// The {} output entries that are the same at every call, by a function of their own: g++\n"
                             "// vectorises no basic block as large as {}'s, and stores them there 8 bytes at a time.\n"
                             "template <typename S>\nMBGEN_GENERATED_NOINLINE void {}_constants({}) {{\n{}}}\n\n",
                             c.count, f.name, prefix, parameters, stores);
  c.call = fmt::format("  {}_constants<S>({});\n", prefix, arguments);
  return c;
}

/// The output assignments placed early: after[k] holds those printed after the k-th statement of
/// `order` (the print order), the rest are returned. An output is written as soon as its value
/// exists, instead of all at the end: a value kept for the end outlives most of the function, so
/// it is spilled to the stack and reloaded to be stored (talos' mass matrix: 12,734 -> 11,756
/// instructions per call, 12 % faster; bench/README.md). No output is written before the last statement reading an
/// input, so every input is read before any output is written, as when all were written last:
/// a caller passing an output that overlaps an input gets what it got before.
std::string place_output_assignments(const TracedFunction& f, const StatementPrinter& printer, const std::vector<std::string>& names,
                                     const std::vector<int>& order, std::vector<std::string>& after, const std::vector<bool>& placed,
                                     bool skip_constants) {
  auto name = [&](int id) -> const std::string& { return names[static_cast<std::size_t>(id)]; };
  std::vector<int> position(static_cast<std::size_t>(f.graph.size()), -1);
  int last_read = -1;
  auto reads_input = [&](int operand) { return operand >= 0 && f.graph.node(operand).op == Op::Input; };
  for (std::size_t k = 0; k < order.size(); ++k) {
    const int id = order[k];
    position[static_cast<std::size_t>(id)] = static_cast<int>(k);
    if (reads_input(f.graph.node(id).a) || reads_input(f.graph.node(id).b)) last_read = static_cast<int>(k);
  }
  // An output that copies an input reads it where it is written: then every write stays at the end.
  for (const auto& ids : f.output_ids)
    for (int id : ids)
      if (f.graph.node(id).op == Op::Input) last_read = static_cast<int>(order.size()) - 1;
  after.assign(order.size(), std::string());
  std::string first;  // outputs written before any statement: no statement reads an input, and their values are leaves
  for (std::size_t o = 0; o < f.outputs.size(); ++o)
    for (std::size_t i = 0; i < (placed[o] ? f.output_ids[o].size() : 0); ++i) {
      const int id = f.output_ids[o][i];
      if (skip_constants && f.graph.is_constant(id)) continue;
      const int k = std::max(position[static_cast<std::size_t>(id)], last_read);
      (k < 0 ? first : after[static_cast<std::size_t>(k)]) += printer.assignment(fmt::format("{}[{}]", f.outputs[o].name, i), id, name);
    }
  return first;
}

std::vector<int> statement_ids(const TracedFunction& f, const std::vector<bool>& seen, const StatementPrinter& printer) {
  std::vector<int> statements;
  for (int id = 0; id < f.graph.size(); ++id)
    if (seen[static_cast<std::size_t>(id)] && is_statement(f.graph.node(id)) && !printer.in_prologue(id)) statements.push_back(id);
  return statements;
}

}  // namespace

std::string unused_inputs(const TracedFunction& f) {
  std::string out;
  for (const ArraySpec& a : f.inputs) out += fmt::format("  (void){};\n", a.name);
  // An empty output (contact_points without contact spheres) is never written to.
  for (const ArraySpec& a : f.outputs)
    if (a.size == 0) out += fmt::format("  (void){};\n", a.name);
  return out;
}

namespace {
/// emit_statements after its prologue, printed by `printer`.
std::string statements_and_outputs(const TracedFunction& f, const std::vector<bool>& seen, const StatementPrinter& printer,
                                   const StatementStyle& style) {
  const std::vector<std::string> names = printer.leaf_and_temporary_names();
  auto name = [&](int id) -> const std::string& { return names[static_cast<std::size_t>(id)]; };
  const std::vector<int> run = statement_ids(f, seen, printer);
  // Which outputs are written as soon as they exist; the others are written at the end.
  std::vector<bool> early(f.outputs.size(), style.early_outputs);
  for (std::size_t o = 0; o < f.outputs.size(); ++o)
    if (std::find(style.early_anyway.begin(), style.early_anyway.end(), f.outputs[o].name) != style.early_anyway.end()) early[o] = true;
  std::vector<bool> late(early.size());
  for (std::size_t o = 0; o < early.size(); ++o) late[o] = !early[o];
  const bool skip = style.constants_apart;
  if (std::find(early.begin(), early.end(), true) == early.end())
    return printer.statements(run, name) + output_assignments(f, printer, names, nullptr, skip);
  std::vector<std::string> after;
  const std::string first = place_output_assignments(f, printer, names, printer.print_order(run), after, early, skip);
  return first + printer.statements(run, name, &after) + output_assignments(f, printer, names, &late, skip);
}
}  // namespace

std::string emit_statements(const TracedFunction& f, StatementStyle style) {
  const std::vector<bool> seen = reachable(f);
  const StatementPrinter printer(f, seen, style);
  return printer.prologue() + statements_and_outputs(f, seen, printer, style);
}

std::string batch_parameters(const TracedFunction& f, const std::string& scalar, int lanes) {
  std::string args = input_parameters(f, scalar, lanes);
  for (const ArraySpec& a : f.outputs) args += fmt::format("{}{}", args.empty() ? "" : ", ", array_parameter(a.name, scalar, lanes));
  return args;
}

std::string public_batch_parameters(const TracedFunction& f, const std::string& scalar, int lanes) {
  std::string args = input_parameters(f, scalar, lanes);
  for (std::size_t k = 0; k + static_cast<std::size_t>(f.work_outputs) < f.outputs.size(); ++k)
    args += fmt::format("{}{}", args.empty() ? "" : ", ", array_parameter(f.outputs[k].name, scalar, lanes));
  return args;
}

namespace {
SplitStatements split_statements_of(const TracedFunction& f, const std::string& prefix, int max_statements, StatementStyle style);

/// The attribute scalar_stores_macro.fmt defines, on the statements of a one-state function whose
/// catalogue row asks for its output entries to be stored one by one (pack_output_stores).
constexpr const char* kScalarStores = "MBGEN_GENERATED_SCALAR_STORES";
bool scalar_stores(const TracedFunction& f, const StatementStyle& style) { return !f.pack_output_stores && style.lanes == 0; }
}  // namespace

SplitStatements split_statements(const TracedFunction& f, const std::string& prefix, int max_statements, StatementStyle style) {
  const ConstantOutputs constants = constant_outputs(f, prefix);
  style.constants_apart = style.lanes == 0 && constants.count >= kConstantOutputsApart;
  SplitStatements out = split_statements_of(f, prefix, max_statements, style);
  if (style.constants_apart) {
    out.parts += constants.definition;
    out.body += constants.call;
  }
  return out;
}

namespace {
SplitStatements split_statements_of(const TracedFunction& f, const std::string& prefix, int max_statements, StatementStyle style) {
  const std::vector<bool> seen = reachable(f);
  StatementStyle apart_style = style;  // the statements are in functions of their own, unless returned below
  apart_style.angles_by_pointer = true;
  const StatementPrinter printer(f, seen, apart_style);
  const std::vector<int> statements = statement_ids(f, seen, printer);
  const int count = static_cast<int>(statements.size());
  const std::string angle_pointers = fmt::format("_sin + {0}, _cos + {0}", printer.angle_pointer_bias());
  if (count <= max_statements) {
    if (!printer.has_prologue() || count < kStatementsApartFrom) return {"", emit_statements(f, style)};
    // One part of all the statements, reading the sines through pointers (angle_pointer_bias).
    SplitStatements out;
    out.parts = fmt::format("// {0}'s statements, apart from the sines and cosines of its inputs (the body's prologue):\n"
                            "// they read them through pointers, in shorter instructions than from their own frame.\n"
                            "template <typename S>\nMBGEN_GENERATED_NOINLINE {2}void {0}_statements({1}, const S* __restrict _sin, "
                            "const S* __restrict _cos) {{\n",
                            prefix, parameters(f, "S"), scalar_stores(f, style) ? std::string(kScalarStores) + " " : "");
    out.parts += unused_inputs(f) + "  (void)_sin;\n  (void)_cos;\n" + statements_and_outputs(f, seen, printer, apart_style) + "}\n\n";
    out.body = printer.prologue() + fmt::format("  {}_statements<S>({}, {});\n", prefix, call_arguments(f), angle_pointers);
    return out;
  }

  // Parts of equal size, in id order (a topological order): part_of[id] for statements.
  const int parts = (count + max_statements - 1) / max_statements;
  const int per_part = (count + parts - 1) / parts;
  std::vector<int> part_of(static_cast<std::size_t>(f.graph.size()), -1);
  for (int k = 0; k < count; ++k) part_of[static_cast<std::size_t>(statements[static_cast<std::size_t>(k)])] = k / per_part;
  // The last part reading each statement (`parts`: the caller, which assigns the outputs).
  std::vector<int> last_use(part_of);
  auto use = [&](int operand, int part) {
    if (operand >= 0 && part_of[static_cast<std::size_t>(operand)] >= 0)
      last_use[static_cast<std::size_t>(operand)] = std::max(last_use[static_cast<std::size_t>(operand)], part);
  };
  for (int id : statements) {
    use(f.graph.node(id).a, part_of[static_cast<std::size_t>(id)]);
    use(f.graph.node(id).b, part_of[static_cast<std::size_t>(id)]);
  }
  for (const auto& ids : f.output_ids)
    for (int id : ids) use(id, parts);

  // Workspace slots for the values that outlive their part. A part reads the workspace in its
  // statements and writes its own values at its end, so a slot whose value is last read in
  // part p takes a value of part p; the lowest free slot first (deterministic, and the
  // workspace stays as small as the widest boundary between parts).
  std::vector<int> slot(static_cast<std::size_t>(f.graph.size()), -1);
  std::set<int> free_slots;
  int slots = 0;
  std::vector<std::vector<int>> released(static_cast<std::size_t>(parts) + 1), stored(static_cast<std::size_t>(parts));
  for (int id : statements) {
    const int p = part_of[static_cast<std::size_t>(id)], last = last_use[static_cast<std::size_t>(id)];
    if (last == p) continue;
    stored[static_cast<std::size_t>(p)].push_back(id);
    released[static_cast<std::size_t>(last)].push_back(id);
  }
  for (int p = 0; p < parts; ++p) {
    for (int id : released[static_cast<std::size_t>(p)]) free_slots.insert(slot[static_cast<std::size_t>(id)]);
    for (int id : stored[static_cast<std::size_t>(p)]) {
      int& s = slot[static_cast<std::size_t>(id)];
      if (free_slots.empty()) {
        s = slots++;
      } else {
        s = *free_slots.begin();
        free_slots.erase(free_slots.begin());
      }
    }
  }

  const std::vector<std::string> local_names = printer.leaf_and_temporary_names();
  std::vector<std::string> workspace_names(local_names);
  for (int id : statements)
    if (slot[static_cast<std::size_t>(id)] >= 0) workspace_names[static_cast<std::size_t>(id)] = fmt::format("w[{}]", slot[static_cast<std::size_t>(id)]);

  const std::string value = printer.value_type();
  SplitStatements out;
  for (int p = 0; p < parts; ++p) {
    out.parts += fmt::format("template <typename S>\nMBGEN_GENERATED_NOINLINE void {}_part{}({}, {}{}* w) {{\n", prefix, p,
                             input_parameters(f, "S", style.lanes), printer.has_prologue() ? "const S* __restrict _sin, const S* __restrict _cos, " : "",
                             printer.batch() ? "typename Lanes<S>::type" : "S");
    if (printer.batch()) out.parts += "  typedef typename Lanes<S>::type V __attribute__((unused));\n";
    out.parts += unused_inputs(f);
    if (printer.has_prologue()) out.parts += "  (void)_sin;\n  (void)_cos;\n";
    auto name = [&](int id) -> const std::string& {
      const std::size_t i = static_cast<std::size_t>(id);
      return part_of[i] == p ? local_names[i] : workspace_names[i];
    };
    const std::vector<int> run(statements.begin() + p * per_part, statements.begin() + std::min(count, (p + 1) * per_part));
    out.parts += printer.statements(run, name);
    // A workspace slot holds a vector whole: plain assignment in both forms.
    for (int id : stored[static_cast<std::size_t>(p)])
      out.parts += fmt::format("  {} = {};\n", workspace_names[static_cast<std::size_t>(id)], local_names[static_cast<std::size_t>(id)]);
    out.parts += "}\n\n";
  }
  std::string arguments;
  for (const ArraySpec& a : f.inputs) arguments += a.name + ", ";
  if (printer.has_prologue()) arguments += angle_pointers + ", ";
  out.body = printer.prologue();
  out.body += fmt::format("  // {} statements in {} parts (kept apart: compile time grows faster than their size);\n"
                         "  // w carries the {} values that cross a part boundary.\n  {} w[{}];\n",
                         count, parts, slots, value, std::max(slots, 1));
  for (int p = 0; p < parts; ++p) out.body += fmt::format("  {}_part{}<S>({}w);\n", prefix, p, arguments);
  out.body += output_assignments(f, printer, workspace_names, nullptr, style.constants_apart);
  return out;
}
}  // namespace

std::string emit_definition(const TracedFunction& f, const EmitContext& ctx) {
  if (f.work_outputs > 0) throw std::logic_error("emit_definition: " + f.name + " has work outputs: its row writes its entry points");
  return emit_definition(f, ctx, "",
                         emit_entry_points(f.name, call_arguments(f), [&](const std::string& s) { return parameters(f, s); }, ctx));
}

std::string emit_definition(const TracedFunction& f, const EmitContext& ctx, const std::string& helpers,
                            const std::string& entry_points) {
  const SplitStatements split = split_statements(f, f.name, ctx.max_statements_per_part, {0, ctx.inline_sincos});
  std::string noinline;
  if (!split.parts.empty()) noinline = ctx.templates.render("noinline_macro", {});
  if (split.parts.find(kScalarStores) != std::string::npos) noinline += ctx.templates.render("scalar_stores_macro", {});
  return ctx.templates.render("function_source",
                              {{"banner", ctx.banner},
                               {"header", ctx.header},
                               {"robot", ctx.robot},
                               {"function", f.name},
                               {"doc", f.doc},
                               {"cost", describe_operations(count_operations(f))},
                               {"sincos", sincos_helper(ctx, uses_trig(f))},
                               {"noinline", noinline},
                               {"parts", helpers + split.parts},
                               {"impl_parameters", parameters(f, "S")},
                               {"body", unused_inputs(f) + split.body},
                               {"entry_points", entry_points}});
}

namespace {
std::string input_names(const TracedFunction& f, std::size_t count) {
  std::string args;
  for (std::size_t i = 0; i < count; ++i) args += (i ? ", " : "") + f.inputs[i].name;
  return args;
}
}  // namespace

std::string emit_selection_definition(const TracedFunction& f, const TracedFunction& source, const std::vector<int>& selection,
                                      const EmitContext& ctx) {
  if (f.inputs.size() != source.inputs.size() || f.outputs.size() != 1 || source.outputs.size() != 1 ||
      static_cast<int>(selection.size()) != f.outputs[0].size)
    throw std::logic_error("emit_selection_definition: " + f.name + " is not a selection of " + source.name);
  std::string copies;
  for (std::size_t i = 0; i < selection.size(); ++i) copies += fmt::format("  {}[{}] = all[{}];\n", f.outputs[0].name, i, selection[i]);
  std::string definitions;
  for (const std::string& s : scalar_types(ctx.scalars))
    definitions += ctx.templates.render("selection_definition", {{"public_name", ctx.public_name(f.name, s)},
                                                                 {"parameters", parameters(f, s)},
                                                                 {"scalar", s},
                                                                 {"callee", ctx.public_name(source.name, s)},
                                                                 {"size", std::to_string(source.outputs[0].size)},
                                                                 {"arguments", input_names(f, f.inputs.size())},
                                                                 {"copies", copies}});
  return ctx.templates.render("selection_source", {{"banner", ctx.banner},
                                                   {"header", ctx.header},
                                                   {"robot", ctx.robot},
                                                   {"doc", f.doc},
                                                   {"source_function", source.name},
                                                   {"kept", std::to_string(selection.size())},
                                                   {"size", std::to_string(source.outputs[0].size)},
                                                   {"definitions", definitions}});
}

std::string emit_contact_free_definition(const TracedFunction& f, const TracedFunction& source, const std::vector<int>& independent,
                                         const EmitContext& ctx) {
  std::string copies;
  for (std::size_t i = 0; i < independent.size(); ++i) copies += fmt::format("  vy[{}] = v[{}];\n", i, independent[i]);
  std::string definitions;
  for (const std::string& s : scalar_types(ctx.scalars))
    definitions += ctx.templates.render("contact_free_definition", {{"public_name", ctx.public_name(f.name, s)},
                                                                    {"parameters", parameters(f, s)},
                                                                    {"scalar", s},
                                                                    {"callee", ctx.public_name(source.name, s)},
                                                                    {"ny", std::to_string(independent.size())},
                                                                    {"copies", copies}});
  return ctx.templates.render("contact_free_source", {{"banner", ctx.banner},
                                                      {"header", ctx.header},
                                                      {"robot", ctx.robot},
                                                      {"doc", f.doc},
                                                      {"source_function", source.name},
                                                      {"definitions", definitions}});
}

std::string emit_product_definition(const TracedFunction& f, const TracedFunction& source, const EmitContext& ctx) {
  const std::size_t n_in = source.inputs.size();
  if (f.inputs.size() != n_in + 1 || f.outputs.size() != 1 || source.outputs.size() != 1 ||
      source.outputs[0].size != f.outputs[0].size * f.inputs[n_in].size)
    throw std::logic_error("emit_product_definition: " + f.name + " is not a product of " + source.name);
  const int rows = f.outputs[0].size, cols = f.inputs[n_in].size;
  const std::string& A = source.outputs[0].name;
  const std::string& x = f.inputs[n_in].name;
  std::string definitions;
  for (const std::string& scalar : scalar_types(ctx.scalars)) {
    std::string statements;
    for (int r = 0; r < rows; ++r) {
      std::string sum;
      for (int c = 0; c < cols; ++c) {
        const int id = source.output_ids[0][static_cast<std::size_t>(r * cols + c)];
        if (source.graph.is_constant(id, 0)) continue;
        const std::string term = source.graph.is_constant(id, 1) ? fmt::format("{}[{}]", x, c)
                                                                 : fmt::format("{}[{}] * {}[{}]", A, r * cols + c, x, c);
        sum += (sum.empty() ? "" : " + ") + term;
      }
      statements += fmt::format("  {}[{}] = {};\n", f.outputs[0].name, r, sum.empty() ? scalar + "(0)" : sum);
    }
    definitions += ctx.templates.render("product_definition", {{"public_name", ctx.public_name(f.name, scalar)},
                                                               {"parameters", parameters(f, scalar)},
                                                               {"scalar", scalar},
                                                               {"callee", ctx.public_name(source.name, scalar)},
                                                               {"matrix", A},
                                                               {"size", std::to_string(source.outputs[0].size)},
                                                               {"arguments", input_names(f, n_in)},
                                                               {"rows", statements}});
  }
  return ctx.templates.render("product_source", {{"banner", ctx.banner},
                                                 {"header", ctx.header},
                                                 {"robot", ctx.robot},
                                                 {"doc", f.doc},
                                                 {"source_function", source.name},
                                                 {"matrix", A},
                                                 {"vector", x},
                                                 {"definitions", definitions}});
}

}  // namespace mbgen::codegen
