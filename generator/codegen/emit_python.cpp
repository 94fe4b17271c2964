#include "codegen/emit_python.hpp"

#include <fmt/format.h>

#include <algorithm>
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

/// A docstring as a raw string literal (the header's texts hold quotes and backslashes).
std::string doc_literal(const std::string& text) { return "R\"mbgen(" + text + ")mbgen\""; }

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

constexpr const char* kUnitsNote =
    "Units (SI, the header's conventions): q in rad for a revolute joint and m for a prismatic one, a floating\n"
    "base's position in m and orientation as a unit quaternion (x, y, z, w); v in rad/s and m/s (a floating\n"
    "base's linear and angular velocity in its own axes); accelerations in rad/s^2 and m/s^2; forces in N m\n"
    "and N; lengths in m, masses in kg, inertias in kg m^2.";

constexpr const char* kBatchNote =
    "Every array argument may also carry a leading batch dimension N (the same N for all that do);\n"
    "the results then do too.";

std::string traced_doc(const TracedFunction& f, int lanes) {
  std::string d = f.doc + "\n\nArguments:\n";
  for (const ArraySpec& a : f.inputs) d += fmt::format("  {} {}: {}\n", a.name, shape_tuple(a), without_size(a.doc));
  const std::size_t results = f.outputs.size() - static_cast<std::size_t>(f.work_outputs);
  d += results == 1 ? "Returns:\n" : "Returns a tuple:\n";
  for (std::size_t k = 0; k < results; ++k) {
    const ArraySpec& a = f.outputs[k];
    d += fmt::format("  {} {}: {}\n", a.name, shape_tuple(a), without_size(a.doc));
  }
  d += fmt::format("{}\n{}", kUnitsNote, kBatchNote);
  if (lanes > 0) d += fmt::format("\nA batch runs {} states at a time through {} (--batch).", lanes, batch_name(f.name));
  return d;
}

/// m.def of a traced function: its inputs read, its outputs made, the C++ function per state (W
/// states at a time through its batch form when it has one: Call::run_lanes).
std::string bind_traced(const TracedFunction& f, const PythonModuleContents& c, const EmitContext& ctx) {
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
  const std::string one = fmt::format("[&](const Call::State& s) {{ {}::{}({}); }}", ctx.robot,
                                      ctx.public_name(f.name, "double"), arguments);
  const std::string run =
      lanes ? fmt::format("call.run_lanes<{w}>(\n"
                          "            {one},\n"
                          "            [&](const Call::Lanes<{w}>& l) {{ {r}::{batch}({lane_arguments}); }});\n",
                          fmt::arg("w", c.batch_width), fmt::arg("one", one), fmt::arg("r", ctx.robot),
                          fmt::arg("batch", ctx.public_name(batch_name(f.name), "double")),
                          fmt::arg("lane_arguments", lane_arguments))
            : fmt::format("call.run({});\n", one);
  return fmt::format(
      "  m.def(\n"
      "      \"{name}\",\n"
      "      []({parameters}) {{\n"
      "        Call call(\"{name}\");\n"
      "{reads}{makes}"
      "        {run}"
      "        return call.result();\n"
      "      }},\n"
      "      {names}{doc});\n",
      fmt::arg("name", f.name), fmt::arg("parameters", parameters), fmt::arg("reads", reads), fmt::arg("makes", makes),
      fmt::arg("run", run), fmt::arg("names", names), fmt::arg("doc", doc_literal(traced_doc(f, lanes ? c.batch_width : 0))));
}

/// The header's sizes and tables as module attributes.
std::string bind_tables(const PythonModuleContents& c, const EmitContext& ctx) {
  std::string out;
  const auto attribute = [&](const std::string& name, const std::string& value) {
    out += fmt::format("  m.attr(\"{}\") = {};\n", name, value);
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

/// closure_positions and close_loops: q (and v) copied, closed in place, with the Newton result.
std::string bind_closures(const PythonModuleContents& c, const EmitContext& ctx) {
  return fmt::format(
      R"py(  py::enum_<{r}::ClosureStatus>(m, "ClosureStatus", "What closure_positions ended with ({r}.hpp).")
      .value("converged", {r}::ClosureStatus::converged)
      .value("not_converged", {r}::ClosureStatus::not_converged)
      .value("singular", {r}::ClosureStatus::singular);
  py::class_<{r}::ClosureResult<double>>(m, "ClosureResult", "The Newton iteration's outcome ({r}.hpp: ClosureResult).")
      .def_readonly("status", &{r}::ClosureResult<double>::status)
      .def_readonly("iterations", &{r}::ClosureResult<double>::iterations)
      .def_readonly("residual", &{r}::ClosureResult<double>::residual, "max |Phi| over the kept closure rows (m, rad)")
      .def_readonly("pivot_ratio", &{r}::ClosureResult<double>::pivot_ratio)
      .def_readonly("relative_pivot_ratio", &{r}::ClosureResult<double>::relative_pivot_ratio)
      .def_readonly("subsystem", &{r}::ClosureResult<double>::subsystem)
      .def_readonly("worst_subsystem", &{r}::ClosureResult<double>::worst_subsystem)
      .def("__repr__", [](const {r}::ClosureResult<double>& x) {{
        return "ClosureResult(status=" + std::string(py::str(py::cast(x.status))) + ", iterations=" +
               std::to_string(x.iterations) + ", residual=" + std::string(py::str(py::float_(x.residual))) + ")";
      }});
  m.def(
      "closure_positions",
      [](py::object q) {{
        Call call("closure_positions");
        const int q_ = call.input("q", q, {{{nq}}});
        call.require_one_state();
        const int out_ = call.output({{{nq}}});
        {r}::ClosureResult<double> result{{}};
        call.run([&](const Call::State& s) {{
          std::copy(s.in(q_), s.in(q_) + {nq}, s.out(out_));
          result = {r}::{closure_positions}(s.out(out_));
        }});
        return py::make_tuple(call.result(), result);
      }},
      py::arg("q"),
      R"mbgen(Closes the loops: Newton on the closures for the dependent coordinates (q's entries are the
warm start), the independent ones held, with the header's default options.

Arguments:
  q ({nq},): joint positions (one state)
Returns a tuple:
  q ({nq},): the closed positions (a new array; q is left as it was)
  result: ClosureResult (status, iterations, residual, pivot ratios, sub-system))mbgen");
  m.def(
      "close_loops",
      [](py::object q, py::object v) {{
        Call call("close_loops");
        const int q_ = call.input("q", q, {{{nq}}});
        const int v_ = call.input("v", v, {{{nv}}});
        call.require_one_state();
        const int q_out = call.output({{{nq}}});
        const int v_out = call.output({{{nv}}});
        {r}::ClosureResult<double> result{{}};
        call.run([&](const Call::State& s) {{
          std::copy(s.in(q_), s.in(q_) + {nq}, s.out(q_out));
          std::copy(s.in(v_), s.in(v_) + {nv}, s.out(v_out));
          result = {r}::{close_loops}(s.out(q_out), s.out(v_out));
        }});
        py::tuple qv = call.result().cast<py::tuple>();
        return py::make_tuple(qv[0], qv[1], result);
      }},
      py::arg("q"), py::arg("v"),
      R"mbgen(closure_positions, and when it converges v's dependent entries from its independent ones at
the closed q (v = T vy).

Arguments:
  q ({nq},): joint positions, v ({nv},): joint velocities (one state)
Returns a tuple:
  q ({nq},): closed positions, v ({nv},): consistent velocities (new arrays), result: ClosureResult)mbgen");
)py",
      fmt::arg("r", ctx.robot), fmt::arg("nq", c.nq), fmt::arg("nv", c.nv),
      fmt::arg("closure_positions", ctx.public_name("closure_positions", "double")),
      fmt::arg("close_loops", ctx.public_name("close_loops", "double")));
}

/// self_distances (batchable, as the traced functions) and self_distances_near (one state: its
/// rows are as many as the pairs found near).
std::string bind_distances(const PythonModuleContents& c, const EmitContext& ctx) {
  return fmt::format(
      R"py(  m.def(
      "self_distances",
      [](py::object q) {{
        Call call("self_distances");
        const int q_ = call.input("q", q, {{{nq}}});
        const int distance = call.output({{{pairs}}});
        const int normal = call.output({{{pairs}, 3}});
        const int witness = call.output({{{pairs}, 6}});
        const int jacobian = call.output({{{pairs}, {nv}}});
        call.run([&](const Call::State& s) {{
          {r}::{self_distances}(s.in(q_), s.out(distance), s.out(normal), s.out(witness), s.out(jacobian));
        }});
        return call.result();
      }},
      py::arg("q"),
      R"mbgen(Self-distances of the kept pairs (distance_pair_names) between the bodies' swept-sphere
volumes, and their Jacobians ({r}.hpp: self_distances).

Arguments:
  q ({nq},): joint positions
Returns a tuple:
  distance ({pairs},): core distance - r1 - r2 (m, negative when overlapping)
  normal ({pairs}, 3): unit normal from the pair's first body to its second, world
  witness ({pairs}, 6): point (m) on the first body's surface, then on the second's, world
  jacobian ({pairs}, {nv}): row k = d distance[k] / d v
{batch})mbgen");
  m.def(
      "self_distances_near",
      [](py::object q, double threshold) {{
        Call call("self_distances_near");
        const int q_ = call.input("q", q, {{{nq}}});
        call.require_one_state();
        const int distance = call.output({{{pairs}}});
        const int normal = call.output({{{pairs}, 3}});
        const int witness = call.output({{{pairs}, 6}});
        const int jacobian = call.output({{{pairs}, {nv}}});
        py::array_t<int> near({pairs});
        int* near_rows = near.mutable_data();
        int num_near = 0;
        call.run([&](const Call::State& s) {{
          {r}::{self_distances_near}(s.in(q_), threshold, s.out(distance), near_rows, &num_near, s.out(normal),
                                     s.out(witness), s.out(jacobian));
        }});
        py::tuple all = call.result().cast<py::tuple>();
        const py::slice rows(0, num_near, 1);
        return py::make_tuple(all[0], near[rows], all[1][rows], all[2][rows], all[3][rows]);
      }},
      py::arg("q"), py::arg("threshold"),
      R"mbgen(The near set: self_distances for the pairs closer than threshold only ({r}.hpp:
self_distances_near); pass the avoidance's activation distance.

Arguments:
  q ({nq},): joint positions (one state); threshold: m
Returns a tuple:
  distance ({pairs},): every pair (m): exact when near, else a lower bound >= threshold
  near (num_near,): the near pairs, ascending
  normal (num_near, 3), witness (num_near, 6), jacobian (num_near, {nv}): rows of the near pairs)mbgen");
)py",
      fmt::arg("r", ctx.robot), fmt::arg("nq", c.nq), fmt::arg("nv", c.nv), fmt::arg("pairs", c.num_distance_pairs),
      fmt::arg("batch", kBatchNote), fmt::arg("self_distances", ctx.public_name("self_distances", "double")),
      fmt::arg("self_distances_near", ctx.public_name("self_distances_near", "double")));
}

/// Simulator on the generated Backend (mbgen/python/simulator_binding.hpp), with the header's
/// contact law and ground; the end stops are the runtime's default law (the header has the ranges,
/// not a scene's `joint_limits:` parameters).
std::string bind_simulator(const PythonModuleContents& c, const EmitContext& ctx) {
  const std::string scene =
      c.contact ? fmt::format("        scene.contact_parameters = {{{0}::contact_stiffness, {0}::contact_damping, {0}::contact_exponent,\n"
                              "                                     {0}::contact_friction, {0}::contact_stiction_velocity}};\n"
                              "        scene.ground.normal = mbgen::Vec3<double>({0}::ground_normal[0], {0}::ground_normal[1], {0}::ground_normal[2]);\n"
                              "        scene.ground.offset = {0}::ground_offset;\n",
                              ctx.robot)
                : std::string();
  return fmt::format(
      "  mbgen::python::bind_simulator<{r}::Backend>(\n"
      "      m, \"The simulator (docs/simulation.md) on {r}'s generated Backend: the header's contact law and ground, \"\n"
      "         \"the runtime's end stops at the joint ranges; the loops kept closed.\")\n"
      "      .def(py::init([](const std::string& integrator, double step, bool contact, bool joint_stops) {{\n"
      "        mbgen::sim::SimulatorOptions scene;\n"
      "{scene}"
      "        return std::make_unique<mbgen::sim::Simulator<{r}::Backend>>(\n"
      "            {r}::Backend{{}}, mbgen::python::simulator_options(scene, integrator, step, contact, joint_stops));\n"
      "      }}),\n"
      "           py::arg(\"integrator\") = \"rk4\", py::arg(\"step\") = 1e-4, py::arg(\"contact\") = true,\n"
      "           py::arg(\"joint_stops\") = true, mbgen::python::kSimulatorArguments);\n",
      fmt::arg("r", ctx.robot), fmt::arg("scene", scene));
}

/// DifferentialIk on the generated Backend (mbgen/python/differential_ik_binding.hpp): its frames
/// the header's frame_names, its pairs the header's, joint_limits=True its limited joints.
std::string bind_differential_ik(const EmitContext& ctx) {
  return fmt::format(
      "  mbgen::python::bind_differential_ik<mbgen::control::BasicDifferentialIk<{r}::Backend>>(\n"
      "      m, \"The differential IK (docs/control.md) on {r}'s generated Backend: the tasks' frames among frame_names, \"\n"
      "         \"the pairs distance_pair_names, the ranges limited_joint_names.\")\n"
      "      .def(py::init([](const py::iterable& tasks, const py::kwargs& kwargs) {{\n"
      "             const auto options = mbgen::python::differential_ik_options(kwargs, mbgen::python::backend_limits({r}::Backend{{}}));\n"
      "             const auto specs = mbgen::python::detail::task_specs(tasks);\n"
      "             return mbgen::python::configuration([&] {{\n"
      "               return std::make_unique<mbgen::control::BasicDifferentialIk<{r}::Backend>>({r}::Backend{{}}, specs, options);\n"
      "             }});\n"
      "           }}),\n"
      "           py::arg(\"tasks\"), mbgen::python::kDifferentialIkArguments);\n",
      fmt::arg("r", ctx.robot));
}

}  // namespace

std::string python_module_file(const EmitContext& ctx) { return ctx.robot + "_python.cpp"; }

std::string emit_python_module(const PythonModuleContents& c, const EmitContext& ctx) {
  if (ctx.scalars == ScalarChoice::Float)
    throw std::invalid_argument("--python binds the double functions, and the scalar chosen is float alone: "
                                "generate both (--scalar both) or double");
  std::string functions;
  for (const TracedFunction& f : c.traced) functions += bind_traced(f, c, ctx);
  functions += bind_closures(c, ctx);
  if (c.self_distances) functions += bind_distances(c, ctx);
  if (c.backend) functions += bind_simulator(c, ctx) + bind_differential_ik(ctx);
  return fmt::format(
      "{banner}"
      "// The Python module of {r} (mbgen generate --python; docs/python.md): every function of {header}\n"
      "// for double, with the same names and arguments, NumPy arrays in and out\n"
      "// (mbgen/python/generated_module.hpp: shapes, batches, copies, the GIL), and the header's sizes\n"
      "// and tables as attributes. Build it with mbgen_add_robot(... PYTHON).\n"
      "#include <pybind11/numpy.h>\n"
      "#include <pybind11/pybind11.h>\n"
      "\n"
      "#include <algorithm>\n"
      "#include <string>\n"
      "\n"
      "#include \"{header}\"\n"
      "#include \"mbgen/python/generated_module.hpp\"\n"
      "{backend_includes}"
      "\n"
      "namespace py = pybind11;\n"
      "using mbgen::python::Call;\n"
      "\n"
      "PYBIND11_MODULE({r}, m) {{\n"
      "  m.doc() = \"{r}: mbgen's generated dynamics (see {header} for the conventions: q, v, row-major "
      "matrices, a floating base's coordinates).\";\n"
      "{tables}\n"
      "{functions}"
      "}}\n",
      fmt::arg("banner", ctx.banner), fmt::arg("r", ctx.robot), fmt::arg("header", ctx.header),
      fmt::arg("tables", bind_tables(c, ctx)), fmt::arg("functions", functions),
      fmt::arg("backend_includes", c.backend ? "#include \"mbgen/python/differential_ik_binding.hpp\"\n"
                                              "#include \"mbgen/python/simulator_binding.hpp\"\n"
                                            : ""));
}

}  // namespace mbgen::codegen
