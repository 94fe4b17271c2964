#include "mbgen/codegen/emit_cpp.hpp"

#include <fmt/format.h>

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

std::string signature(const TracedFunction& f, const std::string& scalar) {
  std::string args;
  for (const ArraySpec& a : f.inputs) args += fmt::format("{}const {}* {}", args.empty() ? "" : ", ", scalar, a.name);
  for (const ArraySpec& a : f.outputs) args += fmt::format("{}{}* {}", args.empty() ? "" : ", ", scalar, a.name);
  return fmt::format("void {}({})", f.name, args);
}

std::string call_arguments(const TracedFunction& f) {
  std::string args;
  for (const ArraySpec& a : f.inputs) args += fmt::format("{}{}", args.empty() ? "" : ", ", a.name);
  for (const ArraySpec& a : f.outputs) args += fmt::format("{}{}", args.empty() ? "" : ", ", a.name);
  return args;
}

}  // namespace

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
      case Op::Max: ++c.max; break;
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
                     "{} sin/cos, {} square roots{}",
                     c.total(), c.add, c.mul, c.div, c.neg, c.trig, c.sqrt,
                     c.max > 0 ? fmt::format(", {} max (selects)", c.max) : std::string());
}

std::string emit_declaration(const TracedFunction& f, ScalarChoice scalars) {
  std::string out = fmt::format("/// {}\n", f.doc);
  for (const ArraySpec& a : f.inputs) out += fmt::format("/// in  {}: {}\n", a.name, a.doc);
  for (const ArraySpec& a : f.outputs) out += fmt::format("/// out {}: {}\n", a.name, a.doc);
  out += fmt::format("/// Cost: {}.\n", describe_operations(count_operations(f)));
  for (const std::string& s : scalar_types(scalars)) out += signature(f, s) + ";\n";
  return out;
}

std::string emit_statements(const TracedFunction& f) {
  const std::vector<bool> seen = reachable(f);
  std::vector<std::string> names(static_cast<std::size_t>(f.graph.size()));
  auto operand = [&](int id) -> const std::string& { return names[static_cast<std::size_t>(id)]; };
  std::string body;
  body.reserve(64 * static_cast<std::size_t>(f.graph.size()));
  int temporaries = 0;
  for (int id = 0; id < f.graph.size(); ++id) {
    if (!seen[static_cast<std::size_t>(id)]) continue;
    const Node& n = f.graph.node(id);
    std::string& name = names[static_cast<std::size_t>(id)];
    std::string expr;
    switch (n.op) {
      case Op::Constant: name = literal(n.value); continue;
      case Op::Input: name = fmt::format("{}[{}]", f.inputs.at(static_cast<std::size_t>(n.input)).name, n.index); continue;
      case Op::Add: expr = fmt::format("{} + {}", operand(n.a), operand(n.b)); break;
      case Op::Sub: expr = fmt::format("{} - {}", operand(n.a), operand(n.b)); break;
      case Op::Mul: expr = fmt::format("{} * {}", operand(n.a), operand(n.b)); break;
      case Op::Div: expr = fmt::format("{} / {}", operand(n.a), operand(n.b)); break;
      case Op::Neg: expr = fmt::format("-{}", operand(n.a)); break;
      case Op::Sin: expr = fmt::format("std::sin({})", operand(n.a)); break;
      case Op::Cos: expr = fmt::format("std::cos({})", operand(n.a)); break;
      case Op::Sqrt: expr = fmt::format("std::sqrt({})", operand(n.a)); break;
      // A select, not std::fmax: no libm call on a microcontroller.
      case Op::Max: expr = fmt::format("{0} > {1} ? {0} : {1}", operand(n.a), operand(n.b)); break;
    }
    name = fmt::format("_t{}", temporaries++);
    body += fmt::format("  const S {} = {};\n", name, expr);
  }
  for (std::size_t o = 0; o < f.outputs.size(); ++o)
    for (std::size_t i = 0; i < f.output_ids[o].size(); ++i)
      body += fmt::format("  {}[{}] = {};\n", f.outputs[o].name, i, operand(f.output_ids[o][i]));
  return body;
}

std::string emit_definition(const TracedFunction& f, const std::string& ns, const std::string& header,
                            ScalarChoice scalars) {
  const std::string body = emit_statements(f);
  std::string out = fmt::format("#include \"{}\"\n\n#include <cmath>\n\nnamespace {} {{\n\nnamespace {{\n\n", header, ns);
  out += fmt::format("// {}\n// {}.\ntemplate <typename S>\n", f.doc, describe_operations(count_operations(f)));
  std::string impl_sig = signature(f, "S");
  impl_sig.replace(impl_sig.find(f.name), f.name.size(), f.name + "_impl");
  std::string unused;
  for (const ArraySpec& a : f.inputs) unused += fmt::format("  (void){};\n", a.name);
  out += impl_sig + " {\n" + unused + body + "}\n\n}  // namespace\n\n";
  for (const std::string& s : scalar_types(scalars))
    out += fmt::format("{} {{ {}_impl<{}>({}); }}\n\n", signature(f, s), f.name, s, call_arguments(f));
  out += fmt::format("}}  // namespace {}\n", ns);
  return out;
}

std::string emit_selection_definition(const TracedFunction& f, const TracedFunction& source, const std::vector<int>& selection,
                                      const std::string& ns, const std::string& header, ScalarChoice scalars) {
  if (f.inputs.size() != source.inputs.size() || f.outputs.size() != 1 || source.outputs.size() != 1 ||
      static_cast<int>(selection.size()) != f.outputs[0].size)
    throw std::logic_error("emit_selection_definition: " + f.name + " is not a selection of " + source.name);
  std::string out = fmt::format("#include \"{}\"\n\nnamespace {} {{\n\n", header, ns);
  out += fmt::format("// {}\n// {} computes every entry; this keeps {} of its {}.\n", f.doc, source.name, selection.size(),
                     source.outputs[0].size);
  for (const std::string& scalar : scalar_types(scalars)) {
    out += signature(f, scalar) + " {\n";
    out += fmt::format("  {} all[{}];\n  {}({}, all);\n", scalar, source.outputs[0].size, source.name, [&] {
      std::string args;
      for (const ArraySpec& a : f.inputs) args += (args.empty() ? "" : ", ") + a.name;
      return args;
    }());
    for (std::size_t i = 0; i < selection.size(); ++i) out += fmt::format("  {}[{}] = all[{}];\n", f.outputs[0].name, i, selection[i]);
    out += "}\n\n";
  }
  out += fmt::format("}}  // namespace {}\n", ns);
  return out;
}

std::string emit_product_definition(const TracedFunction& f, const TracedFunction& source, const std::string& ns,
                                    const std::string& header, ScalarChoice scalars) {
  const std::size_t n_in = source.inputs.size();
  if (f.inputs.size() != n_in + 1 || f.outputs.size() != 1 || source.outputs.size() != 1 ||
      source.outputs[0].size != f.outputs[0].size * f.inputs[n_in].size)
    throw std::logic_error("emit_product_definition: " + f.name + " is not a product of " + source.name);
  const int rows = f.outputs[0].size, cols = f.inputs[n_in].size;
  const std::string& A = source.outputs[0].name;
  const std::string& x = f.inputs[n_in].name;
  std::string out = fmt::format("#include \"{}\"\n\nnamespace {} {{\n\n", header, ns);
  out += fmt::format("// {}\n// {} computes {}; this multiplies its structurally nonzero entries by {}.\n", f.doc, source.name, A, x);
  for (const std::string& scalar : scalar_types(scalars)) {
    out += signature(f, scalar) + " {\n";
    std::string args;
    for (std::size_t i = 0; i < n_in; ++i) args += (i ? ", " : "") + f.inputs[i].name;
    out += fmt::format("  {} {}[{}];\n  {}({}, {});\n", scalar, A, source.outputs[0].size, source.name, args, A);
    for (int r = 0; r < rows; ++r) {
      std::string sum;
      for (int c = 0; c < cols; ++c) {
        const int id = source.output_ids[0][static_cast<std::size_t>(r * cols + c)];
        if (source.graph.is_constant(id, 0)) continue;
        const std::string term = source.graph.is_constant(id, 1) ? fmt::format("{}[{}]", x, c)
                                                                 : fmt::format("{}[{}] * {}[{}]", A, r * cols + c, x, c);
        sum += (sum.empty() ? "" : " + ") + term;
      }
      out += fmt::format("  {}[{}] = {};\n", f.outputs[0].name, r, sum.empty() ? scalar + "(0)" : sum);
    }
    out += "}\n\n";
  }
  out += fmt::format("}}  // namespace {}\n", ns);
  return out;
}

}  // namespace mbgen::codegen
