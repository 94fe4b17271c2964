// `mbgen fit-ssv`: SSV compounds fitted to a robot's meshes, written as an extras `ssv:` section.
#include "cli/fit_ssv_command.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <regex>
#include <sstream>

#include "cli/ssv_picture.hpp"
#include "load/fit_link_ssvs.hpp"
#include "load/load_error.hpp"
#include "cli/description_options.hpp"
#include "cli/exit_codes.hpp"
#include "mesh/mesh_path.hpp"
#include "model/load_description.hpp"

#ifndef MBGEN_VERSION
#define MBGEN_VERSION "unknown"
#endif

namespace mbgen::cli {

namespace {

constexpr const char* kFitBanner = "# Written by mbgen fit-ssv";

struct FitSsvOptions {
  DescriptionOptions input;
  std::string out, picture_data;
  int budget = mesh::FitOptions{}.budget;
  bool quiet = false;
};

std::string yaml_key(const std::string& name) {
  static const std::regex plain("[A-Za-z0-9_][A-Za-z0-9_.-]*");
  return std::regex_match(name, plain) ? name : fmt::format("\"{}\"", name);
}

std::string point(const Vec3<double>& p) { return fmt::format("[{:.6f}, {:.6f}, {:.6f}]", p.x(), p.y(), p.z()); }

std::string primitive_yaml(const mesh::FittedPrimitive& p) {
  const char* kind = p.points.size() == 1 ? "point" : p.points.size() == 2 ? "line" : "triangle";
  std::string points = p.points.size() == 1 ? point(p.points[0]) : "[";
  if (p.points.size() > 1) {
    for (std::size_t i = 0; i < p.points.size(); ++i) points += (i ? ", " : "") + point(p.points[i]);
    points += "]";
  }
  return fmt::format("{{{}: {}, radius: {:.6f}}}", kind, points, p.radius);
}

std::string fit_yaml(const gen::Description& d, const std::vector<gen::LinkFit>& fits, int budget) {
  std::string y = fmt::format("{} {} from {}, at most {} primitives per link.\n", kFitBanner, MBGEN_VERSION,
                              std::filesystem::path(d.description_file).filename().string(), budget);
  y += "# Each compound encloses its link's meshes (every vertex checked). Review it, then use this file\n"
       "# as the extras (or paste `ssv:` into yours): a link's `ssv:` replaces what the URDF gives it.\n"
       "# Per link: primitives; swept volume / the meshes' convex hull; largest distance from the SSVs to the mesh.\n"
       "ssv:";
  // An empty section must still be a map, so that the file loads as extras.
  y += fits.empty() ? " {}  # no link had a mesh or box to fit\n" : "\n";
  for (const gen::LinkFit& f : fits) {
    const mesh::FitReport& r = f.compound.report;
    std::vector<std::string> names;
    for (const std::string& s : f.sources) names.push_back(std::filesystem::path(s).filename().string());
    y += fmt::format("  {}:  # {} primitive{}; {}; {:.1f} mm; {}\n", yaml_key(f.link), f.compound.primitives.size(),
                     f.compound.primitives.size() == 1 ? "" : "s",
                     r.hull_volume > 0 ? fmt::format("{:.2f} x hull", r.volume / r.hull_volume) : std::string("flat mesh"),
                     1e3 * r.largest_gap, fmt::join(names, ", "));
    for (const mesh::FittedPrimitive& p : f.compound.primitives) y += fmt::format("    - {}\n", primitive_yaml(p));
  }
  return y;
}

/// Writes `text` to `path` unless a file is there that fit-ssv did not write.
void write_fit_file(const std::string& path, const std::string& text) {
  if (std::filesystem::exists(path)) {
    std::ifstream in(path);
    std::string first;
    std::getline(in, first);
    if (first.rfind(kFitBanner, 0) != 0)
      throw codegen::OutputRefused(fmt::format("{}: error: the file exists and was not written by mbgen fit-ssv (no `{}` on its "
                                           "first line)\n  fix: choose another --out, or move the file away; mbgen never "
                                           "overwrites files it did not write", path, kFitBanner));
  }
  codegen::write_via_temporary(path, text);
}

int run_fit_ssv(const FitSsvOptions& o) {
  return run_command(o.input.description, std::cerr, [&] {
    gen::LoadOptions load = o.input.load_options();
    load.reduce = false;          // every link of the description gets its compound
    load.apply_scene_fit = false;  // fitted here, once, with this command's budget
    gen::Description d = gen::load_description(o.input.description, load);
    mesh::FitOptions fit;
    fit.budget = o.budget;
    const std::vector<gen::LinkFit> fits = gen::fit_link_ssvs(d, load.package_paths, fit);
    for (const std::string& w : d.warnings) std::cerr << "warning: " << w << "\n";
    write_fit_file(o.out, fit_yaml(d, fits, o.budget));
    if (!o.picture_data.empty()) write_ssv_picture_data(o.picture_data, d, fits);
    if (!o.quiet) {
      std::cout << fmt::format("{:<28} {:>6} {:>5} {:>10} {:>10} {:>7} {:>7}\n", "link", "tris", "SSVs", "volume L",
                               "hull L", "ratio", "gap mm");
      int primitives = 0;
      for (const gen::LinkFit& f : fits) {
        const mesh::FitReport& r = f.compound.report;
        primitives += static_cast<int>(f.compound.primitives.size());
        std::cout << fmt::format("{:<28} {:>6} {:>5} {:>10.3f} {:>10.3f} {:>7.2f} {:>7.1f}\n", f.link, r.triangles,
                                 f.compound.primitives.size(), 1e3 * r.volume, 1e3 * r.hull_volume,
                                 r.hull_volume > 0 ? r.volume / r.hull_volume : 0.0, 1e3 * r.largest_gap);
      }
      std::cout << fmt::format("mbgen fit-ssv: {} link{} fitted, {} primitives -> {}\n", fits.size(), fits.size() == 1 ? "" : "s",
                               primitives, o.out);
    }
    return static_cast<int>(kSuccess);
  });
}

}  // namespace

void add_fit_ssv_command(CLI::App& app, int& status) {
  auto options = std::make_shared<FitSsvOptions>();
  CLI::App* cmd = app.add_subcommand("fit-ssv", "Fit swept-sphere compounds to each link's meshes; write them as extras");
  add_description_options(cmd, options->input,
                          {"YAML extras (links it gives an `ssv:` are not refitted)", "for the meshes"});
  cmd->add_option("--out", options->out, "the YAML file to write (an extras file with `ssv:` only)")->required();
  cmd->add_option("--budget", options->budget, "most SSV primitives per link (default 4; a plate counts 2)")
      ->check(CLI::Range(1, 64));
  cmd->add_option("--picture-data", options->picture_data,
                  "also write the meshes and SSV outlines at the nominal pose to this folder (scripts/ssv_picture.sh draws them)");
  cmd->add_flag("--quiet", options->quiet, "print nothing on success");
  cmd->callback([options, &status] { status = run_fit_ssv(*options); });
}

}  // namespace mbgen::cli
