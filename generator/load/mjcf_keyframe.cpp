// <keyframe>: the first <key> with a qpos is the pose the file's author closed the loops in
// (Cassie's `home`: standing, every joint inside its range). It becomes the assembly's starting
// pose (d.assembly_seed), read in MuJoCo's qpos layout: a free joint's 7 numbers (position, then
// quaternion w x y z; the base does not move the loops, so they are skipped), a ball's quaternion
// (as the angles of the x-y-z hinge chain mbgen makes of it), a hinge's or slide's one number
// (radians and metres whatever <compiler angle>; mbgen's coordinate is MuJoCo's, ref included).
#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "load/load_error.hpp"
#include "load/mjcf_tree.hpp"

namespace mbgen::gen::mjcf {

void read_mjcf_keyframe(const Tree& tree, Description& d) {
  const tinyxml2::XMLElement* keyframe = tree.root->FirstChildElement("keyframe");
  if (!keyframe) return;
  const tinyxml2::XMLElement* key = keyframe->FirstChildElement("key");
  while (key && !key->Attribute("qpos")) key = key->NextSiblingElement("key");
  if (!key) return;
  const Element x = tree.element(key, -1);
  const std::vector<double> qpos = *x.numbers("qpos", 0);
  std::size_t needed = 0;
  for (const Tree::QposJoint& j : tree.qpos_layout) needed += j.type == "free" ? 7 : j.type == "ball" ? 4 : 1;
  const std::string name = key->Attribute("name") ? key->Attribute("name") : "";
  if (qpos.size() != needed)
    x.fail(fmt::format("qpos has {} numbers; the joints need {} (7 per free joint, 4 per ball, 1 per hinge or slide)", qpos.size(), needed),
           "give one number per coordinate, in the order the joints appear in the file");
  std::size_t at = 0;
  for (const Tree::QposJoint& j : tree.qpos_layout) {
    const double* p = qpos.data() + at;
    if (j.type == "free") {
      at += 7;
      continue;
    }
    if (j.type == "ball") {
      at += 4;
      // R = Rx(a) Ry(b) Rz(c), the chain's order: sin b = R_02, tan a = -R_12 / R_22, tan c = -R_01 / R_00.
      const Eigen::Quaterniond r(p[0], p[1], p[2], p[3]);
      if (!(r.norm() > 1e-9)) x.fail(fmt::format("the quaternion of ball joint '{}' is zero", j.name), "give a unit quaternion w x y z");
      const Mat3<double> R = r.normalized().toRotationMatrix();
      const double angle[3] = {std::atan2(-R(1, 2), R(2, 2)), std::asin(std::clamp(R(0, 2), -1.0, 1.0)), std::atan2(-R(0, 1), R(0, 0))};
      const std::vector<std::string>& parts = tree.joints.at(j.name);
      for (std::size_t k = 0; k < parts.size(); ++k) d.assembly_seed[parts[k]] = angle[k];
      continue;
    }
    at += 1;
    if (!std::isfinite(p[0])) x.fail(fmt::format("the value of joint '{}' is not finite", j.name), "give a finite number");
    d.assembly_seed[j.name] = p[0];
  }
  d.assembly_seed_source = fmt::format("keyframe{} ({}:{})", name.empty() ? "" : fmt::format(" '{}'", name), tree.path, key->GetLineNum());
}

}  // namespace mbgen::gen::mjcf
