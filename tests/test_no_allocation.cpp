// After Data is made, no algorithm allocates: every generic algorithm runs under a malloc guard.
#include <gtest/gtest.h>

#include <random>

#include "malloc_guard.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

TEST(MallocGuard, CountsAllocations) {
  // The guard must be able to fail: a heap allocation inside it is seen.
  MallocGuard guard;
  auto* p = new std::vector<double>(100);
  VecX<double> x(50);
  std::size_t seen = guard.count();
  delete p;
  EXPECT_GE(seen, 3u);
  EXPECT_EQ(x.size(), 50);
}

class NoAllocationTest : public ::testing::TestWithParam<gen::BaseType> {};

TEST_P(NoAllocationTest, AlgorithmsDoNotAllocate) {
  const Model model = load_tree(shared_robot("talos/talos_reduced.urdf"), GetParam());
  Data<double> data(model);
  Rk4Workspace<double> ws(model);
  std::mt19937_64 rng(5);
  VecX<double> q = random_configuration<double>(model, rng);
  VecX<double> v = random_vector<double>(model.nv(), rng);
  const VecX<double> tau = random_vector<double>(model.nv(), rng);
  VecX<double> q_next(model.nq()), qdot(model.nq());
  Mat6X<double> J(6, model.nv());
  Mat3X<double> Jp(3, model.nv());
  const FrameIndex frame(model.num_frames() - 1);
  double sink = 0;
  {
    MallocGuard guard;
    forward_kinematics<double>(model, data, q, v, tau);
    update_frame_placements<double>(model, data);
    sink += rnea<double>(model, data, q, v, tau).sum();
    sink += nonlinear_effects<double>(model, data, q, v).sum();
    sink += crba<double>(model, data, q).sum();
    sink += aba<double>(model, data, q, v, tau).sum();
    compute_joint_jacobians<double>(model, data, q);
    frame_jacobian<double>(model, data, frame, ReferenceFrame::LocalWorldAligned, J);
    point_jacobian<double>(model, data, BodyIndex(1), Vec3<double>(0.1, 0, 0), ReferenceFrame::Local, Jp);
    sink += center_of_mass<double>(model, data, q, v).sum();
    sink += jacobian_center_of_mass<double>(model, data, q).sum();
    sink += centroidal_momentum<double>(model, data, q, v).sum();
    sink += kinetic_energy<double>(model, data, q, v) + potential_energy<double>(model, data, q);
    integrate<double>(model, q, v, q_next);
    configuration_derivative<double>(model, q, v, qdot);
    rk4_step<double>(model, data, ws, q, v, tau, 1e-3);
    EXPECT_EQ(guard.count(), 0u);
  }
  EXPECT_TRUE(std::isfinite(sink) && J.allFinite() && Jp.allFinite());
}

INSTANTIATE_TEST_SUITE_P(Base, NoAllocationTest, ::testing::Values(gen::BaseType::Fixed, gen::BaseType::Floating),
                         [](const auto& info) { return info.param == gen::BaseType::Fixed ? "fixed" : "floating"; });

}  // namespace
}  // namespace mbgen::test
