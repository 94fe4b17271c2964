#include "load/sdf_spanning_tree.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <stdexcept>

namespace mbgen::gen {

SpanningTree choose_spanning_tree(const std::string& root, const std::vector<std::string>& links,
                                  const std::vector<GraphJoint>& joints, const std::set<std::string>& forced_cuts) {
  std::map<std::string, std::vector<int>> leaving;  // link -> joints whose parent it is, document order
  for (int j = 0; j < static_cast<int>(joints.size()); ++j)
    if (!forced_cuts.count(joints[j].name)) leaving[joints[j].parent].push_back(j);
  std::set<std::string> reached = {root};
  std::vector<bool> in_tree(joints.size(), false);
  SpanningTree out;
  auto non_ball_first = [&](std::vector<int>& candidates) {
    std::stable_sort(candidates.begin(), candidates.end(), [&](int a, int b) { return !joints[a].ball && joints[b].ball; });
  };
  auto take = [&](int j, bool reversed, std::vector<std::string>& next) {
    const std::string& link = reversed ? joints[j].parent : joints[j].child;
    if (reached.count(link)) return;
    reached.insert(link);
    in_tree[j] = true;
    out.tree.push_back(j);
    out.reversed.push_back(reversed);
    next.push_back(link);
  };
  std::vector<std::string> layer = {root};
  while (!layer.empty()) {
    while (!layer.empty()) {
      std::vector<int> candidates;
      for (const std::string& link : layer)
        for (int j : leaving[link]) candidates.push_back(j);
      non_ball_first(candidates);
      std::vector<std::string> next;
      for (int j : candidates) take(j, false, next);
      layer = std::move(next);
    }
    // Stuck: follow joints backwards from the links reached into those that are not.
    std::vector<int> backwards;
    for (int j = 0; j < static_cast<int>(joints.size()); ++j)
      if (!forced_cuts.count(joints[j].name) && !in_tree[j] && reached.count(joints[j].child) && !reached.count(joints[j].parent))
        backwards.push_back(j);
    non_ball_first(backwards);
    for (int j : backwards) take(j, true, layer);
  }
  for (const std::string& link : links)
    if (!reached.count(link))
      throw std::runtime_error(fmt::format("link '{}' is reached from '{}' by no chain of joints{}",
                                           link, root, forced_cuts.empty() ? "" : " (closure_joints excluded)"));
  for (int j = 0; j < static_cast<int>(joints.size()); ++j)
    if (!in_tree[j]) out.cut.push_back(j);
  return out;
}

}  // namespace mbgen::gen
