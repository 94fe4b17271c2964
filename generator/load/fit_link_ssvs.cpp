#include "load/fit_link_ssvs.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <filesystem>

#include "mesh/mesh_path.hpp"
#include "mesh/read_mesh.hpp"

namespace mbgen::gen {

SsvPrimitive to_ssv_primitive(const mesh::FittedPrimitive& p, const std::string& source) {
  SsvPrimitive s;
  s.kind = p.points.size() == 1 ? SsvPrimitive::Kind::Point : p.points.size() == 2 ? SsvPrimitive::Kind::Line : SsvPrimitive::Kind::Triangle;
  s.points = p.points;
  s.radius = p.radius;
  s.source = source;
  return s;
}

std::vector<LinkFit> fit_link_ssvs(Description& d, const std::map<std::string, std::string>& package_paths,
                                   const mesh::FitOptions& options) {
  if (options.budget < 1)
    throw std::invalid_argument(fmt::format("an SSV budget of {} primitives per link: give at least 1", options.budget));
  const std::string folder = std::filesystem::path(d.description_file).parent_path().string();
  std::vector<LinkFit> fits;
  for (const auto& [link, geometries] : d.link_meshes) {
    if (d.ssv_from_extras.count(link)) continue;
    LinkFit fit;
    fit.link = link;
    mesh::TriangleMesh gathered;
    bool usable = true;
    for (const MeshGeometry& g : geometries) {
      try {
        if (g.box) {
          if (!(g.scale.allFinite() && g.scale.minCoeff() > 0))
            throw mesh::MeshError(fmt::format("<box size=\"{} {} {}\">: a box needs three sizes > 0", g.scale.x(), g.scale.y(), g.scale.z()));
          mesh::append_transformed(mesh::box_mesh(g.scale), Vec3<double>::Ones(), g.X_LG, gathered);
          fit.sources.push_back("box");
          continue;
        }
        const std::string path = mesh::resolve_mesh_path(g.reference, folder, package_paths);
        if (!(g.scale.allFinite() && (g.scale.array() != 0).all()))
          throw mesh::MeshError(fmt::format("{}: scale \"{} {} {}\" must be finite and not zero", path, g.scale.x(), g.scale.y(), g.scale.z()));
        mesh::append_transformed(mesh::read_mesh(path), g.scale, g.X_LG, gathered);
        fit.sources.push_back(path);
      } catch (const mesh::MeshError& e) {
        d.warnings.push_back(fmt::format("{}: {}; link '{}' gets no fitted SSV (fix the reference, or give the link an "
                                         "`ssv:` compound in the extras)", g.source, e.what(), link));
        usable = false;
        break;
      }
    }
    if (!usable) continue;
    fit.compound = mesh::fit_ssv_compound(gathered, options);
    fit.mesh = std::move(gathered);
    std::vector<std::string> names;
    for (const std::string& s : fit.sources) names.push_back(std::filesystem::path(s).filename().string());
    const std::string source = fmt::format("fitted to {}", fmt::join(names, ", "));
    for (const mesh::FittedPrimitive& p : fit.compound.primitives) d.ssv[link].push_back(to_ssv_primitive(p, source));
    fits.push_back(std::move(fit));
  }
  return fits;
}

}  // namespace mbgen::gen
