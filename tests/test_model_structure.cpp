// ModelStructure (runtime/include/mbgen/model_structure.hpp, Model::update_structure): the
// model's structure is the Model's, computed from its loops and tree, and a Data made from a
// model changed since is refused rather than indexed wrongly.
#include <gtest/gtest.h>

#include <algorithm>
#include <set>

#include "mbgen/mbgen.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

TEST(ModelStructure, LolasTablesFollowFromItsSubSystems) {
  const gen::Description d = load_lola();
  const Model& model = d.model;
  const ModelStructure& s = model.structure();
  // The closed system's coordinates: every coordinate no sub-system makes dependent, ascending.
  std::set<int> dependent;
  for (const SubSystem& sub : model.subsystems) dependent.insert(sub.dependent.begin(), sub.dependent.end());
  ASSERT_EQ(s.num_independent(), d.closed_dof);
  ASSERT_EQ(s.num_independent() + static_cast<int>(dependent.size()), model.nv());
  EXPECT_TRUE(std::is_sorted(s.independent_v.begin(), s.independent_v.end()));
  for (int v = 0; v < model.nv(); ++v) {
    const int column = s.column_of_v[static_cast<std::size_t>(v)];
    EXPECT_EQ(column < 0, dependent.count(v) > 0) << v;
    if (column >= 0) {
      EXPECT_EQ(s.independent_v[static_cast<std::size_t>(column)], v);
    }
  }
  // Each body's sub-system, and each sub-system's layout against its own lists.
  ASSERT_EQ(s.subsystems.size(), model.subsystems.size());
  int on_subsystems = 0;
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& sub = model.subsystems[k];
    const SubSystemLayout& layout = s.subsystems[k];
    for (std::size_t j = 0; j < sub.bodies.size(); ++j) {
      EXPECT_EQ(s.subsystem_of_body[sub.bodies[j]], static_cast<int>(k));
      const int role = layout.coordinate_role[j];
      const std::vector<int>& list = role >= 0 ? sub.independent : sub.dependent;
      EXPECT_EQ(list[static_cast<std::size_t>(role >= 0 ? role : -1 - role)], sub.coordinates[j]);
      const int parent = layout.parent_local[j];
      EXPECT_EQ(parent >= 0 ? sub.bodies[static_cast<std::size_t>(parent)] : sub.root, model.body(sub.bodies[j]).parent);
    }
    on_subsystems += static_cast<int>(sub.bodies.size());
  }
  int counted = 0;
  for (int b = 0; b < model.num_bodies(); ++b) counted += s.subsystem_of_body[BodyIndex(b)] >= 0;
  EXPECT_EQ(counted, on_subsystems);
  EXPECT_EQ(s.cycle_bodies.size(), 22u);  // knee nut, rod and shank, and the ankle's 8, per leg
}

TEST(ModelStructure, ADataOfAModelChangedSinceIsRefused) {
  const gen::Description d = load_lola();
  Model tree = d.model;
  tree.closures.clear();
  tree.subsystems.clear();
  EXPECT_FALSE(tree.structure_is_current());
  try {
    Data<double> data(tree);
    FAIL() << "no error for a stale structure";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("call model.update_structure()"), std::string::npos) << e.what();
  }
  tree.update_structure();
  EXPECT_TRUE(tree.structure_is_current());
  EXPECT_EQ(tree.structure().num_independent(), tree.nv());
  EXPECT_TRUE(tree.structure().cycle_bodies.empty());
  Data<double> data(tree);  // now accepted
  EXPECT_EQ(data.tau_y.size(), tree.nv());
}

TEST(ModelStructure, ARotorOnALoopJointChangesWhichBodiesAreRigid) {
  const gen::Description d = load_lola();
  Model model = d.model;
  // A rigid body of a sub-system whose parent in it is rigid too: a rotor body on its joint makes
  // the parent's gathered inertia no longer a rigid body's.
  std::size_t k = 0, j = 0;
  bool found = false;
  for (k = 0; k < model.subsystems.size() && !found; ++k) {
    const SubSystemLayout& layout = model.structure().subsystems[k];
    for (j = 0; j < layout.rigid.size() && !found; ++j) {
      const int parent = layout.parent_local[j];
      found = layout.rigid[j] && parent >= 0 && layout.rigid[static_cast<std::size_t>(parent)];
    }
  }
  ASSERT_TRUE(found) << "Lola's linkages have rigid chains";
  --k, --j;
  const std::size_t parent = static_cast<std::size_t>(model.structure().subsystems[k].parent_local[j]);
  Joint& joint = model.mutable_joint(model.body(model.subsystems[k].bodies[j]).joint);
  joint.rotor_gear_ratio = 50, joint.rotor_inertia = 1e-4;
  EXPECT_FALSE(model.structure_is_current());
  model.update_structure();
  EXPECT_FALSE(model.structure().subsystems[k].rigid[parent]);
}

}  // namespace
}  // namespace mbgen::test
