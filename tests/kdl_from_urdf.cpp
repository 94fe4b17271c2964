#include "kdl_from_urdf.hpp"

#include <set>
#include <stdexcept>

#include <kdl/frames.hpp>
#include <kdl/rigidbodyinertia.hpp>
#include <kdl/rotationalinertia.hpp>
#include <kdl/segment.hpp>
#include <urdf_parser/urdf_parser.h>

namespace mbgen::peer {
namespace {

KDL::Vector to_kdl(const urdf::Vector3& v) { return KDL::Vector(v.x, v.y, v.z); }

KDL::Rotation to_kdl(const urdf::Rotation& r) { return KDL::Rotation::Quaternion(r.x, r.y, r.z, r.w); }

KDL::Frame to_kdl(const urdf::Pose& p) { return KDL::Frame(to_kdl(p.rotation), to_kdl(p.position)); }

KDL::Joint to_kdl(const urdf::Joint& joint) {
  const KDL::Frame X_PJ = to_kdl(joint.parent_to_joint_origin_transform);
  switch (joint.type) {
    case urdf::Joint::REVOLUTE:
    case urdf::Joint::CONTINUOUS:
      return KDL::Joint(joint.name, X_PJ.p, X_PJ.M * to_kdl(joint.axis), KDL::Joint::RotAxis);
    case urdf::Joint::PRISMATIC:
      return KDL::Joint(joint.name, X_PJ.p, X_PJ.M * to_kdl(joint.axis), KDL::Joint::TransAxis);
    case urdf::Joint::FIXED:
      return KDL::Joint(joint.name, KDL::Joint::None);
    default:
      throw std::runtime_error("kdl_from_urdf: joint '" + joint.name +
                               "' is floating or planar, which a KDL tree cannot represent");
  }
}

/// The URDF inertial in the link frame: mass, centre of mass, and the rotational inertia about
/// the centre of mass, rotated from the inertial frame into the link frame (as kdl_parser does).
KDL::RigidBodyInertia to_kdl(const urdf::Inertial& inertial) {
  const KDL::Frame X_LI = to_kdl(inertial.origin);
  const KDL::RotationalInertia I_inertial_frame(inertial.ixx, inertial.iyy, inertial.izz, inertial.ixy,
                                                inertial.ixz, inertial.iyz);
  // Rotating a massless body about its own origin rotates its rotational inertia: R I R^T.
  const KDL::RigidBodyInertia rotated = X_LI.M * KDL::RigidBodyInertia(0.0, KDL::Vector::Zero(), I_inertial_frame);
  return KDL::RigidBodyInertia(inertial.mass, X_LI.p, rotated.getRotationalInertia());
}

void add_children(const urdf::ModelInterface& model,
                  const std::map<std::string, std::vector<urdf::JointConstSharedPtr>>& children_of,
                  const std::string& link_name, KDL::Tree& tree) {
  auto it = children_of.find(link_name);
  if (it == children_of.end()) return;
  for (const urdf::JointConstSharedPtr& joint : it->second) {
    urdf::LinkConstSharedPtr child = model.getLink(joint->child_link_name);
    if (!child) throw std::runtime_error("kdl_from_urdf: joint '" + joint->name + "' names an unknown child link");
    const KDL::RigidBodyInertia inertia = child->inertial ? to_kdl(*child->inertial) : KDL::RigidBodyInertia::Zero();
    const KDL::Segment segment(child->name, to_kdl(*joint), to_kdl(joint->parent_to_joint_origin_transform), inertia);
    if (!tree.addSegment(segment, link_name))
      throw std::runtime_error("kdl_from_urdf: cannot add segment '" + child->name + "' under '" + link_name + "'");
    add_children(model, children_of, child->name, tree);
  }
}

/// Inertia of the subtree rooted at segment `element`, expressed in its parent segment's frame,
/// with the subtree's joints at `q` (by name, default 0).
KDL::RigidBodyInertia welded_subtree_inertia(KDL::SegmentMap::const_iterator element,
                                             const std::map<std::string, double>& q) {
  const KDL::Segment& segment = GetTreeElementSegment(element->second);
  KDL::RigidBodyInertia inertia = segment.getInertia();
  for (KDL::SegmentMap::const_iterator child : GetTreeElementChildren(element->second))
    inertia = inertia + welded_subtree_inertia(child, q);
  double q_joint = 0.0;
  if (auto it = q.find(segment.getJoint().getName()); it != q.end()) q_joint = it->second;
  return segment.pose(segment.getJoint().getType() == KDL::Joint::None ? 0.0 : q_joint) * inertia;
}

}  // namespace

KDL::Tree kdl_tree_from_urdf_file(const std::string& path) {
  urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(path);
  if (!model) throw std::runtime_error("kdl_from_urdf: urdfdom could not parse '" + path + "'");
  // The graph from the joint list, not from urdfdom's tree pointers (which silently keep one of
  // two parent joints of a link). Joints in name order, as urdfdom stores them.
  std::map<std::string, std::vector<urdf::JointConstSharedPtr>> children_of;
  for (const auto& [name, joint] : model->joints_) children_of[joint->parent_link_name].push_back(joint);
  const std::string root = model->getRoot()->name;
  KDL::Tree tree(root);
  add_children(*model, children_of, root, tree);
  return tree;
}

KDL::Tree kdl_floating_tree_from_urdf_file(const std::string& path) {
  urdf::ModelInterfaceSharedPtr model = urdf::parseURDFFile(path);
  if (!model) throw std::runtime_error("kdl_from_urdf: urdfdom could not parse '" + path + "'");
  std::map<std::string, std::vector<urdf::JointConstSharedPtr>> children_of;
  for (const auto& [name, joint] : model->joints_) children_of[joint->parent_link_name].push_back(joint);
  const urdf::LinkConstSharedPtr root = model->getRoot();
  KDL::Tree tree("kdl_world");
  const struct {
    const char* name;
    KDL::Joint::JointType type;
  } virtual_joints[] = {{"floating_x", KDL::Joint::TransX}, {"floating_y", KDL::Joint::TransY},
                        {"floating_z", KDL::Joint::TransZ}, {"floating_rx", KDL::Joint::RotX},
                        {"floating_ry", KDL::Joint::RotY},  {"floating_rz", KDL::Joint::RotZ}};
  std::string parent = "kdl_world";
  for (int k = 0; k < 6; ++k) {
    const bool last = k == 5;
    const std::string segment_name = last ? root->name : std::string(virtual_joints[k].name) + "_link";
    const KDL::RigidBodyInertia inertia =
        last && root->inertial ? to_kdl(*root->inertial) : KDL::RigidBodyInertia::Zero();
    const KDL::Segment segment(segment_name, KDL::Joint(virtual_joints[k].name, virtual_joints[k].type),
                               KDL::Frame::Identity(), inertia);
    if (!tree.addSegment(segment, parent))
      throw std::runtime_error("kdl_from_urdf: cannot add virtual segment '" + segment_name + "'");
    parent = segment_name;
  }
  add_children(*model, children_of, root->name, tree);
  return tree;
}

KDL::Chain kdl_chain_with_welded_branches(const KDL::Tree& tree, const std::string& root, const std::string& tip,
                                          const std::map<std::string, double>& off_chain_q) {
  KDL::Chain plain;
  if (!tree.getChain(root, tip, plain))
    throw std::runtime_error("kdl_from_urdf: no chain from '" + root + "' to '" + tip + "'");
  std::set<std::string> on_chain{root};
  for (const KDL::Segment& s : plain.segments) on_chain.insert(s.getName());
  const KDL::SegmentMap& segments = tree.getSegments();
  KDL::Chain chain;
  for (const KDL::Segment& s : plain.segments) {
    KDL::Segment welded = s;
    KDL::RigidBodyInertia inertia = s.getInertia();
    const auto element = segments.find(s.getName());
    for (KDL::SegmentMap::const_iterator child : GetTreeElementChildren(element->second))
      if (!on_chain.count(child->first)) inertia = inertia + welded_subtree_inertia(child, off_chain_q);
    welded.setInertia(inertia);
    chain.addSegment(welded);
  }
  return chain;
}

std::vector<std::string> kdl_chain_joint_names(const KDL::Chain& chain) {
  std::vector<std::string> names;
  for (const KDL::Segment& s : chain.segments)
    if (s.getJoint().getType() != KDL::Joint::None) names.push_back(s.getJoint().getName());
  return names;
}

std::map<std::string, unsigned> kdl_tree_joint_indices(const KDL::Tree& tree) {
  std::map<std::string, unsigned> indices;
  for (const auto& [name, element] : tree.getSegments()) {
    const KDL::Segment& s = GetTreeElementSegment(element);
    if (s.getJoint().getType() != KDL::Joint::None) indices[s.getJoint().getName()] = GetTreeElementQNr(element);
  }
  return indices;
}

}  // namespace mbgen::peer
