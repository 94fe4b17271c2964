// Model reductions (generator/model/reduce_model.cpp: scene `lock`, `merge_below`), checked
// against the whole robot:
//  - a locked scene's forward dynamics equals the whole robot's with the joint held, computed
//    independently: CRBA and RNEA of the whole model, the locked rows and columns removed
//    (M_rr qdd_r = tau_r - h_r at v_locked = 0), 1e-10 relative; and, over time, the whole robot
//    with a stiff PD on the joints converges to it as the PD stiffens (w = 1e2, 1e3, 1e4 rad/s);
//  - merge_below conserves the total mass and the centre of mass at the welded pose (1e-12);
//  - what cannot be reduced is a LoadError naming the joint or loop.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <random>

#include "load/load_error.hpp"
#include "model/reduce_model.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

namespace fs = std::filesystem;

/// Loads a shared robot with an extras file holding `yaml`, floating base.
gen::Description load_with(const std::string& robot, const std::string& yaml, bool reduce = true) {
  const fs::path extras = fs::temp_directory_path() /
                          (std::string("mbgen_test_reduce_") + ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".yaml");
  { std::ofstream(extras) << yaml; }
  gen::LoadOptions options;
  options.extras_file = extras.string();
  options.base = gen::BaseType::Floating;
  options.reduce = reduce;
  return gen::load_description(shared_robot(robot), options);
}

/// q and v index of each joint of `reduced` in `whole` (by name), per coordinate.
struct CoordinateMap {
  std::vector<int> q, v;
};
CoordinateMap map_coordinates(const Model& whole, const Model& reduced) {
  CoordinateMap m;
  for (int k = 1; k < reduced.num_joints(); ++k) {
    const Joint& r = reduced.joint(JointIndex(k));
    const Joint& w = whole.joint(*whole.find_joint(r.name));
    for (int i = 0; i < r.nq; ++i) m.q.push_back(w.idx_q + i);
    for (int i = 0; i < r.nv; ++i) m.v.push_back(w.idx_v + i);
  }
  return m;
}

TEST(ReduceModel, LockedSceneIsTheWholeRobotWithTheJointsHeld) {
  const std::map<std::string, double> locked = {{"FL_HFE", 0.3}, {"FL_KFE", -0.6}, {"HR_HAA", 0.1}};
  const gen::Description reduced = load_with("solo12/solo12.urdf", "scene:\n  lock: {FL_HFE: 0.3, FL_KFE: -0.6, HR_HAA: 0.1}\n");
  const gen::Description whole = load_with("solo12/solo12.urdf", "scene:\n  lock: {FL_HFE: 0.3, FL_KFE: -0.6, HR_HAA: 0.1}\n", false);
  const Model &W = whole.model, &R = reduced.model;
  ASSERT_EQ(R.nv(), W.nv() - 3);
  ASSERT_EQ(R.num_bodies(), W.num_bodies() - 3);
  EXPECT_NEAR(R.total_mass(), W.total_mass(), 1e-12 * W.total_mass());
  const CoordinateMap map = map_coordinates(W, R);
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  Data<double> dw(W), dr(R);
  for (int trial = 0; trial < 5; ++trial) {
    VecX<double> qw = random_configuration<double>(W, rng), vw = VecX<double>::Zero(W.nv()), tw = VecX<double>::Zero(W.nv());
    for (const auto& [name, value] : locked) qw[W.joint(*W.find_joint(name)).idx_q] = value;
    VecX<double> qr(R.nq()), vr(R.nv()), tr(R.nv());
    for (int i = 0; i < R.nq(); ++i) qr[i] = qw[map.q[static_cast<std::size_t>(i)]];
    for (int i = 0; i < R.nv(); ++i) {
      vr[i] = vw[map.v[static_cast<std::size_t>(i)]] = u(rng);
      tr[i] = tw[map.v[static_cast<std::size_t>(i)]] = 5 * u(rng);
    }
    // The whole robot with the locked joints held: rows and columns of the free coordinates.
    const MatX<double> M = crba<double>(W, dw, qw);
    const VecX<double> h = rnea<double>(W, dw, qw, vw, VecX<double>::Zero(W.nv()));
    MatX<double> M_rr(R.nv(), R.nv());
    VecX<double> rhs(R.nv());
    for (int i = 0; i < R.nv(); ++i) {
      rhs[i] = tw[map.v[static_cast<std::size_t>(i)]] - h[map.v[static_cast<std::size_t>(i)]];
      for (int j = 0; j < R.nv(); ++j) M_rr(i, j) = M(map.v[static_cast<std::size_t>(i)], map.v[static_cast<std::size_t>(j)]);
    }
    const VecX<double> expected = M_rr.ldlt().solve(rhs);
    const VecX<double> qdd = aba<double>(R, dr, qr, vr, tr);
    EXPECT_LT((qdd - expected).norm(), 1e-10 * (1 + expected.norm())) << "trial " << trial;
  }
  // The welded joints' names stay frames (closures, SSVs and Jacobians may name them).
  EXPECT_TRUE(R.find_frame("FL_KFE").has_value());
  EXPECT_FALSE(R.find_joint("FL_KFE").has_value());
  EXPECT_EQ(reduced.reductions.size(), 2u);
  EXPECT_NE(reduced.reductions.back().find("3 DoF (18 -> 15)"), std::string::npos) << reduced.reductions.back();
}

/// RK4 on (q, v) for `duration` s at step h, the joint forces from tau(q, v); positions through
/// integrate() (the base's quaternion stays on its manifold).
template <typename Forces>
void rk4(const Model& m, VecX<double>& q, VecX<double>& v, Forces tau, double h, double duration) {
  Data<double> d(m);
  const auto acc = [&](const VecX<double>& x, const VecX<double>& y) -> VecX<double> { return aba<double>(m, d, x, y, tau(x, y)); };
  VecX<double> q2(m.nq()), q3(m.nq()), q4(m.nq()), next(m.nq());
  for (long k = 0, steps = std::lround(duration / h); k < steps; ++k) {
    const VecX<double> a1 = acc(q, v);
    const VecX<double> v2 = v + a1 * (h / 2);
    integrate<double>(m, q, v * (h / 2), q2);
    const VecX<double> a2 = acc(q2, v2);
    const VecX<double> v3 = v + a2 * (h / 2);
    integrate<double>(m, q, v2 * (h / 2), q3);
    const VecX<double> a3 = acc(q3, v3);
    const VecX<double> v4 = v + a3 * h;
    integrate<double>(m, q, v3 * h, q4);
    const VecX<double> a4 = acc(q4, v4);
    integrate<double>(m, q, (v + 2 * v2 + 2 * v3 + v4) * (h / 6), next);
    q = next;
    v += (a1 + 2 * a2 + 2 * a3 + a4) * (h / 6);
  }
}

// The independent check of a lock: the whole robot with a stiff PD holding the joints converges
// to the locked scene as the PD's natural frequency w grows (the joints' compliance falls as
// 1/w^2), both falling freely for 0.1 s from the same state.
TEST(ReduceModel, AStiffPdOnTheWholeRobotConvergesToTheLockedScene) {
  const std::map<std::string, double> locked = {{"FL_HFE", 0.3}, {"FL_KFE", -0.6}, {"HR_HAA", 0.1}};
  const gen::Description reduced = load_with("solo12/solo12.urdf", "scene:\n  lock: {FL_HFE: 0.3, FL_KFE: -0.6, HR_HAA: 0.1}\n");
  const gen::Description whole = load_with("solo12/solo12.urdf", "scene:\n  lock: {FL_HFE: 0.3, FL_KFE: -0.6, HR_HAA: 0.1}\n", false);
  const Model &W = whole.model, &R = reduced.model;
  const CoordinateMap map = map_coordinates(W, R);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  VecX<double> qw = random_configuration<double>(W, rng), vw = VecX<double>::Zero(W.nv());
  for (const auto& [name, value] : locked) qw[W.joint(*W.find_joint(name)).idx_q] = value;
  VecX<double> qr(R.nq()), vr(R.nv());
  for (int i = 0; i < R.nq(); ++i) qr[i] = qw[map.q[static_cast<std::size_t>(i)]];
  for (int i = 0; i < R.nv(); ++i) vr[i] = vw[map.v[static_cast<std::size_t>(i)]] = 2 * u(rng);
  const double h = 2e-5, duration = 0.1;
  rk4(R, qr, vr, [&](const VecX<double>&, const VecX<double>&) { return VecX<double>::Zero(R.nv()); }, h, duration);
  // Each locked joint's PD: kp = m w^2, kd = 2 m w (critically damped), m its diagonal of M.
  Data<double> dw(W);
  const MatX<double> M = crba<double>(W, dw, qw);
  std::vector<double> errors;
  for (double w : {1e2, 1e3, 1e4}) {
    VecX<double> q = qw, v = vw;
    rk4(W, q, v,
        [&](const VecX<double>& x, const VecX<double>& y) {
          VecX<double> tau = VecX<double>::Zero(W.nv());
          for (const auto& [name, value] : locked) {
            const Joint& j = W.joint(*W.find_joint(name));
            const double m = M(j.idx_v, j.idx_v);
            tau[j.idx_v] = -m * w * w * (x[j.idx_q] - value) - 2 * m * w * y[j.idx_v];
          }
          return tau;
        },
        h, duration);
    double e = 0;
    for (int i = 0; i < R.nq(); ++i) e = std::max(e, std::abs(q[map.q[static_cast<std::size_t>(i)]] - qr[i]));
    errors.push_back(e);
  }
  std::printf("stiff PD against the locked scene after %g s: w = 1e2: %.2g, 1e3: %.2g, 1e4: %.2g\n", duration, errors[0], errors[1], errors[2]);
  EXPECT_LT(errors[1], errors[0] / 30);
  EXPECT_LT(errors[2], errors[1] / 30);
  EXPECT_LT(errors[2], 1e-5);
}

TEST(ReduceModel, MergeBelowConservesMassAndCentreOfMass) {
  // solo12's lower legs and feet weigh ~0.16 kg each limb, its upper legs with them ~0.3 kg.
  const gen::Description reduced = load_with("solo12/solo12.urdf", "scene:\n  merge_below: 0.2\n");
  const gen::Description whole = load_with("solo12/solo12.urdf", "scene:\n  merge_below: 0.2\n", false);
  const Model &W = whole.model, &R = reduced.model;
  EXPECT_LT(R.nv(), W.nv());
  EXPECT_NEAR(R.total_mass(), W.total_mass(), 1e-12 * W.total_mass());
  const CoordinateMap map = map_coordinates(W, R);
  std::mt19937 rng(5);
  Data<double> dw(W), dr(R);
  for (int trial = 0; trial < 5; ++trial) {
    const VecX<double> qr = random_configuration<double>(R, rng);
    VecX<double> qw = neutral_configuration<double>(W);  // merged joints at 0: the welded pose
    for (int i = 0; i < R.nq(); ++i) qw[map.q[static_cast<std::size_t>(i)]] = qr[i];
    const Vec3<double> cw = center_of_mass<double>(W, dw, qw), cr = center_of_mass<double>(R, dr, qr);
    EXPECT_LT((cw - cr).norm(), 1e-12) << "trial " << trial;
  }
  EXPECT_NE(reduced.reductions.front().find("merge_below 0.2 kg"), std::string::npos) << reduced.reductions.front();
}

TEST(ReduceModel, NothingWithoutAScene) {
  gen::LoadOptions options;
  options.base = gen::BaseType::Floating;
  options.pick_up_robot_yaml = false;
  const gen::Description d = gen::load_description(shared_robot("solo12/solo12.urdf"), options);
  EXPECT_TRUE(d.reductions.empty());
  EXPECT_EQ(d.model.nv(), 18);
}

TEST(ReduceModel, ALoopsJointCannotBeLocked) {
  gen::LoadOptions options;
  options.extras_file = (fs::temp_directory_path() / "mbgen_test_reduce_four_bar.yaml").string();
  {
    std::ifstream in(MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.yaml");
    std::stringstream s;
    s << in.rdbuf();
    std::string yaml = s.str();
    const std::size_t scene = yaml.find("scene:\n");
    ASSERT_NE(scene, std::string::npos);
    yaml.insert(scene + 7, "  lock: [coupler_joint]\n");
    std::ofstream(*options.extras_file) << yaml;
  }
  try {
    gen::load_description(MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.urdf", options);
    FAIL() << "no error";
  } catch (const gen::LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("a joint of the loop"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("coupler_joint"), std::string::npos) << e.what();
  }
}

TEST(ReduceModel, BadLocksAreClearErrors) {
  const auto error_of = [](const std::string& yaml) {
    try {
      load_with("solo12/solo12.urdf", yaml);
    } catch (const gen::LoadError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(error_of("scene:\n  lock: [FL_HFX]\n").find("FL_HFE"), std::string::npos);  // a suggestion
  EXPECT_NE(error_of("scene:\n  lock: {FL_KFE: 100}\n").find("outside its limits"), std::string::npos);
  EXPECT_NE(error_of("scene:\n  lock: [FL_KFE, FL_KFE]\n").find("twice"), std::string::npos);
  EXPECT_NE(error_of("scene:\n  lock: 3\n").find("must be a list of joints"), std::string::npos);
  EXPECT_NE(error_of("scene:\n  merge_below: -1\n").find("is negative"), std::string::npos);
}

TEST(ReduceModel, WeldJointsRefusesWhatItCannotWeld) {
  const Model m = load_tree(shared_robot("solo12/solo12.urdf"), gen::BaseType::Floating);
  EXPECT_THROW(gen::weld_joints(m, {{"nope", 0.0}}), std::invalid_argument);
  EXPECT_THROW(gen::weld_joints(m, {{"root_joint", 0.0}}), std::invalid_argument);
  EXPECT_EQ(gen::weld_joints(m, {}).nv(), m.nv());
}

}  // namespace
}  // namespace mbgen::test
