// MJCF <equality> -> ClosureSpecs, <actuator> -> actuated joints.
//   <connect body1 body2 anchor>: a point closure ("spherical", as the YAML extras name it):
//     the anchor is given in body1's frame; its partner point in body2 is where the anchor sits
//     at MuJoCo's reference pose qpos0 (the pose the file is written in), so frame C is at the
//     anchor in body1 (X_AC) and at that point in body2 (X_BC), the two coinciding at qpos0;
//   <connect site1 site2>: a point closure between the two site frames;
//   <weld body1 body2>: a weld closure holding the relative pose of qpos0.
// body2 defaults to the world. Couplings (<joint>, <tendon> equalities) and <distance> are load
// errors: mbgen has no closure type for them yet, and dropping them would change the dynamics.
#include <fmt/format.h>

#include <algorithm>

#include "load/load_error.hpp"
#include "load/mjcf_tree.hpp"

namespace mbgen::gen::mjcf {

namespace {

struct Side {
  std::string name;
  int body = 0;        ///< tree body
  FrameIndex frame;
  SE3<double> X_FS;    ///< the named frame's pose in its MJCF body frame (identity for a body)
};

Side body_side(const Tree& tree, const Element& x, const char* attribute, bool optional) {
  const auto name = x.attribute(attribute);
  if (!name) {
    if (optional) return Side{"world", 0, tree.bodies[0].frame, SE3<double>::Identity()};
    x.fail(fmt::format("has no {}", attribute), fmt::format("name a body: {}=\"...\"", attribute));
  }
  auto it = tree.body_index.find(*name);
  if (it == tree.body_index.end())
    x.fail(fmt::format("{}=\"{}\" names no body", attribute, *name), "name a <body> of the file");
  return Side{*name, it->second, tree.bodies[it->second].frame, SE3<double>::Identity()};
}

Side site_side(const Tree& tree, const Element& x, const char* attribute) {
  const std::string name = *x.attribute(attribute);
  auto it = tree.sites.find(name);
  if (it == tree.sites.end()) x.fail(fmt::format("{}=\"{}\" names no site", attribute, name), "name a <site> of the file");
  if (!it->second.frame.valid())
    x.fail(fmt::format("site '{}' shares its name with a body or joint, so it has no frame of its own", name),
           "rename the site");
  return Side{name, it->second.body, it->second.frame, it->second.X_BS};
}

}  // namespace

void add_mjcf_equalities(const Tree& tree, Description& d) {
  int index = 0;
  for (const tinyxml2::XMLElement* eq = tree.root->FirstChildElement("equality"); eq;
       eq = eq->NextSiblingElement("equality")) {
    for (const tinyxml2::XMLElement* e = eq->FirstChildElement(); e; e = e->NextSiblingElement()) {
      ++index;
      const std::string kind = e->Name();
      const Element x = tree.element(e, -1);
      if (kind == "joint" || kind == "tendon")
        x.fail(fmt::format("not supported: a <{}> equality (a polynomial coupling of {}s)", kind, kind),
               "remove it and model the coupling as a closure in the YAML extras, or drive both joints");
      if (kind != "connect" && kind != "weld")
        x.fail(fmt::format("not supported: a <{}> equality", kind), "use <connect> or <weld>");
      if (x.string("active", "true") == "false") {
        d.warnings.push_back(fmt::format("{}:{}: inactive <{}> skipped", tree.path, e->GetLineNum(), kind));
        continue;
      }
      for (const char* a : {"relpose", "anchor"})
        if (kind == "weld" && e->Attribute(a))
          x.fail(fmt::format("not supported: {} on a <weld>", a), "weld the bodies at the pose the file is written in");
      const bool by_site = x.attribute("site1") || x.attribute("site2");
      Side a, b;
      if (by_site) {
        if (!x.attribute("site1") || !x.attribute("site2"))
          x.fail("names only one site", "give both site1 and site2");
        a = site_side(tree, x, "site1");
        b = site_side(tree, x, "site2");
      } else {
        a = body_side(tree, x, "body1", false);
        b = body_side(tree, x, "body2", true);
      }
      if (tree.bodies[a.body].body == tree.bodies[b.body].body)
        x.fail(fmt::format("'{}' and '{}' move as one body, so the constraint joins a body to itself", a.name, b.name),
               "name two bodies on either side of a loop");
      ClosureSpec c;
      c.name = x.string("name", fmt::format("{}_{}", kind, index));
      c.type = kind == "connect" ? "spherical" : "weld";
      c.frame_a = a.name;
      c.frame_b = b.name;
      c.resolved_a = a.frame;
      c.resolved_b = b.frame;
      c.source = fmt::format("{}:{}: <{}>", tree.path, e->GetLineNum(), kind);
      c.source_line = e->GetLineNum();
      if (kind == "connect" && !by_site) c.X_AC.translation = x.vec3("anchor", Vec3<double>::Zero());
      // C where it sits in frame_b at qpos0: X_BC = X_W(b)^-1 X_W(a) X_AC, with X_W(side) the
      // named frame's world pose at qpos0.
      const SE3<double> X_WA = tree.bodies[a.body].X_WB0 * a.X_FS;
      const SE3<double> X_WB = tree.bodies[b.body].X_WB0 * b.X_FS;
      c.X_BC = X_WB.inverse() * X_WA * c.X_AC;
      if (by_site && kind == "connect") c.X_BC = SE3<double>::Identity();  // the two site origins coincide
      d.closures.push_back(c);
    }
  }
}

void add_mjcf_actuators(const Tree& tree, Description& d) {
  for (const tinyxml2::XMLElement* act = tree.root->FirstChildElement("actuator"); act;
       act = act->NextSiblingElement("actuator")) {
    for (const tinyxml2::XMLElement* e = act->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const Element x = tree.element(e, -1);
      const auto joint = x.attribute("joint");
      if (!joint)
        x.fail("not supported: an actuator on something other than a joint (tendon, site, body)",
               "actuate a hinge or slide joint: joint=\"...\"");
      auto it = tree.joints.find(*joint);
      if (it == tree.joints.end()) x.fail(fmt::format("joint=\"{}\" names no joint", *joint), "name a <joint> of the file");
      if (it->second.size() != 1)
        x.fail(fmt::format("not supported: an actuator on the {} joint '{}'", it->second.empty() ? "free" : "ball", *joint),
               "actuate hinge or slide joints");
      if (std::find(d.actuated_joints.begin(), d.actuated_joints.end(), *joint) == d.actuated_joints.end())
        d.actuated_joints.push_back(*joint);
    }
  }
}

}  // namespace mbgen::gen::mjcf
