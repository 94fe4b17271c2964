// scene_functions (generator/codegen/scene_functions.hpp): what each scene output brings, and a
// generation with two outputs (mbgen_add_robot OUTPUTS mass_matrix center_of_mass, compiled with
// -Werror like every generated library) computing what the full generation computes.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "codegen/scene_functions.hpp"
#include "iiwa14.hpp"
#include "iiwa14_two_outputs.hpp"

namespace mbgen::codegen {
namespace {

TEST(SceneFunctions, NoOutputsMeansEverythingButTheDerivatives) {
  const FunctionSelection s = select_functions(std::vector<std::string>{}, false);
  EXPECT_EQ(s.left_out, (std::vector<std::string>{"inverse_dynamics_derivatives", "forward_dynamics_derivatives",
                                                  "contact_forward_dynamics_derivatives",
                                                  "rigid_contact_forward_dynamics_derivatives"}));
  EXPECT_TRUE(s.backend);
  EXPECT_EQ(s.emitted.size(), all_functions().size() - 4);
  // `all` is the same; named beside it, a derivative comes too; named alone, only it (and closure_positions).
  EXPECT_EQ(select_functions({"all"}, false).generated, s.generated);
  const FunctionSelection with = select_functions({"all", "fd_derivatives"}, false);
  EXPECT_TRUE(with.emits("forward_dynamics_derivatives"));
  EXPECT_FALSE(with.emits("inverse_dynamics_derivatives"));
  EXPECT_EQ(with.emitted.size(), s.emitted.size() + 1);
  EXPECT_EQ(select_functions({"id_derivatives"}, false).generated,
            (std::vector<std::string>{"closure_positions", "inverse_dynamics_derivatives"}));
  // The derivatives under the ground: on request, and a contact scene's request brings the
  // simulation's functions, as every output of a scene with contact does.
  EXPECT_EQ(select_functions({"contact_fd_derivatives"}, false).generated,
            (std::vector<std::string>{"closure_positions", "contact_forward_dynamics_derivatives"}));
  EXPECT_TRUE(select_functions({"contact_fd_derivatives"}, true).emits("contact_accelerations"));
  // The rigid contacts' derivatives: on request, alone.
  EXPECT_EQ(select_functions({"rigid_contact_fd_derivatives"}, false).generated,
            (std::vector<std::string>{"closure_positions", "rigid_contact_forward_dynamics_derivatives"}));
}

TEST(SceneFunctions, EachOutputBringsWhatItNeeds) {
  // The closed system's dynamics come with the coordinate maps, and full_accelerations (its one copy).
  const FunctionSelection fd = select_functions({"forward_dynamics"}, false);
  for (const char* f : {"forward_dynamics", "full_accelerations", "velocity_map", "full_velocities", "acceleration_bias", "closure_positions"})
    EXPECT_TRUE(fd.emits(f)) << f;
  EXPECT_FALSE(fd.emits("mass_matrix"));
  EXPECT_FALSE(fd.backend);
  // A contact-free contact_accelerations calls full_accelerations; full_velocities is velocity_map's product.
  const FunctionSelection sim = select_functions({"simulation"}, false);
  EXPECT_TRUE(sim.backend);
  EXPECT_TRUE(sim.emits("forward_dynamics"));
  EXPECT_FALSE(sim.emits("self_distances"));
  EXPECT_FALSE(sim.emits("centroidal_momentum_matrix"));
  // A scene with contact simulates: the Backend comes with any outputs.
  EXPECT_TRUE(select_functions({"mass_matrix"}, true).backend);
  const FunctionSelection jac = select_functions({"jacobians"}, false);
  EXPECT_TRUE(jac.emits("frame_poses"));
  EXPECT_TRUE(jac.emits("frame_jacobians"));
  EXPECT_FALSE(jac.emits("forward_kinematics"));
  // left_out is the complement, in all_functions() order.
  std::vector<std::string> expected;
  for (const std::string& f : all_functions())
    if (!jac.emits(f)) expected.push_back(f);
  EXPECT_EQ(jac.left_out, expected);
  // generated is the emitted set in the same order.
  std::vector<std::string> emitted;
  for (const std::string& f : all_functions())
    if (jac.emits(f)) emitted.push_back(f);
  EXPECT_EQ(jac.generated, emitted);
}

TEST(SceneFunctions, AnUnknownOutputIsAClearError) {
  try {
    (void)select_functions({"mass_matrx"}, false);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unknown output 'mass_matrx'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("mass_matrix"), std::string::npos) << e.what();
  }
}

/// The generation with two outputs computes what the full one does, bit for bit (same code).
TEST(SceneFunctions, TwoOutputsComputeWhatTheFullGenerationDoes) {
  static_assert(iiwa14_two_outputs::nv == iiwa14::nv);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-2, 2);
  double q[iiwa14::nq];
  for (double& x : q) x = u(rng);
  double M_full[iiwa14::nv * iiwa14::nv], M_two[iiwa14::nv * iiwa14::nv], com_full[3], com_two[3];
  iiwa14::mass_matrix(q, M_full);
  iiwa14_two_outputs::mass_matrix(q, M_two);
  iiwa14::center_of_mass(q, com_full);
  iiwa14_two_outputs::center_of_mass(q, com_two);
  EXPECT_TRUE(std::equal(std::begin(M_full), std::end(M_full), std::begin(M_two)));
  EXPECT_TRUE(std::equal(std::begin(com_full), std::end(com_full), std::begin(com_two)));
}

}  // namespace
}  // namespace mbgen::codegen
