#include "codegen/generate_robot.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <set>

#include "codegen/emit_batch.hpp"
#include "codegen/emit_closure_positions.hpp"
#include "codegen/emit_self_distances.hpp"
#include "codegen/scene_functions.hpp"
#include "codegen/trace_dynamics.hpp"
#include "codegen/trace_loop_maps.hpp"
#include "collision/collision_scene.hpp"
#include "collision/contact_spheres.hpp"
#include "load/load_error.hpp"
#include "model/actuated_coordinates.hpp"
#include "model/topology.hpp"
#include "mbgen/control/joint_limit_potential.hpp"
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
  const Model& model = description.model;
  const EmitContext ctx{templates, options.name, templates.render("header_file", {{"robot", options.name}}),
                        banner(options, templates), options.scalars, options.max_statements_per_part,
                        /*inline_sincos=*/options.batch > 0};

  std::vector<std::string> frame_names = options.frames.empty() ? default_frames(model) : options.frames;
  std::vector<FrameIndex> frames;
  for (const std::string& name : frame_names) {
    auto f = model.find_frame(name);
    if (!f)
      throw gen::LoadError(description.extras_file.empty() ? description.description_file : description.extras_file, 0,
                           fmt::format("frame '{}'", name), "is not a frame of the robot",
                           "name a link or a fixed joint of the description (see `mbgen inspect`)");
    frames.push_back(*f);
  }

  // The spanning tree alone for everything but the closed system's dynamics: with loops, the
  // tree functions are those of the tree (inverse dynamics without closure forces, the tree's
  // mass matrix), and forward_dynamics / full_accelerations those of the closed system.
  Model tree = model;
  tree.closures.clear();
  tree.subsystems.clear();
  const bool loops = !model.subsystems.empty();
  // Each function's graph is bounded (options.max_operations): past it, a LoadError names the
  // function, instead of the memory filling up on a description too large to unroll.
  const GraphLimit limit(options.max_operations);
  auto traced = [&](const std::string& name, auto&& trace) {
    try {
      return trace();
    } catch (const GraphLimitExceeded& e) {
      throw gen::LoadError(description.description_file, 0, fmt::format("function '{}'", name),
                           fmt::format("needs more than {} operations unrolled (nv {}): too large to generate", e.limit,
                                       model.nv()),
                           "generate less (a scene with fewer outputs or a reduced model), or raise the limit with "
                           "--max-operations (about 100 bytes of memory per node while generating)");
    }
  };
  // Only what the scene's outputs ask for (scene_functions.hpp); the rest is left out.
  std::string left_out_reason;
  const FunctionSelection selection = select_functions(description, options.outputs, &left_out_reason);
  std::vector<TracedFunction> functions;
  const auto add = [&](const std::string& name, auto&& trace) {
    if (selection.emits(name)) functions.push_back(traced(name, trace));
  };
  add("forward_dynamics", [&] { return trace_generated_forward_dynamics(model); });
  add("full_accelerations", [&] { return trace_full_accelerations(model); });
  add("velocity_map", [&] { return trace_velocity_map(model); });
  add("full_velocities", [&] { return trace_full_velocities(model); });
  add("acceleration_bias", [&] { return trace_acceleration_bias(model); });
  add("inverse_dynamics", [&] { return trace_inverse_dynamics(tree); });
  // The closed system's inverse dynamics for the description's actuated set.
  const Actuation actuation = gen::description_actuation(description, options.notes);
  add("actuator_forces", [&] { return trace_actuator_forces(model, actuation); });
  add("mass_matrix", [&] { return trace_mass_matrix(tree); });
  add("mass_matrix_factor", [&] { return trace_mass_matrix_factor(tree); });  // of mass_matrix's output
  add("mass_matrix_solve", [&] { return trace_mass_matrix_solve(tree); });
  add("forward_kinematics", [&] { return trace_forward_kinematics(tree); });
  if (!frames.empty()) {
    add("frame_poses", [&] { return trace_frame_poses(tree, frames); });
    add("frame_jacobians", [&] { return trace_frame_jacobians(tree, frames); });
  }
  add("center_of_mass", [&] { return trace_center_of_mass(tree); });
  add("centroidal_momentum_matrix", [&] { return trace_centroidal_momentum_matrix(tree); });
  if (!frames.empty()) add("task_kinematics", [&] { return trace_task_kinematics(tree, frames); });
  // Ground contact: the vertex spheres of the scene's contact links. With the simulation, emitted
  // for every robot (empty, num_contact_spheres = 0, without `contact:`).
  const std::vector<sim::ContactSphere> contacts = gen::contact_spheres(description);
  add("contact_points", [&] { return trace_contact_points(tree, contacts); });
  const double contact_exponent = contacts.empty() ? 1.5 : description.scene->contact->parameters.exponent;
  add("contact_accelerations", [&] { return trace_contact_accelerations(model, contacts, contact_exponent); });
  const auto function_named = [&](const std::string& name) -> const TracedFunction& {
    const auto it = std::find_if(functions.begin(), functions.end(), [&](const TracedFunction& g) { return g.name == name; });
    if (it == functions.end()) throw std::logic_error("generate_robot: " + name + " was not traced");
    return *it;
  };
  const auto left_out_note = [&](const std::string& function) {
    return templates.render("left_out_declaration", {{"function", function}, {"reason", left_out_reason}});
  };

  // Self-distances: the scene decides which pairs exist (the same pruning as `mbgen inspect`,
  // seeded, so the output stays deterministic).
  SelfDistanceCode distances;
  if (selection.emits("self_distances")) {
    const gen::CollisionScene scene = gen::build_collision_scene(description, gen::collision_scene_options(description));
    if (options.notes) {
      options.notes->push_back(fmt::format("collision pruning: {} of {} pairs kept; {}; {:.2f} s", scene.model.pairs.size(),
                                           scene.decisions.size(), gen::sampling_summary(scene), scene.seconds));
      for (const std::string& w : scene.warnings) options.notes->push_back("warning: " + w);
    }
    distances = traced("self_distances", [&] { return emit_self_distances(model, scene.model, ctx); });
  } else {
    distances.header_fields = {{"num_distance_pairs", "0"},
                               {"distance_pair_rows", "1"},
                               {"distance_pair_names", "{\"\", \"\"}"},
                               {"distance_declarations", left_out_note("self_distances")}};
  }

  std::vector<std::string> body_names;
  for (int k = 1; k < model.num_bodies(); ++k) body_names.push_back(model.body(BodyIndex(k)).name);
  // The closed system's coordinates: every tree coordinate not dependent in a loop (all of them
  // for a tree), in v order. forward_dynamics takes and returns these.
  const std::vector<int> independent = Data<double>(model).independent_v;
  std::vector<std::string> independent_names;
  for (int v : independent) independent_names.push_back(gen::coordinate_name(model, v));
  std::vector<std::string> actuated_names;
  for (int v : actuation.actuated_v) actuated_names.push_back(gen::coordinate_name(model, v));
  std::string declarations, scalar_declarations;
  for (const TracedFunction& f : functions) declarations += emit_declaration(f, ctx);
  for (const std::string& f : selection.left_out)
    if (f != "self_distances") declarations += left_out_note(f);
  for (const std::string& s : scalar_types(options.scalars)) {
    if (!scalar_declarations.empty()) scalar_declarations += '\n';  // a rendered template ends without one
    scalar_declarations += templates.render("scalar_declarations",
                                            {{"robot", ctx.robot},
                                             {"scalar", s},
                                             {"closure_positions", ctx.public_name("closure_positions", s)},
                                             {"close_loops", ctx.public_name("close_loops", s)},
                                             {"independent_velocities", ctx.public_name("independent_velocities", s)}});
  }
  TemplateFields header_fields = {
      {"banner", ctx.banner},
      {"robot", ctx.robot},
      {"nq", std::to_string(model.nq())},
      {"nv", std::to_string(model.nv())},
      {"num_bodies", std::to_string(model.num_bodies() - 1)},
      {"num_frames", std::to_string(frames.size())},
      {"floating_base", model.floating_base() ? "true" : "false"},
      {"joint_names", quoted_list(model.joint_names())},
      {"ny", std::to_string(independent.size())},
      {"has_loops", loops ? "true" : "false"},
      {"independent_joint_names", quoted_list(independent_names)},
      {"independent_v_index", fmt::format("{}", fmt::join(independent, ", "))},
      {"na", std::to_string(actuation.num_actuators())},
      // C++ has no empty arrays: one placeholder entry when nothing is actuated.
      {"actuated_joint_names", actuated_names.empty() ? std::string("\"\"") : quoted_list(actuated_names)},
      {"actuated_v_index", actuation.actuated_v.empty() ? std::string("-1") : fmt::format("{}", fmt::join(actuation.actuated_v, ", "))},
      {"body_names", quoted_list(body_names)},
      {"frame_names", frame_names.empty() ? std::string()
                                          : templates.render("frame_names", {{"robot", ctx.robot}, {"names", quoted_list(frame_names)}})},
      {"declarations", declarations},
      {"scalar_declarations", scalar_declarations}};
  header_fields.insert(header_fields.end(), distances.header_fields.begin(), distances.header_fields.end());
  const auto number = [](double x) { return fmt::format("{}", x); };  // shortest round-trip
  // The description's position ranges, for a controller's joint-limit potential on this code
  // (control::joint_position_limits reads them back; the same rule as from a Model).
  {
    std::vector<std::string> names, q_index, v_index, lower, upper;
    for (const control::JointLimit& l : control::joint_position_limits(model)) {
      names.push_back(l.joint), q_index.push_back(std::to_string(l.q_index)), v_index.push_back(std::to_string(l.v_index));
      lower.push_back(number(l.lower)), upper.push_back(number(l.upper));
    }
    const bool none = names.empty();  // C and C++ have no empty arrays: one placeholder entry
    header_fields.push_back({"num_limited_joints", std::to_string(names.size())});
    header_fields.push_back({"limited_joint_names", none ? std::string("\"\"") : quoted_list(names)});
    header_fields.push_back({"limited_q_index", none ? std::string("-1") : fmt::format("{}", fmt::join(q_index, ", "))});
    header_fields.push_back({"limited_v_index", none ? std::string("-1") : fmt::format("{}", fmt::join(v_index, ", "))});
    header_fields.push_back({"limited_lower", none ? std::string("0") : fmt::format("{}", fmt::join(lower, ", "))});
    header_fields.push_back({"limited_upper", none ? std::string("0") : fmt::format("{}", fmt::join(upper, ", "))});
  }
  header_fields.push_back({"num_contact_spheres", std::to_string(contacts.size())});
  std::string contact_block;
  if (!contacts.empty()) {
    const gen::ContactSpec& spec = *description.scene->contact;
    std::vector<std::string> names, radii;
    for (const sim::ContactSphere& c : contacts) names.push_back(c.name), radii.push_back(number(c.radius));
    const Vec3<double>& n = spec.ground.normal;
    contact_block = templates.render("contact", {{"robot", ctx.robot},
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
  header_fields.push_back({"contact", contact_block});
  // Batch functions: those of batched_functions() the scene generates, over options.batch states.
  std::string batch_block;
  std::vector<const TracedFunction*> batched;
  if (options.batch > 0) {
    if (!valid_batch_width(options.batch))
      throw std::invalid_argument(fmt::format("batch width {}: must be a power of two from 2 to 16", options.batch));
    std::vector<std::string> names;
    for (const std::string& name : batched_functions()) {
      const auto it = std::find_if(functions.begin(), functions.end(), [&](const TracedFunction& g) { return g.name == name; });
      if (it == functions.end()) continue;
      batched.push_back(&*it);
      names.push_back(batch_name(name));
    }
    batch_block = templates.render("batch_width", {{"robot", ctx.robot},
                                                   {"lanes", std::to_string(options.batch)},
                                                   {"functions", fmt::format("{}", fmt::join(names, ", "))}});
    for (const TracedFunction* f : batched) batch_block += emit_batch_declaration(*f, options.batch, ctx);
  }
  header_fields.push_back({"batch", batch_block});
  const std::vector<std::string> scalars = scalar_types(options.scalars);
  const bool has_double = std::find(scalars.begin(), scalars.end(), "double") != scalars.end();
  const Vec3<double>& g = model.gravity;
  // The differential IK's members, when the scene generates what they call.
  const auto member_note = [&](const char* member, const std::string& missing) {
    return fmt::format("  // {}: left out (the scene generates no {})", member, missing);
  };
  std::vector<std::string> kinematics_missing;
  for (const char* f : {"frame_poses", "frame_jacobians", "center_of_mass", "centroidal_momentum_matrix", "task_kinematics"})
    if (!selection.emits(f) || (frames.empty() && (std::string(f).rfind("frame_", 0) == 0 || std::string(f) == "task_kinematics")))
      kinematics_missing.push_back(f);
  const std::string kinematics_member = kinematics_missing.empty()
                                            ? templates.render("backend_kinematics", {{"robot", ctx.robot}})
                                            : member_note("task_kinematics", fmt::format("{}", fmt::join(kinematics_missing, ", ")));
  const std::string distances_member = selection.emits("self_distances") ? templates.render("backend_distances", {{"robot", ctx.robot}})
                                                                         : member_note("self_distances", "self_distances");
  header_fields.push_back(
      {"backend",
       !selection.backend
           ? templates.render("left_out_declaration",
                              {{"function", "Backend"},
                               {"reason", "the simulator's adapter: the scene asks for neither `simulation` nor `contact:`"}})
           : templates.render("backend", {{"robot", ctx.robot},
                                    {"default_scalar", has_double ? "double" : "float"},
                                    {"total_mass", number(model.total_mass())},
                                    {"gravity", fmt::format("{}, {}, {}", number(g.x()), number(g.y()), number(g.z()))},
                                    {"contact_radius", contacts.empty() ? std::string("(void)k, 0.0") : fmt::format("{}::contact_sphere_radius[k]", ctx.robot)},
                                    {"contact_name", contacts.empty() ? std::string("(void)k, \"\"") : fmt::format("{}::contact_sphere_names[k]", ctx.robot)},
                                    {"contact_exponent", number(contact_exponent)},
                                    {"subsystem_name", subsystem_name_statements(model)},
                                    {"frame_name", frame_names.empty() ? std::string("(void)k, \"\"") : fmt::format("{}::frame_names[k]", ctx.robot)},
                                    {"kinematics", kinematics_member},
                                    {"distances", distances_member}})});

  std::vector<GeneratedFile> files;
  files.push_back({ctx.header, templates.render("header", header_fields)});
  for (const TracedFunction& f : functions) {
    std::string source;
    // One copy of the unrolled dynamics: with loops, forward_dynamics is full_accelerations read
    // at the independent coordinates; without, full_accelerations is forward_dynamics whole.
    if (loops && f.name == "forward_dynamics") {
      source = emit_selection_definition(f, function_named("full_accelerations"), independent, ctx);
    } else if (!loops && f.name == "full_accelerations") {
      std::vector<int> all(static_cast<std::size_t>(model.nv()));
      for (int i = 0; i < model.nv(); ++i) all[static_cast<std::size_t>(i)] = i;
      source = emit_selection_definition(f, function_named("forward_dynamics"), all, ctx);
    } else if (f.name == "contact_accelerations" && contacts.empty()) {
      source = emit_contact_free_definition(f, function_named("full_accelerations"), independent, ctx);
    } else if (f.name == "full_velocities") {
      source = emit_product_definition(f, function_named("velocity_map"), ctx);
    } else
      source = emit_definition(f, ctx);
    files.push_back({ctx.source_file(f.name), source});
  }
  files.push_back({ctx.source_file("closure_positions"),
                   traced("closure_positions", [&] { return emit_closure_positions_definition(model, ctx); })});
  if (selection.emits("self_distances")) files.push_back({ctx.source_file("self_distances"), distances.source});
  if (options.batch > 0)
    for (const std::string& name : batched_functions()) {
      const auto it = std::find_if(batched.begin(), batched.end(), [&](const TracedFunction* g) { return g->name == name; });
      files.push_back({ctx.source_file(batch_name(name)),
                       it != batched.end()
                           ? emit_batch_definition(**it, options.batch, ctx)
                           : templates.render("left_out_source", {{"banner", ctx.banner},
                                                                  {"header", ctx.header},
                                                                  {"robot", ctx.robot},
                                                                  {"function", batch_name(name)},
                                                                  {"reason", fmt::format("{} is not generated", name)}})});
    }
  for (const std::string& f : selection.left_out)
    files.push_back({ctx.source_file(f), templates.render("left_out_source", {{"banner", ctx.banner},
                                                                              {"header", ctx.header},
                                                                              {"robot", ctx.robot},
                                                                              {"function", f},
                                                                              {"reason", left_out_reason}})});
  return files;
}

}  // namespace mbgen::codegen
