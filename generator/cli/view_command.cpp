// `mbgen view`: a robot and a trajectory as one HTML page (generator/view/, docs/view.md).
#include "cli/view_command.hpp"

#include <fmt/format.h>

#include <iostream>
#include <memory>

#include "cli/description_options.hpp"
#include "cli/exit_codes.hpp"
#include "load/fit_link_ssvs.hpp"
#include "model/load_description.hpp"
#include "view/trajectory_csv.hpp"
#include "view/view_page.hpp"
#include "view/view_scene.hpp"
#include "collision/contact_spheres.hpp"

namespace mbgen::cli {

namespace {

struct ViewCommandOptions {
  DescriptionOptions input;
  std::string trajectory, out;
  view::ViewOptions view;
  bool fit = false, no_meshes = false, quiet = false;
};

int run_view(ViewCommandOptions o) {
  return run_command(o.input.description, std::cerr, [&] {
    const gen::LoadOptions load = o.input.load_options();
    gen::Description d = gen::load_description(o.input.description, load);
    if (o.fit) gen::fit_link_ssvs(d, load.package_paths, mesh::FitOptions{});
    std::unique_ptr<view::Trajectory> trajectory;
    if (!o.trajectory.empty()) {
      std::vector<std::string> contacts;
      for (const ContactSphere& s : gen::contact_spheres(d)) contacts.push_back(s.name);
      trajectory = std::make_unique<view::Trajectory>(view::read_trajectory_csv(o.trajectory, d.model, contacts));
    }
    o.view.meshes = !o.no_meshes;
    o.view.package_paths = load.package_paths;
    std::vector<std::string> warnings = d.warnings;
    const view::ViewerAssets assets = view::read_viewer_assets(view::installed_viewer_directory());
    const nlohmann::json scene = view::view_scene(d, trajectory.get(), o.view, warnings);
    for (const std::string& w : warnings) std::cerr << "warning: " << w << "\n";
    const std::string page = view::view_page(scene, assets);
    view::write_view_page(o.out, page);
    if (!o.quiet)
      std::cout << fmt::format("mbgen view: {}: {} bodies, {} SSVs, {} meshes, {} pairs, {} closures, {} frame{} -> {} ({:.1f} MB)\n",
                               d.model.name, scene["bodies"].size(), scene["ssv"].size(), scene["meshes"].size(), scene["pairs"].size(),
                               scene["closures"].size(), scene["frames"]["t"].size(), scene["frames"]["t"].size() == 1 ? "" : "s", o.out,
                               static_cast<double>(page.size()) / 1e6);
    return static_cast<int>(kSuccess);
  });
}

}  // namespace

void add_view_command(CLI::App& app, int& status) {
  auto options = std::make_shared<ViewCommandOptions>();
  CLI::App* cmd = app.add_subcommand("view", "Write one HTML page showing the robot's SSVs, meshes and loops, at its pose or along a trajectory");
  add_description_options(cmd, options->input, {"YAML extras (default: robot.yaml beside the description, if any)", "for the meshes"});
  cmd->add_option("--out", options->out, "the HTML file to write (self-contained: opens from disk)")->required();
  cmd->add_option("--trajectory", options->trajectory, "a CSV of t and q (and contact forces) to play back: what mbgen_sim and mbgen_walk "
                                                       "write with --trajectory (docs/view.md)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--near", options->view.near_threshold, "pairs nearer than this (m) are coloured, with their witness segment (default 0.03)")
      ->check(CLI::Range(1e-6, 10.0));
  cmd->add_option("--fps", options->view.fps, "frames per second kept of the trajectory (default 30; 0: every row)")->check(CLI::Range(0.0, 1e4));
  cmd->add_flag("--fit", options->fit, "fit SSVs to the meshes of links that have none (as mbgen fit-ssv does)");
  cmd->add_flag("--no-meshes", options->no_meshes, "draw the SSVs only");
  cmd->add_flag("--quiet", options->quiet, "print nothing on success");
  cmd->callback([options, &status] { status = run_view(*options); });
}

}  // namespace mbgen::cli
