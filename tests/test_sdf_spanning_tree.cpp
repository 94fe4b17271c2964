// The spanning tree of a joint graph (generator/load/sdf_spanning_tree.hpp): which joints the
// tree keeps and which become closures, by the stated rule, on graphs small enough to check by hand.
#include <gtest/gtest.h>

#include "load/sdf_spanning_tree.hpp"

namespace mbgen::gen {
namespace {

std::vector<std::string> names(const std::vector<GraphJoint>& joints, const std::vector<int>& indices) {
  std::vector<std::string> out;
  for (int i : indices) out.push_back(joints[static_cast<std::size_t>(i)].name);
  return out;
}

// A four-bar written as a graph: the coupler's tip is the child of two joints.
const std::vector<GraphJoint> kFourBar = {
    {"crank", "ground", "a", false}, {"coupler", "a", "b", false}, {"rocker", "ground", "c", false}, {"tip", "c", "b", false}};

TEST(SdfSpanningTree, TheLinkReachedTwiceKeepsTheJointOfTheShallowerLayer) {
  const SpanningTree t = choose_spanning_tree("ground", {"ground", "a", "b", "c"}, kFourBar, {});
  EXPECT_EQ(names(kFourBar, t.tree), (std::vector<std::string>{"crank", "rocker", "coupler"}));
  EXPECT_EQ(names(kFourBar, t.cut), (std::vector<std::string>{"tip"}));
}

TEST(SdfSpanningTree, WithinALayerBallJointsAreCutFirst) {
  // 'b' is reached in the same layer by a ball and by a revolute joint: the ball is cut, although
  // it comes first in the document (Cassie's rods: their ball ends become point closures).
  const std::vector<GraphJoint> joints = {
      {"a_joint", "root", "a", false}, {"c_joint", "root", "c", false}, {"ball", "a", "b", true}, {"hinge", "c", "b", false}};
  const SpanningTree t = choose_spanning_tree("root", {"root", "a", "b", "c"}, joints, {});
  EXPECT_EQ(names(joints, t.cut), (std::vector<std::string>{"ball"}));
  // Without the preference, document order would have kept the ball: the rule is what decides.
  std::vector<GraphJoint> no_ball = joints;
  no_ball[2].ball = false;
  EXPECT_EQ(names(no_ball, choose_spanning_tree("root", {"root", "a", "b", "c"}, no_ball, {}).cut),
            (std::vector<std::string>{"hinge"}));
}

TEST(SdfSpanningTree, ForcedCutsOverrideTheRule) {
  const SpanningTree t = choose_spanning_tree("ground", {"ground", "a", "b", "c"}, kFourBar, {"coupler"});
  EXPECT_EQ(names(kFourBar, t.tree), (std::vector<std::string>{"crank", "rocker", "tip"}));
  EXPECT_EQ(names(kFourBar, t.cut), (std::vector<std::string>{"coupler"}));
}

TEST(SdfSpanningTree, ALinkHangingByTheJointsItParentsIsReachedBackwards) {
  // Cut 'rocker': 'c' is then only the parent of 'tip', whose child 'b' is in the tree.
  const SpanningTree t = choose_spanning_tree("ground", {"ground", "a", "b", "c"}, kFourBar, {"rocker"});
  EXPECT_EQ(names(kFourBar, t.tree), (std::vector<std::string>{"crank", "coupler", "tip"}));
  EXPECT_EQ(t.reversed, (std::vector<bool>{false, false, true}));
  EXPECT_EQ(names(kFourBar, t.cut), (std::vector<std::string>{"rocker"}));
}

TEST(SdfSpanningTree, AnUnreachableLinkIsNamed) {
  try {
    choose_spanning_tree("ground", {"ground", "a", "b", "c", "loose"}, kFourBar, {});
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("link 'loose'"), std::string::npos) << e.what();
  }
}

TEST(SdfSpanningTree, ATreeIsKeptWhole) {
  const std::vector<GraphJoint> chain = {{"j1", "root", "a", false}, {"j2", "a", "b", true}};
  const SpanningTree t = choose_spanning_tree("root", {"root", "a", "b"}, chain, {});
  EXPECT_EQ(t.tree.size(), 2u);
  EXPECT_TRUE(t.cut.empty());
}

}  // namespace
}  // namespace mbgen::gen
