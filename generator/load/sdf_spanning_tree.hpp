#pragma once
// The spanning tree of a description whose joints form a graph (SDFormat: a link may be the child
// of two joints). mbgen's dynamics run on a tree; every joint left out of it becomes a loop
// closure (load_sdf.cpp). Kept apart from libsdformat so the rule is tested on plain graphs.
#include <set>
#include <string>
#include <vector>

namespace mbgen::gen {

/// One joint of the graph, directed from its parent link to its child link.
struct GraphJoint {
  std::string name, parent, child;
  bool ball = false;  ///< ball joints are cut first: a 3-D point closure is the cheapest loop
};

struct SpanningTree {
  std::vector<int> tree;  ///< joints of the tree, parents before children (indices into the input)
  /// Parallel to `tree`: the joint is followed from its child to its parent (its child link is
  /// the tree parent), which the search does only for links no joint reaches in its own direction.
  std::vector<bool> reversed;
  std::vector<int> cut;   ///< joints left out: the loop closures, in document order
};

/// The rule: breadth-first from `root`, following joints from parent to child; within one layer
/// of the search, joints that are not ball joints are taken first, then document order. A link
/// enters the tree by the first joint that reaches it; every other joint is cut. When the search
/// stops with links unreached (a cut of `forced_cuts` left a link hanging by the joints it is the
/// parent of), one joint is followed backwards into each such link it can reach, by the same
/// preference, and the search goes on from there. Joints named in `forced_cuts` (the extras'
/// `closure_joints:`) are never tree joints. Throws std::runtime_error naming a link that no
/// chain of joints reaches.
SpanningTree choose_spanning_tree(const std::string& root, const std::vector<std::string>& links,
                                  const std::vector<GraphJoint>& joints, const std::set<std::string>& forced_cuts);

}  // namespace mbgen::gen
