// `mbgen inspect`: what the loader understood, as a readable report (in the spirit of urdfdom's
// check_urdf) or as one JSON object for scripts and tests. Output is deterministic: everything
// is printed in model order or from ordered containers.
#include "cli/inspect_command.hpp"

#include <fmt/format.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <cmath>
#include <iostream>
#include <memory>
#include <optional>

#include "model/load_description.hpp"
#include "cli/inspect_collision.hpp"
#include "codegen/scene_functions.hpp"
#include "codegen/trace_dynamics.hpp"
#include "codegen/trace_loop_maps.hpp"
#include "codegen/traced_function.hpp"
#include "collision/contact_spheres.hpp"
#include "load/load_error.hpp"
#include "cli/description_options.hpp"
#include "cli/exit_codes.hpp"
#include "mesh/mesh_path.hpp"
#include "mbgen/algorithm/closure.hpp"
#include "model/topology.hpp"

namespace mbgen::cli {

namespace {

using gen::BaseType;
using gen::Description;
using Json = nlohmann::ordered_json;  // keys in the order written: a stable, readable object

struct InspectOptions {
  DescriptionOptions input;
  bool json = false;
  int samples = -1;  ///< collision pruning samples; -1: the scene's prune_samples or the default
};

const char* to_string(FrameKind kind) {
  switch (kind) {
    case FrameKind::Body: return "body";
    case FrameKind::Link: return "link";
    case FrameKind::Joint: return "joint";
    case FrameKind::User: return "user";
  }
  return "unknown";
}

const char* to_string(BaseType base) { return base == BaseType::Floating ? "floating" : "fixed"; }

std::string vec(const Vec3<double>& v) { return fmt::format("({:.6g}, {:.6g}, {:.6g})", v.x(), v.y(), v.z()); }

Json vec_json(const Vec3<double>& v) { return Json::array({v.x(), v.y(), v.z()}); }

/// {xyz, rpy} of a pose, rpy as in URDF (roll, pitch, yaw about fixed x, y, z).
Json origin_json(const SE3<double>& X) {
  const Vec3<double> ypr = X.rotation.eulerAngles(2, 1, 0);
  return Json{{"xyz", vec_json(X.translation)}, {"rpy", vec_json(Vec3<double>(ypr[2], ypr[1], ypr[0]))}};
}

std::string joint_summary(const Joint& j) {
  std::string s = fmt::format("{}: {}", j.name, mbgen::to_string(j.type));
  if (j.type == JointType::Floating) return s + ", 6 DoF";
  s += fmt::format(", axis {}", vec(j.axis));
  s += j.bounded ? fmt::format(", limits [{:.6g}, {:.6g}]", j.lower, j.upper) : ", unbounded";
  return s;
}

void print_tree(const Model& model, BodyIndex b, const std::string& prefix, bool last, std::ostream& out) {
  const Body& body = model.body(b);
  if (b == kWorldBody) {
    out << "world\n";
  } else {
    out << prefix << (last ? "└─ " : "├─ ") << body.name << "  [" << joint_summary(model.joint(body.joint)) << "]"
        << fmt::format("  mass {:.6g} kg\n", body.inertia.mass);
  }
  const std::string child_prefix = b == kWorldBody ? "" : prefix + (last ? "   " : "│  ");
  for (std::size_t i = 0; i < body.children.size(); ++i)
    print_tree(model, body.children[i], child_prefix, i + 1 == body.children.size(), out);
}

std::vector<std::string> body_names(const Model& m, const std::vector<BodyIndex>& bodies) {
  std::vector<std::string> names;
  for (BodyIndex b : bodies) names.push_back(m.body(b).name);
  return names;
}

std::vector<std::string> coordinate_names(const Model& m, const std::vector<int>& coordinates) {
  std::vector<std::string> names;
  for (int v : coordinates) names.push_back(gen::coordinate_name(m, v));
  return names;
}

void print_loops(const Description& d, std::ostream& out) {
  const Model& m = d.model;
  if (m.closures.empty()) return;
  out << fmt::format("\nloops ({}), each closure's cycle from its first body through the root to its second:\n",
                     m.closures.size());
  for (const LoopClosure& c : m.closures)
    if (c.type == ClosureType::Coupling)
      out << fmt::format("  {}: coupling, 1 row: joint '{}' follows '{}'\n", c.name, m.joint(m.body(c.body_b).joint).name,
                         m.joint(m.body(c.body_a).joint).name);
    else
      out << fmt::format("  {}: {}, {} rows: {}\n", c.name, mbgen::to_string(c.type), c.rows(),
                         fmt::join(body_names(m, gen::cycle_path(m, c)), " - "));
  const gen::AssemblyReport& a = d.assembly;
  out << fmt::format("assembly: from {}; largest joint change from it {:.6g} (joint '{}'), max |Phi| {:.3g}, "
                     "smallest kept singular value of Phi_q {:.6g} (largest {:.6g}), worst condition of Phi_z {:.4g}, "
                     "{} starting pose(s), {} iterations, {} joint(s) outside their ranges\n",
                     d.assembly_seed_source.empty() ? std::string("the zero pose") : d.assembly_seed_source,
                     a.max_joint_change, a.max_change_joint, a.residual, a.sigma_min, a.sigma_max,
                     a.dependent_conditioning > 0 ? 1 / a.dependent_conditioning : INFINITY, a.seeds, a.iterations, a.outside_ranges);
  out << fmt::format("sub-systems ({}):\n", m.subsystems.size());
  for (std::size_t k = 0; k < m.subsystems.size(); ++k) {
    const SubSystem& s = m.subsystems[k];
    std::vector<std::string> closures;
    int rows = 0;
    for (int c : s.closures) {
      closures.push_back(m.closures[c].name);
      rows += m.closures[c].rows();
    }
    out << fmt::format("  {}: closures {}; root '{}'; {} coordinates, {} constraint rows, rank {} ({} redundant)\n", k + 1,
                       fmt::join(closures, ", "), m.body(s.root).name, s.coordinates.size(), rows, s.rank(), rows - s.rank());
    out << fmt::format("     bodies: {}\n", fmt::join(body_names(m, s.bodies), ", "));
    out << fmt::format("     independent ({}): {}\n", s.independent.size(),
                       s.independent.empty() ? "-" : fmt::format("{}", fmt::join(coordinate_names(m, s.independent), ", ")));
    out << fmt::format("     dependent ({}): {}\n", s.dependent.size(), fmt::join(coordinate_names(m, s.dependent), ", "));
  }
  out << fmt::format("closed-system DoF: {} (tree {} - rank {})\n", d.closed_dof, m.nv(), m.nv() - d.closed_dof);
}

void print_text(const Description& d, const codegen::FunctionSelection& selection, const gen::CollisionScene* collision, std::ostream& out,
                const std::vector<std::string>& reduction_report) {
  const Model& m = d.model;
  out << "description: " << d.description_file << "\n";
  out << "extras:      " << (d.extras_file.empty() ? "(none)" : d.extras_file) << "\n";
  out << "robot:       " << d.robot_name << "\n";
  out << "base:        " << to_string(d.base) << "\n";
  out << fmt::format("DoF:         {} (nq = {}, nv = {})\n", m.nv(), m.nq(), m.nv());
  out << fmt::format("total mass:  {:.6g} kg\n", m.total_mass());
  out << fmt::format("bodies:      {} moving, {} joints\n\n", m.num_bodies() - 1, m.num_joints() - 1);

  out << "body tree (body  [joint: type, axis in joint frame, limits]  mass):\n";
  print_tree(m, kWorldBody, "", true, out);

  out << fmt::format("\nframes ({}):\n", m.num_frames());
  for (int f = 0; f < m.num_frames(); ++f) {
    const Frame& frame = m.frame(FrameIndex(f));
    out << fmt::format("  {} ({}, on body '{}')\n", frame.name, to_string(frame.kind), m.body(frame.body).name);
  }
  out << fmt::format("\nclosures as given ({}):\n", d.closures.size());
  for (const gen::ClosureSpec& c : d.closures)
    if (c.type == "coupling")
      out << fmt::format("  {}: coupling '{}' = {} * '{}' {} {} ({})\n", c.name, c.frame_b, c.ratio, c.frame_a,
                         c.offset < 0 ? "-" : "+", std::abs(c.offset), c.source);
    else
      out << fmt::format("  {}: {} between '{}' and '{}'\n", c.name, c.type, c.frame_a, c.frame_b);
  print_loops(d, out);
  out << fmt::format("\nactuated joints ({}): {}\n", d.actuated_joints.size(), fmt::join(d.actuated_joints, ", "));
  if (!d.joint_type_overrides.empty()) {
    out << fmt::format("joint type overrides ({}, each a chain of revolute joints <joint>_x, _y[, _z]):\n",
                       d.joint_type_overrides.size());
    for (const auto& [joint, type] : d.joint_type_overrides) out << fmt::format("  {}: {}\n", joint, type);
  }
  out << fmt::format("drives ({}):\n", d.drives.size());
  for (const gen::DriveSpec& drive : d.drives)
    out << fmt::format("  {}: gear ratio {:.6g}, rotor inertia {:.6g} kg m^2, model {}\n", drive.joint, drive.gear_ratio,
                       drive.rotor_inertia, drive.model);
  if (!d.ssv.empty()) {
    out << fmt::format("ssv compounds ({}):\n", d.ssv.size());
    for (const auto& [link, compound] : d.ssv)
      out << fmt::format("  {}: {} primitive(s), from {}\n", link, compound.size(),
                         compound.empty() ? "-" : compound.front().source);
  }
  // URDF meshes and boxes are kept per link for fitting: only links left without any compound
  // need the user's attention. MJCF geoms have no such list: their count is all there is.
  std::vector<std::string> bare_links;
  for (const auto& [link, meshes] : d.link_meshes)
    if (!d.ssv.count(link) || d.ssv.at(link).empty()) bare_links.push_back(link);
  if (!bare_links.empty()) {
    out << fmt::format("collision meshes or boxes without an SSV on {} link(s): {} (fit SSVs to them with `mbgen fit-ssv` "
                       "or `scene: collision: fit: true`, or model them with `ssv:` in the extras)\n",
                       bare_links.size(), fmt::join(bare_links, ", "));
  } else if (d.link_meshes.empty() && !d.collision_geometry_not_modelled.empty()) {
    std::vector<std::string> counts;
    for (const auto& [kind, n] : d.collision_geometry_not_modelled) counts.push_back(fmt::format("{} {}", n, kind));
    out << fmt::format("collision geometry without an SSV: {} (model it with `ssv:` in the extras)\n", fmt::join(counts, ", "));
  }
  if (!reduction_report.empty()) {
    out << "model reductions (scene: lock, merge_below, loops):\n";
    for (const std::string& line : reduction_report) out << "  " << line << "\n";
  }
  if (d.scene) out << fmt::format("scene outputs: {}\n", fmt::join(d.scene->outputs, ", "));
  {
    out << fmt::format("generated functions: {}{}\n", fmt::join(selection.generated, ", "), selection.backend ? ", Backend" : "");
    if (!selection.left_out.empty() || !selection.backend)
      out << fmt::format("left out by the scene: {}{}{}\n", fmt::join(selection.left_out, ", "),
                         selection.left_out.empty() || selection.backend ? "" : ", ", selection.backend ? "" : "Backend");
  }
  if (d.scene && d.scene->contact) {
    const gen::ContactSpec& c = *d.scene->contact;
    const ContactParameters& p = c.parameters;
    out << fmt::format("ground contact: {} spheres (the SSV vertices of {}); k {:g} N/m^{:g}, damping {:g} s/m, friction {:g}, "
                       "stiction {:g} m/s; ground n ({:g}, {:g}, {:g}), offset {:g} m\n",
                       gen::contact_spheres(d).size(), fmt::join(c.links, ", "), p.stiffness, p.exponent, p.damping, p.friction,
                       p.stiction_velocity, c.ground.normal.x(), c.ground.normal.y(), c.ground.normal.z(), c.ground.offset);
  }
  if (d.scene && !d.scene->rigid_contacts.empty()) {
    std::vector<std::string> held;
    for (const gen::RigidContactSpec& c : d.scene->rigid_contacts)
      held.push_back(fmt::format("{} ({}, {} rows)", c.frame, c.kind, c.rows()));
    out << fmt::format("rigid contacts (rigid_contact_fd_derivatives): {}\n", fmt::join(held, ", "));
  }
  if (d.scene && !d.scene->derivatives_wrt.empty())
    out << fmt::format("derivatives with respect to: {} (the other blocks left out)\n", fmt::join(d.scene->derivatives_wrt, ", "));
  if (collision) print_collision_scene(*collision, out);
  std::vector<std::string> warnings = d.warnings;
  if (collision) warnings.insert(warnings.end(), collision->warnings.begin(), collision->warnings.end());
  if (!d.notes.empty()) {  // values changed on loading (round-off zeroed, inertias repaired)
    out << fmt::format("\nnotes ({}):\n", d.notes.size());
    for (const std::string& n : d.notes) out << "  - " << n << "\n";
  }
  out << fmt::format("\nwarnings ({}):\n", warnings.size());
  for (const std::string& w : warnings) out << "  - " << w << "\n";
  out << fmt::format("\nverdict: OK: '{}' loads ({} DoF, {} closure(s), closed-system DoF {}, {} warning(s))\n",
                     d.robot_name, m.nv(), d.closures.size(), d.closed_dof, warnings.size());
}

Json to_json(const Description& d) {
  const Model& m = d.model;
  Json bodies = Json::array(), joints = Json::array(), frames = Json::array();
  for (int b = 1; b < m.num_bodies(); ++b) {
    const Body& body = m.body(BodyIndex(b));
    bodies.push_back({{"name", body.name},
                      {"parent", m.body(body.parent).name},
                      {"joint", m.joint(body.joint).name},
                      {"mass", body.inertia.mass},
                      {"com", vec_json(body.inertia.com)}});
    const Joint& j = m.joint(body.joint);
    const bool has_axis = j.type != JointType::Floating;
    joints.push_back({{"name", j.name},
                      {"type", mbgen::to_string(j.type)},
                      {"parent", m.body(j.parent).name},
                      {"child", m.body(j.child).name},
                      {"axis", has_axis ? vec_json(j.axis) : Json()},
                      {"lower", j.bounded ? Json(j.lower) : Json()},  // null: unbounded
                      {"upper", j.bounded ? Json(j.upper) : Json()},
                      {"idx_q", j.idx_q},
                      {"idx_v", j.idx_v}});
  }
  for (int f = 0; f < m.num_frames(); ++f) {
    const Frame& frame = m.frame(FrameIndex(f));
    frames.push_back({{"name", frame.name}, {"kind", to_string(frame.kind)}, {"body", m.body(frame.body).name}});
  }
  Json closures = Json::array();
  for (const gen::ClosureSpec& c : d.closures) {
    if (c.type == "coupling") {
      closures.push_back({{"name", c.name},
                          {"type", c.type},
                          {"leader", c.frame_a},
                          {"follower", c.frame_b},
                          {"ratio", c.ratio},
                          {"offset", c.offset},
                          {"source", c.source}});
      continue;
    }
    closures.push_back({{"name", c.name},
                        {"type", c.type},
                        {"parent", c.frame_a},
                        {"child", c.frame_b},
                        {"parent_origin", origin_json(c.X_AC)},
                        {"child_origin", origin_json(c.X_BC)},
                        {"axis", vec_json(c.axis)},
                        {"source", c.source}});
  }
  Json drives = Json::array();
  for (const gen::DriveSpec& drive : d.drives)
    drives.push_back({{"joint", drive.joint},
                      {"gear_ratio", drive.gear_ratio},
                      {"rotor_inertia", drive.rotor_inertia},
                      {"model", drive.model}});
  Json ssv = Json::object();
  for (const auto& [link, compound] : d.ssv) {
    Json list = Json::array();
    for (const gen::SsvPrimitive& p : compound) {
      static const char* kinds[] = {"point", "line", "triangle"};
      Json points = Json::array();
      for (const Vec3<double>& point : p.points) points.push_back(vec_json(point));
      list.push_back({{"kind", kinds[static_cast<int>(p.kind)]}, {"points", points}, {"radius", p.radius}, {"source", p.source}});
    }
    ssv[link] = list;
  }
  Json scene;  // null when the extras give none
  if (d.scene) {
    auto pairs = [](const std::vector<std::pair<std::string, std::string>>& v) {
      Json a = Json::array();
      for (const auto& [x, y] : v) a.push_back({x, y});
      return a;
    };
    scene = {{"outputs", d.scene->outputs},
             {"jacobian_frames", d.scene->jacobian_frames},
             {"collision",
              {{"margin", d.scene->collision_margin},
               {"exclude", pairs(d.scene->collision_exclude)},
               {"include", pairs(d.scene->collision_include)},
               {"prune_samples", d.scene->prune_samples}}},
             {"scalar", d.scene->scalar}};
    // Empty: all three inputs (docs/extras.md).
    scene["derivatives_wrt"] = d.scene->derivatives_wrt;
    Json held = Json::array();
    for (const gen::RigidContactSpec& c : d.scene->rigid_contacts)
      held.push_back({{"frame", c.frame}, {"kind", c.kind}, {"rows", c.rows()}});
    scene["rigid_contacts"] = held;
    if (d.scene->contact) {
      const gen::ContactSpec& c = *d.scene->contact;
      Json spheres = Json::array();
      for (const ContactSphere& s : gen::contact_spheres(d))
        spheres.push_back({{"name", s.name}, {"body", m.body(s.body).name}, {"center", {s.center.x(), s.center.y(), s.center.z()}}, {"radius", s.radius}});
      scene["contact"] = {{"links", c.links},
                          {"spheres", spheres},
                          {"stiffness", c.parameters.stiffness},
                          {"damping", c.parameters.damping},
                          {"exponent", c.parameters.exponent},
                          {"friction", c.parameters.friction},
                          {"stiction_velocity", c.parameters.stiction_velocity},
                          {"ground", {{"normal", {c.ground.normal.x(), c.ground.normal.y(), c.ground.normal.z()}}, {"offset", c.ground.offset}}}};
    }
  }
  Json loops = Json::array();
  for (const LoopClosure& c : m.closures)
    loops.push_back({{"name", c.name},
                     {"type", mbgen::to_string(c.type)},
                     {"rows", c.rows()},
                     {"body_a", m.body(c.body_a).name},
                     {"body_b", m.body(c.body_b).name},
                     {"root", m.body(closure_top(m, c)).name},
                     {"bodies", body_names(m, gen::cycle_path(m, c))}});
  Json subsystems = Json::array();
  for (const SubSystem& s : m.subsystems) {
    std::vector<std::string> closures;
    int rows = 0;
    for (int c : s.closures) {
      closures.push_back(m.closures[c].name);
      rows += m.closures[c].rows();
    }
    subsystems.push_back({{"closures", closures},
                          {"root", m.body(s.root).name},
                          {"bodies", body_names(m, s.bodies)},
                          {"independent", coordinate_names(m, s.independent)},
                          {"dependent", coordinate_names(m, s.dependent)},
                          {"rows", rows},
                          {"rank", s.rank()},
                          {"kept_rows", s.rows},
                          {"size", s.coordinates.size()}});
  }
  Json assembly;  // null without closures
  if (!m.closures.empty())
    assembly = {{"max_joint_change", d.assembly.max_joint_change},
                {"joint", d.assembly.max_change_joint},
                {"residual", d.assembly.residual},
                {"sigma_min", d.assembly.sigma_min},
                {"sigma_max", d.assembly.sigma_max},
                {"dependent_condition", d.assembly.dependent_conditioning > 0 ? 1 / d.assembly.dependent_conditioning : -1.0},
                {"seeds", d.assembly.seeds},
                {"start", d.assembly_seed_source.empty() ? std::string("zero pose") : d.assembly_seed_source},
                {"outside_ranges", d.assembly.outside_ranges},
                {"q", std::vector<double>(d.assembly.q.data(), d.assembly.q.data() + d.assembly.q.size())}};
  Json overrides = Json::object();
  for (const auto& [joint, type] : d.joint_type_overrides) overrides[joint] = type;
  return Json{{"description", d.description_file},
              {"extras", d.extras_file.empty() ? Json() : Json(d.extras_file)},
              {"robot", d.robot_name},
              {"base", to_string(d.base)},
              {"dof", m.nv()},
              {"nq", m.nq()},
              {"nv", m.nv()},
              {"total_mass", m.total_mass()},
              {"bodies", bodies},
              {"joints", joints},
              {"frames", frames},
              {"closures", closures},
              {"actuated", d.actuated_joints},
              {"joint_type_overrides", overrides},
              {"loops", loops},
              {"subsystems", subsystems},
              {"closed_dof", d.closed_dof},
              {"assembly", assembly},
              {"drives", drives},
              {"ssv", ssv},
              {"scene", scene},
              {"warnings", d.warnings},
              {"notes", d.notes},
              {"ok", true}};
}

int run_inspect(const InspectOptions& options, std::ostream& out, std::ostream& err) {
  return run_command(options.input.description, err, [&] {
    const gen::LoadOptions load = options.input.load_options();
    const Description d = gen::load_description(options.input.description, load);
    // What a generation of this description emits; also checks the scene's outputs against the
    // generator's catalogue before anything is printed.
    const codegen::FunctionSelection selection = codegen::select_functions(d, {});
    // What the reductions removed, and the forward dynamics' operations before and after.
    std::vector<std::string> reduction_report = d.reductions;
    if (!d.reductions.empty() && !options.json) {
      gen::LoadOptions whole = load;
      whole.reduce = false;
      const Description full = gen::load_description(options.input.description, whole);
      const auto fd_operations = [](const Model& m) { return codegen::count_operations(codegen::trace_generated_forward_dynamics(m)).total(); };
      const long before = fd_operations(full.model), after = fd_operations(d.model);
      reduction_report.push_back(fmt::format("loops: {} closure(s), {} sub-system(s) (whole robot: {}, {})", d.model.closures.size(),
                                             d.model.subsystems.size(), full.model.closures.size(), full.model.subsystems.size()));
      reduction_report.push_back(fmt::format("forward_dynamics: {} operations, the whole robot's {} ({:.2f}x fewer)", after, before,
                                             static_cast<double>(before) / static_cast<double>(after)));
    }
    std::optional<gen::CollisionScene> collision;
    if (!d.ssv.empty()) {
      gen::CollisionSceneOptions scene_options = gen::collision_scene_options(d);
      if (options.samples >= 0) scene_options.samples = options.samples;
      scene_options.progress = !options.json;
      collision = gen::build_collision_scene(d, scene_options);
    }
    if (options.json) {
      Json j = to_json(d);
      if (collision) j["collision_pairs"] = collision_scene_json(*collision);
      j["functions"] = {{"generated", selection.generated},
                        {"left_out", selection.left_out},
                        {"backend", selection.backend}};
      out << j.dump(2) << "\n";
    } else {
      print_text(d, selection, collision ? &*collision : nullptr, out, reduction_report);
    }
    return static_cast<int>(kSuccess);
  });
}

}  // namespace

void add_inspect_command(CLI::App& app, int& status) {
  auto options = std::make_shared<InspectOptions>();
  CLI::App* inspect = app.add_subcommand("inspect", "Load a robot description and report what mbgen understood");
  add_description_options(inspect, options->input);
  inspect->add_flag("--json", options->json, "print one JSON object instead of the report");
  inspect->add_option("--samples", options->samples,
                      "configurations sampled to prune collision pairs (default: the scene's prune_samples, else 10000)")
      ->check(CLI::NonNegativeNumber);
  inspect->callback([options, &status] { status = run_inspect(*options, std::cout, std::cerr); });
}

}  // namespace mbgen::cli
