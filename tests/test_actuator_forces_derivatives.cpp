// The actuators' forces' derivatives (runtime algorithm/actuator_forces_derivatives.hpp) against
// forward-mode dual numbers pushed through the generic actuator_forces (which recomputes tau_y,
// the closure's maps and, for a dependent actuator, the Givens solve with B in dual arithmetic),
// the configuration moved along the tangent T e_c of the closed set: 1e-10 relative (max-norm),
// on every closed-loop description with its own actuators, on floating-base Lola (the residual
// is the base's six rows), and on the crank-driven slider-crank actuated at its slider, a
// dependent coordinate (B depends on y: the dB f term). No allocation.
#include <gtest/gtest.h>

#include <random>

#include "autodiff_reference.hpp"
#include "derivative_errors.hpp"
#include "malloc_guard.hpp"
#include "mbgen/algorithm/actuator_forces_derivatives.hpp"
#include "model/actuated_coordinates.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

VecX<double> independent_of(const Model& model, const VecX<double>& v) {
  VecX<double> vy(model.structure().num_independent());
  for (int i = 0; i < vy.size(); ++i) vy[i] = v[model.structure().independent_v[static_cast<std::size_t>(i)]];
  return vy;
}

/// Worst relative error of the six derivatives over `states` consistent states of d.
double worst_against_duals(const gen::Description& d, const Actuation& act, int states, unsigned seed) {
  const Model& model = d.model;
  const int ny = model.structure().num_independent(), na = act.num_actuators();
  Data<double> data(model);
  Data<Dual> dual(model);
  ActuatorForceDerivatives<double> out(model, act);
  std::mt19937_64 rng(seed);
  double worst = 0;
  int done = 0;
  for (int attempt = 0; attempt < 4 * states && done < states; ++attempt) {
    VecX<double> q, v;
    if (!consistent_state(model, d.assembly.q, rng, 0.05, q, v)) continue;
    ++done;
    const VecX<double> yd = independent_of(model, v), ydd = random_vector<double>(ny, rng, 5.0);
    EXPECT_EQ(actuator_forces_derivatives<double>(model, data, act, out, q, yd, ydd), ClosureStatus::Converged);
    MatX<double> df[3] = {MatX<double>(na, ny), MatX<double>(na, ny), MatX<double>(na, ny)};
    MatX<double> dr[3] = {MatX<double>(ny, ny), MatX<double>(ny, ny), MatX<double>(ny, ny)};
    VecX<Dual> f(na), r(ny);
    for (int c = 0; c < ny; ++c) {
      const VecX<Dual> qs[3] = {seeded_configuration_along(model, q, out.dynamics.T.col(c)), seeded_vector(q), seeded_vector(q)};
      const VecX<Dual> yds[3] = {seeded_vector(yd), seeded_vector(yd, c), seeded_vector(yd)};
      const VecX<Dual> ydds[3] = {seeded_vector(ydd), seeded_vector(ydd), seeded_vector(ydd, c)};
      for (int which = 0; which < 3; ++which) {
        actuator_forces<Dual>(model, dual, act, qs[which], yds[which], ydds[which], f, r);
        df[which].col(c) = derivative_part(f);
        dr[which].col(c) = derivative_part(r);
      }
    }
    const MatX<double>* got_f[3] = {&out.df_dy, &out.df_dyd, &out.df_dydd};
    const MatX<double>* got_r[3] = {&out.dr_dy, &out.dr_dyd, &out.dr_dydd};
    for (int which = 0; which < 3; ++which) {
      if (na > 0) worst = std::max(worst, max_relative(*got_f[which], df[which]));
      worst = std::max(worst, max_relative(*got_r[which], dr[which]));
    }
  }
  EXPECT_EQ(done, states) << "consistent states drawn";
  return worst;
}

class ActuatorForcesDerivativesOnLoops : public ::testing::TestWithParam<LoopCase> {};

TEST_P(ActuatorForcesDerivativesOnLoops, MatchDualNumbers) {
  const gen::Description d = load_loop_case(GetParam());
  const double worst = worst_against_duals(d, gen::description_actuation(d), 2, 71);
  std::printf("  %s: actuator forces' derivatives against dual numbers %.1e\n", GetParam().name.c_str(), worst);
  EXPECT_LT(worst, 1e-10);
}

INSTANTIATE_TEST_SUITE_P(Loops, ActuatorForcesDerivativesOnLoops, ::testing::ValuesIn(loop_cases()),
                         [](const ::testing::TestParamInfo<LoopCase>& info) { return info.param.name; });

TEST(ActuatorForcesDerivatives, FloatingLolaMatchesDualNumbers) {
  const gen::Description d = load_lola();
  const double worst = worst_against_duals(d, gen::description_actuation(d), 1, 72);
  std::printf("  lola floating: %.1e\n", worst);
  EXPECT_LT(worst, 1e-10);
}

TEST(ActuatorForcesDerivatives, ADependentActuatorMatchesDualNumbers) {
  gen::LoadOptions options;
  options.extras_file = MBGEN_SOURCE_DIR "/robots/mechanisms/slider_crank.yaml";
  const gen::Description d = gen::load_description(MBGEN_SOURCE_DIR "/robots/mechanisms/slider_crank.urdf", options);
  const int slider = d.model.joint(*d.model.find_joint("slider_joint")).idx_v;
  ASSERT_EQ(d.model.structure().column_of_v[static_cast<std::size_t>(slider)], -1) << "the slider must be dependent here";
  const Actuation by_slider = make_actuation(d.model, {slider});
  ASSERT_EQ(by_slider.blocks.size(), 1u);
  const double worst = worst_against_duals(d, by_slider, 5, 73);
  std::printf("  slider-crank by its slider: %.1e\n", worst);
  EXPECT_LT(worst, 1e-10);
}

TEST(ActuatorForcesDerivatives, AllocateNothing) {
  const gen::Description d = load_lola();
  const Model& model = d.model;
  const Actuation act = gen::description_actuation(d);
  std::mt19937_64 rng(74);
  VecX<double> q, v;
  ASSERT_TRUE(consistent_state(model, d.assembly.q, rng, 0.05, q, v));
  const VecX<double> yd = independent_of(model, v), ydd = random_vector<double>(yd.size(), rng);
  Data<double> data(model);
  ActuatorForceDerivatives<double> out(model, act);
  MallocGuard guard;
  actuator_forces_derivatives<double>(model, data, act, out, q, yd, ydd);
  EXPECT_EQ(guard.count(), 0u);
}

}  // namespace
}  // namespace mbgen::test
