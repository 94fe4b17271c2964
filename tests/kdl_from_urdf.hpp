#pragma once
// orocos-kdl peer models built from a URDF directly (urdfdom), independent of mbgen's loader and
// Model: the same conversion as ROS's kdl_parser, which Debian does not package. Used by the
// peer test (tests/test_peer_kdl.cpp) and the benchmarks (bench/).
//
//  - every URDF link becomes a KDL::Segment hooked onto the segment of its parent link;
//  - the segment's joint is the URDF joint with its origin and axis expressed in the parent link
//    frame (KDL::Joint::RotAxis / TransAxis), fixed joints become KDL::Joint::None;
//  - the segment's tip frame is the joint origin (parent link -> child link at q = 0);
//  - the segment's inertia is the URDF <inertial>: mass, centre of mass, and the rotational
//    inertia about the centre of mass rotated from the inertial frame into the link frame.
// The root link's inertia is ignored (it never moves: a fixed base), as in kdl_parser.
#include <map>
#include <string>
#include <vector>

#include <kdl/chain.hpp>
#include <kdl/tree.hpp>

namespace mbgen::peer {

/// Parses a URDF file with urdfdom and converts it. Throws std::runtime_error if it cannot.
KDL::Tree kdl_tree_from_urdf_file(const std::string& path);

/// The same robot with a floating base, as KDL users model one: six virtual joints between a new
/// root segment "kdl_world" and the URDF root link, translations along the world x, y, z axes
/// (joints floating_x, floating_y, floating_z) then rotations about x, y, z (floating_rx,
/// floating_ry, floating_rz: roll-pitch-yaw), all through the root link's origin. The first five
/// carry massless segments; the sixth is the root link with its inertia. With the virtual joints
/// at zero and at rest, their forces are the wrench on the base at its origin in world axes.
KDL::Tree kdl_floating_tree_from_urdf_file(const std::string& path);

/// The chain root -> tip of `tree`, with every subtree that hangs off the chain (links reached
/// through joints that are not on the chain) welded rigidly onto the chain segment it hangs from:
/// its inertia is lumped into that segment with the off-chain joints held at `off_chain_q`
/// (joint name -> position; absent joints at 0). The chain then has the mass distribution of
/// the whole robot with the off-chain joints locked, so its mass matrix and its inverse dynamics
/// (off-chain joints at rest) equal the chain-joint block of the full tree's.
KDL::Chain kdl_chain_with_welded_branches(const KDL::Tree& tree, const std::string& root, const std::string& tip,
                                          const std::map<std::string, double>& off_chain_q = {});

/// Names of the moving joints of a chain, in chain order.
std::vector<std::string> kdl_chain_joint_names(const KDL::Chain& chain);

/// Moving joint name -> its index in the tree's JntArray (TreeElement::q_nr).
std::map<std::string, unsigned> kdl_tree_joint_indices(const KDL::Tree& tree);

}  // namespace mbgen::peer
