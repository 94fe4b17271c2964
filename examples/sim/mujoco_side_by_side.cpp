// mbgen_sim_vs_mujoco: the Cassie MJCF of ../shared/robots dropped on the floor by MuJoCo 2.2
// (Debian), with its own soft `connect` loops and soft contact, and by mbgen's simulator, with the
// same description's loops closed exactly, through the generic backend and the generated one
// (cassie_sim.hpp, built with this program) (docs/simulation.md, "Side by side with MuJoCo").
//
// Both start from the file's `home` keyframe (standing, every joint inside its range) with the
// loops closed by mbgen's Newton (--assembled: mbgen's assembled pose, outside nine ranges), 5 cm
// above the floor, at rest, motors off, the joint ranges enforced on both sides (MuJoCo's limit
// constraints, mbgen's end stops; --no-joint-limits: neither), with the file's joint springs and damping (MuJoCo's passive forces; mbgen applies the same
// -k (q - q_spring) - d qdot as passive forces, evaluated at every stage), except the ball
// joints' damping and, unless --springs, the springs (see below). Every collision
// capsule touches the floor on both sides (examples/data/cassie_sim.yaml lists their bodies for
// mbgen; the pelvis ellipsoid, which mbgen does not model, collides in MuJoCo only). Per simulated
// second: CPU time, the largest loop-closure violation (the distance between each connect's two
// anchors; mbgen's max |Phi|, checked in double by the generic runtime), the largest penetration,
// the pelvis position after `duration` with its difference from MuJoCo's, and the largest
// difference of the pelvis heights over the run (--csv writes them, every ms, for the plot).
#include <fmt/format.h>
#include <fmt/os.h>
#include <mujoco/mujoco.h>
#include <tinyxml2.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cassie_sim.hpp"
#include "collision/contact_spheres.hpp"
#include "examples/sim/run_scenario.hpp"
#include "model/load_description.hpp"
#include "tests/mujoco_without_assets.hpp"

using namespace mbgen;

namespace {

/// The MJCF without what MuJoCo would load from disk (meshes, textures), with a floor.
std::string mujoco_copy(const std::string& path) {
  tinyxml2::XMLDocument doc;
  if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS) throw std::runtime_error("cannot read " + path);
  test::remove_mujoco_assets(doc);
  tinyxml2::XMLElement* root = doc.FirstChildElement("mujoco");
  tinyxml2::XMLElement* floor = doc.NewElement("geom");
  floor->SetAttribute("name", "floor");
  floor->SetAttribute("type", "plane");
  floor->SetAttribute("size", "0 0 1");
  floor->SetAttribute("contype", "15");
  floor->SetAttribute("conaffinity", "15");
  floor->SetAttribute("condim", "3");
  floor->SetAttribute("friction", "1 0.005 0.0001");
  root->FirstChildElement("worldbody")->InsertFirstChild(floor);
  const std::string out = (std::filesystem::temp_directory_path() / "mbgen_sim_vs_mujoco_cassie.xml").string();
  doc.SaveFile(out.c_str());
  return out;
}

/// Where each mbgen coordinate lives in MuJoCo (a ball's three hinges share its quaternion).
struct JointMap {
  const Joint* joint;
  int mj_joint, qpos, dof, ball_axis;  ///< ball_axis: 0, 1, 2 for a ball's x, y, z hinge; -1 otherwise
};

std::vector<JointMap> map_joints(const Model& model, const mjModel* m) {
  std::vector<JointMap> maps;
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    JointMap map{&joint, mj_name2id(m, mjOBJ_JOINT, joint.name.c_str()), 0, 0, -1};
    if (joint.type == JointType::Floating) {
      for (int k = 0; k < m->njnt; ++k)
        if (m->jnt_type[k] == mjJNT_FREE) map.mj_joint = k;
    } else if (map.mj_joint < 0) {
      map.mj_joint = mj_name2id(m, mjOBJ_JOINT, joint.name.substr(0, joint.name.size() - 2).c_str());
      map.ball_axis = joint.name.back() - 'x';
    }
    if (map.mj_joint < 0) throw std::runtime_error("no MuJoCo joint for " + joint.name);
    map.qpos = m->jnt_qposadr[map.mj_joint];
    map.dof = m->jnt_dofadr[map.mj_joint] + std::max(map.ball_axis, 0);
    maps.push_back(map);
  }
  return maps;
}

/// MuJoCo's qpos for mbgen's q: hinges alike, a ball's x-y-z hinge chain as the quaternion of
/// Rx Ry Rz, the free joint's quaternion w first.
void to_mujoco(const std::vector<JointMap>& maps, const VecX<double>& q, mjData* d, const mjModel* m) {
  for (int k = 0; k < m->nq; ++k) d->qpos[k] = m->qpos0[k];
  for (const JointMap& map : maps) {
    const int iq = map.joint->idx_q;
    if (map.joint->type == JointType::Floating) {
      for (int k = 0; k < 3; ++k) d->qpos[map.qpos + k] = q[iq + k];
      d->qpos[map.qpos + 3] = q[iq + 6];
      for (int k = 0; k < 3; ++k) d->qpos[map.qpos + 4 + k] = q[iq + 3 + k];
    } else if (map.ball_axis == 0) {
      const Eigen::Quaterniond r = Eigen::AngleAxisd(q[iq], Vec3<double>::UnitX()) * Eigen::AngleAxisd(q[iq + 1], Vec3<double>::UnitY()) *
                                   Eigen::AngleAxisd(q[iq + 2], Vec3<double>::UnitZ());
      d->qpos[map.qpos] = r.w(), d->qpos[map.qpos + 1] = r.x(), d->qpos[map.qpos + 2] = r.y(), d->qpos[map.qpos + 3] = r.z();
    } else if (map.ball_axis < 0) {
      d->qpos[map.qpos] = q[iq];
    }
  }
  for (int k = 0; k < m->nv; ++k) d->qvel[k] = 0;
}

/// mbgen's q for MuJoCo's qpos (to_mujoco's inverse): a ball's quaternion as the angles of its
/// x-y-z hinge chain (R = Rx(a) Ry(b) Rz(c): sin b = R_02, tan a = -R_12 / R_22, tan c = -R_01 / R_00).
VecX<double> from_mujoco(const std::vector<JointMap>& maps, const double* qpos, int nq) {
  VecX<double> q = VecX<double>::Zero(nq);
  for (const JointMap& map : maps) {
    const int iq = map.joint->idx_q;
    const double* p = qpos + map.qpos;
    if (map.joint->type == JointType::Floating) {
      for (int k = 0; k < 3; ++k) q[iq + k] = p[k];
      for (int k = 0; k < 3; ++k) q[iq + 3 + k] = p[4 + k];
      q[iq + 6] = p[3];
    } else if (map.ball_axis >= 0) {
      const Mat3<double> R = Eigen::Quaterniond(p[0], p[1], p[2], p[3]).normalized().toRotationMatrix();
      const double angle[3] = {std::atan2(-R(1, 2), R(2, 2)), std::asin(std::clamp(R(0, 2), -1.0, 1.0)), std::atan2(-R(0, 1), R(0, 0))};
      q[iq] = angle[map.ball_axis];
    } else {
      q[iq] = p[0];
    }
  }
  return q;
}

/// Largest distance between the two anchors of MuJoCo's connect constraints (m).
double connect_violation(const mjModel* m, const mjData* d) {
  double worst = 0;
  for (int e = 0; e < m->neq; ++e) {
    if (m->eq_type[e] != mjEQ_CONNECT) continue;
    Vec3<double> p[2];
    for (int s = 0; s < 2; ++s) {
      const int b = s == 0 ? m->eq_obj1id[e] : m->eq_obj2id[e];
      Mat3<double> R;
      for (int k = 0; k < 9; ++k) R(k / 3, k % 3) = d->xmat[9 * b + k];
      const Vec3<double> a(m->eq_data[mjNEQDATA * e + 3 * s], m->eq_data[mjNEQDATA * e + 3 * s + 1], m->eq_data[mjNEQDATA * e + 3 * s + 2]);
      p[s] = Vec3<double>(d->xpos[3 * b], d->xpos[3 * b + 1], d->xpos[3 * b + 2]) + R * a;
    }
    worst = std::max(worst, (p[0] - p[1]).norm());
  }
  return worst;
}

struct Row {
  std::string who;
  double cpu_per_second = 0, loop_violation = 0, penetration = 0;
  Vec3<double> pelvis = Vec3<double>::Zero();
  double end_time = 0;
  std::string status = "ok";
  std::string label;                  ///< short, for the plot's legend (no commas: a CSV header)
  std::vector<double> pelvis_height;  ///< m, every ms from t = 0 while the run lasts
  int stops_touched = 0;              ///< end stops entered (mbgen's)
  double deepest_stop = 0;            ///< rad
};

/// mbgen's drop with `backend` at step h, RK4, the passive forces evaluated at every stage: the
/// CPU time per simulated second, the largest loop violation (max |Phi| of the kept rows, by the
/// generic runtime in double, every ms) and penetration, where the pelvis ends.
template <typename Backend, typename Passive>
Row run_mbgen(Backend backend, const std::string& who, double h, const gen::Description& d, const VecX<double>& q0, double duration,
              const Passive& passive) {
  Row r;
  r.who = who;
  r.label = fmt::format("mbgen {} (RK4 {} ms; exact loops; end stops)", who.find("generated") != std::string::npos ? "generated" : "generic", 1e3 * h);
  sim::SimulatorOptions o;
  o.step = h;
  if (d.scene && d.scene->contact) o.contact_parameters = d.scene->contact->parameters;
  if (d.scene) o.joint_stops = d.scene->joint_limits;
  sim::Simulator<Backend> simulator(std::move(backend), o);
  simulator.set_passive_forces(passive);
  const VecX<double> v0 = VecX<double>::Zero(d.model.nv());
  simulator.set_state(q0.data(), v0.data());
  Data<double> check(d.model);
  double cpu = 0;
  r.pelvis_height.push_back(q0[2]);
  for (int k = 1; k <= static_cast<int>(std::lround(duration / 1e-3)); ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    const sim::StepStatus s = simulator.run_until(k * 1e-3);
    cpu += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    closure_residual<double>(d.model, check, simulator.q());
    for (const SubSystem& sub : d.model.subsystems)
      for (int row : sub.rows) r.loop_violation = std::max(r.loop_violation, std::abs(check.Phi[row]));
    for (const auto& c : simulator.contacts()) r.penetration = std::max(r.penetration, double(c.penetration));
    if (s == sim::StepStatus::ok) r.pelvis_height.push_back(simulator.q()[2]);
    if (s != sim::StepStatus::ok) {
      r.status = fmt::format("{} at {:.3f} s{}", sim::to_string(s), simulator.time(),
                             s == sim::StepStatus::closure_lost
                                 ? fmt::format(" ({}, {})", simulator.closure_status() == 2 ? "singular" : "not converged",
                                               simulator.backend().subsystem_name(simulator.closure_subsystem()))
                                 : "");
      break;
    }
  }
  r.cpu_per_second = cpu / std::max(simulator.time(), 1e-9);
  r.pelvis = simulator.q().template head<3>();
  r.end_time = simulator.time();
  for (const auto& stop : simulator.joint_stops()) {
    if (stop.max_penetration > 0) ++r.stops_touched;
    r.deepest_stop = std::max(r.deepest_stop, double(stop.max_penetration));
  }
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  double duration = 1.0;
  std::string mjcf = MBGEN_SHARED_ROBOTS "/cassie_mjcf/cassie.xml", extras = MBGEN_SOURCE_DIR "/examples/data/cassie_sim.yaml";
  bool springs = false, joint_limits = true, use_keyframe = true;
  std::string csv;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool has_value = i + 1 < argc;
    if (a == "--springs") springs = true;
    else if (a == "--no-joint-limits") joint_limits = false;
    else if (a == "--assembled") use_keyframe = false;
    else if (a == "--csv" && has_value) csv = argv[++i];
    else if (a == "--duration" && has_value) duration = std::atof(argv[++i]);
    else if (a == "--robot" && has_value) mjcf = argv[++i];
    else if (a == "--extras" && has_value) extras = argv[++i];
    else {
      fmt::print(stderr, "usage: mbgen_sim_vs_mujoco [--duration S] [--robot cassie.xml] [--extras cassie_sim.yaml] [--springs] "
                        "[--no-joint-limits] [--assembled] [--csv pelvis_heights.csv]\n");
      return 2;
    }
  }
  gen::LoadOptions options;
  options.extras_file = extras;
  gen::Description d = gen::load_description(mjcf, options);
  if (!d.scene) d.scene.emplace();
  if (!joint_limits) d.scene->joint_limits.enabled = false;
  const std::vector<ContactSphere> spheres = gen::contact_spheres(d);
  char error[1000] = "";
  mjModel* m = mj_loadXML(mujoco_copy(mjcf).c_str(), nullptr, error, sizeof error);
  if (!m) {
    fmt::print(stderr, "MuJoCo: {}\n", error);
    return 1;
  }
  mjData* md = mj_makeData(m);
  const std::vector<JointMap> maps = map_joints(d.model, m);
  // The achilles rods' ball joints carry damping 0.01 on their spin about the rod's own axis, a
  // coordinate of ~1e-6 kg m^2: a time constant of ~1e-4 s, stiff for an explicit integrator
  // (MuJoCo's Euler takes damping implicitly). Both sides drop it: the rods then spin freely.
  for (int j = 0; j < m->njnt; ++j)
    if (m->jnt_type[j] == mjJNT_BALL)
      for (int k = 0; k < 3; ++k) m->dof_damping[m->jnt_dofadr[j] + k] = 0;
  // The shin and heel springs (1500 and 1250 N m/rad) are left out unless --springs, on both
  // sides: at the assembled pose the heel springs are deflected by 0.17 rad, and their ~550 Hz
  // oscillation drives the achilles linkage to its dead point within 24 ms (docs/simulation.md).
  if (!springs)
    for (int j = 0; j < m->njnt; ++j) m->jnt_stiffness[j] = 0;
  // The joint ranges (autolimits): MuJoCo's limit constraints, mbgen's end stops; both or neither.
  int limited = 0;
  for (int j = 0; j < m->njnt; ++j) {
    if (!joint_limits) m->jnt_limited[j] = 0;
    limited += m->jnt_limited[j];
  }

  // The start: the file's `home` keyframe (standing, every joint in its range) with the loops
  // closed by mbgen's Newton, or without one mbgen's assembled pose; the lowest contact sphere
  // 5 cm above the floor.
  sim::GenericBackend<double> probe(d.model, spheres);
  VecX<double> q0 = simulate::start_pose(probe, d, 0.05);
  std::string start = "the assembled pose";
  if (const int key = mj_name2id(m, mjOBJ_KEY, "home"); key >= 0 && use_keyframe) {
    VecX<double> q = from_mujoco(maps, m->key_qpos + key * m->nq, d.model.nq());
    if (probe.closure_positions(q.data()) != 0) {
      fmt::print(stderr, "mbgen's Newton does not close the loops at the `home` keyframe\n");
      return 1;
    }
    VecX<double> p(3 * probe.num_contacts()), J(6 * probe.nv() * probe.num_contacts());
    probe.contact_points(q.data(), p.data(), J.data());
    double lowest = 1e9;
    for (int k = 0; k < probe.num_contacts(); ++k) lowest = std::min(lowest, p[3 * k + 2] - probe.contact_radius(k));
    q[2] += 0.05 - lowest;
    q0 = q;
    start = "the `home` keyframe";
  }
  int outside = 0;
  for (const JointLimit& l : joint_position_limits(d.model)) outside += q0[l.q_index] < l.lower || q0[l.q_index] > l.upper;
  fmt::print("start: {}, loops closed, 5 cm up; {} joints outside their ranges\n", start, outside);
  to_mujoco(maps, q0, md, m);
  mj_forward(m, md);
  {
    Data<double> check(d.model);
    forward_kinematics<double>(d.model, check, q0);
    update_frame_placements<double>(d.model, check);
    double worst = 0;
    for (int b = 1; b < m->nbody; ++b) {
      const Vec3<double> p(md->xpos[3 * b], md->xpos[3 * b + 1], md->xpos[3 * b + 2]);
      worst = std::max(worst, (check.X_WF[d.model.frame_index(mj_id2name(m, mjOBJ_BODY, b))].translation - p).norm());
    }
    fmt::print("start pose: MuJoCo's body positions differ from mbgen's by {:.1e} m at most; connect violation {:.1e} m\n", worst,
               connect_violation(m, md));
  }

  std::vector<Row> rows;
  std::vector<Vec3<double>> mujoco_pelvis;  // every ms
  {  // MuJoCo: its own integrator and timestep (the file's), soft connects, soft contact.
    Row r;
    r.who = fmt::format("MuJoCo {} ({}, {} ms, soft connect + contact)", mj_version() / 100.0,
                        m->opt.integrator == mjINT_EULER ? "semi-implicit Euler" : "RK4", 1e3 * m->opt.timestep);
    r.label = fmt::format("MuJoCo {} ({} ms; soft loops and limits)", mj_version() / 100.0, 1e3 * m->opt.timestep);
    double cpu = 0;
    mujoco_pelvis.push_back(Vec3<double>(md->qpos[0], md->qpos[1], md->qpos[2]));
    while (md->time < duration - 1e-9) {
      const auto t0 = std::chrono::steady_clock::now();
      mj_step(m, md);
      cpu += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      r.loop_violation = std::max(r.loop_violation, connect_violation(m, md));
      for (int c = 0; c < md->ncon; ++c) r.penetration = std::max(r.penetration, -md->contact[c].dist);
      if (std::abs(md->time / 1e-3 - std::round(md->time / 1e-3)) < 1e-6)
        mujoco_pelvis.push_back(Vec3<double>(md->qpos[0], md->qpos[1], md->qpos[2]));
    }
    r.cpu_per_second = cpu / duration;
    r.pelvis = Vec3<double>(md->qpos[0], md->qpos[1], md->qpos[2]);
    r.end_time = md->time;
    rows.push_back(r);
  }
  // mbgen: the same passive forces through the controller, at every step.
  std::vector<std::pair<int, double>> stiffness;  // v index -> k, with q_spring in spring_q
  std::vector<double> spring_q;
  std::vector<std::pair<int, double>> damping;
  for (const JointMap& map : maps) {
    if (map.joint->type == JointType::Floating) continue;
    const int v = map.joint->idx_v;
    if (map.ball_axis < 0 && m->jnt_stiffness[map.mj_joint] != 0) {
      stiffness.push_back({v, m->jnt_stiffness[map.mj_joint]});
      spring_q.push_back(m->qpos_spring[map.qpos]);
    }
    if (m->dof_damping[map.dof] != 0) damping.push_back({v, m->dof_damping[map.dof]});
  }
  const auto passive = [&](const double* q, const double* v, double* tau) {
    for (std::size_t k = 0; k < stiffness.size(); ++k) {
      const int iv = stiffness[k].first;
      tau[iv] -= stiffness[k].second * (q[d.model.q_index_of_v(iv)] - spring_q[k]);
    }
    for (const auto& [iv, c] : damping) tau[iv] -= c * v[iv];
  };
  // The generated backend is the default description's (cassie_sim.hpp, built with this program).
  const bool generated = mjcf == MBGEN_SHARED_ROBOTS "/cassie_mjcf/cassie.xml" &&
                         extras == MBGEN_SOURCE_DIR "/examples/data/cassie_sim.yaml" && cassie_sim::nv == d.model.nv();
  for (double h : {1e-4, 5e-4}) {
    rows.push_back(run_mbgen(sim::GenericBackend<double>(d.model, spheres), fmt::format("mbgen generic O(n) (RK4, {} ms, exact loops, Hunt-Crossley)", 1e3 * h),
                             h, d, q0, duration, passive));
    if (generated)
      rows.push_back(run_mbgen(cassie_sim::Backend{}, fmt::format("mbgen generated O(n) (RK4, {} ms, exact loops, Hunt-Crossley)", 1e3 * h),
                               h, d, q0, duration, passive));
  }

  fmt::print("\nCassie (MJCF, {:.1f} kg, nv {}, 4 loops) dropped from 5 cm, passive, {:.1f} s; joint ranges: {} ({} in MuJoCo, {} "
             "in mbgen):\n\n",
             d.model.total_mass(), d.model.nv(), duration, joint_limits ? "limited on both sides" : "free on both sides", limited,
             joint_limits ? static_cast<int>(joint_position_limits(d.model).size()) : 0);
  fmt::print("| simulation | CPU s per simulated s | largest loop violation (m) | largest penetration (mm) | ends at (s) | pelvis there (m) | "
             "MuJoCo's pelvis then: difference (m) | largest pelvis height difference on the way (m) | stops entered, deepest (rad) | status |\n"
             "|---|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows) {
    const std::size_t k = std::min(mujoco_pelvis.size() - 1, static_cast<std::size_t>(std::lround(r.end_time / 1e-3)));
    double worst_height = 0;
    for (std::size_t i = 0; i < r.pelvis_height.size() && i < mujoco_pelvis.size(); ++i)
      worst_height = std::max(worst_height, std::abs(r.pelvis_height[i] - mujoco_pelvis[i].z()));
    const std::string stops = r.who.rfind("MuJoCo", 0) == 0 ? "-" : fmt::format("{}, {:.3f}", r.stops_touched, r.deepest_stop);
    fmt::print("| {} | {:.3f} | {:.1e} | {:.2f} | {:.3f} | ({:.3f}, {:.3f}, {:.3f}) | {:.3f} | {:.3f} | {} | {} |\n", r.who, r.cpu_per_second,
               r.loop_violation, 1e3 * r.penetration, r.end_time, r.pelvis.x(), r.pelvis.y(), r.pelvis.z(),
               (r.pelvis - mujoco_pelvis[k]).norm(), worst_height, stops, r.status);
  }
  if (!csv.empty()) {  // the pelvis height every ms, one column per run (empty after a run stopped)
    auto out = fmt::output_file(csv);
    out.print("t");
    for (const Row& r : rows) out.print(",{}", r.label);
    out.print("\n");
    for (std::size_t i = 0; i < mujoco_pelvis.size(); ++i) {
      out.print("{:.3f}", 1e-3 * static_cast<double>(i));
      for (std::size_t k = 0; k < rows.size(); ++k) {
        const double z = k == 0 ? mujoco_pelvis[i].z() : i < rows[k].pelvis_height.size() ? rows[k].pelvis_height[i] : NAN;
        if (std::isnan(z)) out.print(",");
        else out.print(",{:.6f}", z);
      }
      out.print("\n");
    }
    fmt::print("\npelvis heights: {}\n", csv);
  }
  mj_deleteData(md);
  mj_deleteModel(m);
  // The claims this program checks: mbgen's loops stay closed to 1e-10 m while it runs (exit 3),
  // and, with the joint ranges on both sides, every mbgen run completes the drop (exit 4).
  for (std::size_t k = 1; k < rows.size(); ++k)
    if (!(rows[k].loop_violation <= 1e-10)) return 3;
  if (joint_limits)
    for (std::size_t k = 1; k < rows.size(); ++k)
      if (rows[k].status != "ok") return 4;
  return 0;
}
