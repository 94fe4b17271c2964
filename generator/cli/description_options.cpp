#include "cli/description_options.hpp"

#include <stdexcept>

#include "mesh/mesh_path.hpp"

namespace mbgen::cli {

gen::LoadOptions DescriptionOptions::load_options() const {
  gen::LoadOptions load;
  if (!extras.empty()) load.extras_file = extras;
  if (floating) load.base = gen::BaseType::Floating;
  if (fixed) load.base = gen::BaseType::Fixed;
  load.repair_inertia = repair_inertia;
  if (!mimic.empty()) load.couple_mimics = mimic == "couple";
  for (const std::string& p : package_paths) load.package_paths.insert(mesh::parse_package_path(p));
  return load;
}

void add_description_options(CLI::App* command, DescriptionOptions& options, const DescriptionHelp& help) {
  command->add_option("DESCRIPTION", options.description, "URDF, MJCF (.xml) or SDFormat (.sdf) file")->required()->check(CLI::ExistingFile);
  command->add_option("--extras", options.extras, help.extras)->check(CLI::ExistingFile);
  CLI::Option* floating = command->add_flag("--floating", options.floating, "floating base (overrides the extras)");
  command->add_flag("--fixed", options.fixed, "fixed base (overrides the extras)")->excludes(floating);
  command->add_flag("--repair-inertia", options.repair_inertia,
                    "replace inertias no rigid body has by the nearest valid ones (a note each) instead of refusing");
  command
      ->add_option("--mimic", options.mimic,
                   "couple: a URDF <mimic> joint follows its leader through a coupling (one DoF fewer); independent: it "
                   "is a joint of its own, as Pinocchio and MuJoCo load it by default (overrides the extras' `mimic`)")
      ->check(CLI::IsMember({"couple", "independent"}));
  command
      ->add_option("--package-path", options.package_paths,
                   "NAME=DIR: package://NAME/x and model://NAME/x are DIR/x (repeatable; ROS_PACKAGE_PATH is searched after these), " +
                       help.package_path)
      ->check([](const std::string& value) -> std::string {
        try {
          mesh::parse_package_path(value);
          return "";
        } catch (const std::invalid_argument& e) {
          return e.what();
        }
      });
}

}  // namespace mbgen::cli
