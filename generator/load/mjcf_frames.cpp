// <frame> (MuJoCo 3): a pose, and optionally a childclass, that groups the children of a body or
// of <worldbody>; MuJoCo compiles it away, composing its pose onto each direct child. mbgen does
// the same before reading the tree: each frame's children move up into the enclosing element with
// their poses written as pos + quat (fromto's two points for a geom that has them), the frame's
// childclass becomes their class (childclass for bodies and frames) where they name none, and the
// frame is removed. Nested frames compose outermost first. What a frame may hold is what MuJoCo
// allows (body, geom, site, camera, light, frame): a joint or inertial inside one is an error.
#include <fmt/format.h>

#include <Eigen/Geometry>

#include "load/mjcf_support.hpp"

namespace mbgen::gen::mjcf {

namespace {

std::string numbers_text(std::initializer_list<double> values) {
  std::string text;
  for (double v : values) text += fmt::format("{}{:.17g}", text.empty() ? "" : " ", v);
  return text;
}

/// The class an element inside `enclosing` resolves its defaults by: its own, else the nearest
/// childclass of the elements around it, else "main".
std::string class_of(const tinyxml2::XMLElement* e) {
  if (const char* own = e->Attribute("class")) return own;
  for (const tinyxml2::XMLNode* p = e->Parent(); p && p->ToElement(); p = p->Parent())
    if (const char* c = p->ToElement()->Attribute("childclass")) return c;
  return "main";
}

/// Writes X_FC (the frame's pose composed with the child's) as the child's pose.
void write_pose(tinyxml2::XMLElement* child, const SE3<double>& X) {
  for (const char* a : {"quat", "axisangle", "euler", "xyaxes", "zaxis"}) child->DeleteAttribute(a);
  const Eigen::Quaterniond r(X.rotation);
  child->SetAttribute("pos", numbers_text({X.translation.x(), X.translation.y(), X.translation.z()}).c_str());
  child->SetAttribute("quat", numbers_text({r.w(), r.x(), r.y(), r.z()}).c_str());
}

/// Moves `frame`'s children up before it, their poses composed with the frame's; removes it.
void dissolve(const std::string& path, tinyxml2::XMLElement* frame, const Defaults& defaults, const Compiler& compiler) {
  const Element f(path, frame, defaults, class_of(frame));
  check_attributes(f, {"name", "childclass", "pos", "quat", "axisangle", "euler", "xyaxes", "zaxis"});
  if (const char* cls = frame->Attribute("childclass"); cls && !defaults.has_class(cls))
    f.fail(fmt::format("uses childclass '{}', which no <default> defines", cls), "define it with <default class=\"...\"> or correct the name");
  const SE3<double> X_PF = pose(f, compiler);
  const char* childclass = frame->Attribute("childclass");
  tinyxml2::XMLNode* parent = frame->Parent();
  tinyxml2::XMLNode* previous = frame;
  while (tinyxml2::XMLElement* child = frame->FirstChildElement()) {
    const std::string kind = child->Name();
    if (kind != "body" && kind != "geom" && kind != "site" && kind != "camera" && kind != "light" && kind != "frame")
      not_supported(path, child, fmt::format("<{}> inside a <frame>", kind),
                    "MuJoCo's frames hold bodies, geoms, sites, cameras, lights and frames: put it in the body itself");
    // Resolved while still inside the frame, so that the frame's childclass gives its defaults.
    const Element c(path, child, defaults, class_of(child));
    // A sphere ignores fromto (MuJoCo, and mjcf_geoms.cpp): its pos is what moves.
    const bool has_fromto = kind == "geom" && c.attribute("fromto").has_value() && c.string("type", "sphere") != "sphere";
    if (has_fromto) {
      const std::vector<double> p = *c.numbers("fromto", 6);
      const Vec3<double> a = X_PF.act(Vec3<double>(p[0], p[1], p[2])), b = X_PF.act(Vec3<double>(p[3], p[4], p[5]));
      child->SetAttribute("fromto", numbers_text({a.x(), a.y(), a.z(), b.x(), b.y(), b.z()}).c_str());
    } else {
      write_pose(child, X_PF * pose(c, compiler));
    }
    if (childclass) {
      const char* which = kind == "body" || kind == "frame" ? "childclass" : "class";
      if (!child->Attribute(which)) child->SetAttribute(which, childclass);
    }
    parent->InsertAfterChild(previous, child);  // unlinks it from the frame
    previous = child;
  }
  parent->DeleteChild(frame);
}

void dissolve_in(const std::string& path, tinyxml2::XMLElement* e, const Defaults& defaults, const Compiler& compiler) {
  // Dissolving a frame puts its children (nested frames among them) where it was: scan again.
  for (tinyxml2::XMLElement* c = e->FirstChildElement("frame"); c; c = e->FirstChildElement("frame")) dissolve(path, c, defaults, compiler);
  for (tinyxml2::XMLElement* b = e->FirstChildElement("body"); b; b = b->NextSiblingElement("body")) dissolve_in(path, b, defaults, compiler);
}

}  // namespace

void dissolve_frames(const std::string& path, tinyxml2::XMLElement* root, const Defaults& defaults, const Compiler& compiler) {
  if (tinyxml2::XMLElement* world = root->FirstChildElement("worldbody")) dissolve_in(path, world, defaults, compiler);
}

}  // namespace mbgen::gen::mjcf
