// The scaling benchmark's model (bench/loop_chain.cpp): a chain of k parallelogram four-bars must
// load as k sub-systems of three bodies, each with one independent coordinate and rank 2 (a planar
// loop closed by a revolute closure: 2 of its 5 rows independent), closed at the zero pose; and
// the O(n) forward dynamics must equal the KKT reference on it (1e-10 relative, as
// test_loop_forward_dynamics.cpp), so the benchmark times two methods that agree.
#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "loop_chain.hpp"
#include "model/topology.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

TEST(LoopChain, LoadsAsKNestedSubsystemsAndAgreesWithTheReference) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "mbgen_test_loop_chain";
  std::filesystem::create_directories(dir);
  for (int k : {1, 3, 8}) {
    const std::string urdf = bench::write_loop_chain(dir.string(), k);
    gen::LoadOptions options;
    options.extras_file = urdf.substr(0, urdf.size() - 5) + ".yaml";
    const gen::Description d = gen::load_description(urdf, options);
    const Model& model = d.model;
    ASSERT_EQ(model.nv(), 3 * k);
    ASSERT_EQ(static_cast<int>(model.subsystems.size()), k);
    for (const SubSystem& s : model.subsystems) {
      EXPECT_EQ(s.bodies.size(), 3u);
      EXPECT_EQ(s.rank(), 2);
      ASSERT_EQ(s.independent.size(), 1u);
      EXPECT_EQ(gen::coordinate_name(model, s.independent[0]).rfind("crank_joint_", 0), 0u);
    }
    EXPECT_EQ(d.closed_dof, k);
    EXPECT_LT(d.assembly.max_joint_change, 1e-9) << "closed at the zero pose";

    Data<double> data(model), reference_data(model);
    ConstrainedDynamicsWorkspace<double> reference(model);
    std::mt19937_64 rng(61);
    for (int trial = 0; trial < 5; ++trial) {
      VecX<double> q, v;
      ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.3, q, v));
      const VecX<double> tau = random_vector<double>(model.nv(), rng, 5.0);
      ASSERT_EQ(forward_dynamics_loops<double>(model, data, q, v, tau), ClosureStatus::Converged);
      EXPECT_LT(relative_error(data.ddq, forward_dynamics_kkt<double>(model, reference_data, reference, q, v, tau)), 1e-10)
          << "k = " << k;
    }
  }
}

}  // namespace
}  // namespace mbgen::test
