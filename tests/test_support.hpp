#pragma once
// Shared by the tests: the robot descriptions to run on, seeded random states, and a relative
// error measure. Tolerances are stated in each test.
#include <algorithm>
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "model/load_description.hpp"
#include "mbgen/mbgen.hpp"
#include "runtime_instances.hpp"

namespace mbgen::test {

/// Every URDF in ../shared/robots and robots/, sorted (the test names stay stable).
inline std::vector<std::string> all_urdfs() {
  std::vector<std::string> files;
  for (const char* root : {MBGEN_SHARED_ROBOTS, MBGEN_SOURCE_DIR "/robots"}) {
    if (!std::filesystem::exists(root)) continue;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(root))
      if (entry.is_regular_file() && entry.path().extension() == ".urdf") files.push_back(entry.path().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

inline std::string shared_robot(const std::string& relative) { return std::string(MBGEN_SHARED_ROBOTS) + "/" + relative; }

/// The description's assembled pose (its neutral one for a tree) lowered until its lowest contact
/// sphere sinks `depth` into the level ground z = 0 (a floating base's z moved).
inline VecX<double> sunk_into_ground(const gen::Description& d, const std::vector<ContactSphere>& spheres, double depth) {
  VecX<double> q = d.assembly.q.size() ? d.assembly.q : neutral_configuration<double>(d.model);
  Data<double> data(d.model);
  VecX<double> p(3 * static_cast<int>(spheres.size())), J(6 * d.model.nv() * static_cast<int>(spheres.size()));
  contact_points<double>(d.model, data, spheres, q, p.data(), J.data());
  double lowest = 1e9;
  for (std::size_t k = 0; k < spheres.size(); ++k) lowest = std::min(lowest, p[3 * static_cast<int>(k) + 2] - spheres[k].radius);
  q[2] -= lowest + depth;
  return q;
}

/// A readable test-name suffix for a path: its parent folder and stem.
inline std::string short_name(const std::string& path) {
  std::filesystem::path p(path);
  std::string s = p.parent_path().filename().string() + "_" + p.stem().string();
  for (char& c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}

/// Loads the tree model of a URDF alone (no extras), fixed or floating base.
inline Model load_tree(const std::string& path, gen::BaseType base) {
  gen::LoadOptions options;
  options.base = base;
  options.pick_up_robot_yaml = false;
  return gen::load_description(path, options).model;
}

/// The bases a URDF can be loaded with: fixed always; floating unless the robot hangs from a
/// "world" link by moving joints only (the loader refuses that, see test_load_urdf.cpp).
inline std::vector<gen::BaseType> loadable_bases(const std::string& path) {
  std::vector<gen::BaseType> bases{gen::BaseType::Fixed};
  gen::LoadOptions options;
  options.base = gen::BaseType::Floating;
  options.pick_up_robot_yaml = false;
  try {
    gen::load_description(path, options);
    bases.push_back(gen::BaseType::Floating);
  } catch (const std::exception&) {
  }
  return bases;
}

/// A URDF and the base to load it with: the parameter of the tests that run on every robot.
struct UrdfCase {
  std::string path;
  gen::BaseType base;
};
inline void PrintTo(const UrdfCase& c, std::ostream* os) {
  *os << c.path << (c.base == gen::BaseType::Fixed ? " fixed" : " floating");
}
/// Every URDF with every base it loads with.
inline std::vector<UrdfCase> all_urdf_cases() {
  std::vector<UrdfCase> out;
  for (const std::string& path : all_urdfs())
    for (gen::BaseType base : loadable_bases(path)) out.push_back({path, base});
  return out;
}
/// Test-name suffix for INSTANTIATE_TEST_SUITE_P over all_urdf_cases().
inline std::string urdf_case_name(const ::testing::TestParamInfo<UrdfCase>& info) {
  return short_name(info.param.path) + (info.param.base == gen::BaseType::Fixed ? "_fixed" : "_floating");
}

/// Configurations q (+) h v and q (-) h v on the manifold, for central differences.
struct CentralPair {
  VecX<double> plus, minus;
};
inline CentralPair central_pair(const Model& model, const VecX<double>& q, const VecX<double>& v, double h) {
  CentralPair p{VecX<double>(model.nq()), VecX<double>(model.nq())};
  integrate<double>(model, q, v * h, p.plus);
  integrate<double>(model, q, v * -h, p.minus);
  return p;
}

/// The closed-loop descriptions the loop tests run on: the parallel_legs models (disney_robot
/// with its 9 valid overrides, tests/data/parallel_legs), the mechanisms, Lola, Cassie (MJCF) and
/// tests/data/closure_types (one chain per closure type).
struct LoopCase {
  std::string name, urdf, extras;  ///< extras empty: the robot.yaml beside the URDF
};
inline std::vector<LoopCase> loop_cases() {
  std::vector<LoopCase> cases;
  for (const char* m : {"5bar_linkage", "cassie_like", "digit_like_2legs", "robot_delta", "talos_like", "wl16_like"})
    cases.push_back({m, shared_robot(std::string("parallel_legs/") + m + "/robot.urdf"), ""});
  cases.push_back({"disney_robot", shared_robot("parallel_legs/disney_robot/robot.urdf"),
                   MBGEN_TEST_DATA "/parallel_legs/disney_robot_9_of_10.yaml"});
  for (const char* m : {"four_bar", "slider_crank", "ankle_2dof"})
    cases.push_back({m, MBGEN_SOURCE_DIR "/robots/mechanisms/" + std::string(m) + ".urdf",
                     MBGEN_SOURCE_DIR "/robots/mechanisms/" + std::string(m) + ".yaml"});
  // Rotor bodies inside both loops (model: body drives on the actuators and joints in the loops).
  cases.push_back({"ankle_2dof_rotors", MBGEN_SOURCE_DIR "/robots/mechanisms/ankle_2dof.urdf",
                   MBGEN_TEST_DATA "/mechanisms/ankle_2dof_rotors.yaml"});
  cases.push_back({"lola", MBGEN_SOURCE_DIR "/robots/lola/lola.urdf", MBGEN_SOURCE_DIR "/robots/lola/lola.yaml"});
  // MJCF: four <connect> equalities, ball joints as hinge chains, a floating base.
  cases.push_back({"cassie_mjcf", shared_robot("cassie_mjcf/cassie.xml"), ""});
  // Every closure type (weld, point, revolute, prismatic, universal) on its own 6-DoF chain.
  cases.push_back({"closure_types", MBGEN_TEST_DATA "/closure_types.urdf", MBGEN_TEST_DATA "/closure_types.yaml"});
  // Couplings (URDF <mimic>, MJCF joint equalities): side by side and a follower below its leader.
  cases.push_back({"panda_coupled", shared_robot("panda/panda.urdf"), MBGEN_TEST_DATA "/mimic/panda_coupled.yaml"});
  cases.push_back({"two_link_mimic", MBGEN_TEST_DATA "/mimic/two_link.urdf", MBGEN_TEST_DATA "/mimic/two_link.yaml"});
  cases.push_back({"mjcf_joint_coupling", MBGEN_TEST_DATA "/mjcf/joint_coupling.xml", ""});
  cases.push_back({"mjcf_tendon_coupling", MBGEN_TEST_DATA "/mjcf/tendon_coupling.xml", ""});
  return cases;
}
inline void PrintTo(const LoopCase& c, std::ostream* os) { *os << c.name; }
inline gen::Description load_loop_case(const LoopCase& c) {
  gen::LoadOptions options;
  if (!c.extras.empty()) options.extras_file = c.extras;
  return gen::load_description(c.urdf, options);
}

/// A seeded random consistent state of a closed-loop model: from the closed pose q_closed, the
/// independent coordinates move by up to `spread` (rad; a tenth of it in metres for prismatic
/// joints, whose travel is short), Newton closes the loops again, and v = G vy
/// with vy uniform in [-1, 1]. False if Newton does not converge there.
template <typename Rng>
bool consistent_state_once(const Model& model, const VecX<double>& q_closed, Rng& rng, double spread, VecX<double>& q,
                           VecX<double>& v) {
  Data<double> data(model);
  q = q_closed;
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  // The move is followed in 10 steps, Newton warm-started from the last closed pose (as a
  // simulation would): one jump could leave Newton's basin on the ill-conditioned models.
  std::vector<double> target(model.nq());
  for (int i = 0; i < model.nq(); ++i) target[i] = q[i];
  for (int y : model.structure().independent_v) {
    const int i = model.q_index_of_v(y);
    if (i < 0) continue;  // inside a floating base: left where it is
    const Joint& joint = model.joint(model.joint_of_v(y));
    double& x = target[i];
    x += spread * (joint.type == JointType::Prismatic ? 0.1 : 1.0) * unit(rng);
    // Within the limits (Lola's knee nut stops at 5 mm), or no farther out than the closed pose
    // already is (Cassie's assembled knee lies outside its limits: clamping would jump).
    const double start_x = q_closed[i];
    if (joint.bounded) x = std::clamp(x, std::min(joint.lower, start_x), std::max(joint.upper, start_x));
  }
  const VecX<double> start = q;
  for (int step = 1; step <= 10; ++step) {
    for (int y : model.structure().independent_v) {
      const int i = model.q_index_of_v(y);
      if (i >= 0) q[i] = start[i] + (target[i] - start[i]) * step / 10.0;
    }
    if (closure_positions<double>(model, data, q).status != ClosureStatus::Converged) return false;
  }
  VecX<double> vy(static_cast<int>(model.structure().independent_v.size()));
  for (int i = 0; i < vy.size(); ++i) vy[i] = unit(rng);
  v.resize(model.nv());
  full_velocities<double>(model, data, q, vy, v);
  return true;
}

/// consistent_state_once, retried with half the spread (three times at most) where the random
/// move runs into a fold of the loops: wl16_like's actuators meet one within a few hundredths of
/// every closed pose its assembly finds (LOOPS.md's "poor assembly" warning; see test_topology).
template <typename Rng>
bool consistent_state(const Model& model, const VecX<double>& q_closed, Rng& rng, double spread, VecX<double>& q,
                      VecX<double>& v) {
  for (int attempt = 0; attempt < 4; ++attempt, spread /= 2)
    if (consistent_state_once(model, q_closed, rng, spread, q, v)) return true;
  return false;
}

/// Lola (robots/lola) with its extras, floating.
inline gen::Description load_lola() {
  gen::LoadOptions options;
  options.extras_file = MBGEN_SOURCE_DIR "/robots/lola/lola.yaml";
  options.base = gen::BaseType::Floating;
  return gen::load_description(MBGEN_SOURCE_DIR "/robots/lola/lola.urdf", options);
}

/// ||a - b|| / max(1, ||b||): relative for large values, absolute near zero.
template <typename A, typename B> double relative_error(const A& a, const B& b) {
  return (a - b).norm() / std::max(1.0, static_cast<double>(b.norm()));
}

}  // namespace mbgen::test
