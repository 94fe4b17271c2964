// Topology stage of loading (generator/include/mbgen/gen/topology.hpp): joint type overrides,
// closures into the Model, assembly and sub-systems, on the parallel_legs models (against
// LOOPS.md), the mechanisms and Lola.
#include <gtest/gtest.h>

#include <Eigen/SVD>

#include "mbgen/gen/load_error.hpp"
#include "mbgen/gen/topology.hpp"
#include "test_support.hpp"

namespace mbgen {
namespace {

using gen::Description;
using gen::LoadError;

const std::string kData = MBGEN_TEST_DATA;

Description load(const std::string& urdf, const std::string& extras = "") {
  gen::LoadOptions options;
  if (!extras.empty()) options.extras_file = extras;
  return gen::load_description(urdf, options);
}

int total_rank(const Model& model) {
  int r = 0;
  for (const SubSystem& s : model.subsystems) r += s.rank();
  return r;
}

double max_abs_phi(const Model& model, const VecX<double>& q) {
  Data<double> data(model);
  return closure_residual<double>(model, data, q).cwiseAbs().maxCoeff();
}

// ---- parallel_legs: figures of LOOPS.md --------------------------------------------------

struct LegsFigures {
  std::string model;
  std::string extras;   ///< empty: the robot.yaml beside the URDF
  int tree_dof, rows, rank, mobility, motors;
  int subsystems_by_joint, subsystems_by_body;  ///< LOOPS.md's two groupings
};

// Expected figures: /work/shared/robots/LOOPS.md, "Figures at the assembled pose", computed
// there with an independent rigid-body library. Sub-systems: LOOPS.md gives "2 (or 1 if loops
// sharing their meeting body are merged too)"; mbgen groups by shared moving joints (the first
// figure), see topology.hpp. disney_robot: LOOPS.md's figures are for 9 of its 10 overrides
// (the name defect); tests/data/parallel_legs/disney_robot_9_of_10.yaml leaves the misspelt one out.
const std::vector<LegsFigures> kLegs = {
    {"5bar_linkage", "", 6, 6, 3, 3, 2, 1, 1},
    {"cassie_like", "", 19, 12, 12, 7, 5, 2, 1},
    {"robot_delta", "", 14, 18, 9, 5, 2, 1, 1},
    {"talos_like", "", 13, 6, 6, 7, 6, 1, 1},
    {"wl16_like", "", 42, 30, 30, 12, 6, 1, 1},
    {"digit_like_2legs", "", 48, 36, 36, 12, 12, 4, 2},
    {"disney_robot", kData + "/parallel_legs/disney_robot_9_of_10.yaml", 50, 36, 36, 14, 12, 2, 1},
};

class LegsTopology : public ::testing::TestWithParam<LegsFigures> {};

TEST_P(LegsTopology, FiguresMatchLoopsMd) {
  const LegsFigures& f = GetParam();
  const Description d = load(test::shared_robot("parallel_legs/" + f.model + "/robot.urdf"), f.extras);
  const Model& m = d.model;
  EXPECT_EQ(m.nv(), f.tree_dof);
  EXPECT_EQ(m.num_constraint_rows(), f.rows);
  EXPECT_EQ(total_rank(m), f.rank);
  EXPECT_EQ(d.closed_dof, f.mobility);
  EXPECT_EQ(static_cast<int>(d.actuated_joints.size()), f.motors);
  const int groups = static_cast<int>(m.subsystems.size());
  EXPECT_TRUE(groups == f.subsystems_by_joint || groups == f.subsystems_by_body) << groups;
  EXPECT_LT(d.assembly.residual, 1e-12);
  EXPECT_LT(max_abs_phi(m, d.assembly.q), 1e-12);
  std::cout << "[ figures  ] " << f.model << ": tree " << m.nv() << ", rows " << m.num_constraint_rows() << ", rank "
            << total_rank(m) << ", mobility " << d.closed_dof << ", sub-systems " << groups
            << ", assembly: max joint change " << d.assembly.max_joint_change << " (" << d.assembly.max_change_joint
            << "), seeds " << d.assembly.seeds << ", sigma_min " << d.assembly.sigma_min << " / sigma_max "
            << d.assembly.sigma_max << "\n";
}

INSTANTIATE_TEST_SUITE_P(SharedRobots, LegsTopology, ::testing::ValuesIn(kLegs),
                         [](const auto& info) { return info.param.model; });

}  // namespace
}  // namespace mbgen
