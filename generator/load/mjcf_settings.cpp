// File-level MJCF settings and checks: <compiler>, <option>, which top-level elements are read,
// and the helpers that turn what is not supported into a LoadError. See docs/mjcf.md.
#include <fmt/format.h>

#include <cctype>
#include <set>

#include "load/load_error.hpp"
#include "load/mjcf_support.hpp"

namespace mbgen::gen::mjcf {

[[noreturn]] void not_supported(const std::string& path, const tinyxml2::XMLElement* e, const std::string& what,
                                const std::string& fix) {
  throw LoadError(path, e->GetLineNum(), fmt::format("<{}>", e->Name()), "not supported: " + what, fix);
}

void check_attributes(const Element& e, const std::set<std::string>& known) {
  for (const tinyxml2::XMLAttribute* a = e.xml()->FirstAttribute(); a; a = a->Next())
    if (!known.count(a->Name()))
      e.fail(fmt::format("attribute '{}' is not supported", a->Name()),
             "remove it, or model its effect another way (see docs/mjcf.md)");
}

Compiler read_compiler(const std::string& path, const tinyxml2::XMLElement* root, const Defaults& defaults) {
  Compiler c;
  for (const tinyxml2::XMLElement* e = root->FirstChildElement("compiler"); e; e = e->NextSiblingElement("compiler")) {
    const Element x(path, e, defaults, "main");
    const std::string angle = x.string("angle", c.degrees ? "degree" : "radian");
    if (angle != "degree" && angle != "radian") x.fail(fmt::format("angle=\"{}\"", angle), "use angle=\"degree\" or \"radian\"");
    c.degrees = angle == "degree";
    c.eulerseq = x.string("eulerseq", c.eulerseq);
    if (c.eulerseq.size() != 3 || c.eulerseq.find_first_not_of("xyzXYZ") != std::string::npos)
      x.fail(fmt::format("eulerseq=\"{}\"", c.eulerseq), "give three letters from xyzXYZ, e.g. eulerseq=\"xyz\"");
    c.autolimits = x.string("autolimits", c.autolimits ? "true" : "false") == "true";
    c.meshdir = x.string("meshdir", x.string("assetdir", c.meshdir));
    if (x.string("coordinate", "local") != "local")
      x.fail("not supported: coordinate=\"global\"", "convert the file to local coordinates (MuJoCo 2.3 removed them too)");
    if (x.string("inertiafromgeom", "auto") == "true")
      x.fail("not supported: inertiafromgeom=\"true\" (inertia computed from geoms)",
             "give every body an <inertial> and remove inertiafromgeom");
    for (const char* a : {"boundmass", "boundinertia", "settotalmass"})
      if (x.number(a, a == std::string("settotalmass") ? -1 : 0) > 0)
        x.fail(fmt::format("not supported: {} (MuJoCo would change the inertias)", a), fmt::format("remove {}", a));
    if (x.string("balanceinertia", "false") == "true")
      x.fail("not supported: balanceinertia (MuJoCo would change the inertias)",
             "remove it and give inertias that satisfy the triangle inequality");
  }
  return c;
}

Vec3<double> read_gravity(const std::string& path, const tinyxml2::XMLElement* root, const Defaults& defaults) {
  Vec3<double> g(0, 0, -9.81);
  for (const tinyxml2::XMLElement* e = root->FirstChildElement("option"); e; e = e->NextSiblingElement("option")) {
    const Element x(path, e, defaults, "main");
    g = x.vec3("gravity", g);
    // A medium (density, viscosity, wind) adds passive fluid forces that mbgen does not model.
    for (const char* medium : {"density", "viscosity"})
      if (x.number(medium, 0) != 0)
        x.fail(fmt::format("not supported: {} (fluid forces)", medium), fmt::format("remove {} (vacuum is the default)", medium));
    if (!x.vec3("wind", Vec3<double>::Zero()).isZero(0.0))
      x.fail("not supported: wind (fluid forces)", "remove wind");
    for (const tinyxml2::XMLElement* f = e->FirstChildElement("flag"); f; f = f->NextSiblingElement("flag"))
      if (const char* gravity = f->Attribute("gravity"); gravity && std::string(gravity) == "disable") g.setZero();
  }
  return g;
}

void check_top_level(const std::string& path, const tinyxml2::XMLElement* root) {
  static const std::set<std::string> ignored = {"compiler", "option", "size",  "default", "asset",   "worldbody",
                                                "equality", "actuator", "sensor", "keyframe", "contact", "visual",
                                                "statistic", "custom", "tendon"};  // tendon: mjcf_tendons.cpp
  for (const tinyxml2::XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string kind = e->Name();
    if (ignored.count(kind)) continue;
    if (kind == "include")
      not_supported(path, e, "<include> (files are not merged)", "paste the included file's content in place");
    not_supported(path, e, fmt::format("the top-level element <{}>", kind), "remove it (see docs/mjcf.md for what is read)");
  }
}

}  // namespace mbgen::gen::mjcf
