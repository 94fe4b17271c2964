// Swept-sphere volumes from MJCF collision geoms, as collision_ssv.cpp does for URDF:
//   sphere                    -> point-SSV at the geom's pos, radius size[0];
//   capsule                   -> line-SSV between the end points, radius size[0] (exact): the end
//                                points are `fromto`, else pos -+ size[1] along the geom's z axis;
//   cylinder                  -> the same line-SSV (a capsule that covers the cylinder, conservative).
// Only geoms that take part in collisions count: contype and conaffinity (after the class
// defaults; MuJoCo's default is 1 and 1) not both zero, or the geom is named in a <contact><pair>.
// Other colliding geom types (box, ellipsoid, mesh, plane, ...) are counted as not modelled; mesh
// geoms are also kept in `link_meshes` for fitting (fit_link_ssvs.hpp): the <mesh> asset's file
// (under the compiler's meshdir) and scale, placed by the geom's pos and orientation. MuJoCo moves
// a mesh to its inertial frame and offsets the geom by the same amount, so the vertices land in
// the body exactly where the file's coordinates, scaled and placed by the geom, put them
// (tests/test_peer_mujoco.cpp checks this against libmujoco).  A mesh with refpos/refquat
// (MuJoCo 2's own mesh frame) is not applied: a warning, and its geoms get no fit.
// Points are in the MJCF body's frame, which is the Frame named after the body.
#include <fmt/format.h>

#include <filesystem>
#include <map>
#include <set>

#include "load/mjcf_tree.hpp"

namespace mbgen::gen::mjcf {

namespace {

std::set<std::string> paired_geoms(const tinyxml2::XMLElement* root) {
  std::set<std::string> names;
  for (const tinyxml2::XMLElement* c = root->FirstChildElement("contact"); c; c = c->NextSiblingElement("contact"))
    for (const tinyxml2::XMLElement* p = c->FirstChildElement("pair"); p; p = p->NextSiblingElement("pair"))
      for (const char* a : {"geom1", "geom2"})
        if (const char* name = p->Attribute(a)) names.insert(name);
  return names;
}

/// The <mesh> assets by name (a mesh without a name is named after its file, less the extension).
struct MeshAsset {
  std::string file;
  Vec3<double> scale = Vec3<double>::Ones();
  bool reference_frame = false;  ///< refpos or refquat given
  int line = 0;
};

std::map<std::string, MeshAsset> mesh_assets(const Tree& tree) {
  std::map<std::string, MeshAsset> assets;
  for (const tinyxml2::XMLElement* a = tree.root->FirstChildElement("asset"); a; a = a->NextSiblingElement("asset"))
    for (const tinyxml2::XMLElement* m = a->FirstChildElement("mesh"); m; m = m->NextSiblingElement("mesh")) {
      const Element x(tree.path, m, *tree.defaults, m->Attribute("class") ? m->Attribute("class") : "main");
      MeshAsset asset;
      asset.file = x.string("file", "");
      if (asset.file.empty()) continue;  // a mesh given by its vertices in the file: not read here
      if (!tree.compiler.meshdir.empty()) asset.file = (std::filesystem::path(tree.compiler.meshdir) / asset.file).string();
      asset.scale = x.vec3("scale", Vec3<double>::Ones());
      asset.reference_frame = x.attribute("refpos").has_value() || x.attribute("refquat").has_value();
      asset.line = m->GetLineNum();
      const std::string name = x.string("name", std::filesystem::path(x.string("file", "")).stem().string());
      if (auto it = assets.find(name); it != assets.end())
        x.fail(fmt::format("mesh name '{}' is taken (line {}; a mesh without a name is named after its file)", name, it->second.line),
               "give each <mesh> its own name");
      assets[name] = asset;
    }
  return assets;
}

}  // namespace

void add_mjcf_geoms(const Tree& tree, Description& d) {
  const std::set<std::string> paired = paired_geoms(tree.root);
  const std::map<std::string, MeshAsset> meshes = mesh_assets(tree);
  for (int b = 0; b < static_cast<int>(tree.bodies.size()); ++b) {
    const TreeBody& tb = tree.bodies[b];
    if (!tb.xml) continue;
    int index = 0;
    for (const tinyxml2::XMLElement* e = tb.xml->FirstChildElement("geom"); e; e = e->NextSiblingElement("geom")) {
      ++index;
      const Element x = tree.element(e, b);
      const char* name = e->Attribute("name");
      const bool collides = x.number("contype", 1) != 0 || x.number("conaffinity", 1) != 0 || (name && paired.count(name));
      if (!collides) continue;
      const std::string type = x.string("type", "sphere");
      if (type != "sphere" && type != "capsule" && type != "cylinder") {
        ++d.collision_geometry_not_modelled[type];
        if (type == "mesh") {
          const std::string mesh = x.string("mesh", "");
          auto it = meshes.find(mesh);
          if (it == meshes.end())
            x.fail(fmt::format("names mesh '{}', which no <asset> <mesh> gives a file", mesh),
                   "add <mesh name=\"" + mesh + "\" file=\"...\"/> under <asset>, or fix the name");
          const std::string source = fmt::format("{}:{}: <geom> {} of body '{}'", tree.path, e->GetLineNum(),
                                                 name ? fmt::format("'{}'", name) : std::to_string(index), tb.name);
          if (it->second.reference_frame)
            d.warnings.push_back(fmt::format("{}: mesh '{}' (line {}) has refpos/refquat, which mbgen does not apply; "
                                             "this geom gets no fitted SSV (remove them, or model the body with `ssv:`)",
                                             source, mesh, it->second.line));
          else
            d.link_meshes[tb.name].push_back({it->second.file, false, it->second.scale, pose(x, tree.compiler), source});
        }
        continue;
      }
      const std::vector<double> size = x.numbers("size", 0).value_or(std::vector<double>{});
      const bool fromto = x.attribute("fromto").has_value() && type != "sphere";
      const std::size_t needed = type == "sphere" || fromto ? 1 : 2;
      if (size.size() < needed)
        x.fail(fmt::format("a {} needs {} size number(s), {} given", type, needed, size.size()),
               type == "sphere" ? "give size=\"radius\"" : "give size=\"radius half_length\", or size=\"radius\" with fromto");
      SsvPrimitive p;
      p.radius = size[0];
      p.source = fmt::format("{}:{}: <geom> {} of body '{}'", tree.path, e->GetLineNum(),
                             name ? fmt::format("'{}'", name) : std::to_string(index), tb.name);
      if (!(p.radius >= 0)) x.fail(fmt::format("has a negative radius ({})", p.radius), "give a radius >= 0");
      if (type == "sphere") {
        p.kind = SsvPrimitive::Kind::Point;
        p.points = {x.vec3("pos", Vec3<double>::Zero())};
      } else if (fromto) {
        const std::vector<double> f = *x.numbers("fromto", 6);
        p.kind = SsvPrimitive::Kind::Line;
        p.points = {Vec3<double>(f[0], f[1], f[2]), Vec3<double>(f[3], f[4], f[5])};
      } else {
        const SE3<double> X_BG = pose(x, tree.compiler);
        const Vec3<double> half = X_BG.rotation.col(2) * size[1];
        p.kind = SsvPrimitive::Kind::Line;
        p.points = {X_BG.translation - half, X_BG.translation + half};
      }
      d.ssv[tb.name].push_back(p);
    }
  }
}

}  // namespace mbgen::gen::mjcf
