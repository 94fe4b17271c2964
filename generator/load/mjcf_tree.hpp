#pragma once
// The MJCF body tree as read (load_mjcf.cpp), for the readers that run after the mbgen Model is
// built: collision geoms (mjcf_geoms.cpp), equality constraints and actuators (mjcf_equality.cpp).
#include <map>
#include <string>
#include <vector>

#include "load/mjcf_support.hpp"

namespace mbgen::gen::mjcf {

struct TreeBody {
  std::string name;
  const tinyxml2::XMLElement* xml = nullptr;  ///< <worldbody> for the world
  int parent = -1;                            ///< index in Tree::bodies; -1 for the world
  std::string childclass;                     ///< the class its own elements default to
  SE3<double> X_WB0;                          ///< world pose of the MJCF body frame at MuJoCo's qpos0
  BodyIndex body;                             ///< the mbgen body it moves with (merged or not)
  SE3<double> X_FB;                           ///< pose of the MJCF body frame in that mbgen body's frame
  FrameIndex frame;                           ///< the Frame named after it
};

struct Site {
  int body = 0;       ///< index in Tree::bodies
  SE3<double> X_BS;   ///< in the MJCF body frame
  FrameIndex frame;
};

struct Tree {
  std::string path;
  Compiler compiler;
  const Defaults* defaults = nullptr;
  const tinyxml2::XMLElement* root = nullptr;  ///< <mujoco>
  std::vector<TreeBody> bodies;                ///< [0] is the world
  std::map<std::string, int> body_index;
  std::map<std::string, Site> sites;
  /// MJCF joint name -> the mbgen joints it became (one, or three for a ball); "" for a free joint.
  std::map<std::string, std::vector<std::string>> joints;
  /// The joints in MuJoCo's qpos order (document order, depth first): free 7 numbers, ball 4, hinge and slide 1.
  struct QposJoint {
    std::string name;
    std::string type;  ///< free, ball, hinge, slide
    double ref = 0;    ///< hinge, slide: the position at MuJoCo's reference pose qpos0 (its `ref`)
  };
  std::vector<QposJoint> qpos_layout;

  /// An element of body b (or of <equality>, <actuator>: b = -1) with its class resolved.
  Element element(const tinyxml2::XMLElement* e, int b) const;
};

/// Swept-sphere volumes for the colliding sphere, capsule and cylinder geoms (mjcf_geoms.cpp).
void add_mjcf_geoms(const Tree& tree, Description& d);
/// A <tendon><fixed>: its length sum coef_i q_i over its joints (mjcf_tendons.cpp).
struct FixedTendon {
  struct Term {
    std::string joint;
    double coef = 1, ref = 0;  ///< ref: the joint's position at qpos0
  };
  std::vector<Term> joints;
  int line = 0;
};
/// Every <tendon><fixed> by name, checked: a tendon that carries forces of its own (stiffness,
/// damping, friction, armature, a range) or a <spatial> one is a LoadError.
std::map<std::string, FixedTendon> read_fixed_tendons(const Tree& tree);
/// <equality><tendon tendon1>: a coupling of the tendon's two joints, the second following.
ClosureSpec tendon_coupling(const Tree& tree, const Model& model, const Element& x, int index,
                            const std::map<std::string, FixedTendon>& tendons);

/// <equality> -> closures, <actuator> -> actuated joints (mjcf_equality.cpp).
void add_mjcf_equalities(const Tree& tree, Description& d);
void add_mjcf_actuators(const Tree& tree, Description& d);
/// The first <keyframe><key> with a qpos -> d.assembly_seed (mjcf_keyframe.cpp).
void read_mjcf_keyframe(const Tree& tree, Description& d);

}  // namespace mbgen::gen::mjcf
