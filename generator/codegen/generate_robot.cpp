#include "codegen/generate_robot.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <set>

#include "codegen/emit_batch.hpp"
#include "codegen/emit_closure_positions.hpp"
#include "codegen/emit_python.hpp"
#include "codegen/emit_self_distances.hpp"
#include "codegen/function_catalog.hpp"
#include "codegen/scene_functions.hpp"
#include "codegen/trace_dynamics.hpp"
#include "codegen/trace_loop_maps.hpp"
#include "collision/collision_scene.hpp"
#include "collision/contact_spheres.hpp"
#include "load/load_error.hpp"
#include "model/actuated_coordinates.hpp"
#include "model/topology.hpp"
#include "mbgen/joint_limits.hpp"
#include "mbgen/mbgen.hpp"

#ifndef MBGEN_VERSION
#define MBGEN_VERSION "0.0.0"
#endif

namespace mbgen::codegen {

namespace {

std::string banner(const CodegenOptions& options, const TemplateSet& templates) {
  std::string inputs;
  for (const InputFile& in : options.inputs) inputs += templates.render("banner_input", {{"file", in.name}, {"sha256", in.sha256}});
  return templates.render("banner", {{"version", MBGEN_VERSION}, {"inputs", inputs}});
}

/// Quoted, comma-separated C string literals: "a", "b".
std::string quoted_list(const std::vector<std::string>& items) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    std::string escaped;
    for (char c : items[i]) escaped += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
    out += fmt::format("{}\"{}\"", i ? ", " : "", escaped);
  }
  return out;
}

/// The body of Backend::subsystem_name: a table of each sub-system's closures, comma-separated.
std::string subsystem_name_statements(const Model& model) {
  if (model.subsystems.empty()) return "(void)k;\n    return \"\";";
  std::vector<std::string> names;
  for (const SubSystem& s : model.subsystems) {
    std::vector<std::string> closures;
    for (int c : s.closures) closures.push_back(model.closures[static_cast<std::size_t>(c)].name);
    names.push_back(fmt::format("{}", fmt::join(closures, ", ")));
  }
  return fmt::format("static constexpr const char* names[] = {{{}}};\n    return names[k];", quoted_list(names));
}

}  // namespace

std::string sanitize_identifier(const std::string& name) {
  static const std::set<std::string> keywords = {
      "alignas", "alignof", "and", "asm", "auto", "bool", "break", "case", "catch", "char", "class", "const",
      "constexpr", "continue", "default", "delete", "do", "double", "else", "enum", "explicit", "export", "extern",
      "false", "float", "for", "friend", "goto", "if", "inline", "int", "long", "mutable", "namespace", "new",
      "noexcept", "not", "nullptr", "operator", "or", "private", "protected", "public", "register", "return", "short",
      "signed", "sizeof", "static", "struct", "switch", "template", "this", "throw", "true", "try", "typedef",
      "typeid", "typename", "union", "unsigned", "using", "virtual", "void", "volatile", "while", "std"};
  std::string out;
  for (unsigned char c : name) out += std::isalnum(c) ? static_cast<char>(c) : '_';
  if (out.empty() || std::isdigit(static_cast<unsigned char>(out[0])) || keywords.count(out)) out = "_" + out;
  return out;
}

namespace {

/// The frames of frame_poses and frame_jacobians: the options', else the leaf bodies.
struct FrameChoice {
  std::vector<std::string> names;
  std::vector<FrameIndex> indices;
};

FrameChoice choose_frames(const gen::Description& description, const CodegenOptions& options) {
  const Model& model = description.model;
  FrameChoice frames{options.frames.empty() ? default_frames(model) : options.frames, {}};
  for (const std::string& name : frames.names) {
    auto f = model.find_frame(name);
    if (!f)
      throw gen::LoadError(description.extras_file.empty() ? description.description_file : description.extras_file, 0,
                           fmt::format("frame '{}'", name), "is not a frame of the robot",
                           "name a link or a fixed joint of the description (see `mbgen inspect`)");
    frames.indices.push_back(*f);
  }
  return frames;
}

/// Everything one generation computes before it writes: the selection, the traces, the inputs
/// the traces and the header read.
struct Generation {
  const gen::Description& description;
  const CodegenOptions& options;
  const TemplateSet& templates;
  const Model& model;
  EmitContext ctx;
  FrameChoice frames;
  /// The spanning tree alone for everything but the closed system's dynamics: with loops, the
  /// tree functions are those of the tree (inverse dynamics without closure forces, the tree's
  /// mass matrix), and forward_dynamics / full_accelerations those of the closed system.
  Model tree;
  Actuation actuation;
  std::vector<ContactSphere> contacts;
  double contact_exponent = 1.5;
  /// The derivatives' inputs: --derivatives-wrt, else the scene's `derivatives_wrt`, else all.
  DerivativeBlocks derivative_blocks;
  std::vector<RigidContact> rigid_contacts;  ///< the scene's `rigid_contacts`
  std::string left_out_reason;
  FunctionSelection selection;
  std::vector<int> independent;       ///< the closed system's coordinates (v indices)
  std::vector<TracedFunction> traced;  ///< catalogue order
  SelfDistanceCode distances;

  Generation(const gen::Description& d, const CodegenOptions& o, const TemplateSet& t)
      : description(d),
        options(o),
        templates(t),
        model(d.model),
        ctx{t, o.name, t.render("header_file", {{"robot", o.name}}), banner(o, t), o.scalars, o.max_statements_per_part,
            /*inline_sincos=*/o.batch > 0},
        frames(choose_frames(d, o)),
        tree(gen::spanning_tree(d.model)),
        actuation(gen::description_actuation(d, o.notes)),
        contacts(gen::contact_spheres(d)),
        independent(d.model.structure().independent_v) {
    if (!contacts.empty()) contact_exponent = description.scene->contact->parameters.exponent;
    derivative_blocks = DerivativeBlocks::from_names(
        !options.derivatives_wrt.empty() ? options.derivatives_wrt
        : description.scene             ? description.scene->derivatives_wrt
                                        : std::vector<std::string>{});
    selection = select_functions(description, options.outputs, &left_out_reason);
    if (description.scene)
      for (const gen::RigidContactSpec& c : description.scene->rigid_contacts) {
        const auto frame = model.find_frame(c.frame);
        if (!frame)  // a model reduction (lock, merge_below) took it away
          throw gen::LoadError(description.extras_file, c.line, "scene: rigid_contacts: frame",
                               fmt::format("'{}' is no frame of the reduced model", c.frame),
                               "hold a frame the reduction keeps, or reduce less");
        rigid_contacts.push_back({*frame, c.kind == "point" ? RigidContactKind::Point : RigidContactKind::Frame});
      }
  }

  bool loops() const { return !model.subsystems.empty(); }

  /// Each function's graph is bounded (options.max_operations): past it, a LoadError names the
  /// function, instead of the memory filling up on a description too large to unroll.
  template <typename Trace> auto bounded(const std::string& name, Trace&& trace) const {
    const GraphLimit limit(options.max_operations);
    try {
      return trace();
    } catch (const GraphLimitExceeded& e) {
      throw gen::LoadError(description.description_file, 0, fmt::format("function '{}'", name),
                           fmt::format("needs more than {} operations unrolled (nv {}): too large to generate", e.limit,
                                       model.nv()),
                           "generate less (a scene with fewer outputs or a reduced model), or raise the limit with "
                           "--max-operations (about 100 bytes of memory per node while generating)");
    }
  }

  std::string left_out_note(const std::string& function) const {
    return templates.render("left_out_declaration", {{"function", function}, {"reason", left_out_reason}});
  }
};

/// The catalogue's traced rows the selection emits (a per-frame row only when there are frames).
void trace_functions(Generation& g) {
  const TraceInputs in{g.model,    g.tree,          g.frames.indices,    g.actuation,
                       g.contacts, g.contact_exponent, g.derivative_blocks, g.rigid_contacts};
  for (const GeneratedFunction& row : function_catalog()) {
    if (row.writer != Writer::traced || !g.selection.emits(row.name) || (row.per_frame && g.frames.indices.empty())) continue;
    g.traced.push_back(g.bounded(row.name, [&] { return row.trace(in); }));
    g.traced.back().pack_output_stores = row.pack_output_stores;
    if (g.traced.back().name != row.name)
      throw std::logic_error(fmt::format("function catalogue: the tracer of {} traced {}", row.name, g.traced.back().name));
  }
}

/// Self-distances: the scene decides which pairs exist (the same pruning as `mbgen inspect`,
/// seeded, so the output stays deterministic).
void emit_distances(Generation& g) {
  if (!g.selection.emits("self_distances")) {
    g.distances.header_fields = {{"num_distance_pairs", "0"},
                                 {"distance_pair_rows", "1"},
                                 {"distance_pair_names", "{\"\", \"\"}"},
                                 {"distance_declarations", g.left_out_note("self_distances")}};
    return;
  }
  const gen::CollisionScene scene = gen::build_collision_scene(g.description, gen::collision_scene_options(g.description));
  if (g.options.notes) {
    g.options.notes->push_back(fmt::format("collision pruning: {} of {} pairs kept; {}; {:.2f} s", scene.model.pairs.size(),
                                           scene.decisions.size(), gen::sampling_summary(scene), scene.seconds));
    for (const std::string& w : scene.warnings) g.options.notes->push_back("warning: " + w);
  }
  g.distances = g.bounded("self_distances", [&] { return emit_self_distances(g.model, scene.model, g.ctx); });
}

const auto number = [](double x) { return fmt::format("{}", x); };  // shortest round-trip

/// The sizes, names and index tables of the header.
TemplateFields structure_fields(const Generation& g) {
  const Model& model = g.model;
  std::vector<std::string> body_names;
  for (int k = 1; k < model.num_bodies(); ++k) body_names.push_back(model.body(BodyIndex(k)).name);
  std::vector<std::string> independent_names;
  for (int v : g.independent) independent_names.push_back(gen::coordinate_name(model, v));
  std::vector<std::string> actuated_names;
  for (int v : g.actuation.actuated_v) actuated_names.push_back(gen::coordinate_name(model, v));
  return {{"banner", g.ctx.banner},
          {"robot", g.ctx.robot},
          {"nq", std::to_string(model.nq())},
          {"nv", std::to_string(model.nv())},
          {"num_bodies", std::to_string(model.num_bodies() - 1)},
          {"num_frames", std::to_string(g.frames.indices.size())},
          {"floating_base", model.floating_base() ? "true" : "false"},
          {"joint_names", quoted_list(model.joint_names())},
          {"ny", std::to_string(g.independent.size())},
          {"has_loops", g.loops() ? "true" : "false"},
          {"independent_joint_names", quoted_list(independent_names)},
          {"independent_v_index", fmt::format("{}", fmt::join(g.independent, ", "))},
          {"na", std::to_string(g.actuation.num_actuators())},
          // C++ has no empty arrays: one placeholder entry when nothing is actuated.
          {"actuated_joint_names", actuated_names.empty() ? std::string("\"\"") : quoted_list(actuated_names)},
          {"actuated_v_index",
           g.actuation.actuated_v.empty() ? std::string("-1") : fmt::format("{}", fmt::join(g.actuation.actuated_v, ", "))},
          {"body_names", quoted_list(body_names)},
          {"frame_names", g.frames.names.empty() ? std::string()
                                                 : g.templates.render("frame_names", {{"robot", g.ctx.robot}, {"names", quoted_list(g.frames.names)}})}};
}

/// The emitted functions' declarations, the left-out ones' notes, and each scalar's loop entry points.
void add_declarations(const Generation& g, TemplateFields& fields) {
  std::string declarations, scalar_declarations;
  for (const TracedFunction& f : g.traced) declarations += emit_declaration(f, g.ctx);
  for (const std::string& f : g.selection.left_out)
    if (f != "self_distances") declarations += g.left_out_note(f);  // its note sits with the distance tables
  for (const std::string& s : scalar_types(g.options.scalars)) {
    if (!scalar_declarations.empty()) scalar_declarations += '\n';  // a rendered template ends without one
    scalar_declarations += g.templates.render("scalar_declarations",
                                              {{"robot", g.ctx.robot},
                                               {"scalar", s},
                                               {"closure_positions", g.ctx.public_name("closure_positions", s)},
                                               {"close_loops", g.ctx.public_name("close_loops", s)},
                                               {"independent_velocities", g.ctx.public_name("independent_velocities", s)}});
  }
  fields.push_back({"declarations", declarations});
  fields.push_back({"scalar_declarations", scalar_declarations});
}

/// The description's position ranges, for a controller's joint-limit potential on this code
/// (joint_position_limits reads them back; the same rule as from a Model).
void add_joint_limits(const Generation& g, TemplateFields& fields) {
  std::vector<std::string> names, q_index, v_index, lower, upper;
  for (const JointLimit& l : joint_position_limits(g.model)) {
    names.push_back(l.joint), q_index.push_back(std::to_string(l.q_index)), v_index.push_back(std::to_string(l.v_index));
    lower.push_back(number(l.lower)), upper.push_back(number(l.upper));
  }
  const bool none = names.empty();  // C and C++ have no empty arrays: one placeholder entry
  fields.push_back({"num_limited_joints", std::to_string(names.size())});
  fields.push_back({"limited_joint_names", none ? std::string("\"\"") : quoted_list(names)});
  fields.push_back({"limited_q_index", none ? std::string("-1") : fmt::format("{}", fmt::join(q_index, ", "))});
  fields.push_back({"limited_v_index", none ? std::string("-1") : fmt::format("{}", fmt::join(v_index, ", "))});
  fields.push_back({"limited_lower", none ? std::string("0") : fmt::format("{}", fmt::join(lower, ", "))});
  fields.push_back({"limited_upper", none ? std::string("0") : fmt::format("{}", fmt::join(upper, ", "))});
}

/// Ground contact: the vertex spheres of the scene's contact links and the law's parameters.
void add_contact(const Generation& g, TemplateFields& fields) {
  fields.push_back({"num_contact_spheres", std::to_string(g.contacts.size())});
  std::string block;
  if (!g.contacts.empty()) {
    const gen::ContactSpec& spec = *g.description.scene->contact;
    std::vector<std::string> names, radii;
    for (const ContactSphere& c : g.contacts) names.push_back(c.name), radii.push_back(number(c.radius));
    const Vec3<double>& n = spec.ground.normal;
    block = g.templates.render("contact", {{"robot", g.ctx.robot},
                                           {"links", fmt::format("{}", fmt::join(spec.links, ", "))},
                                           {"names", quoted_list(names)},
                                           {"radii", fmt::format("{}", fmt::join(radii, ", "))},
                                           {"stiffness", number(spec.parameters.stiffness)},
                                           {"damping", number(spec.parameters.damping)},
                                           {"exponent", number(spec.parameters.exponent)},
                                           {"friction", number(spec.parameters.friction)},
                                           {"stiction_velocity", number(spec.parameters.stiction_velocity)},
                                           {"ground_normal", fmt::format("{}, {}, {}", number(n.x()), number(n.y()), number(n.z()))},
                                           {"ground_offset", number(spec.ground.offset)}});
  }
  fields.push_back({"contact", block});
}

/// The traced functions with a batch form, in catalogue order.
std::vector<const TracedFunction*> batched_traces(const Generation& g) {
  std::vector<const TracedFunction*> batched;
  if (g.options.batch <= 0) return batched;
  for (const TracedFunction& f : g.traced)
    if (find_function(f.name)->batch == Batch::yes) batched.push_back(&f);
  return batched;
}

/// Batch functions: those of the catalogue's batch rows the scene generates, over options.batch states.
void add_batch(const Generation& g, TemplateFields& fields) {
  std::string block;
  if (g.options.batch > 0) {
    if (!valid_batch_width(g.options.batch))
      throw std::invalid_argument(fmt::format("batch width {}: must be a power of two from 2 to 16", g.options.batch));
    std::vector<std::string> names;
    for (const TracedFunction* f : batched_traces(g)) names.push_back(batch_name(f->name));
    block = g.templates.render("batch_width", {{"robot", g.ctx.robot},
                                               {"lanes", std::to_string(g.options.batch)},
                                               {"functions", fmt::format("{}", fmt::join(names, ", "))}});
    for (const TracedFunction* f : batched_traces(g)) block += emit_batch_declaration(*f, g.options.batch, g.ctx);
  }
  fields.push_back({"batch", block});
}

/// NAME::Backend, the simulator's and the IK's adapter, when the scene generates what it calls;
/// its controller members when the kinematics and the distances are generated too.
void add_backend(const Generation& g, TemplateFields& fields) {
  if (!g.selection.backend) {
    fields.push_back({"backend", g.templates.render("left_out_declaration",
                                                    {{"function", "Backend"},
                                                     {"reason", "the simulator's adapter: the scene asks for neither `simulation` nor `contact:`"}})});
    return;
  }
  const std::vector<std::string> scalars = scalar_types(g.options.scalars);
  const bool has_double = std::find(scalars.begin(), scalars.end(), "double") != scalars.end();
  const Vec3<double>& gravity = g.model.gravity;
  const auto member_note = [&](const char* member, const std::string& missing) {
    return fmt::format("  // {}: left out (the scene generates no {})", member, missing);
  };
  // task_kinematics and the four functions it stands for.
  const GeneratedFunction& kinematics = *find_function("task_kinematics");
  std::vector<std::string> kinematics_missing;
  std::vector<std::string> kinematics_parts = kinematics.with_all_of;
  kinematics_parts.push_back(kinematics.name);
  for (const std::string& f : kinematics_parts)
    if (!g.selection.emits(f) || (find_function(f)->per_frame && g.frames.indices.empty())) kinematics_missing.push_back(f);
  const std::string kinematics_member = kinematics_missing.empty()
                                            ? g.templates.render("backend_kinematics", {{"robot", g.ctx.robot}})
                                            : member_note("task_kinematics", fmt::format("{}", fmt::join(kinematics_missing, ", ")));
  const std::string distances_member = g.selection.emits("self_distances")
                                           ? g.templates.render("backend_distances", {{"robot", g.ctx.robot}})
                                           : member_note("self_distances", "self_distances");
  // The step's derivatives (sim::StepDerivatives) read all three blocks.
  const std::string derivatives_member =
      !g.selection.emits("contact_forward_dynamics_derivatives")
          ? member_note("contact_dynamics_derivatives", "contact_forward_dynamics_derivatives: the contact_fd_derivatives output")
      : !g.derivative_blocks.all()
          ? member_note("contact_dynamics_derivatives",
                        fmt::format("contact_forward_dynamics_derivatives with respect to all of q, v and tau (derivatives_wrt "
                                    "takes {} only)",
                                    g.derivative_blocks.names()))
          : g.templates.render("backend_derivatives", {{"robot", g.ctx.robot}});
  const std::string robot = g.ctx.robot;
  fields.push_back(
      {"backend",
       g.templates.render("backend",
                          {{"robot", robot},
                           {"default_scalar", has_double ? "double" : "float"},
                           {"total_mass", number(g.model.total_mass())},
                           {"gravity", fmt::format("{}, {}, {}", number(gravity.x()), number(gravity.y()), number(gravity.z()))},
                           {"contact_radius", g.contacts.empty() ? std::string("(void)k, 0.0") : fmt::format("{}::contact_sphere_radius[k]", robot)},
                           {"contact_name", g.contacts.empty() ? std::string("(void)k, \"\"") : fmt::format("{}::contact_sphere_names[k]", robot)},
                           {"contact_exponent", number(g.contact_exponent)},
                           {"subsystem_name", subsystem_name_statements(g.model)},
                           {"frame_name", g.frames.names.empty() ? std::string("(void)k, \"\"") : fmt::format("{}::frame_names[k]", robot)},
                           {"kinematics", kinematics_member},
                           {"distances", distances_member},
                           {"derivatives", derivatives_member}})});
}

std::string header_file(const Generation& g) {
  TemplateFields fields = structure_fields(g);
  add_declarations(g, fields);
  fields.insert(fields.end(), g.distances.header_fields.begin(), g.distances.header_fields.end());
  add_joint_limits(g, fields);
  add_contact(g, fields);
  add_batch(g, fields);
  add_backend(g, fields);
  return g.templates.render("header", fields);
}

std::string left_out_source(const Generation& g, const std::string& function, const std::string& reason) {
  return g.templates.render("left_out_source", {{"banner", g.ctx.banner},
                                                {"header", g.ctx.header},
                                                {"robot", g.ctx.robot},
                                                {"function", function},
                                                {"reason", reason}});
}

/// One source file per catalogue row (a note for a left-out one), and per batch row with --batch.
std::vector<GeneratedFile> source_files(const Generation& g) {
  std::vector<GeneratedFile> files;
  for (const TracedFunction& f : g.traced) {
    const GeneratedFunction& row = *find_function(f.name);
    const DefinitionInputs in{f, g.traced, g.model, g.independent, !g.contacts.empty(), g.ctx};
    files.push_back({g.ctx.source_file(f.name), row.definition ? row.definition(in) : emit_definition(f, g.ctx)});
  }
  for (const GeneratedFunction& row : function_catalog()) {
    if (!g.selection.emits(row.name)) continue;
    if (row.writer == Writer::closure_positions)
      files.push_back({g.ctx.source_file(row.name),
                       g.bounded(row.name, [&] { return emit_closure_positions_definition(g.model, g.ctx); })});
    if (row.writer == Writer::self_distances) files.push_back({g.ctx.source_file(row.name), g.distances.source});
  }
  if (g.options.batch > 0) {
    const std::vector<const TracedFunction*> batched = batched_traces(g);
    for (const std::string& name : batched_functions()) {
      const auto it = std::find_if(batched.begin(), batched.end(), [&](const TracedFunction* f) { return f->name == name; });
      if (it == batched.end()) {
        files.push_back({g.ctx.source_file(batch_name(name)), left_out_source(g, batch_name(name), fmt::format("{} is not generated", name))});
        continue;
      }
      const GeneratedFunction& row = *find_function(name);
      const DefinitionInputs in{**it, g.traced, g.model, g.independent, !g.contacts.empty(), g.ctx};
      files.push_back({g.ctx.source_file(batch_name(name)), row.batch_definition ? row.batch_definition(in, g.options.batch)
                                                                                 : emit_batch_definition(**it, g.options.batch, g.ctx)});
    }
  }
  for (const std::string& f : g.selection.left_out) files.push_back({g.ctx.source_file(f), left_out_source(g, f, g.left_out_reason)});
  return files;
}

/// The Python module of what the header declares.
std::string python_module(const Generation& g) {
  int pairs = 0;
  for (const auto& [name, value] : g.distances.header_fields)
    if (name == "num_distance_pairs") pairs = std::stoi(value);
  PythonModuleContents contents{g.traced,      g.selection.emits("self_distances"), !g.contacts.empty(),
                                !g.frames.names.empty(), g.selection.backend, g.model.nq(), g.model.nv(), pairs,
                                g.options.batch,         {}};
  for (const TracedFunction* f : batched_traces(g)) contents.batched.push_back(f->name);
  const TemplateSet templates =
      TemplateSet::load(python_templates_directory(g.templates.directory()), python_template_catalog());
  return emit_python_module(contents, g.ctx, templates);
}

}  // namespace

std::vector<std::string> default_frames(const Model& model) {
  std::vector<std::string> frames;
  for (int k = 1; k < model.num_bodies(); ++k) {
    const Body& b = model.body(BodyIndex(k));
    if (b.children.empty()) frames.push_back(b.name);
  }
  return frames;
}

std::vector<GeneratedFile> generate_robot(const gen::Description& description, const CodegenOptions& options,
                                          const TemplateSet& templates) {
  Generation g(description, options, templates);
  trace_functions(g);
  emit_distances(g);
  std::vector<GeneratedFile> files = {{g.ctx.header, header_file(g)}};
  for (GeneratedFile& f : source_files(g)) files.push_back(std::move(f));
  if (options.python) files.push_back({python_module_file(g.ctx), python_module(g)});
  return files;
}

}  // namespace mbgen::codegen
