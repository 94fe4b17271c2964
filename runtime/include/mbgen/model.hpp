#pragma once
// Model: the constant description of a tree-structured multibody system (bodies, joints,
// inertias, named frames), in double precision. Algorithms take a Model and a Data<S> (work
// memory for scalar S); see data.hpp. Fixed joints never appear here: the loader merges them.
//
// Conventions (also in the README and in every generated header):
//  - spatial vectors are [linear; angular]; body velocities are expressed in the body frame;
//  - a floating base has q = [x y z, qx qy qz qw] (position of the base in the world, unit
//    quaternion world-from-base, Hamilton, scalar last) and v = [v_B, w_B], the base's spatial
//    velocity in its own frame (linear velocity of the base origin and angular velocity, both in
//    base coordinates);
//  - gravity is a world vector, default (0, 0, -9.81).
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "mbgen/index.hpp"
#include "mbgen/loop_closure.hpp"
#include "mbgen/model_structure.hpp"
#include "mbgen/spatial/inertia.hpp"

namespace mbgen {

enum class JointType { Revolute, Prismatic, Floating };

const char* to_string(JointType type);

struct Joint {
  std::string name;
  JointType type = JointType::Revolute;
  Vec3<double> axis = Vec3<double>::UnitZ();  ///< unit, in the joint frame (revolute, prismatic)
  /// Pose of the joint frame J in the parent body frame P; the child body frame coincides with J
  /// when the joint coordinate is zero.
  SE3<double> X_PJ;
  bool X_PJ_is_identity = true;  ///< set by Model::add_body; lets the double path skip the transform
  BodyIndex parent;
  BodyIndex child;
  int idx_q = 0, idx_v = 0, nq = 0, nv = 0;
  bool bounded = false;  ///< revolute with limits, prismatic; false for continuous and floating
  double lower = 0, upper = 0, velocity_limit = 0, effort_limit = 0, damping = 0, friction = 0;
  /// Geared drive (harmonic drive, ball screw) of a 1-DoF joint; see algorithm/rotor.hpp.
  /// Armature model: the rotor's reflected inertia N^2 I_r, added to the diagonal of M (as
  /// Pinocchio's Model::armature). Body model: a rotor that spins about the joint axis, fixed in
  /// the parent body, at N times the joint rate, with its gyroscopic coupling.
  double armature = 0;           ///< reflected inertia on the diagonal, kg m^2 (revolute) or kg (prismatic)
  double rotor_gear_ratio = 0;   ///< body model: rotor rate / joint rate (rad/rad or rad/m); 0 = no rotor body
  double rotor_inertia = 0;      ///< body model: rotor inertia about its spin axis, kg m^2
  bool has_rotor_body() const { return rotor_gear_ratio != 0 && rotor_inertia != 0; }
};

struct Body {
  std::string name;
  BodyIndex parent;           ///< kWorldBody for a root
  JointIndex joint;           ///< the joint that moves this body (invalid for the world)
  Inertia<double> inertia;    ///< lumped inertia of the body (and of links merged into it), in its frame
  std::vector<BodyIndex> children;
};

enum class FrameKind { Body, Link, Joint, User };

/// A named frame fixed in a body: every URDF link (merged or not) and every fixed joint.
struct Frame {
  std::string name;
  FrameKind kind = FrameKind::Link;
  BodyIndex body;
  SE3<double> X_BF;  ///< pose of the frame in its body
};

class Model {
 public:
  Model();

  std::string name;
  Vec3<double> gravity{0.0, 0.0, -9.81};
  /// Loop closures on top of the tree, and the sub-systems they form (empty for a tree).
  /// Filled by the loader's topology stage; see loop_closure.hpp. After changing them, call
  /// update_structure(): a Data made from a model whose structure is not current is refused.
  std::vector<LoopClosure> closures;
  std::vector<SubSystem> subsystems;

  /// What the algorithms read of the model's structure (model_structure.hpp): the closed
  /// system's coordinates, the loops' bodies, the sub-systems' layouts.
  const ModelStructure& structure() const { return structure_; }
  /// Computes structure() from the bodies, joints, closures and sub-systems as they are now
  /// (add_body does it; so must whoever changes the loops, or a joint's rotor, afterwards).
  /// Throws std::invalid_argument if a sub-system is not one the O(n) recursion can treat.
  void update_structure();
  /// structure() equals what update_structure() would compute now.
  bool structure_is_current() const;
  /// Total number of stacked constraint rows of all closures (redundant ones included).
  int num_constraint_rows() const {
    int m = 0;
    for (const LoopClosure& c : closures) m += c.rows();
    return m;
  }

  int nq() const { return nq_; }
  int nv() const { return nv_; }
  int num_bodies() const { return bodies_.size(); }  ///< including the world
  int num_joints() const { return joints_.size(); }  ///< including the world's placeholder
  int num_frames() const { return frames_.size(); }
  bool floating_base() const;

  const Body& body(BodyIndex i) const { return bodies_[i]; }
  const Joint& joint(JointIndex j) const { return joints_[j]; }
  const Frame& frame(FrameIndex f) const { return frames_[f]; }
  Body& mutable_body(BodyIndex i) { return bodies_[i]; }
  Joint& mutable_joint(JointIndex j) { return joints_[j]; }
  Frame& mutable_frame(FrameIndex f) { return frames_[f]; }
  /// Joint j moves body j: the numbering is shared but the types are not.
  static JointIndex joint_of(BodyIndex b) { return JointIndex(b.value()); }
  static BodyIndex body_of(JointIndex j) { return BodyIndex(j.value()); }

  /// Adds a body moved by `joint` relative to `parent` (which must already exist). The joint's
  /// parent, child, idx_q, idx_v, nq and nv are filled in here.
  BodyIndex add_body(BodyIndex parent, Joint joint, std::string body_name, const Inertia<double>& inertia);
  FrameIndex add_frame(Frame frame);

  std::optional<BodyIndex> find_body(const std::string& body_name) const;
  std::optional<JointIndex> find_joint(const std::string& joint_name) const;
  std::optional<FrameIndex> find_frame(const std::string& frame_name) const;
  /// Like find_frame, but throws std::out_of_range naming the frame if absent.
  FrameIndex frame_index(const std::string& frame_name) const;

  /// The joint whose velocity block holds coordinate v (0 <= v < nv); the world's placeholder
  /// (index 0) if v is out of range.
  JointIndex joint_of_v(int v) const;
  /// q index of velocity coordinate v when its joint has one DoF (position and rate then pair
  /// up), else -1 (inside a floating joint, or out of range).
  int q_index_of_v(int v) const;
  /// The velocity coordinate before v on the path to the root: the previous coordinate of v's
  /// joint, else the last coordinate of the parent body's joint; -1 at a root (Featherstone's
  /// lambda over coordinates: M(v, w) can be nonzero only if one is an ancestor of the other).
  int velocity_parent(int v) const { return velocity_parents_[static_cast<std::size_t>(v)]; }

  /// Total mass of the moving bodies.
  double total_mass() const;
  /// Names of the moving joints in q order.
  std::vector<std::string> joint_names() const;

 private:
  IndexedVector<BodyIndex, Body> bodies_;
  IndexedVector<JointIndex, Joint> joints_;
  IndexedVector<FrameIndex, Frame> frames_;
  int nq_ = 0, nv_ = 0;
  std::vector<int> velocity_parents_;
  ModelStructure structure_;
};

inline const char* to_string(JointType type) {
  switch (type) {
    case JointType::Revolute: return "revolute";
    case JointType::Prismatic: return "prismatic";
    case JointType::Floating: return "floating";
  }
  return "unknown";
}

inline Model::Model() {
  Body world;
  world.name = "world";
  bodies_.push_back(world);
  Joint none;
  none.name = "universe";
  joints_.push_back(none);
}

inline bool Model::floating_base() const {
  for (BodyIndex c : bodies_[kWorldBody].children)
    if (joints_[joint_of(c)].type == JointType::Floating) return true;
  return false;
}

inline BodyIndex Model::add_body(BodyIndex parent, Joint joint, std::string body_name,
                                 const Inertia<double>& inertia) {
  if (!parent.valid() || parent.value() >= bodies_.size())
    throw std::out_of_range("Model::add_body: parent body index out of range");
  BodyIndex index(bodies_.size());
  joint.parent = parent;
  joint.child = index;
  joint.nq = joint.type == JointType::Floating ? 7 : 1;
  joint.nv = joint.type == JointType::Floating ? 6 : 1;
  joint.X_PJ_is_identity = joint.X_PJ.rotation == Mat3<double>::Identity() && joint.X_PJ.translation.isZero(0.0);
  joint.idx_q = nq_;
  joint.idx_v = nv_;
  for (int k = 0; k < joint.nv; ++k) {
    const Joint& parent_joint = joints_[JointIndex(parent.value())];
    velocity_parents_.push_back(k > 0 ? nv_ + k - 1 : parent == kWorldBody ? -1 : parent_joint.idx_v + parent_joint.nv - 1);
  }
  nq_ += joint.nq;
  nv_ += joint.nv;
  Body body;
  body.name = std::move(body_name);
  body.parent = parent;
  body.joint = JointIndex(index.value());
  body.inertia = inertia;
  bodies_.push_back(std::move(body));
  joints_.push_back(std::move(joint));
  bodies_[parent].children.push_back(index);
  update_structure();
  return index;
}

inline FrameIndex Model::add_frame(Frame frame) {
  frames_.push_back(std::move(frame));
  return FrameIndex(frames_.size() - 1);
}

inline std::optional<BodyIndex> Model::find_body(const std::string& body_name) const {
  for (int i = 0; i < bodies_.size(); ++i)
    if (bodies_[BodyIndex(i)].name == body_name) return BodyIndex(i);
  return std::nullopt;
}

inline std::optional<JointIndex> Model::find_joint(const std::string& joint_name) const {
  for (int i = 1; i < joints_.size(); ++i)
    if (joints_[JointIndex(i)].name == joint_name) return JointIndex(i);
  return std::nullopt;
}

inline std::optional<FrameIndex> Model::find_frame(const std::string& frame_name) const {
  for (int i = 0; i < frames_.size(); ++i)
    if (frames_[FrameIndex(i)].name == frame_name) return FrameIndex(i);
  return std::nullopt;
}

inline FrameIndex Model::frame_index(const std::string& frame_name) const {
  if (auto f = find_frame(frame_name)) return *f;
  throw std::out_of_range("no frame named '" + frame_name + "' in model '" + name + "'");
}

inline JointIndex Model::joint_of_v(int v) const {
  for (int j = 1; j < joints_.size(); ++j) {
    const Joint& joint = joints_[JointIndex(j)];
    if (v >= joint.idx_v && v < joint.idx_v + joint.nv) return JointIndex(j);
  }
  return JointIndex(0);
}

inline int Model::q_index_of_v(int v) const {
  const JointIndex j = joint_of_v(v);
  return j.value() > 0 && joints_[j].nv == 1 ? joints_[j].idx_q : -1;
}

inline double Model::total_mass() const {
  double m = 0;
  for (int i = 1; i < bodies_.size(); ++i) m += bodies_[BodyIndex(i)].inertia.mass;
  return m;
}

inline std::vector<std::string> Model::joint_names() const {
  std::vector<std::string> names;
  for (int j = 1; j < joints_.size(); ++j) names.push_back(joints_[JointIndex(j)].name);
  return names;
}

/// Deepest body that supports both a and b (the world if nothing else): where a closure's
/// fundamental cycle turns. Bodies are numbered parents first, so the larger index climbs.
inline BodyIndex common_ancestor(const Model& model, BodyIndex a, BodyIndex b) {
  while (a != b) {
    if (a.value() > b.value())
      a = model.body(a).parent;
    else
      b = model.body(b).parent;
  }
  return a;
}

/// The top of a closure's fundamental cycle: the deepest body supporting both of its sides, the
/// bodies strictly below it on the two paths being the cycle. A coupling relates the joints that
/// move body_a and body_b, so its cycle must contain both bodies (and what lies between them):
/// its top is taken from their parents (a follower below its leader still has the leader's body
/// on its cycle).
inline BodyIndex closure_top(const Model& model, const LoopClosure& c) {
  if (c.type == ClosureType::Coupling) return common_ancestor(model, model.body(c.body_a).parent, model.body(c.body_b).parent);
  return common_ancestor(model, c.body_a, c.body_b);
}

/// The structure of `model` as it is now (Model::update_structure stores it).
inline ModelStructure compute_structure(const Model& model) {
  ModelStructure out;
  const std::size_t nv = static_cast<std::size_t>(model.nv());
  std::vector<bool> dependent(nv, false);
  for (const SubSystem& s : model.subsystems)
    for (int z : s.dependent)
      if (z >= 0 && static_cast<std::size_t>(z) < nv) dependent[static_cast<std::size_t>(z)] = true;
  out.column_of_v.assign(nv, -1);
  for (std::size_t i = 0; i < nv; ++i)
    if (!dependent[i]) {
      out.column_of_v[i] = static_cast<int>(out.independent_v.size());
      out.independent_v.push_back(static_cast<int>(i));
    }
  out.subsystem_of_body = IndexedVector<BodyIndex, int>(static_cast<std::size_t>(model.num_bodies()), -1);
  for (std::size_t k = 0; k < model.subsystems.size(); ++k)
    for (BodyIndex b : model.subsystems[k].bodies) out.subsystem_of_body[b] = static_cast<int>(k);
  std::vector<bool> on_cycle(static_cast<std::size_t>(model.num_bodies()), false);
  for (const LoopClosure& c : model.closures) {
    const BodyIndex top = closure_top(model, c);
    for (BodyIndex b : {c.body_a, c.body_b})
      for (; b != top; b = model.body(b).parent) on_cycle[static_cast<std::size_t>(b.value())] = true;
  }
  for (int k = 1; k < model.num_bodies(); ++k)
    if (on_cycle[static_cast<std::size_t>(k)]) out.cycle_bodies.push_back(BodyIndex(k));
  for (const SubSystem& s : model.subsystems) {
    SubSystemLayout layout;
    const auto fail = [&](const std::string& what) {
      throw std::invalid_argument("sub-system of closure(s) rooted at body '" + model.body(s.root).name + "': " + what);
    };
    if (s.coordinates.size() != s.bodies.size()) fail("needs one coordinate per body");
    for (std::size_t j = 0; j < s.bodies.size(); ++j) {
      const Body& body = model.body(s.bodies[j]);
      const Joint& joint = model.joint(body.joint);
      if (joint.nv != 1 || joint.idx_v != s.coordinates[j])
        fail("body '" + body.name + "' must be moved by the 1-DoF joint of coordinate " + std::to_string(s.coordinates[j]));
      int parent = -1;
      for (std::size_t i = 0; i < j; ++i)
        if (s.bodies[i] == body.parent) parent = static_cast<int>(i);
      if (parent < 0 && body.parent != s.root)
        fail("body '" + body.name + "' hangs from '" + model.body(body.parent).name + "', which is neither in the sub-system nor its root");
      layout.parent_local.push_back(parent);
      bool found = false;
      int role = 0;
      for (std::size_t c = 0; c < s.independent.size(); ++c)
        if (s.independent[c] == s.coordinates[j]) role = static_cast<int>(c), found = true;
      for (std::size_t d = 0; d < s.dependent.size(); ++d)
        if (s.dependent[d] == s.coordinates[j]) role = -1 - static_cast<int>(d), found = true;
      if (!found) fail("coordinate " + std::to_string(s.coordinates[j]) + " is neither independent nor dependent");
      layout.coordinate_role.push_back(role);
    }
    // Leaves first: a body is rigid when every child is a rigid body of the sub-system whose
    // joint carries no rotor body (a rotor's inertia would join this body's).
    layout.rigid.assign(s.bodies.size(), 1);
    for (std::size_t j = s.bodies.size(); j-- > 0;)
      for (const BodyIndex child : model.body(s.bodies[j]).children) {
        std::size_t c = 0;
        while (c < s.bodies.size() && s.bodies[c] != child) ++c;
        if (c == s.bodies.size() || model.joint(model.body(child).joint).has_rotor_body() || !layout.rigid[c]) layout.rigid[j] = 0;
      }
    if (!s.closures.empty() && static_cast<int>(s.dependent.size()) != s.rank())
      fail("has " + std::to_string(s.dependent.size()) + " dependent coordinates for " + std::to_string(s.rank()) +
           " independent constraint rows: Phi_z must be square");
    out.subsystems.push_back(std::move(layout));
  }
  return out;
}

inline void Model::update_structure() { structure_ = compute_structure(*this); }

inline bool Model::structure_is_current() const { return structure_ == compute_structure(*this); }

}  // namespace mbgen
