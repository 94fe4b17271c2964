#include "codegen/generate_robot.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cctype>
#include <set>

#include "codegen/emit_closure_positions.hpp"
#include "codegen/emit_self_distances.hpp"
#include "codegen/trace_dynamics.hpp"
#include "codegen/trace_loop_maps.hpp"
#include "collision/collision_scene.hpp"
#include "load/load_error.hpp"
#include "model/topology.hpp"
#include "mbgen/mbgen.hpp"

#ifndef MBGEN_VERSION
#define MBGEN_VERSION "0.0.0"
#endif

namespace mbgen::codegen {

namespace {

std::string banner(const CodegenOptions& options) {
  std::string out = fmt::format("{} {} from", kBannerFirstLine, MBGEN_VERSION);
  for (const InputFile& in : options.inputs) out += fmt::format("\n//   {} (sha256 {})", in.name, in.sha256);
  out += "\n// Do not edit: regenerate with `mbgen generate`.\n";
  return out;
}

std::string string_array(const std::string& name, const std::vector<std::string>& items) {
  std::string out = fmt::format("inline constexpr const char* {}[] = {{", name);
  for (std::size_t i = 0; i < items.size(); ++i) {
    std::string escaped;
    for (char c : items[i]) escaped += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
    out += fmt::format("{}\"{}\"", i ? ", " : "", escaped);
  }
  return out + "};\n";
}

const char* kConventions = R"(// Conventions (the same as mbgen's runtime):
//  - arrays are plain C arrays; matrices are row-major;
//  - q has nq entries, v, qdd and tau have nv, in joint_names order;
//  - a floating base comes first: q = [x y z qx qy qz qw] (base position in the world, unit quaternion
//    world-from-base, Hamilton, scalar last), v = [v_B w_B] (the base's linear velocity and angular
//    velocity, both in base coordinates); its tau entries are the wrench on the base in base
//    coordinates, and its qdd entries the derivative of v (a spatial, not classical, acceleration);
//  - spatial vectors are [linear; angular]; gravity is (0, 0, -9.81) in the world;
//  - no function allocates, throws or keeps state: all may run concurrently.
//  - a robot with kinematic loops (has_loops): forward_dynamics and full_accelerations are those
//    of the closed system: q is every tree joint's position with the loops closed
//    (closure_positions), v the independent velocities (ny, independent_joint_names order), tau
//    every tree joint's force (nv; forces on dependent joints act through the loops);
//    forward_dynamics returns the independent accelerations (ny), full_accelerations every tree
//    joint's (nv, joint_names_full order). The maps between the two coordinate sets:
//    closure_positions (positions), velocity_map / full_velocities / independent_velocities
//    (v = T vy and back), acceleration_bias (qdd = T ydd + g). The other functions are the
//    spanning tree's (its inverse dynamics carries no closure forces). Without loops ny = nv,
//    T is the identity and closure_positions returns at once.
)";

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

std::vector<GeneratedFile> generate_robot(const gen::Description& description, const CodegenOptions& options) {
  const Model& model = description.model;
  const std::string& ns = options.name;
  const std::string header = ns + ".hpp";

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
  std::vector<TracedFunction> functions;
  functions.push_back(loops ? trace_forward_dynamics_loops(model) : trace_forward_dynamics(tree));
  functions.push_back(trace_full_accelerations(model));
  functions.push_back(trace_velocity_map(model));
  functions.push_back(trace_full_velocities(model));
  functions.push_back(trace_acceleration_bias(model));
  functions.push_back(trace_inverse_dynamics(tree));
  functions.push_back(trace_mass_matrix(tree));
  functions.push_back(trace_forward_kinematics(tree));
  if (!frames.empty()) {
    functions.push_back(trace_frame_poses(tree, frames));
    functions.push_back(trace_frame_jacobians(tree, frames));
  }
  functions.push_back(trace_center_of_mass(tree));
  functions.push_back(trace_centroidal_momentum_matrix(tree));

  // Self-distances: the scene decides which pairs exist (the same pruning as `mbgen inspect`,
  // seeded, so the output stays deterministic).
  const gen::CollisionScene scene = gen::build_collision_scene(description, gen::collision_scene_options(description));
  if (options.notes) {
    if (scene.sampling.drawn > 0)
      options.notes->push_back(fmt::format("collision pruning: {} of {} pairs kept; {}; {:.2f} s", scene.model.pairs.size(),
                                           scene.decisions.size(), gen::sampling_summary(scene), scene.seconds));
    for (const std::string& w : scene.warnings) options.notes->push_back("warning: " + w);
  }
  const SelfDistanceCode distances = emit_self_distances(model, scene.model, ns, header, options.scalars);

  const std::string top = banner(options);
  std::vector<GeneratedFile> files;

  std::vector<std::string> body_names;
  for (int k = 1; k < model.num_bodies(); ++k) body_names.push_back(model.body(BodyIndex(k)).name);
  std::string h = top + "#pragma once\n\n" + kConventions + fmt::format("\nnamespace {} {{\n\n", ns);
  h += fmt::format("constexpr int nq = {};\nconstexpr int nv = {};\nconstexpr int num_bodies = {};\n", model.nq(),
                   model.nv(), model.num_bodies() - 1);
  h += fmt::format("constexpr int num_frames = {};\nconstexpr bool floating_base = {};\n", frames.size(),
                   model.floating_base() ? "true" : "false");
  h += string_array("joint_names", model.joint_names());
  h += "// Every tree joint, the order of q, v, tau and of full_accelerations (the same as joint_names).\n";
  h += "inline constexpr const auto& joint_names_full = joint_names;\n";
  // The closed system's coordinates: every tree coordinate not dependent in a loop (all of them
  // for a tree), in v order. forward_dynamics takes and returns these.
  const std::vector<int> independent = Data<double>(model).independent_v;
  std::vector<std::string> independent_names;
  for (int v : independent) independent_names.push_back(gen::coordinate_name(model, v));
  h += fmt::format("constexpr int ny = {};  // independent coordinates (nv for a robot without loops)\n", independent.size());
  h += fmt::format("constexpr bool has_loops = {};\n", loops ? "true" : "false");
  h += string_array("independent_joint_names", independent_names);
  h += "// The v index of each independent coordinate (ascending).\n";
  h += fmt::format("inline constexpr int independent_v_index[] = {{{}}};\n", fmt::join(independent, ", "));
  h += string_array("body_names", body_names);
  if (!frame_names.empty()) h += string_array("frame_names", frame_names);
  for (const TracedFunction& f : functions) h += "\n" + emit_declaration(f, options.scalars);
  h += "\n/// The independent velocities vy (ny) of every tree joint's v (nv): the inverse of full_velocities on\n"
       "/// velocities that keep the loops closed.\n"
       "template <typename S> inline void independent_velocities(const S* v, S* vy) {\n"
       "  for (int i = 0; i < ny; ++i) vy[i] = v[independent_v_index[i]];\n}\n";
  h += emit_closure_positions_declaration(options.scalars);
  h += distances.declaration;
  h += fmt::format("\n}}  // namespace {}\n", ns);
  files.push_back({header, h});
  for (const TracedFunction& f : functions) {
    std::string definition;
    // One copy of the unrolled dynamics: with loops, forward_dynamics is full_accelerations
    // (functions[1]) read at the independent coordinates; without, full_accelerations is
    // forward_dynamics (functions[0]) whole.
    if (loops && f.name == "forward_dynamics") {
      definition = emit_selection_definition(f, functions[1], Data<double>(model).independent_v, ns, header, options.scalars);
    } else if (!loops && f.name == "full_accelerations") {
      std::vector<int> all(static_cast<std::size_t>(model.nv()));
      for (int i = 0; i < model.nv(); ++i) all[static_cast<std::size_t>(i)] = i;
      definition = emit_selection_definition(f, functions[0], all, ns, header, options.scalars);
    } else if (f.name == "full_velocities") {
      const auto map = std::find_if(functions.begin(), functions.end(), [](const TracedFunction& g) { return g.name == "velocity_map"; });
      definition = emit_product_definition(f, *map, ns, header, options.scalars);
    } else
      definition = emit_definition(f, ns, header, options.scalars);
    files.push_back({fmt::format("{}_{}.cpp", ns, f.name), top + "\n" + definition});
  }
  files.push_back({fmt::format("{}_closure_positions.cpp", ns),
                   top + "\n" + emit_closure_positions_definition(model, ns, header, options.scalars)});
  files.push_back({fmt::format("{}_self_distances.cpp", ns), top + "\n" + distances.definition});
  return files;
}

}  // namespace mbgen::codegen
