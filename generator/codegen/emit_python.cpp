#include "codegen/emit_python.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "codegen/emit_batch.hpp"

namespace mbgen::codegen {

namespace {

/// The NumPy shape of one state of `a` as a C++ initialiser list: {47} or {46, 46}.
std::string shape_list(const ArraySpec& a) {
  if (a.shape.empty()) return fmt::format("{{{}}}", a.size);
  std::string s;
  for (int d : a.shape) s += fmt::format("{}{}", s.empty() ? "" : ", ", d);
  return "{" + s + "}";
}

/// The NumPy shape of one state of `a` as Python prints it: (47,) or (46, 46).
std::string shape_tuple(const ArraySpec& a) {
  if (a.shape.empty()) return fmt::format("({},)", a.size);
  std::string s;
  for (int d : a.shape) s += fmt::format("{}{}", s.empty() ? "" : ", ", d);
  return "(" + s + ")";
}

/// An argument's header text without its leading C++ size ("[4 x 12] per frame ..." -> "per frame
/// ..."): the docstring gives the NumPy shape instead.
std::string without_size(const std::string& doc) {
  if (doc.empty() || doc[0] != '[') return doc;
  const std::size_t end = doc.find("] ");
  return end == std::string::npos ? doc : doc.substr(end + 2);
}

/// The docstring of a traced function (function_doc.fmt): its arguments and results with their
/// NumPy shapes, and with lanes > 0 the batch form it runs through.
std::string traced_doc(const TracedFunction& f, int lanes, const TemplateSet& t) {
  std::string arguments, results;
  for (const ArraySpec& a : f.inputs) arguments += fmt::format("  {} {}: {}\n", a.name, shape_tuple(a), without_size(a.doc));
  const std::size_t count = f.outputs.size() - static_cast<std::size_t>(f.work_outputs);
  for (std::size_t k = 0; k < count; ++k) {
    const ArraySpec& a = f.outputs[k];
    results += fmt::format("  {} {}: {}\n", a.name, shape_tuple(a), without_size(a.doc));
  }
  const std::string lanes_note =
      lanes > 0 ? t.render("lanes_note", {{"lanes", std::to_string(lanes)}, {"batch_function", batch_name(f.name)}}) : "";
  return t.render("function_doc", {{"doc", f.doc},
                                   {"arguments", arguments},
                                   {"returns", count == 1 ? "Returns:" : "Returns a tuple:"},
                                   {"results", results},
                                   {"lanes_note", lanes_note}});
}

/// m.def of a traced function (function.fmt): its inputs read, its outputs made, the C++ function
/// per state (run.fmt), or W states at a time through its batch form when it has one (run_lanes.fmt).
std::string bind_traced(const TracedFunction& f, const PythonModuleContents& c, const EmitContext& ctx, const TemplateSet& t) {
  std::string parameters, reads, makes, arguments, lane_arguments, names;
  for (const ArraySpec& a : f.inputs) {
    parameters += fmt::format("{}py::object {}", parameters.empty() ? "" : ", ", a.name);
    reads += fmt::format("        const int {0}_ = call.input(\"{0}\", {0}, {1});\n", a.name, shape_list(a));
    arguments += fmt::format("{}s.in({}_)", arguments.empty() ? "" : ", ", a.name);
    lane_arguments += fmt::format("{}l.in({}_)", lane_arguments.empty() ? "" : ", ", a.name);
    names += fmt::format("py::arg(\"{}\"), ", a.name);
  }
  for (std::size_t k = 0; k + static_cast<std::size_t>(f.work_outputs) < f.outputs.size(); ++k) {
    const ArraySpec& a = f.outputs[k];
    makes += fmt::format("        const int {}_ = call.output({});\n", a.name, shape_list(a));
    arguments += fmt::format(", s.out({}_)", a.name);
    lane_arguments += fmt::format(", l.out({}_)", a.name);
  }
  const bool lanes = std::find(c.batched.begin(), c.batched.end(), f.name) != c.batched.end();
  const std::string one_state = t.render(
      "one_state", {{"robot", ctx.robot}, {"public_name", ctx.public_name(f.name, "double")}, {"arguments", arguments}});
  const std::string run = lanes ? t.render("run_lanes", {{"lanes", std::to_string(c.batch_width)},
                                                         {"one_state", one_state},
                                                         {"robot", ctx.robot},
                                                         {"batch_function", ctx.public_name(batch_name(f.name), "double")},
                                                         {"lane_arguments", lane_arguments}})
                                : t.render("run", {{"one_state", one_state}});
  return t.render("function", {{"name", f.name},
                               {"parameters", parameters},
                               {"reads", reads},
                               {"makes", makes},
                               {"run", run},
                               {"names", names},
                               {"doc", traced_doc(f, lanes ? c.batch_width : 0, t)}}) +
         "\n";
}

/// The header's sizes and tables as module attributes (attribute.fmt).
std::string bind_tables(const PythonModuleContents& c, const EmitContext& ctx, const TemplateSet& t) {
  std::string out;
  const auto attribute = [&](const std::string& name, const std::string& value) {
    out += t.render("attribute", {{"name", name}, {"value", value}}) + "\n";
  };
  const std::string& r = ctx.robot;
  for (const char* name : {"nq", "nv", "ny", "na", "num_bodies", "num_frames", "floating_base", "has_loops",
                           "num_limited_joints", "num_distance_pairs", "num_contact_spheres"})
    attribute(name, fmt::format("{}::{}", r, name));
  attribute("batch_width", std::to_string(c.batch_width));  // 0: generated without --batch
  attribute("joint_names", fmt::format("mbgen::python::names({}::joint_names)", r));
  attribute("body_names", fmt::format("mbgen::python::names({}::body_names)", r));
  attribute("independent_joint_names", fmt::format("mbgen::python::names({0}::independent_joint_names, {0}::ny)", r));
  attribute("independent_v_index", fmt::format("mbgen::python::numbers({0}::independent_v_index, {0}::ny)", r));
  attribute("actuated_joint_names", fmt::format("mbgen::python::names({0}::actuated_joint_names, {0}::na)", r));
  attribute("actuated_v_index", fmt::format("mbgen::python::numbers({0}::actuated_v_index, {0}::na)", r));
  attribute("frame_names", c.frames ? fmt::format("mbgen::python::names({}::frame_names)", r) : std::string("py::list()"));
  for (const char* table : {"limited_joint_names"})
    attribute(table, fmt::format("mbgen::python::names({0}::{1}, {0}::num_limited_joints)", r, table));
  for (const char* table : {"limited_q_index", "limited_v_index", "limited_lower", "limited_upper"})
    attribute(table, fmt::format("mbgen::python::numbers({0}::{1}, {0}::num_limited_joints)", r, table));
  attribute("distance_pair_names", fmt::format("mbgen::python::pairs({0}::distance_pair_names, {0}::num_distance_pairs)", r));
  if (c.contact) {
    attribute("contact_sphere_names", fmt::format("mbgen::python::names({}::contact_sphere_names)", r));
    attribute("contact_sphere_radius", fmt::format("mbgen::python::numbers({0}::contact_sphere_radius, {0}::num_contact_spheres)", r));
    for (const char* number : {"contact_stiffness", "contact_damping", "contact_exponent", "contact_friction",
                               "contact_stiction_velocity", "ground_offset"})
      attribute(number, fmt::format("{}::{}", r, number));
    attribute("ground_normal", fmt::format("mbgen::python::numbers({}::ground_normal, 3)", r));
    // The arguments contact_accelerations takes for the scene's own ground and law.
    attribute("default_ground", fmt::format("mbgen::python::numbers({{{0}::ground_normal[0], {0}::ground_normal[1], "
                                            "{0}::ground_normal[2], {0}::ground_offset}}, 4)",
                                            r));
    attribute("default_law", fmt::format("mbgen::python::numbers({{{0}::contact_stiffness, {0}::contact_damping, "
                                         "{0}::contact_friction, {0}::contact_stiction_velocity}}, 4)",
                                         r));
  }
  return out;
}

}  // namespace

const std::vector<TemplateSpec>& python_template_catalog() {
  static const PlaceholderSpec robot{"robot", "the robot's name: the module's, the C++ namespace's"};
  static const PlaceholderSpec one_state{"one_state", "one_state.fmt rendered"};
  static const std::vector<TemplateSpec> catalog = {
      {"module",
       "the module's source file: includes, PYBIND11_MODULE",
       {{"banner", "the banner of the header's template set (banner.fmt rendered)"},
        robot,
        {"header", "the header's file name"},
        {"backend_includes", "backend_includes.fmt rendered when the header has a Backend, else nothing"},
        {"tables", "attribute.fmt rendered per size and table, each line ending in a newline"},
        {"functions", "the bindings (function.fmt per traced function, closures.fmt, distances.fmt, simulator.fmt, "
                      "differential_ik.fmt), each ending in a newline"}}},
      {"backend_includes", "the includes of the simulator's and the IK's bindings", {}},
      {"attribute", "one module attribute", {{"name", "its Python name"}, {"value", "the C++ expression of its value"}}},
      {"function",
       "the binding of one traced function",
       {{"name", "the function's name"},
        {"parameters", "the lambda's parameters: py::object q, py::object v"},
        {"reads", "one line per input: its index in the Call, its shape checked"},
        {"makes", "one line per output: its index in the Call, its array made"},
        {"run", "run.fmt or run_lanes.fmt rendered"},
        {"names", "py::arg(\"q\"), ... : the keyword names, each followed by a comma and a space"},
        {"doc", "function_doc.fmt rendered (inside a raw string literal R\"mbgen(...)mbgen\")"}}},
      {"function_doc",
       "a traced function's docstring",
       {{"doc", "the header's description of the function"},
        {"arguments", "one line per argument: name, NumPy shape, what it is"},
        {"returns", "Returns: or Returns a tuple:"},
        {"results", "one line per result, as the arguments"},
        {"lanes_note", "lanes_note.fmt rendered when the function runs batches through its batch form, else nothing"}}},
      {"lanes_note",
       "what a docstring says of the batch form",
       {{"lanes", "W of --batch"}, {"batch_function", "the batch entry point's name"}}},
      {"one_state",
       "the call of the one-state function for one state of a Call",
       {robot, {"public_name", "the double entry point's name"}, {"arguments", "s.in(q_), ..., s.out(qdd_)"}}},
      {"run", "a Call over its states, one at a time", {one_state}},
      {"run_lanes",
       "a Call over its states, W at a time through the batch function",
       {{"lanes", "W of --batch"},
        one_state,
        robot,
        {"batch_function", "the batch entry point's name"},
        {"lane_arguments", "l.in(q_), ..., l.out(qdd_)"}}},
      {"closures",
       "ClosureStatus, ClosureResult, closure_positions and close_loops",
       {robot,
        {"nq", "number of position coordinates"},
        {"nv", "number of velocity coordinates"},
        {"closure_positions", "its double entry point's name"},
        {"close_loops", "its double entry point's name"}}},
      {"distances",
       "self_distances and self_distances_near (when the header declares them)",
       {robot,
        {"nq", "number of position coordinates"},
        {"nv", "number of velocity coordinates"},
        {"pairs", "num_distance_pairs"},
        {"self_distances", "its double entry point's name"},
        {"self_distances_near", "its double entry point's name"}}},
      {"simulator",
       "Simulator on the generated Backend (when the header has one)",
       {robot, {"scene", "simulator_contact.fmt rendered when the scene has contact spheres, else nothing"}}},
      {"simulator_contact", "the simulator's contact law and ground from the header", {robot}},
      {"differential_ik", "DifferentialIk on the generated Backend (when the header has one)", {robot}},
  };
  return catalog;
}

std::string python_templates_directory(const std::string& cpp_templates) {
  return (std::filesystem::path(cpp_templates) / "python").string();
}

std::string python_module_file(const EmitContext& ctx) { return ctx.robot + "_python.cpp"; }

std::string emit_python_module(const PythonModuleContents& c, const EmitContext& ctx, const TemplateSet& t) {
  if (ctx.scalars == ScalarChoice::Float)
    throw std::invalid_argument("--python binds the double functions, and the scalar chosen is float alone: "
                                "generate both (--scalar both) or double");
  const std::string& r = ctx.robot;
  const std::string nq = std::to_string(c.nq), nv = std::to_string(c.nv);
  std::string functions;
  for (const TracedFunction& f : c.traced) functions += bind_traced(f, c, ctx, t);
  functions += t.render("closures", {{"robot", r},
                                     {"nq", nq},
                                     {"nv", nv},
                                     {"closure_positions", ctx.public_name("closure_positions", "double")},
                                     {"close_loops", ctx.public_name("close_loops", "double")}});
  if (c.self_distances)
    functions += t.render("distances", {{"robot", r},
                                        {"nq", nq},
                                        {"nv", nv},
                                        {"pairs", std::to_string(c.num_distance_pairs)},
                                        {"self_distances", ctx.public_name("self_distances", "double")},
                                        {"self_distances_near", ctx.public_name("self_distances_near", "double")}});
  if (c.backend) {
    // The end stops are the runtime's default law: the header has the ranges, not a scene's
    // `joint_limits:` parameters.
    const std::string scene = c.contact ? t.render("simulator_contact", {{"robot", r}}) : "";
    functions += t.render("simulator", {{"robot", r}, {"scene", scene}});
    functions += t.render("differential_ik", {{"robot", r}});
  }
  return t.render("module", {{"banner", ctx.banner},
                             {"robot", r},
                             {"header", ctx.header},
                             {"backend_includes", c.backend ? t.render("backend_includes", {}) : ""},
                             {"tables", bind_tables(c, ctx, t)},
                             {"functions", functions}});
}

}  // namespace mbgen::codegen
