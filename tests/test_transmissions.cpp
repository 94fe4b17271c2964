// `scene: loops: transmission` (generator/model/transmissions.cpp) and its map
// (runtime/include/mbgen/algorithm/transmission_map.hpp), on Lola's knees and ankles:
//  - the reduced model is a tree (nv 46 -> 30) with the outputs actuated, its mass and centre of
//    mass the whole robot's at the reference pose (1e-12);
//  - the map from outputs to actuators equals the closed forms of robots/lola/README.md (1e-11 m),
//    and its Jacobian the closed forms' central differences (1e-9 relative);
//  - with a massless linkage the reduced model's forward dynamics under tau = J^T f equals the
//    exact loop model's under the actuator forces f (1e-10 relative), and with Lola's real
//    linkage masses it does not (the lumping is what the reduction costs);
//  - loops that cannot be a transmission are a LoadError naming them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <set>
#include <sstream>

#include "load/load_error.hpp"
#include "mbgen/algorithm/center_of_mass.hpp"
#include "mbgen/algorithm/transmission_map.hpp"
#include "model/reduce_model.hpp"
#include "model/topology.hpp"
#include "lola_closed_forms.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

namespace fs = std::filesystem;

const std::string kLolaUrdf = MBGEN_SOURCE_DIR "/robots/lola/lola.urdf";
const std::string kLolaYaml = MBGEN_SOURCE_DIR "/robots/lola/lola.yaml";

/// The file `extras` with `scene_line` added to its scene, in a temporary file.
std::string with_scene_line(const std::string& extras, const std::string& scene_line) {
  std::ifstream in(extras);
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  const std::size_t scene = yaml.find("\nscene:\n");
  if (scene == std::string::npos)
    yaml += "\nscene:\n" + scene_line + "\n";
  else
    yaml.insert(scene + 8, scene_line + "\n");
  const fs::path out = fs::temp_directory_path() /
                       (std::string("mbgen_test_transmissions_") + ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".yaml");
  std::ofstream(out) << yaml;
  return out.string();
}

gen::Description load(const std::string& urdf, const std::string& extras) {
  gen::LoadOptions options;
  options.extras_file = extras;
  return gen::load_description(urdf, options);
}

std::vector<std::string> lola_actuators() {
  std::vector<std::string> names;
  for (const char* side : {"l", "r"})
    for (const char* a : {"knee_act_", "ankle_act_lat_", "ankle_act_med_"}) names.push_back(std::string(a) + side);
  return names;
}

/// The reduced model's q with every joint at 0 and the base upright.
VecX<double> neutral(const Model& model) {
  VecX<double> q = VecX<double>::Zero(model.nq());
  if (model.floating_base()) q[6] = 1;
  return q;
}

TEST(Transmissions, LolaBecomesATreeWithItsOutputsActuated) {
  const gen::Description reduced = load(kLolaUrdf, with_scene_line(kLolaYaml, "  loops: transmission"));
  const gen::Description whole = load(kLolaUrdf, kLolaYaml);
  const Model &R = reduced.model, &W = whole.model;
  EXPECT_EQ(R.nv(), W.nv() - 16);  // per leg: the knee's nut and rod, the ankle's two U-P chains
  EXPECT_TRUE(R.closures.empty());
  EXPECT_TRUE(R.subsystems.empty());
  ASSERT_EQ(reduced.transmissions.size(), 4u);
  EXPECT_EQ(reduced.transmissions[0].actuators, std::vector<std::string>({"knee_act_l"}));
  EXPECT_EQ(reduced.transmissions[0].outputs, std::vector<std::string>({"knee_l"}));
  EXPECT_EQ(reduced.transmissions[1].outputs, std::vector<std::string>({"ankle_pitch_l", "ankle_roll_l"}));
  // What `mbgen inspect` prints under "model reductions".
  ASSERT_FALSE(reduced.reductions.empty());
  EXPECT_EQ(reduced.reductions[0], "loops: transmission: knee_loop_l: knee_act_l -> knee_l; linkage knee_nut_l, knee_rod_l (0.4 kg) lumped into its parents");
  const std::set<std::string> actuated(reduced.actuated_joints.begin(), reduced.actuated_joints.end());
  for (const char* j : {"knee_l", "ankle_pitch_l", "ankle_roll_r"}) EXPECT_TRUE(actuated.count(j)) << j;
  for (const std::string& a : lola_actuators()) EXPECT_FALSE(actuated.count(a)) << a;
  EXPECT_NEAR(R.total_mass(), W.total_mass(), 1e-12 * W.total_mass());
  // Lola closes at the zero pose, where the linkage is welded.
  Data<double> dr(R), dw(W);
  const Vec3<double> com_r = center_of_mass<double>(R, dr, neutral(R));
  const Vec3<double> com_w = center_of_mass<double>(W, dw, neutral(W));
  EXPECT_LT((com_r - com_w).norm(), 1e-12);
  ASSERT_TRUE(reduced.transmission_model);
  EXPECT_EQ(reduced.transmission_model->nv(), W.nv());
}

TEST(Transmissions, MapEqualsLolasClosedFormsAndItsJacobianTheDerivative) {
  const gen::Description d = load(kLolaUrdf, with_scene_line(kLolaYaml, "  loops: transmission"));
  const Model& R = d.model;
  TransmissionMap<double> map(*d.transmission_model, R, lola_actuators(), neutral(*d.transmission_model));
  const int na = map.num_actuators();
  std::mt19937 rng(5);
  const auto index = [&](const char* joint) { return R.joint(*R.find_joint(joint)).idx_q; };
  double worst_map = 0, worst_jacobian = 0;
  for (int trial = 0; trial < 50; ++trial) {
    const VecX<double> q = random_configuration<double>(R, rng);
    VecX<double> a(na);
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> J(na, R.nv());
    ASSERT_EQ(map.evaluate(q.data(), a.data(), J.data()), ClosureStatus::Converged) << "trial " << trial;
    const auto closed_forms = [&](const VecX<double>& x) {
      VecX<double> e(6);
      e << knee_actuator(x[index("knee_l")]), ankle_actuator(x[index("ankle_pitch_l")], x[index("ankle_roll_l")], 0.045),
          ankle_actuator(x[index("ankle_pitch_l")], x[index("ankle_roll_l")], -0.045), knee_actuator(x[index("knee_r")]),
          ankle_actuator(x[index("ankle_pitch_r")], x[index("ankle_roll_r")], -0.045),
          ankle_actuator(x[index("ankle_pitch_r")], x[index("ankle_roll_r")], 0.045);
      return e;
    };
    worst_map = std::max(worst_map, (a - closed_forms(q)).cwiseAbs().maxCoeff());
    // The closed forms' central differences along every coordinate of the reduced model (past
    // the base, q and v indices differ by one): truncation ~h^2, round-off ~1e-16 / h.
    const double h = 1e-5;
    for (int v = 6; v < R.nv(); ++v) {
      VecX<double> plus = q, minus = q;
      plus[v + 1] += h, minus[v + 1] -= h;
      const VecX<double> fd = (closed_forms(plus) - closed_forms(minus)) / (2 * h);
      worst_jacobian = std::max(worst_jacobian, (J.col(v) - fd).cwiseAbs().maxCoeff() / J.cwiseAbs().maxCoeff());
    }
    for (int v = 0; v < 6; ++v) EXPECT_EQ(J.col(v).cwiseAbs().maxCoeff(), 0.0);
  }
  std::printf("map against the closed forms: %.2g m; Jacobian: %.2g relative\n", worst_map, worst_jacobian);
  EXPECT_LT(worst_map, 1e-11);
  EXPECT_LT(worst_jacobian, 1e-9);
}

/// Lola read, with the linkage bodies' inertias zeroed when `massless`, reduced or not, and
/// topology built (not validated: a massless linkage moves no mass along its actuators, which
/// load_description refuses for the exact model, rightly for anything but this comparison).
gen::Description lola_with_linkage(bool massless, bool transmission) {
  gen::LoadOptions options;
  options.extras_file = with_scene_line(kLolaYaml, "  loops: transmission");
  gen::Description d = gen::read_description(kLolaUrdf, options);
  if (massless)
    for (int b = 1; b < d.model.num_bodies(); ++b) {
      const std::string& name = d.model.body(BodyIndex(b)).name;
      if (name.rfind("knee_nut", 0) == 0 || name.rfind("knee_rod", 0) == 0 || name.rfind("ankle_act_", 0) == 0)
        d.model.mutable_body(BodyIndex(b)).inertia = Inertia<double>();
    }
  if (transmission) d = gen::reduce_model(std::move(d));
  d = gen::build_topology(std::move(d));
  return d;
}

/// Largest relative difference between the reduced model's accelerations and the exact model's
/// (at the reduced model's joints) over random states, actuator forces f and joint forces.
double transmission_error(bool massless) {
  const gen::Description reduced = lola_with_linkage(massless, true), exact = lola_with_linkage(massless, false);
  const Model &R = reduced.model, &E = exact.model;
  TransmissionMap<double> map(*reduced.transmission_model, R, lola_actuators(), neutral(*reduced.transmission_model));
  const std::vector<std::string> actuators = lola_actuators();
  const int na = map.num_actuators();
  Data<double> dr(R), de(E);
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  double worst = 0;
  for (int trial = 0; trial < 20; ++trial) {
    const VecX<double> q = random_configuration<double>(R, rng);
    VecX<double> v(R.nv()), tau(R.nv()), f(na), a(na);
    for (int i = 0; i < R.nv(); ++i) v[i] = unit(rng), tau[i] = 20 * unit(rng);
    for (int i = 0; i < na; ++i) f[i] = 500 * unit(rng);
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> J(na, R.nv());
    if (map.evaluate(q.data(), a.data(), J.data()) != ClosureStatus::Converged) ADD_FAILURE() << "trial " << trial;
    const VecX<double> q_exact = map.linkage_q();
    // The exact model's independent velocities: the actuators' rates J v, the rest as given;
    // its tree forces: f at the actuators, tau at the joints both models share.
    const VecX<double> a_dot = J * v;
    VecX<double> vy(static_cast<int>(E.structure().independent_v.size())), tau_exact = VecX<double>::Zero(E.nv());
    for (std::size_t k = 0; k < E.structure().independent_v.size(); ++k) {
      const int w = E.structure().independent_v[k];
      const Joint& joint = E.joint(E.joint_of_v(w));
      const auto it = std::find(actuators.begin(), actuators.end(), joint.name);
      vy[static_cast<int>(k)] = it != actuators.end() ? a_dot[it - actuators.begin()] : v[R.joint(*R.find_joint(joint.name)).idx_v + w - joint.idx_v];
    }
    for (int j = 1; j < E.num_joints(); ++j) {
      const Joint& joint = E.joint(JointIndex(j));
      const auto it = std::find(actuators.begin(), actuators.end(), joint.name);
      if (it != actuators.end()) tau_exact[joint.idx_v] = f[it - actuators.begin()];
      if (const auto r = R.find_joint(joint.name))
        for (int i = 0; i < joint.nv; ++i) tau_exact[joint.idx_v + i] = tau[R.joint(*r).idx_v + i];
    }
    forward_dynamics_loops_independent<double>(E, de, q_exact, vy, tau_exact);
    const VecX<double> tau_reduced = tau + J.transpose() * f;
    aba<double>(R, dr, q, v, tau_reduced);
    VecX<double> ddq_exact(R.nv());
    for (int j = 1; j < R.num_joints(); ++j) {
      const Joint& joint = R.joint(JointIndex(j));
      for (int i = 0; i < joint.nv; ++i) ddq_exact[joint.idx_v + i] = de.ddq[E.joint(*E.find_joint(joint.name)).idx_v + i];
    }
    worst = std::max(worst, (dr.ddq - ddq_exact).cwiseAbs().maxCoeff() / ddq_exact.cwiseAbs().maxCoeff());
  }
  return worst;
}

TEST(Transmissions, MasslessLinkageGivesTheExactLoopsDynamics) {
  const double massless = transmission_error(true), lumped = transmission_error(false);
  std::printf("reduced against exact accelerations: massless linkage %.2g, Lola's linkage lumped %.2g (relative)\n", massless, lumped);
  EXPECT_LT(massless, 1e-10);
  // Lola's linkage (0.4 kg per knee, 1.4 kg per ankle) lumped where it was at the reference pose:
  // what the reduction costs, and proof that the comparison sees it.
  EXPECT_GT(lumped, 1e-4);
}

TEST(Transmissions, FourBarBecomesItsRocker) {
  const std::string dir = MBGEN_SOURCE_DIR "/robots/mechanisms/";
  const gen::Description d = load(dir + "four_bar.urdf", with_scene_line(dir + "four_bar.yaml", "  loops: transmission"));
  ASSERT_EQ(d.model.nv(), 1);
  EXPECT_EQ(d.model.joint(JointIndex(1)).name, "rocker_joint");
  ASSERT_EQ(d.transmissions.size(), 1u);
  EXPECT_EQ(d.transmissions[0].actuators, std::vector<std::string>({"crank_joint"}));
}

TEST(Transmissions, CoupledJointsStayLoops) {
  // panda's fingers coupled (`mimic: couple`): no linkage to replace, nothing welded.
  const gen::Description d =
      load(shared_robot("panda/panda.urdf"), with_scene_line(MBGEN_TEST_DATA "/mimic/panda_coupled.yaml", "  loops: transmission"));
  ASSERT_EQ(d.closures.size(), 1u);
  EXPECT_EQ(d.closures[0].type, "coupling");
  EXPECT_EQ(d.model.nv(), 9);
  EXPECT_EQ(d.closed_dof, 8);
  EXPECT_TRUE(d.transmissions.empty());
  for (const std::string& r : d.reductions) EXPECT_EQ(r.find("loops: transmission"), std::string::npos) << r;
  // A coupling whose cycle meets a linkage's (Lola's left knee actuator leading the right hip) is
  // refused: the transmission would weld a coupled joint.
  std::ifstream in(kLolaYaml);
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  yaml.insert(yaml.find("closures:\n") + 10, "  - {name: hip_follows_knee, type: coupling, parent: knee_act_l, child: hip_yaw_r, ratio: 0.1}\n");
  const fs::path mixed = fs::temp_directory_path() / "mbgen_test_transmissions_mixed.yaml";
  std::ofstream(mixed) << yaml;
  try {
    load(kLolaUrdf, with_scene_line(mixed.string(), "  loops: transmission"));
    FAIL() << "no error";
  } catch (const gen::LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("the loops of closure 'hip_follows_knee' mix joint couplings with a linkage"), std::string::npos)
        << e.what();
  }
}

TEST(Transmissions, LoopsThatAreNoTransmissionAreRefused) {
  const std::string dir = MBGEN_SOURCE_DIR "/robots/mechanisms/";
  // The slider driving: its side of the loop is the linkage, the crank and the rod the outputs.
  std::ifstream in(dir + "slider_crank.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string yaml = text.str();
  yaml.replace(yaml.find("independent: [crank_joint]"), 26, "independent: [slider_joint]");
  const fs::path extras = fs::temp_directory_path() / "mbgen_test_transmissions_slider_driven.yaml";
  std::ofstream(extras) << yaml;
  try {
    load(dir + "slider_crank.urdf", with_scene_line(extras.string(), "  loops: transmission"));
    FAIL() << "no error";
  } catch (const gen::LoadError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("rod_slider drive 2 output joint(s) (crank_joint, rod_joint) with 1 actuator(s) (slider_joint)"), std::string::npos)
        << what;
    EXPECT_NE(what.find("scene: loops: transmission"), std::string::npos) << what;
  }
  try {
    load(dir + "four_bar.urdf", with_scene_line(dir + "four_bar.yaml", "  loops: gears"));
    FAIL() << "no error";
  } catch (const gen::LoadError& e) {
    EXPECT_NE(std::string(e.what()).find("exact"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mbgen::test
