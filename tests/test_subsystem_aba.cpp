// The articulated-body algorithm with sub-systems (runtime/include/mbgen/algorithm/subsystem_aba.hpp)
// against the projected equations of motion, computed with the O(n^2) CRBA and RNEA:
//
//   qd = T xd,  qdd = T xdd + g_full,  (T^T M T) xdd = T^T (tau - h(q, qd) - M g_full),
//
// where x stacks the coordinates of tree joints outside sub-systems and each sub-system's y, T
// holds identity blocks for the former and G for the latter. The test needs no closure at all: the
// recursion is exact for any G of full column rank and any g, so random G and g check every term
// (hanging subtrees, two branches meeting at the root, a chain-only sub-system, a rigid one with
// no independent coordinate, a floating root, the world as root, drive armature, rotor bodies
// fixed in a sub-system body, in the root and in the world) independently of how the closure maps
// compute them. Tolerance 1e-10 relative (||a - b|| / max(1, ||b||)): both
// sides are double and well conditioned here (cond(T^T M T) < 1e5).
#include <gtest/gtest.h>

#include <random>

#include "malloc_guard.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

constexpr double kTol = 1e-10;
constexpr int kStates = 50;

/// A sub-system over the named bodies (ascending), rooted at `root`, with p independent coordinates.
SubSystem make_subsystem(const Model& model, const std::vector<std::string>& bodies, const std::string& root, int p) {
  SubSystem s;
  for (const std::string& name : bodies) {
    const BodyIndex b = *model.find_body(name);
    s.bodies.push_back(b);
    s.coordinates.push_back(model.joint(model.body(b).joint).idx_v);
  }
  s.root = root == "world" ? kWorldBody : *model.find_body(root);
  for (int k = 0; k < p; ++k) s.independent.push_back(s.coordinates[static_cast<std::size_t>(k)]);
  for (std::size_t k = static_cast<std::size_t>(p); k < s.coordinates.size(); ++k) s.dependent.push_back(s.coordinates[k]);
  return s;
}

/// Random G (full column rank, entries in [-1, 1] plus the identity on top) and g for every sub-system;
/// T, g_full and the reduced coordinates' layout for the reference.
struct Maps {
  MatX<double> T;       // nv x nx
  VecX<double> g_full;  // nv
};

Maps random_maps(const Model& model, Data<double>& data, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<bool> in_subsystem(static_cast<std::size_t>(model.nv()), false);
  for (const SubSystem& s : model.subsystems)
    for (int c : s.coordinates) in_subsystem[static_cast<std::size_t>(c)] = true;
  int nx = 0;
  for (int c = 0; c < model.nv(); ++c) nx += in_subsystem[static_cast<std::size_t>(c)] ? 0 : 1;
  for (const SubSystem& s : model.subsystems) nx += static_cast<int>(s.independent.size());
  Maps maps{MatX<double>::Zero(model.nv(), nx), VecX<double>::Zero(model.nv())};
  int x = 0;
  for (int c = 0; c < model.nv(); ++c)
    if (!in_subsystem[static_cast<std::size_t>(c)]) maps.T(c, x++) = 1.0;
  for (std::size_t s = 0; s < model.subsystems.size(); ++s) {
    const SubSystem& sub = model.subsystems[s];
    SubSystemWork<double>& w = data.subsystem[s];
    for (int r = 0; r < w.G.rows(); ++r) {
      for (int c = 0; c < w.G.cols(); ++c) w.G(r, c) = (r == c ? 1.0 : 0.0) + 0.5 * uniform(rng);
      w.g[r] = 3.0 * uniform(rng);
    }
    for (int r = 0; r < w.G.rows(); ++r) {
      const int coordinate = sub.coordinates[static_cast<std::size_t>(r)];
      maps.T.block(coordinate, x, 1, w.G.cols()) = w.G.row(r);
      maps.g_full[coordinate] = w.g[r];
    }
    x += static_cast<int>(w.G.cols());
  }
  return maps;
}

struct Case {
  std::string name;
  std::string urdf;
  gen::BaseType base;
  std::vector<std::tuple<std::vector<std::string>, std::string, int>> subsystems;  // bodies, root, p
  std::string armature_joint;  // a joint inside a sub-system given a drive's reflected inertia
  std::vector<std::string> rotor_joints = {};  // joints given a rotor body (rotor.hpp; CRBA and RNEA have it too)
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

class SubsystemAba : public ::testing::TestWithParam<Case> {};

TEST_P(SubsystemAba, EqualsProjectedEquationsOfMotion) {
  const Case& c = GetParam();
  Model model = load_tree(c.urdf, c.base);
  for (const auto& [bodies, root, p] : c.subsystems) model.subsystems.push_back(make_subsystem(model, bodies, root, p));
  if (!c.armature_joint.empty()) model.mutable_joint(*model.find_joint(c.armature_joint)).armature = 0.3;
  // Large rotors (N^2 I_r = 0.5 to 3 kg m^2, gyroscopic moments of the order of the links'), so
  // that a missing or mis-signed term shows far above the tolerance.
  for (std::size_t k = 0; k < c.rotor_joints.size(); ++k) {
    Joint& joint = model.mutable_joint(*model.find_joint(c.rotor_joints[k]));
    joint.rotor_gear_ratio = 50.0 + 20.0 * static_cast<double>(k);
    joint.rotor_inertia = 2e-4 * static_cast<double>(k + 1);
  }
  model.update_structure();  // the rotors change which bodies are rigid
  Data<double> data(model), reference(model);
  std::mt19937_64 rng(23);
  double worst = 0, worst_ydd = 0;
  for (int trial = 0; trial < kStates; ++trial) {
    const Maps maps = random_maps(model, data, rng);
    const VecX<double> q = random_configuration<double>(model, rng);
    const VecX<double> xd = random_vector<double>(static_cast<int>(maps.T.cols()), rng, 2.0);
    const VecX<double> v = maps.T * xd;  // consistent with the maps
    const VecX<double> tau = random_vector<double>(model.nv(), rng, 20.0);

    const VecX<double> qdd = detail::aba_recursion<double>(model, data, q, v, tau);  // the maps are the test's

    const MatX<double> M = crba<double>(model, reference, q);
    const VecX<double> h = nonlinear_effects<double>(model, reference, q, v);
    const MatX<double> Mx = maps.T.transpose() * M * maps.T;
    const VecX<double> xdd = Mx.ldlt().solve(maps.T.transpose() * (tau - h - M * maps.g_full));
    const VecX<double> qdd_expected = maps.T * xdd + maps.g_full;
    worst = std::max(worst, relative_error(qdd, qdd_expected));
    // ydd: the last entries of xdd, sub-system after sub-system.
    int x = static_cast<int>(xdd.size());
    for (std::size_t s = model.subsystems.size(); s-- > 0;) {
      const VecX<double>& ydd = data.subsystem[s].ydd;
      x -= static_cast<int>(ydd.size());
      worst_ydd = std::max(worst_ydd, relative_error(ydd, VecX<double>(xdd.segment(x, ydd.size()))));
    }
  }
  std::printf("  %s: worst relative error %.2e (qdd), %.2e (ydd)\n", c.name.c_str(), worst, worst_ydd);
  EXPECT_LT(worst, kTol);
  EXPECT_LT(worst_ydd, kTol);
}

INSTANTIATE_TEST_SUITE_P(
    Robots, SubsystemAba,
    ::testing::Values(
        // Floating root: a sub-system with two branches meeting at the base and subtrees hanging
        // off it (lf_lowerleg, rf_upperleg...), a chain-only one rooted at a hip, a rigid one (p = 0).
        Case{"hyq",
             shared_robot("hyq/hyq_no_sensors.urdf"),
             gen::BaseType::Floating,
             {{{"lf_hipassembly", "lf_upperleg", "rf_hipassembly"}, "base_link", 2},
              {{"lh_upperleg", "lh_lowerleg"}, "lh_hipassembly", 1},
              {{"rh_upperleg", "rh_lowerleg"}, "rh_hipassembly", 0}},
             "lf_hfe_joint"},
        // Rotor bodies: fixed in the root (lf_haa, rf_haa, lh_hfe), in a sub-system body (lf_hfe,
        // lh_kfe), in a rigid sub-system (rh_kfe), next to an armature (lf_hfe), and outside every
        // sub-system (rf_hfe: the tree ABA's rotor step, whose parent is a sub-system body).
        Case{"hyq_rotors",
             shared_robot("hyq/hyq_no_sensors.urdf"),
             gen::BaseType::Floating,
             {{{"lf_hipassembly", "lf_upperleg", "rf_hipassembly"}, "base_link", 2},
              {{"lh_upperleg", "lh_lowerleg"}, "lh_hipassembly", 1},
              {{"rh_upperleg", "rh_lowerleg"}, "rh_hipassembly", 0}},
             "lf_hfe_joint",
             {"lf_haa_joint", "lf_hfe_joint", "rf_haa_joint", "lh_hfe_joint", "lh_kfe_joint", "rh_kfe_joint", "rf_hfe_joint"}},
        // The world as root: the four-bar's spanning tree, every body in one sub-system.
        Case{"four_bar",
             std::string(MBGEN_SOURCE_DIR) + "/robots/mechanisms/four_bar.urdf",
             gen::BaseType::Fixed,
             {{{"crank", "coupler", "rocker"}, "world", 1}},
             ""},
        // Rotor bodies fixed in the world (the crank's, the rocker's) and in a moving body (the coupler's).
        Case{"four_bar_rotors",
             std::string(MBGEN_SOURCE_DIR) + "/robots/mechanisms/four_bar.urdf",
             gen::BaseType::Fixed,
             {{{"crank", "coupler", "rocker"}, "world", 1}},
             "",
             {"crank_joint", "coupler_joint", "rocker_joint"}}),
    [](const auto& info) { return info.param.name; });

TEST(SubsystemAbaMemory, DoesNotAllocate) {
  Model model = load_tree(shared_robot("hyq/hyq_no_sensors.urdf"), gen::BaseType::Floating);
  model.subsystems.push_back(make_subsystem(model, {"lf_hipassembly", "lf_upperleg", "rf_hipassembly"}, "base_link", 2));
  model.update_structure();
  Data<double> data(model);
  std::mt19937_64 rng(29);
  const Maps maps = random_maps(model, data, rng);
  const VecX<double> q = random_configuration<double>(model, rng);
  const VecX<double> v = maps.T * random_vector<double>(static_cast<int>(maps.T.cols()), rng);
  const VecX<double> tau = random_vector<double>(model.nv(), rng);
  double sink = 0;
  {
    MallocGuard guard;
    sink += detail::aba_recursion<double>(model, data, q, v, tau).sum();
    EXPECT_EQ(guard.count(), 0u);
  }
  EXPECT_TRUE(std::isfinite(sink));
}

// Which bodies' gathered inertia moves to the parent as mass moments (subsystem_backward): on
// Lola, the knee's nut and rod and the ankle actuators' crosses, housings and rods; not the
// shank (the ankle's sub-system hangs from it), the ankle cross or the foot (the toe hangs from it).
TEST(SubsystemWork, RigidBodiesHaveOnlyRigidSubsystemBodiesBelow) {
  const gen::Description d = load_lola();
  const Model& model = d.model;
  const Data<double> data(model);
  std::vector<std::string> rigid, not_rigid;
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& sub = model.subsystems[k];
    for (std::size_t j = 0; j < sub.bodies.size(); ++j) {
      const std::string& name = model.body(sub.bodies[j]).name;
      if (name.back() != 'l') continue;  // the left leg; the right one mirrors it
      (model.structure().subsystems[k].rigid[j] ? rigid : not_rigid).push_back(name);
    }
  }
  std::sort(rigid.begin(), rigid.end());
  std::sort(not_rigid.begin(), not_rigid.end());
  EXPECT_EQ(rigid, (std::vector<std::string>{"ankle_act_lat_cross_l", "ankle_act_lat_housing_l", "ankle_act_lat_rod_l",
                                             "ankle_act_med_cross_l", "ankle_act_med_housing_l", "ankle_act_med_rod_l",
                                             "knee_nut_l", "knee_rod_l"}));
  EXPECT_EQ(not_rigid, (std::vector<std::string>{"ankle_cross_l", "foot_body_l", "shank_l"}));
}

TEST(ModelStructure, RefusesABodyHangingOutsideTheSubsystem) {
  Model model = load_tree(shared_robot("hyq/hyq_no_sensors.urdf"), gen::BaseType::Floating);
  model.subsystems.push_back(make_subsystem(model, {"lf_upperleg", "lf_lowerleg"}, "base_link", 1));
  try {
    model.update_structure();
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "sub-system of closure(s) rooted at body 'base_link': body 'lf_upperleg' hangs from "
                 "'lf_hipassembly', which is neither in the sub-system nor its root");
  }
}

}  // namespace
}  // namespace mbgen::test
