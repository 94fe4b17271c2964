// Self-collision potential and its use as a null-space objective
// (runtime/include/mbgen/control/collision_potential.hpp, control/differential_ik.hpp):
//  - the potential against its formula and its gradient against central differences of P
//    along every velocity coordinate (h = 1e-6; coordinates where the one-sided differences
//    disagree by more than 1e-5, a switch of closest features, are skipped and counted), on the
//    Lola biped's scene (floating base, loops left open: the potential is a tree quantity) with a
//    large activation distance so that many pairs are active, tolerance 1e-6 max(1, |dP/dq|);
//  - closed-loop kinematic simulation on tests/data/collision_arm.urdf: the primary task moves
//    link3's joint point to a target along a path that folds link3's sphere into the base;
//    the redundancy (link3's own joint) is the null space. Without avoidance the distance goes
//    negative (the spheres overlap); with it the distance stays above a stated bound while the
//    primary error converges exactly as without (the secondary motion is invisible to it).
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "malloc_guard.hpp"
#include "mbgen/control/differential_ik.hpp"
#include "collision/collision_scene.hpp"
#include "model/load_description.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

using namespace mbgen::control;

gen::Description load(const std::string& urdf, const std::string& extras, gen::BaseType base) {
  gen::LoadOptions options;
  options.base = base;
  options.pick_up_robot_yaml = false;
  if (!extras.empty()) options.extras_file = extras;
  return gen::load_description(urdf, options);
}

collision::CollisionModel every_pair(const gen::Description& d) {
  gen::CollisionSceneOptions options;
  options.samples = 0;  // every non-adjacent pair
  return gen::build_collision_scene(d, options).model;
}

double potential_at(const Model& model, const collision::CollisionModel& cm, const CollisionPotentialOptions& o,
                    const VecX<double>& q) {
  Data<double> data(model);
  collision::CollisionData<double> cd(model, cm);
  forward_kinematics<double>(model, data, q);
  collision::compute_distances<double>(model, data, cm, cd);
  return collision_potential<double>(cd, o);
}

TEST(CollisionPotential, ValueAndGradientMatchFiniteDifferences) {
  const std::string dir = MBGEN_SOURCE_DIR "/robots/lola/";
  gen::Description d = load(dir + "lola.urdf", dir + "lola.yaml", gen::BaseType::Floating);
  const Model& model = d.model;
  const collision::CollisionModel cm = every_pair(d);
  const CollisionPotentialOptions o{0.25, 50.0};
  Data<double> data(model);
  collision::CollisionData<double> cd(model, cm);
  VecX<double> gradient(model.nv());
  std::mt19937_64 rng(17);
  const double h = 1e-6;
  int checked = 0, skipped = 0, active_total = 0;
  double worst = 0;
  for (int trial = 0; trial < 10; ++trial) {
    const VecX<double> q = random_configuration<double>(model, rng);
    compute_joint_jacobians<double>(model, data, q);
    collision::compute_distances<double>(model, data, cm, cd);
    collision::compute_distance_jacobians<double>(model, data, cm, cd);
    const int active = collision_potential_gradient<double>(cd, o, gradient);
    active_total += active;
    // The value against its formula, pair by pair.
    double expected = 0;
    int counted = 0;
    for (const auto& pair : cd.distances)
      if (pair.result.distance < o.activation_distance) {
        expected += 0.5 * o.stiffness * std::pow(o.activation_distance - pair.result.distance, 2);
        ++counted;
      }
    EXPECT_EQ(counted, active);
    EXPECT_NEAR(collision_potential<double>(cd, o), expected, 1e-14 * std::max(1.0, expected));
    const double p0 = collision_potential<double>(cd, o);
    for (int i = 0; i < model.nv(); ++i) {
      VecX<double> step = VecX<double>::Zero(model.nv()), qp(model.nq()), qm(model.nq());
      step[i] = h;
      integrate<double>(model, q, step, qp);
      integrate<double>(model, q, -step, qm);
      const double pp = potential_at(model, cm, o, qp), pm = potential_at(model, cm, o, qm);
      if (std::abs((pp - p0) / h - (p0 - pm) / h) > 1e-5 * std::max(1.0, std::abs(gradient[i]))) {
        ++skipped;  // closest features switch within h: no derivative to compare with
        continue;
      }
      const double fd = (pp - pm) / (2 * h);
      worst = std::max(worst, std::abs(fd - gradient[i]) / std::max(1.0, std::abs(gradient[i])));
      ++checked;
    }
  }
  std::printf("  Lola: %d active pairs over 10 poses, %d derivatives checked (%d skipped at switches), worst error %.2e\n",
              active_total, checked, skipped, worst);
  EXPECT_GT(active_total, 20);
  EXPECT_GT(checked, 8 * 10 * model.nv() / 10);  // most coordinates are away from a switch
  EXPECT_LT(worst, 1e-6);
}

TEST(CollisionPotential, ZeroAboveTheActivationDistance) {
  const gen::Description d = load(MBGEN_TEST_DATA "/collision_arm.urdf", "", gen::BaseType::Fixed);
  collision::CollisionModel cm = every_pair(d);
  Data<double> data(d.model);
  collision::CollisionData<double> cd(d.model, cm);
  VecX<double> q = VecX<double>::Zero(d.model.nq()), gradient(d.model.nv());
  compute_joint_jacobians<double>(d.model, data, q);
  cm.pairs.erase(std::remove_if(cm.pairs.begin(), cm.pairs.end(),
                                [&](const collision::CollisionPair& p) {
                                  return cm.compounds[static_cast<std::size_t>(p.first)].name == "side" ||
                                         cm.compounds[static_cast<std::size_t>(p.second)].name == "side";
                                }),
                 cm.pairs.end());
  collision::CollisionData<double> kept(d.model, cm);
  collision::compute_distances<double>(d.model, data, cm, kept);
  collision::compute_distance_jacobians<double>(d.model, data, cm, kept);
  // Stretched arm: link3's sphere is 1.45 m out, the nearest kept pair (world - link2) 0.75 apart.
  const CollisionPotentialOptions o{0.1, 100.0};
  EXPECT_EQ(collision_potential_gradient<double>(kept, o, gradient), 0);
  EXPECT_EQ(gradient.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(collision_potential<double>(kept, o), 0.0);
}

/// The collision arm with the pairs of link3 against the base and link1 (the "side" body sits on
/// the base sphere by design and is left out).
struct ArmScene {
  gen::Description d = load(MBGEN_TEST_DATA "/collision_arm.urdf", "", gen::BaseType::Fixed);
  collision::CollisionModel cm;
  ArmScene() {
    cm = every_pair(d);
    std::vector<collision::CollisionPair> kept;
    for (const collision::CollisionPair& p : cm.pairs) {
      const std::string& a = cm.compounds[static_cast<std::size_t>(p.first)].name;
      const std::string& b = cm.compounds[static_cast<std::size_t>(p.second)].name;
      if ((a == "link3" || b == "link3") && a != "side" && b != "side") kept.push_back(p);
    }
    cm.pairs = kept;
  }
};

struct ArmRun {
  double min_distance = 1e9, final_error = 0, worst_primary = 0, worst_null = 0;
};

/// Moves the joint point of link3 from (0.78, 0.17) to (0.35, 0) with gain 5/s for 3 s at 1 kHz,
/// starting at q = (0, 0.6, 2.0, 0): with link3's joint fixed, the path folds link3's sphere
/// through the base (closest approach -0.105 m, computed in closed form for the plain IK).
ArmRun run_arm(const ArmScene& scene, bool avoid) {
  const Model& model = scene.d.model;
  DifferentialIkOptions options;
  options.collision_avoidance = avoid;
  options.collision = CollisionPotentialOptions{0.1, 300.0};
  DifferentialIk<double> ik(model, {{"tip", TaskKind::FramePosition, "link3", 5.0}}, options, &scene.cm);
  ik.target(0).position = Vec3<double>(0.35, 0.0, 0.0);
  VecX<double> q(model.nq()), v(model.nv()), next(model.nq());
  q << 0.0, 0.6, 2.0, 0.0;  // j1, j2, j3, js
  ArmRun run;
  Data<double> check(model);
  collision::CollisionData<double> cd(model, scene.cm);
  const double dt = 1e-3;
  for (int step = 0; step < 3000; ++step) {
    const StepReport report = ik.step(q, v);
    EXPECT_TRUE(report.ok);
    // Primary achieved exactly; the secondary part invisible to it.
    run.worst_primary = std::max(run.worst_primary, (ik.primary_jacobian() * v - ik.primary_velocity()).cwiseAbs().maxCoeff());
    run.worst_null = std::max(run.worst_null, (ik.primary_jacobian() * ik.secondary_velocity()).cwiseAbs().maxCoeff());
    integrate<double>(model, q, v * dt, next);
    q = next;
    forward_kinematics<double>(model, check, q);
    collision::compute_distances<double>(model, check, scene.cm, cd);
    for (const auto& pair : cd.distances) run.min_distance = std::min(run.min_distance, pair.result.distance);
  }
  update_frame_placements<double>(model, check);
  run.final_error = (check.X_WF[model.frame_index("link3")].translation - Vec3<double>(0.35, 0, 0)).norm();
  return run;
}

TEST(CollisionPotential, NullSpaceAvoidanceKeepsTheArmApartWhileTheTaskConverges) {
  const ArmScene scene;
  ASSERT_EQ(scene.cm.pairs.size(), 2u);  // world - link3, link1 - link3
  const ArmRun plain = run_arm(scene, false);
  const ArmRun avoiding = run_arm(scene, true);
  std::printf("  without avoidance: min distance %.4f m, final task error %.2e m\n", plain.min_distance, plain.final_error);
  std::printf("  with avoidance:    min distance %.4f m, final task error %.2e m; |J v - xd| <= %.1e, |J v_secondary| <= %.1e\n",
              avoiding.min_distance, avoiding.final_error, avoiding.worst_primary, avoiding.worst_null);
  EXPECT_LT(plain.min_distance, -0.09);      // the spheres overlap by more than 9 cm
  EXPECT_GT(avoiding.min_distance, 0.06);    // d_a = 0.1 m, stiffness 300: kept more than 6 cm apart (0.067 seen)
  EXPECT_LT(plain.final_error, 1e-5);        // exp(-5 * 3) * 0.45 m = 1.4e-7 m, plus integration error
  EXPECT_LT(avoiding.final_error, 1e-5);
  EXPECT_LT(std::abs(avoiding.final_error - plain.final_error), 1e-9);  // the task never noticed
  EXPECT_LT(avoiding.worst_primary, 1e-10);
  EXPECT_LT(avoiding.worst_null, 1e-12);
}

}  // namespace
}  // namespace mbgen::test
