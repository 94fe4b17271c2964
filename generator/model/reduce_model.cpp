#include "model/reduce_model.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <set>
#include <stdexcept>

#include "load/load_error.hpp"
#include "mbgen/joint.hpp"
#include "model/transmissions.hpp"

namespace mbgen::gen {

Model weld_joints(const Model& model, const std::map<std::string, double>& values) {
  for (const auto& [name, value] : values) {
    const auto j = model.find_joint(name);
    if (!j) throw std::invalid_argument(fmt::format("weld_joints: no joint '{}'", name));
    if (model.joint(*j).nv != 1) throw std::invalid_argument(fmt::format("weld_joints: '{}' is not a 1-DoF joint", name));
  }
  Model out;
  out.name = model.name;
  out.gravity = model.gravity;
  // Each input body's new body, and the pose of its frame in that body.
  std::vector<BodyIndex> new_body(static_cast<std::size_t>(model.num_bodies()), kWorldBody);
  std::vector<SE3<double>> X_new(static_cast<std::size_t>(model.num_bodies()), SE3<double>::Identity());
  std::vector<std::pair<std::string, BodyIndex>> welded;  // each welded joint, and its (input) child body
  std::vector<bool> is_welded(static_cast<std::size_t>(model.num_bodies()), false);
  for (int k = 1; k < model.num_bodies(); ++k) {
    const BodyIndex b(k);
    const Body& body = model.body(b);
    Joint joint = model.joint(body.joint);
    const std::size_t parent = static_cast<std::size_t>(body.parent.value());
    const BodyIndex p = new_body[parent];
    const auto it = values.find(joint.name);
    if (it != values.end()) {
      const double q_j[7] = {it->second};  // a 1-DoF joint reads q_j[0] (sized for any joint)
      const SE3<double> X_PB = joint.X_PJ * joint_motion_transform<double>(joint, q_j);
      new_body[static_cast<std::size_t>(k)] = p;
      X_new[static_cast<std::size_t>(k)] = X_new[parent] * X_PB;
      if (p != kWorldBody)
        out.mutable_body(p).inertia = out.body(p).inertia + body.inertia.transformed(X_new[static_cast<std::size_t>(k)]);
      welded.emplace_back(joint.name, b);
      is_welded[static_cast<std::size_t>(k)] = true;
    } else {
      joint.X_PJ = X_new[parent] * joint.X_PJ;
      new_body[static_cast<std::size_t>(k)] = out.add_body(p, joint, body.name, body.inertia);
    }
  }
  for (int f = 0; f < model.num_frames(); ++f) {
    Frame frame = model.frame(FrameIndex(f));
    const std::size_t b = static_cast<std::size_t>(frame.body.value());
    if (is_welded[b] && frame.kind == FrameKind::Body) frame.kind = FrameKind::Link;  // its body is the parent's now
    frame.X_BF = X_new[b] * frame.X_BF;
    frame.body = new_body[b];
    out.add_frame(frame);
  }
  // A welded joint's name stays a frame: closures, SSVs and Jacobians may name it.
  for (const auto& [name, child] : welded) {
    const std::size_t c = static_cast<std::size_t>(child.value());
    out.add_frame(Frame{name, FrameKind::Joint, new_body[c], X_new[c]});
  }
  return out;
}

namespace {

/// Bodies on some loop's path (below the lowest common ancestor of the closure's two bodies, on
/// either side): their joints move the loop.
std::map<int, std::string> loop_bodies(const Description& d) {
  const Model& m = d.model;
  std::map<int, std::string> on_loop;
  const auto chain = [&](BodyIndex b) {
    std::vector<int> up;
    for (; b != kWorldBody; b = m.body(b).parent) up.push_back(b.value());
    return up;
  };
  for (const ClosureSpec& c : d.closures) {
    if (!c.resolved_a.valid() || !c.resolved_b.valid()) continue;
    const std::vector<int> a = chain(m.frame(c.resolved_a).body), b = chain(m.frame(c.resolved_b).body);
    const std::set<int> in_a(a.begin(), a.end()), in_b(b.begin(), b.end());
    for (int x : a)
      if (!in_b.count(x)) on_loop.emplace(x, c.name);
    for (int x : b)
      if (!in_a.count(x)) on_loop.emplace(x, c.name);
  }
  return on_loop;
}

}  // namespace

Description reduce_model(Description d) {
  if (!d.scene || (d.scene->lock.empty() && d.scene->merge_below <= 0 && d.scene->loops != "transmission")) return d;
  const Model& m = d.model;
  const std::map<int, std::string> on_loop = loop_bodies(d);  // the loops as read, transmissions or not
  std::map<std::string, double> values;
  for (const auto& [name, value] : d.scene->lock) {
    const Joint& joint = m.joint(*m.find_joint(name));
    if (const auto it = on_loop.find(joint.child.value()); it != on_loop.end())
      throw LoadError(d.extras_file, d.scene->lock_line, "scene: lock",
                      fmt::format("locks '{}', a joint of the loop '{}': welded, the loop would lose its freedom", name, it->second),
                      "lock the joints above the loop instead, or leave the loop's joints free");
    values[name] = value;
  }
  // The linkages' joints, welded at the reference pose (their closures leave d.closures).
  if (d.scene->loops == "transmission")
    for (const auto& [name, value] : plan_transmissions(d)) values.emplace(name, value);
  const int nv_before = m.nv();
  const int bodies_before = m.num_bodies() - 1;
  if (!d.scene->lock.empty()) {
    std::vector<std::string> names;
    for (const auto& [name, value] : d.scene->lock) names.push_back(fmt::format("{} at {:g}", name, value));
    d.reductions.push_back(fmt::format("lock: welded {} joint(s): {}", names.size(), fmt::join(names, ", ")));
  }
  if (d.scene->merge_below > 0) {
    // Limb masses: each body with everything below it (children have higher indices).
    std::vector<double> limb(static_cast<std::size_t>(m.num_bodies()), 0.0);
    std::vector<bool> limb_on_loop(static_cast<std::size_t>(m.num_bodies()), false);
    for (int k = m.num_bodies() - 1; k >= 1; --k) {
      const BodyIndex b(k), p = m.body(b).parent;
      limb[static_cast<std::size_t>(k)] += m.body(b).inertia.mass;
      limb_on_loop[static_cast<std::size_t>(k)] = limb_on_loop[static_cast<std::size_t>(k)] || on_loop.count(k) > 0;
      if (p != kWorldBody) {
        limb[static_cast<std::size_t>(p.value())] += limb[static_cast<std::size_t>(k)];
        limb_on_loop[static_cast<std::size_t>(p.value())] = limb_on_loop[static_cast<std::size_t>(p.value())] || limb_on_loop[static_cast<std::size_t>(k)];
      }
    }
    // Closure frames on a limb keep it (a loop's other side hangs there too).
    std::set<int> closure_bodies;
    for (const ClosureSpec& c : d.closures)
      if (c.resolved_a.valid() && c.resolved_b.valid())
        closure_bodies.insert(m.frame(c.resolved_a).body.value()), closure_bodies.insert(m.frame(c.resolved_b).body.value());
    std::vector<std::string> merged;
    std::vector<bool> taken(static_cast<std::size_t>(m.num_bodies()), false);
    for (int k = 1; k < m.num_bodies(); ++k) {
      const BodyIndex b(k), p = m.body(b).parent;
      const std::size_t i = static_cast<std::size_t>(k);
      if (p != kWorldBody && taken[static_cast<std::size_t>(p.value())]) {  // inside a merged limb
        taken[i] = true;
        values.emplace(m.joint(m.body(b).joint).name, 0.0);
        continue;
      }
      const Joint& joint = m.joint(m.body(b).joint);
      bool limb_has_closure = false;
      for (int c : closure_bodies)
        for (BodyIndex x(c); x != kWorldBody && !limb_has_closure; x = m.body(x).parent) limb_has_closure = x == b;
      if (p == kWorldBody || joint.nv != 1 || limb[i] >= d.scene->merge_below || limb_on_loop[i] || limb_has_closure) continue;
      taken[i] = true;
      values.emplace(joint.name, 0.0);  // a `lock:` value, when given, wins
      merged.push_back(fmt::format("{} ({:.3g} kg)", m.body(b).name, limb[i]));
    }
    d.reductions.push_back(fmt::format("merge_below {:g} kg: {} limb(s) lumped into their parents{}{}", d.scene->merge_below,
                                       merged.size(), merged.empty() ? "" : ": ", fmt::join(merged, ", ")));
  }
  std::set<std::string> welded;
  for (const auto& [name, value] : values) welded.insert(name);
  d.model = weld_joints(m, values);
  // What named the welded joints goes with them: drives and independent-coordinate hints.
  const auto gone = [&](const std::string& joint) { return welded.count(joint) > 0; };
  std::vector<std::string> dropped_drives;
  for (const DriveSpec& drive : d.drives)
    if (gone(drive.joint)) dropped_drives.push_back(drive.joint);
  d.drives.erase(std::remove_if(d.drives.begin(), d.drives.end(), [&](const DriveSpec& s) { return gone(s.joint); }), d.drives.end());
  d.actuated_joints.erase(std::remove_if(d.actuated_joints.begin(), d.actuated_joints.end(), gone), d.actuated_joints.end());
  d.reductions.push_back(fmt::format("removed: {} DoF ({} -> {}), {} bodies ({} -> {}){}", nv_before - d.model.nv(), nv_before,
                                     d.model.nv(), bodies_before - (d.model.num_bodies() - 1), bodies_before,
                                     d.model.num_bodies() - 1,
                                     dropped_drives.empty() ? "" : fmt::format(", the drives of {}", fmt::join(dropped_drives, ", "))));
  return d;
}

}  // namespace mbgen::gen
