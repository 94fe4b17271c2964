#include "codegen/emit_batch.hpp"

#include <fmt/format.h>

#include <stdexcept>

#include "codegen/emit_cpp.hpp"

namespace mbgen::codegen {

bool valid_batch_width(int lanes) { return lanes >= 2 && lanes <= 16 && (lanes & (lanes - 1)) == 0; }

std::string batch_name(const std::string& function) { return function + "_batch"; }

namespace {

std::string lanes_doc(const ArraySpec& a, int lanes) {
  return fmt::format("{} -- per state: [i][w] is entry i of state w (w < {})", a.doc, lanes);
}

}  // namespace

std::string emit_batch_declaration(const TracedFunction& f, int lanes, const EmitContext& ctx) {
  const std::string name = batch_name(f.name);
  std::string arguments, prototypes;
  for (const ArraySpec& a : f.inputs) arguments += ctx.templates.render("input_doc", {{"name", a.name}, {"doc", lanes_doc(a, lanes)}});
  for (std::size_t k = 0; k + static_cast<std::size_t>(f.work_outputs) < f.outputs.size(); ++k)
    arguments += ctx.templates.render("output_doc", {{"name", f.outputs[k].name}, {"doc", lanes_doc(f.outputs[k], lanes)}});
  for (const std::string& s : scalar_types(ctx.scalars))
    prototypes += ctx.templates.render("prototype", {{"public_name", ctx.public_name(name, s)},
                                                     {"parameters", public_batch_parameters(f, s, lanes)},
                                                     {"scalar", s},
                                                     {"function", name},
                                                     {"robot", ctx.robot}});
  return ctx.templates.render(
      "function_declaration",
      {{"doc", fmt::format("{} over {} states at once (structure of arrays), each equal to {} bit for bit under the same "
                           "compiler flags.",
                           f.name, lanes, f.name)},
       {"cost", fmt::format("{} per state", describe_operations(count_operations(f)))},
       {"arguments", arguments},
       {"prototypes", prototypes}});
}

std::string emit_batch_definition(const TracedFunction& f, int lanes, const EmitContext& ctx, const std::string& helpers,
                                  const std::string& own_entry_points) {
  const std::string name = batch_name(f.name);
  if (f.work_outputs > 0 && own_entry_points.empty())
    throw std::logic_error("emit_batch_definition: " + f.name + " has work outputs: its row writes its entry points");
  const SplitStatements split = split_statements(f, name, ctx.max_statements_per_part, {lanes, true});
  const std::string entry_points =
      !own_entry_points.empty()
          ? own_entry_points
          : emit_entry_points(name, call_arguments(f), [&](const std::string& s) { return batch_parameters(f, s, lanes); }, ctx);
  return ctx.templates.render("batch_source",
                              {{"banner", ctx.banner},
                               {"header", ctx.header},
                               {"robot", ctx.robot},
                               {"function", f.name},
                               {"lanes", std::to_string(lanes)},
                               {"sincos", ctx.templates.render("sincos", {})},
                               {"doc", f.doc},
                               {"cost", describe_operations(count_operations(f))},
                               {"noinline", split.parts.empty() ? std::string() : ctx.templates.render("noinline_macro", {})},
                               {"parts", helpers + split.parts},
                               {"impl_parameters", batch_parameters(f, "S", lanes)},
                               {"body", unused_inputs(f) + split.body},
                               {"entry_points", entry_points}});
}

}  // namespace mbgen::codegen
