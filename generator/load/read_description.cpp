// read_description: URDF (or MJCF, by the .xml extension) plus extras into one Description, as
// written (model/ validates it and builds the topology). Order matters: the extras' `base` decides how the tree is built, and the extras' names are
// resolved against the built tree.
#include <cctype>
#include <filesystem>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "load/description.hpp"
#include "load/extras_support.hpp"
#include "load/fit_link_ssvs.hpp"
#include "load/joint_type_overrides.hpp"

namespace mbgen::gen {

namespace {
/// The extras file to use: the one given, else a robot.yaml lying beside the URDF.
std::optional<std::string> find_extras(const std::string& path, const LoadOptions& options) {
  if (options.extras_file) return options.extras_file;
  if (!options.pick_up_robot_yaml) return std::nullopt;
  const std::filesystem::path beside = std::filesystem::path(path).parent_path() / "robot.yaml";
  std::error_code ec;
  if (std::filesystem::is_regular_file(beside, ec)) return beside.string();
  return std::nullopt;
}
}  // namespace

DescriptionFormat description_format(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext == ".xml") return DescriptionFormat::Mjcf;
  if (ext == ".sdf" || ext == ".world") return DescriptionFormat::Sdf;
  return DescriptionFormat::Urdf;
}

Description read_description(const std::string& path, const LoadOptions& options) {
  Description d;
  d.description_file = path;
  std::optional<ExtrasFile> extras;
  if (auto file = find_extras(path, options)) {
    extras = read_extras(*file);
    d.extras_file = *file;
  }
  // Read (and, for an MJCF, refused with its line) before either loader runs.
  const double quarter_turns = extras ? extras_quarter_turns(*extras, path) : 0.0;
  const bool extras_couple = extras && extras_couples_mimics(*extras, path);
  const std::vector<std::string> closure_joints = extras ? extras_closure_joints(*extras, path) : std::vector<std::string>{};
  const DescriptionFormat format = description_format(path);
  if (format == DescriptionFormat::Sdf) {
    // A non-static model floats, as in Gazebo; --fixed / --floating or the extras' `base` override it.
    std::optional<BaseType> base = options.base;
    if (!base && extras) base = extras_base(*extras);
    load_sdf(path, base, closure_joints, d, options.repair_inertia);
  } else if (format == DescriptionFormat::Mjcf) {
    // The MJCF's free joint decides the base; --fixed / --floating or the extras' `base` override it.
    std::optional<BaseType> base = options.base;
    if (!base && extras) base = extras_base(*extras);
    load_mjcf(path, base, d, options.repair_inertia);
  } else {
    d.base = options.base.value_or(extras ? extras_base(*extras).value_or(BaseType::Fixed) : BaseType::Fixed);
    ValueReport report{d.warnings, d.notes, options.repair_inertia};
    d.model = load_urdf_model(path, d.base, report, &d.urdf_lines, quarter_turns);
    d.robot_name = d.model.name;
    add_collision_ssvs(path, d);
    add_urdf_mimics(path, d, options.couple_mimics.value_or(extras_couple));
  }
  if (extras) {
    if (extras->schema == ExtrasFile::Schema::ParallelLegs)
      apply_parallel_legs(*extras, d);
    else
      apply_mbgen_extras(*extras, d);
  }
  apply_joint_type_overrides(d);  // before validation: the chains' joints must move mass too
  // `scene: collision: fit`: SSVs for the links' meshes, each link's fit a note (inspect prints it).
  if (d.scene && d.scene->collision_fit && options.apply_scene_fit) {
    mesh::FitOptions fit;
    if (d.scene->collision_fit_budget > 0) fit.budget = d.scene->collision_fit_budget;
    for (const LinkFit& f : fit_link_ssvs(d, options.package_paths, fit))
      d.notes.push_back(fmt::format("link '{}': {} SSV primitives fitted to {} (volume {:.3g} x its convex hull, at most {:.1f} mm "
                                    "from the mesh)", f.link, f.compound.primitives.size(), fmt::join(f.sources, ", "),
                                    f.compound.report.volume / f.compound.report.hull_volume,
                                    1e3 * f.compound.report.largest_gap));
  }
  return d;
}

}  // namespace mbgen::gen
