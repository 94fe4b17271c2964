// Swept-sphere volumes from MJCF collision geoms, as collision_ssv.cpp does for URDF:
//   sphere                    -> point-SSV at the geom's pos, radius size[0];
//   capsule                   -> line-SSV between the end points, radius size[0] (exact): the end
//                                points are `fromto`, else pos -+ size[1] along the geom's z axis;
//   cylinder                  -> the same line-SSV (a capsule that covers the cylinder, conservative).
// Only geoms that take part in collisions count: contype and conaffinity (after the class
// defaults; MuJoCo's default is 1 and 1) not both zero, or the geom is named in a <contact><pair>.
// Other colliding geom types (box, ellipsoid, mesh, plane, ...) are counted as not modelled.
// Points are in the MJCF body's frame, which is the Frame named after the body.
#include <fmt/format.h>

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

}  // namespace

void add_mjcf_geoms(const Tree& tree, Description& d) {
  const std::set<std::string> paired = paired_geoms(tree.root);
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
