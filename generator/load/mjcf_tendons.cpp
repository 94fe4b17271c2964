// MJCF <tendon><fixed>: a fixed tendon's length is a linear function of joint positions,
// L = sum coef_i q_i. mbgen reads one for what an <equality><tendon> makes of it, a coupling of
// its two joints; a tendon that carries forces itself (stiffness, damping, friction, a range,
// armature) or follows sites (<spatial>) would change the dynamics without a coupling to stand
// for it, and is refused. MuJoCo's equality with tendon1 alone holds L - L0 = c0 (L0: the length
// at qpos0, sum coef_i ref_i; the other polycoef terms apply only with a tendon2):
//   coef_a (q_a - ref_a) + coef_b (q_b - ref_b) = c0
//   q_b = -(coef_a / coef_b) q_a + ref_b + (c0 + coef_a ref_a) / coef_b,
// the second joint following the first.
#include <fmt/format.h>

#include <algorithm>
#include <set>

#include "load/load_error.hpp"
#include "load/mjcf_tree.hpp"

namespace mbgen::gen::mjcf {

std::map<std::string, FixedTendon> read_fixed_tendons(const Tree& tree) {
  std::map<std::string, FixedTendon> tendons;
  for (const tinyxml2::XMLElement* group = tree.root->FirstChildElement("tendon"); group;
       group = group->NextSiblingElement("tendon")) {
    for (const tinyxml2::XMLElement* e = group->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const Element x = tree.element(e, -1);
      if (x.kind() != "fixed")
        x.fail(fmt::format("not supported: a <{}> tendon (its length follows sites and wrapping geoms)", x.kind()),
               "remove it and its actuators and equalities; a joint coupling can be a fixed tendon or an <equality><joint>");
      check_attributes(x, {"name", "class", "limited", "range", "stiffness", "damping", "frictionloss", "springlength",
                           "armature", "margin", "solreflimit", "solimplimit", "solreffriction", "solimpfriction", "width",
                           "material", "rgba", "group", "user", "actuatorfrclimited", "actuatorfrcrange"});
      for (const char* force : {"stiffness", "damping", "frictionloss", "armature"})
        if (x.number(force, 0) != 0)
          x.fail(fmt::format("not supported: {} on a tendon (the tendon carries forces of its own)", force),
                 fmt::format("remove {}, or model the force as the joints' own", force));
      if (x.string("limited", "false") == "true" || (x.string("limited", "auto") == "auto" && tree.compiler.autolimits && x.attribute("range")))
        x.fail("not supported: a tendon with a range (its limit carries forces)", "remove limited and range");
      const auto name = x.attribute("name");
      if (!name) x.fail("has no name, so no equality can refer to it", "name it: name=\"...\"");
      FixedTendon t;
      t.line = x.line();
      for (const tinyxml2::XMLElement* j = e->FirstChildElement(); j; j = j->NextSiblingElement()) {
        const Element y = tree.element(j, -1);
        if (y.kind() != "joint") y.fail(fmt::format("<{}> in a fixed tendon", y.kind()), "list <joint joint=\"...\" coef=\"...\"/> elements");
        const auto joint = y.attribute("joint");
        if (!joint) y.fail("has no joint", "name the joint: joint=\"...\"");
        const auto it = std::find_if(tree.qpos_layout.begin(), tree.qpos_layout.end(),
                                     [&](const Tree::QposJoint& q) { return q.name == *joint; });
        if (it == tree.qpos_layout.end()) y.fail(fmt::format("joint=\"{}\" names no joint", *joint), "name a <joint> of the file");
        if (it->type != "hinge" && it->type != "slide")
          y.fail(fmt::format("joint=\"{}\" is a {} joint", *joint, it->type), "a fixed tendon couples hinge or slide joints");
        t.joints.push_back({*joint, y.number("coef", 1), it->ref});
      }
      if (!tendons.emplace(*name, t).second) x.fail(fmt::format("a second tendon named '{}'", *name), "give each tendon its own name");
    }
  }
  return tendons;
}

ClosureSpec tendon_coupling(const Tree& tree, const Model& model, const Element& x, int index,
                            const std::map<std::string, FixedTendon>& tendons) {
  const auto name = x.attribute("tendon1");
  if (!name) x.fail("has no tendon1", "name a fixed tendon: tendon1=\"...\"");
  if (x.attribute("tendon2"))
    x.fail("couples two tendons' lengths: mbgen couples joints", "couple the joints with <equality><joint> instead");
  const auto it = tendons.find(*name);
  if (it == tendons.end()) x.fail(fmt::format("tendon1=\"{}\" names no fixed tendon", *name), "name a <tendon><fixed> of the file");
  const FixedTendon& t = it->second;
  if (t.joints.size() != 2)
    x.fail(fmt::format("tendon '{}' has {} joint(s): an equality on its length couples {}", *name, t.joints.size(),
                       t.joints.size() < 2 ? "nothing (it holds a joint constant)" : "more than two joints"),
           "give the tendon exactly two joints, or lock a joint held constant (`scene: lock` in the YAML extras)");
  const FixedTendon::Term &a = t.joints[0], &b = t.joints[1];
  if (a.joint == b.joint) x.fail(fmt::format("tendon '{}' lists '{}' twice", *name, a.joint), "list two different joints");
  if (a.coef == 0 || b.coef == 0)
    x.fail(fmt::format("tendon '{}' has a zero coef: its equality holds the other joint constant", *name),
           "give both joints a non-zero coef, or lock the joint (`scene: lock` in the YAML extras)");
  const double c0 = x.numbers("polycoef", 5).value_or(std::vector<double>{0, 1, 0, 0, 0})[0];
  ClosureSpec spec;
  spec.name = x.string("name", fmt::format("tendon_{}", index));
  spec.type = "coupling";
  spec.frame_a = a.joint;
  spec.frame_b = b.joint;
  spec.ratio = -a.coef / b.coef;
  spec.offset = b.ref + (c0 + a.coef * a.ref) / b.coef;
  spec.resolved_a = moved_body_frame(model, a.joint);
  spec.resolved_b = moved_body_frame(model, b.joint);
  if (!spec.resolved_a.valid() || !spec.resolved_b.valid()) x.fail("couples a joint that moves no body", "report this model");
  spec.source = fmt::format("{}:{}: <tendon> (tendon '{}', line {})", tree.path, x.line(), *name, t.line);
  spec.source_line = x.line();
  return spec;
}

}  // namespace mbgen::gen::mjcf
