// MJCF <equality> -> ClosureSpecs, <actuator> -> actuated joints.
//   <connect body1 body2 anchor>: a point closure ("spherical", as the YAML extras name it):
//     the anchor is given in body1's frame; its partner point in body2 is where the anchor sits
//     at MuJoCo's reference pose qpos0 (the pose the file is written in), so frame C is at the
//     anchor in body1 (X_AC) and at that point in body2 (X_BC), the two coinciding at qpos0;
//   <connect site1 site2>: a point closure between the two site frames;
//   <weld body1 body2>: a weld closure holding the relative pose of qpos0.
//   <joint joint1 joint2 polycoef>: a coupling closure (loop_closure.hpp), joint1 following
//     joint2: MuJoCo's q1 - ref1 = c0 + c1 (q2 - ref2) is q1 = c1 q2 + (ref1 + c0 - c1 ref2).
//   <tendon tendon1 polycoef>: a coupling of the fixed tendon's two joints (mjcf_tendons.cpp).
// body2 defaults to the world. A joint equality with higher polynomial terms or without joint2
// (a joint held constant), a tendon equality with tendon2 or over other than two joints, and
// <distance> are load errors: dropping them would change the dynamics.
#include <fmt/format.h>

#include <algorithm>
#include <utility>
#include <vector>

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

/// The hinge or slide joint `attribute` names, and its ref.
std::pair<std::string, double> coupled_joint(const Tree& tree, const Element& x, const char* attribute) {
  const std::string name = *x.attribute(attribute);
  const auto it = std::find_if(tree.qpos_layout.begin(), tree.qpos_layout.end(), [&](const Tree::QposJoint& j) { return j.name == name; });
  if (it == tree.qpos_layout.end()) x.fail(fmt::format("{}=\"{}\" names no joint", attribute, name), "name a <joint> of the file");
  if (it->type != "hinge" && it->type != "slide")
    x.fail(fmt::format("{}=\"{}\" is a {} joint", attribute, name, it->type), "couple hinge or slide joints");
  return {name, it->ref};
}

/// <equality><joint>: joint1 = c1 joint2 + offset, as a coupling closure.
ClosureSpec joint_coupling(const Tree& tree, const Model& model, const Element& x, int index) {
  if (!x.attribute("joint1")) x.fail("has no joint1", "name the joint that follows: joint1=\"...\"");
  const auto [follower, ref1] = coupled_joint(tree, x, "joint1");
  if (!x.attribute("joint2"))
    x.fail(fmt::format("holds '{}' at a constant position (no joint2): not a coupling", follower),
           "weld the joint instead (`scene: lock` in the YAML extras), or name the joint it follows: joint2=\"...\"");
  const auto [leader, ref2] = coupled_joint(tree, x, "joint2");
  if (follower == leader) x.fail(fmt::format("couples '{}' to itself", follower), "name two different joints");
  const std::vector<double> c = x.numbers("polycoef", 5).value_or(std::vector<double>{0, 1, 0, 0, 0});
  if (c[2] != 0 || c[3] != 0 || c[4] != 0)
    x.fail(fmt::format("polycoef=\"{} {} {} {} {}\" is a polynomial of degree {}: mbgen couples joints linearly", c[0], c[1], c[2], c[3], c[4],
                       c[4] != 0 ? 4 : c[3] != 0 ? 3 : 2),
           "keep the constant and linear terms (polycoef=\"c0 c1 0 0 0\"), or model the coupling as a closure in the YAML extras");
  if (c[1] == 0)
    x.fail(fmt::format("polycoef's linear term is 0: '{}' is held at a constant position, not coupled", follower),
           "weld the joint instead (`scene: lock` in the YAML extras), or give a non-zero linear term");
  ClosureSpec spec;
  spec.name = x.string("name", fmt::format("joint_{}", index));
  spec.type = "coupling";
  spec.frame_a = leader;
  spec.frame_b = follower;
  spec.ratio = c[1];
  spec.offset = ref1 + c[0] - c[1] * ref2;
  spec.resolved_a = moved_body_frame(model, leader);
  spec.resolved_b = moved_body_frame(model, follower);
  if (!spec.resolved_a.valid() || !spec.resolved_b.valid()) x.fail("couples a joint that moves no body", "report this model");
  spec.source = fmt::format("{}:{}: <joint>", tree.path, x.line());
  spec.source_line = x.line();
  return spec;
}

}  // namespace

void add_mjcf_equalities(const Tree& tree, Description& d) {
  const std::map<std::string, FixedTendon> tendons = read_fixed_tendons(tree);
  int index = 0;
  for (const tinyxml2::XMLElement* eq = tree.root->FirstChildElement("equality"); eq;
       eq = eq->NextSiblingElement("equality")) {
    for (const tinyxml2::XMLElement* e = eq->FirstChildElement(); e; e = e->NextSiblingElement()) {
      ++index;
      const std::string kind = e->Name();
      const Element x = tree.element(e, -1);
      if (kind == "joint" || kind == "tendon") {
        if (x.string("active", "true") == "false") {
          d.warnings.push_back(fmt::format("{}:{}: inactive <{}> equality skipped", tree.path, e->GetLineNum(), kind));
          continue;
        }
        d.closures.push_back(kind == "joint" ? joint_coupling(tree, d.model, x, index) : tendon_coupling(tree, d.model, x, index, tendons));
        continue;
      }
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
