// mbgen_walk: the thesis' controller experiment on the generated code (docs/control.md, "Walking").
//
// A walking pattern (mbgen/control/walking_pattern.hpp: LIPM centre of mass from footsteps, swing-foot
// trajectories, the heading the torso follows) tracked at 1 kHz by the differential IK running on
// the generated functions (BasicDifferentialIk<robot::Backend>: feet, CoM, torso orientation; the
// loops re-closed by the generated Newton after each step), in five configurations: plain,
// + self-collision avoidance, + angular-momentum tracking, + both, and qp ("both" in the QP form:
// the joint ranges, velocity limits and a smallest distance hard, the swing foot's pitch released);
// two walks: straight, and narrow steps while turning (the swing leg brushing past the stance
// leg). From each run and the generated closed-system inverse dynamics (actuator_forces: the
// residual on the floating base is the wrench the ground must supply) it reports per time step
// the smallest self-distance per pair group, the smallest joint-range margin, the vertical angular
// momentum about the CoM and the ground's yaw torque about the vertical through the full-body ZMP
// (the centre of pressure), writes <out>/walk_<variant>_<config>.csv, the charts
// (scripts/plot_walking.gp), and prints the peaks. First the pattern's CoM is corrected until the
// full-body ZMP of the "both" run follows the pattern's ZMP (WalkingPattern::correct_com, a few
// passes: the pendulum alone leaves it up to 25 cm off the stance foot at these fast steps); the
// qp configuration, which stands differently, gets its own correction.
//
//   mbgen_walk [--out DIR] [--steps N] [--no-plot] [--check] [--simulate]
//
// --simulate also runs the "both" and "qp" configurations in closed loop on the ground
// (simulate()), with end stops at the joint ranges, and a plan that leaves the ranges again
// without them; with --check, the simulated robot must complete each walk with its base within
// 0.1 m of the plan's: qp with the stops, "both" (whose plan leaves the ranges) without.
//
// --check verifies what the method guarantees, exit 1 if not: every step's velocity achieves the
// primary task velocity whatever the secondary objectives add (|J v - xd| <= 1e-12 |J| |v|: the
// null-space property, potential form); the task error along the whole walk stays within 1 mm of
// the plain run's (the secondary motion changes it only through the 1 kHz integration of a
// different joint motion); the loops close at every step; the ground wrench from actuator_forces
// equals the rate of change of the centroidal momentum minus gravity at the same (q, v, a) (the
// generated centroidal momentum matrix, differentiated along v), to 1e-6 relative; the corrected
// pattern's full-body ZMP ("both") within 3 mm of its reference; the peak yaw torque with momentum
// tracking, qp included, at most a tenth of the plain run's; and qp inside every joint range with
// the legs at least 5 mm apart.
#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include MBGEN_WALK_HEADER
#include "mbgen/control/walking_pattern.hpp"
#include "mbgen/algorithm/configuration.hpp"
#include "mbgen/control/differential_ik.hpp"
#include "mbgen/sim/simulator.hpp"
#include "mbgen/sim/trajectory_csv.hpp"
#include "model/load_description.hpp"

namespace robot = MBGEN_WALK_NS;
using namespace mbgen;

namespace {

constexpr double kDt = 1e-3;
constexpr double kBound = 0.0;  ///< m: the distance no pair may go below (contact)
constexpr double kCrouch = 0.04;  ///< m the CoM goes down before walking
/// The QP configuration's: the ankles' pitch range ([-0.5, 0.7] rad) leaves no room for kCrouch
/// (the ankle reaches its stop 0.39 s into the crouch), and its knee-linkage ranges keep the knee
/// off its dead point without it.
constexpr double kQpCrouch = 0.0;
/// --simulate: the joint servo (PD toward the IK's reference, natural frequency kBandwidth,
/// critically damped) runs at every simulator step, 4 kHz, as a drive's position loop does; the
/// IK and the feed-forward once per kDt. 120 Hz walks 6 steps with the base 2-5 cm off its
/// reference, 100 Hz completes them too; 50 Hz falls in the third step, and a 120 Hz PD held
/// over 1 ms (the servo at the IK's rate) is unstable.
constexpr double kBandwidth = 120.0;
constexpr double kServoStep = 2.5e-4;  ///< s: the simulator's RK4 step, and the servo's period
/// The CoM correction's passes (correct_com): until the full-body ZMP is within kZmpTolerance of
/// the pattern's, at most kZmpPasses.
constexpr double kZmpTolerance = 3e-3;
constexpr int kZmpPasses = 8;
/// --check: the configurations with momentum tracking may leave at most this share of the plain
/// run's peak yaw torque (measured: 0.6-8 %, the narrow turn's "momentum" the most).
constexpr double kYawReduction = 0.1;
constexpr double kBaseTolerance = 0.1;  ///< m: --simulate --check's bound on the base's distance from its reference

struct Config {
  const char* name;
  bool avoidance, momentum;
  /// The QP form of the step (control::QpStepOptions): the description's joint ranges, velocity
  /// limits and a smallest pair distance as hard inequalities, the swing foot's orientation released
  /// during most of the swing, no crouch.
  bool qp = false;
};
constexpr Config kConfigs[] = {{"plain", false, false},
                               {"avoidance", true, false},
                               {"momentum", false, true},
                               {"both", true, true},
                               {"qp", true, true, true}};
constexpr int kBoth = 3;  ///< kConfigs' "both": the configuration the CoM is corrected for
constexpr int kQp = 4;    ///< kConfigs' "qp": corrected for on its own (it stands differently)
/// The QP configuration's inequalities: no pair closer than kMinDistance, every joint at least
/// kLimitMargin inside its range (activation kLimitActivation); --check holds it to them.
constexpr double kMinDistance = 0.005, kLimitMargin = 0.0, kLimitActivation = 0.1;
/// What the first-order inequalities may miss at 1 kHz: the loops re-closed by Newton move a
/// dependent joint at second order, and a distance's curvature bends it by as much.
constexpr double kLimitTolerance = 1e-3, kDistanceTolerance = 2e-4;
/// The share of the swing (single support) during which the swing foot's pitch (its angular row
/// about the world's y, within 0.45 rad of the foot's lateral axis in these walks) is released:
/// from lift-off to 3/4 of it, tracked softly (weight kReleasedWeight, that of the collision
/// descent); then taken back, the error it left blended out over the rest of the swing
/// (Planner::step). Lifted level, the trailing foot takes the ankle's pitch 0.2 rad past its stop
/// 0.1 s after lift-off: the shank turns back faster than the ankle's drives (0.3 m/s) can turn the
/// foot against it. A planned heel-up pitch instead (rolling on the toe, tried: 0.25-0.5 rad)
/// asked the drives for more than their speed and relaxed the tasks in 30-180 steps; releasing
/// yaw and roll as well let the momentum objective turn the foot (yaw torque humps of 8 N m).
constexpr double kReleaseShare = 0.75, kReleasedWeight = 1.0;
constexpr std::size_t kPitchRow = 4;  ///< TaskTarget::released's angular y
/// QpStepOptions::smoothing of the QP configuration: without it the commanded velocity jumps where
/// a stop's row switches on or the pitch is released (yaw torque spikes of 20-24 N m for a
/// millisecond); 10 leaves 2.2 N m, 30 0.6, 100 lags the CoM correction (75 mm ZMP error).
constexpr double kQpSmoothing = 30.0;

struct Variant {
  const char* name;
  walking::PatternOptions options;
};

/// The pair groups reported: between the two legs, and an arm against anything else.
enum Group { kLegs = 0, kArms = 1, kGroups = 2 };
int group_of(const char* a, const char* b) {
  const auto arm = [](const std::string& s) { return s.find("arm") != std::string::npos; };
  const auto side = [](const std::string& s) { return s.size() > 2 && s[s.size() - 2] == '_' ? s.back() : ' '; };
  if (arm(a) || arm(b)) return kArms;
  if (side(a) != ' ' && side(b) != ' ' && side(a) != side(b)) return kLegs;
  return -1;
}

struct Row {
  double t, d[kGroups], k_z, yaw_torque, task_error, wrench_mismatch, primary_residual;
  Eigen::Vector2d zmp = Eigen::Vector2d::Zero();  ///< the full-body ZMP (from actuator_forces' base residual), world x, y
  double zmp_error = 0;                           ///< |zmp - the pattern's|, m
  double limit_margin = 0;                        ///< the smallest margin to the description's joint ranges (negative: past one)
  VecX<double> q, v, vy;
};

/// Rotation about z by yaw.
Mat3<double> yaw_rotation(double yaw) { return Eigen::AngleAxisd(yaw, Vec3<double>::UnitZ()).toRotationMatrix(); }

/// The generated task_kinematics at one q, and the frames' poses read off its [R | p] rows.
struct Kinematics {
  std::vector<double> X = std::vector<double>(12 * robot::num_frames), J = std::vector<double>(6 * robot::nv * robot::num_frames),
                      com = std::vector<double>(3), Ag = std::vector<double>(6 * robot::nv);
  void evaluate(const double* q) { robot::Backend{}.task_kinematics(q, X.data(), J.data(), com.data(), Ag.data()); }
  Mat3<double> rotation(int k) const {
    Mat3<double> R;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) R(r, c) = X[static_cast<std::size_t>(12 * k + 4 * r + c)];
    return R;
  }
  Vec3<double> position(int k) const {
    return Vec3<double>(X[static_cast<std::size_t>(12 * k + 3)], X[static_cast<std::size_t>(12 * k + 7)], X[static_cast<std::size_t>(12 * k + 11)]);
  }
  Vec3<double> center_of_mass() const { return Vec3<double>(com[0], com[1], com[2]); }
  /// The index of a frame in frame_names.
  static int frame(const std::string& name) {
    for (int k = 0; k < robot::num_frames; ++k)
      if (name == robot::frame_names[k]) return k;
    throw std::runtime_error("mbgen_walk: the generated robot has no frame '" + name + "'");
  }
};

struct RunResult {
  std::vector<Row> rows;
  double peak_d[kGroups] = {1e9, 1e9}, peak_k = 0, peak_yaw = 0, peak_task = 0, peak_mismatch = 0, peak_primary = 0;
  double peak_zmp = 0;  ///< m: the full-body ZMP's largest distance from the pattern's, after the start's settling
  int closest[kGroups] = {-1, -1};  ///< the pair at each group's smallest distance
  double closest_time[kGroups] = {0, 0};
  /// The description's joint ranges (the header's limited_*): the smallest margin to a limit
  /// over the walk (rad or m; negative past it), its joint and time.
  double min_limit_margin = 1e9, min_limit_time = 0;
  int min_limit_joint = -1;
  /// The QP form: the steps whose tasks were relaxed (no exact solution within the inequalities),
  /// the most inequalities active at once.
  int relaxed_steps = 0, most_active = 0;
};

/// The smallest margin of q to the header's joint ranges (rad or m, negative past a limit), and
/// its joint's index in limited_joint_names.
std::pair<double, int> limit_margin(const VecX<double>& q) {
  std::pair<double, int> worst(1e9, -1);
  for (int i = 0; i < robot::num_limited_joints; ++i) {
    const double x = q[robot::limited_q_index[i]];
    const double margin = std::min(x - robot::limited_lower[i], robot::limited_upper[i] - x);
    if (margin < worst.first) worst = {margin, i};
  }
  return worst;
}

/// The controller of the experiment: the IK on the generated backend with the pattern's targets
/// (feet, CoM, torso yaw), for one configuration. `step(k, q, v)` is one 1 kHz tick.
class Planner {
 public:
  Planner(const Model& model, const VecX<double>& q0, const walking::WalkingPattern& pattern, const Config& config)
      : pattern_(pattern), ik_(robot::Backend{}, tasks(), options(model, config)), release_(config.qp),
        crouch_(config.qp ? kQpCrouch : kCrouch),
        yaw_momentum_(pattern.yaw_free_momentum(robot::Backend{}.total_mass())) {
    Kinematics kin;
    kin.evaluate(q0.data());
    for (int f = 0; f < 3; ++f) {
      slot[f] = Kinematics::frame(tasks()[static_cast<std::size_t>(f == 2 ? 3 : f)].frame);
      R0_[f] = kin.rotation(slot[f]);
    }
    com0_ = kin.center_of_mass();
    // The whole body's yaw inertia about the vertical through its CoM at q0: k_z of the body
    // turning rigidly at 1 rad/s (the base's angular velocity, in base axes, along the world's z).
    const Eigen::Quaterniond base(q0[6], q0[3], q0[4], q0[5]);
    const Vec3<double> up = base.toRotationMatrix().transpose() * Vec3<double>::UnitZ();
    for (int i = 0; i < 3; ++i) yaw_inertia_ += kin.Ag[static_cast<std::size_t>(5 * robot::nv + 3 + i)] * up[i];
  }
  /// The weights say which task gives first when the QP form's inequalities leave no exact
  /// solution: the torso's orientation, then the CoM; the feet (on the ground) least.
  static std::vector<control::TaskSpec> tasks() {
    return {{"left_foot", control::TaskKind::FramePose, "foot_l", 20.0, 100.0},
            {"right_foot", control::TaskKind::FramePose, "foot_r", 20.0, 100.0},
            {"com", control::TaskKind::CenterOfMass, "", 20.0, 10.0},
            {"torso", control::TaskKind::FrameOrientation, "torso", 20.0, 1.0}};
  }
  /// Targets of pattern sample k, then one IK step at q.
  control::StepReport step(int k, const VecX<double>& q, VecX<double>& v) {
    const walking::PatternSample& s = pattern_.sample(k);
    for (int f = 0; f < 2; ++f) {
      control::TaskTarget<double>& t = ik_.target(f);
      t.position = s.foot[f];  // the pattern starts from the feet at q0
      t.rotation = yaw_rotation(s.foot_yaw[f]) * R0_[f];
      t.velocity << s.foot_velocity[f], 0, 0, s.foot_yaw_rate[f];
      t.released.fill(false);
    }
    // The swing foot's pitch is free during most of the swing (QP configuration): the foot pitches
    // where the ankle's stop needs it. Then it is taken back: the error the release left, e0 (a
    // world rotation vector, actual times planned^T), is blended out over the rest of the swing,
    // R = exp(e0 (1 - b)) R_planned, omega = -e0 b' + exp(e0 (1 - b)) omega_planned (b the quintic
    // blend): a primary row taken back at once would command the gain times e0 in one step.
    if (release_ && s.stance >= 0) {
      const walking::PatternOptions& o = pattern_.options();
      const int swing = 1 - s.stance;
      const double in_step = std::fmod(s.t - o.start_time, o.step_time) - o.double_support;
      const double swing_time = o.step_time - o.double_support, release_end = kReleaseShare * swing_time;
      control::TaskTarget<double>& t = ik_.target(swing);
      if (in_step >= 0 && in_step < release_end) {
        t.released[kPitchRow] = true;
        taken_back_[swing] = -1;
      } else if (in_step >= release_end) {
        if (taken_back_[swing] < 0) {
          Kinematics kin;
          kin.evaluate(q.data());
          const Eigen::AngleAxisd e(kin.rotation(slot[swing]) * t.rotation.transpose());
          left_error_[swing] = e.angle() * e.axis();
          taken_back_[swing] = s.t;
        }
        const double u = std::min(1.0, (s.t - taken_back_[swing]) / (swing_time - release_end));
        const double keep = 1 - walking::detail::quintic(u), rate = -walking::detail::quintic_rate(u) / (swing_time - release_end);
        const double angle = left_error_[swing].norm();
        const Mat3<double> E =
            Eigen::AngleAxisd(angle * keep, angle > 0 ? Vec3<double>(left_error_[swing] / angle) : Vec3<double>::UnitZ()).toRotationMatrix();
        t.rotation = E * t.rotation;
        t.velocity.tail<3>() = left_error_[swing] * rate + E * t.velocity.tail<3>();
      }
    }
    control::TaskTarget<double>& c = ik_.target(2);
    // The CoM goes down by kCrouch over the first half second (knees bent further: the trailing
    // leg then keeps its knee off the linkage's dead point at the stride's end), then stays.
    const double ramp = std::min(1.0, s.t / 0.5);
    c.position = Vec3<double>(s.com.x(), s.com.y(), com0_.z() - crouch_ * ramp * ramp * (3 - 2 * ramp));
    c.velocity.head<3>() = s.com_velocity;
    c.velocity[2] = s.t < 0.5 ? -crouch_ * 6 * ramp * (1 - ramp) / 0.5 : 0.0;
    control::TaskTarget<double>& torso = ik_.target(3);
    // The torso turns with the pattern's heading (the feet's mean yaw smoothed over a step): a torso
    // that followed the feet's pulses would start and stop the body's yaw momentum at every step.
    torso.rotation = yaw_rotation(s.heading) * R0_[2];
    torso.velocity << 0, 0, 0, 0, 0, s.heading_rate;
    // The momentum objective's target: the vertical angular momentum for which the ground's yaw
    // torque about the ZMP vanishes (zero would leave the pattern's force's moment about the
    // CoM, ~10 N m at these steps, to the foot), plus the body's own turn, its yaw inertia times
    // the heading's rate: the ground starts and stops that turn (at most 0.4 N m here), the arms
    // cannot cancel it within their ranges (without it the shoulders' roll went 1.2 rad past).
    ik_.angular_momentum_target =
        Vec3<double>(0, 0, yaw_momentum_[static_cast<std::size_t>(k)] + yaw_inertia_ * s.heading_rate);
    return ik_.step(q, v);
  }
  control::BasicDifferentialIk<robot::Backend>& ik() { return ik_; }
  int slot[3] = {-1, -1, -1};  ///< the backend frames of the left foot, the right foot, the torso

 private:
  static control::DifferentialIkOptions options(const Model& model, const Config& config) {
    control::DifferentialIkOptions o;
    o.collision_avoidance = config.avoidance;
    o.collision = {0.05, 100.0};
    o.angular_momentum.enabled = config.momentum;
    o.angular_momentum.weight = 1e4;
    o.angular_momentum.axis_weights = {0.0, 0.0, 1.0};  // the vertical component: the arms against the legs' yaw
    if (config.qp) {
      o.qp.enabled = true;
      o.qp.released_weight = kReleasedWeight;
      o.qp.smoothing = kQpSmoothing;
      o.qp.min_distance = kMinDistance;
      o.qp.limit_margin = kLimitMargin;
      o.joint_limits.limits = joint_position_limits(robot::num_limited_joints, robot::limited_joint_names, robot::limited_q_index,
                                                    robot::limited_v_index, robot::limited_lower, robot::limited_upper);
      o.joint_limits.activation = kLimitActivation;
      // The description's velocity limits on the independent coordinates (the floating base has
      // none): without them a limit that the tasks almost fix is held by a null-space motion of
      // any speed; with them that step relaxes the tasks instead.
      for (int c = 0; c < robot::ny; ++c) {
        const int v = robot::independent_v_index[c];
        const double limit = v < 6 ? 0.0 : model.joint(model.joint_of_v(v)).velocity_limit;
        o.velocity_limits.push_back(limit > 0 ? limit : std::numeric_limits<double>::infinity());
      }
    }
    return o;
  }
  const walking::WalkingPattern& pattern_;
  control::BasicDifferentialIk<robot::Backend> ik_;
  bool release_ = false;
  double crouch_ = kCrouch;
  Mat3<double> R0_[3];
  Vec3<double> com0_;
  std::vector<double> yaw_momentum_;  ///< per pattern sample (WalkingPattern::yaw_free_momentum)
  double yaw_inertia_ = 0;            ///< kg m^2: the body's about the vertical through its CoM at q0
  double taken_back_[2] = {-1, -1};   ///< when each foot's released pitch was last taken back (-1: released, or never)
  Vec3<double> left_error_[2] = {Vec3<double>::Zero(), Vec3<double>::Zero()};  ///< the orientation error it left (world rotation vector)
};

RunResult run(const gen::Description& d, const VecX<double>& q0, const walking::WalkingPattern& pattern, const Config& config) {
  const Model& model = d.model;
  Planner planner(model, q0, pattern, config);
  control::BasicDifferentialIk<robot::Backend>& ik = planner.ik();
  robot::Backend backend;
  const int nq = robot::nq, nv = robot::nv, ny = robot::ny, np = robot::num_distance_pairs;
  Kinematics kin;
  std::vector<double>& com = kin.com;
  std::vector<double>& Ag = kin.Ag;
  const int* slot = planner.slot;

  RunResult result;
  VecX<double> q = q0, v(nv), next(nq);
  std::vector<double> distance(static_cast<std::size_t>(std::max(np, 1))), normal(3 * distance.size()), witness(6 * distance.size()),
      distance_J(distance.size() * static_cast<std::size_t>(nv));
  for (int k = 0; k < pattern.samples(); ++k) {
    const walking::PatternSample& s = pattern.sample(k);
    const control::StepReport report = planner.step(k, q, v);
    if (!report.ok)
      throw std::runtime_error(fmt::format("{}: the IK failed at t = {:.3f} s (QP: {})", config.name, s.t, control::to_string(report.qp_status)));
    result.relaxed_steps += report.tasks_relaxed ? 1 : 0;
    result.most_active = std::max(result.most_active, report.active_inequalities);
    Row row;
    row.t = s.t;
    row.yaw_torque = row.wrench_mismatch = 0;  // set after the run (central differences)
    // The null-space guarantee: the commanded velocity achieves the primary task velocity
    // whatever the secondary objectives add (|J v - xd| against |J| |v|).
    row.primary_residual = (ik.primary_jacobian() * v - ik.primary_velocity()).cwiseAbs().maxCoeff() /
                           std::max(1.0, ik.primary_jacobian().norm() * v.norm());
    row.q = q;
    row.v = v;
    row.vy.resize(ny);
    robot::independent_velocities(v.data(), row.vy.data());
    // Task error: the largest position (m) or orientation (rad) error of the tasks at q.
    row.task_error = 0;
    kin.evaluate(q.data());
    for (int f = 0; f < 2; ++f) {
      row.task_error = std::max(row.task_error, (ik.target(f).position - kin.position(slot[f])).norm());
      // A released row's error is not an error of the step (the QP configuration's swing pitch).
      Vec3<double> e = control::orientation_error<double>(ik.target(f).rotation, kin.rotation(slot[f]));
      for (int r = 0; r < 3; ++r)
        if (ik.target(f).released[static_cast<std::size_t>(3 + r)]) e[r] = 0;
      row.task_error = std::max(row.task_error, e.norm());
    }
    row.task_error = std::max(row.task_error, (ik.target(2).position - kin.center_of_mass()).norm());
    row.task_error = std::max(row.task_error, control::orientation_error<double>(ik.target(3).rotation, kin.rotation(slot[2])).norm());
    // Self-distances per group (the generated function, whatever the configuration).
    backend.self_distances(q.data(), distance.data(), normal.data(), witness.data(), distance_J.data());
    for (int g = 0; g < kGroups; ++g) row.d[g] = 1e9;
    for (int p = 0; p < np; ++p) {
      const int g = group_of(robot::distance_pair_names[p][0], robot::distance_pair_names[p][1]);
      if (g < 0) continue;
      row.d[g] = std::min(row.d[g], distance[static_cast<std::size_t>(p)]);
      if (row.d[g] < result.peak_d[g]) result.peak_d[g] = row.d[g], result.closest[g] = p, result.closest_time[g] = s.t;
    }
    const std::pair<double, int> margin = limit_margin(q);
    row.limit_margin = margin.first;
    if (margin.first < result.min_limit_margin)
      result.min_limit_margin = margin.first, result.min_limit_joint = margin.second, result.min_limit_time = s.t;
    // Vertical angular momentum about the CoM: the bottom row of A_G v.
    row.k_z = 0;
    for (int i = 0; i < nv; ++i) row.k_z += Ag[static_cast<std::size_t>(5 * nv + i)] * v[i];
    result.rows.push_back(row);
    integrate<double>(model, q, v * kDt, next);
    q = next;
    int failing = -1;
    const int status = backend.closure_positions(q.data(), &failing);
    if (status != 0)
      throw std::runtime_error(fmt::format("{}: the loops did not close at t = {:.3f} s ({}, status {})", config.name, s.t,
                                           failing >= 0 ? backend.subsystem_name(failing) : "?", status));
  }
  // Ground wrench from the generated inverse dynamics: accelerations of the independent
  // coordinates by central differences, actuator_forces' residual on the base = the wrench the
  // ground applies, [f_B; n_B] in base axes at the base origin. The independent check: the rate
  // of change of the centroidal momentum at the same (q, v, a), dh/dt = A_G a + (dA_G/dq v) v
  // (the last term by central differences along v), must equal that wrench moved to the CoM plus
  // gravity.
  const int n = static_cast<int>(result.rows.size());
  std::vector<double> tau_a(static_cast<std::size_t>(std::max(robot::na, 1))), residual(static_cast<std::size_t>(ny)),
      T(static_cast<std::size_t>(nv * ny)), bias(static_cast<std::size_t>(nv)), Ag_plus(Ag.size()), Ag_minus(Ag.size());
  VecX<double> ydd(ny), a(nv), q_plus(nq), q_minus(nq);
  const double mass = backend.total_mass(), eps = 1e-6;
  for (int k = 1; k + 1 < n; ++k) {
    Row& row = result.rows[static_cast<std::size_t>(k)];
    const Row &before = result.rows[static_cast<std::size_t>(k - 1)], &after = result.rows[static_cast<std::size_t>(k + 1)];
    ydd = (after.vy - before.vy) / (2 * kDt);
    backend.actuator_forces(row.q.data(), row.vy.data(), ydd.data(), tau_a.data(), residual.data());
    const Eigen::Quaterniond base(row.q[6], row.q[3], row.q[4], row.q[5]);
    const Mat3<double> R = base.toRotationMatrix();
    const Vec3<double> f = R * Vec3<double>(residual[0], residual[1], residual[2]);
    const Vec3<double> n_origin = R * Vec3<double>(residual[3], residual[4], residual[5]);
    const Vec3<double> origin = row.q.head<3>();
    // The full-body ZMP (centre of pressure): where the ground's wrench has no horizontal
    // moment, on the plane of the pattern's ZMP (the soles' frames); the yaw torque about the
    // vertical through it.
    const double h = pattern.sample(k).zmp.z(), dz = origin.z() - h;
    row.zmp = Eigen::Vector2d(origin.x() - (n_origin.y() + dz * f.x()) / f.z(), origin.y() + (n_origin.x() - dz * f.y()) / f.z());
    const Vec3<double> n_zmp = n_origin + (origin - Vec3<double>(row.zmp.x(), row.zmp.y(), h)).cross(f);
    row.yaw_torque = n_zmp.z();
    robot::velocity_map(row.q.data(), T.data());
    robot::acceleration_bias(row.q.data(), row.vy.data(), bias.data());
    a = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(T.data(), nv, ny) * ydd +
        Eigen::Map<const VecX<double>>(bias.data(), nv);
    integrate<double>(model, row.q, row.v * eps, q_plus);
    integrate<double>(model, row.q, row.v * -eps, q_minus);
    robot::centroidal_momentum_matrix(q_plus.data(), Ag_plus.data());
    robot::centroidal_momentum_matrix(q_minus.data(), Ag_minus.data());
    robot::centroidal_momentum_matrix(row.q.data(), Ag.data());
    robot::center_of_mass(row.q.data(), com.data());
    using RowMajor = Eigen::Map<const Eigen::Matrix<double, 6, Eigen::Dynamic, Eigen::RowMajor>>;
    const Vec6<double> h_dot = RowMajor(Ag.data(), 6, nv) * a +
                               (RowMajor(Ag_plus.data(), 6, nv) - RowMajor(Ag_minus.data(), 6, nv)) * row.v / (2 * eps);
    const Vec3<double> c(com[0], com[1], com[2]);
    Vec6<double> wrench;
    wrench << f + mass * Vec3<double>(0, 0, -9.81), n_origin + (origin - c).cross(f);
    row.wrench_mismatch = (wrench - h_dot).norm() / std::max(1.0, h_dot.norm());
  }
  if (n >= 3) result.rows.front().zmp = result.rows[1].zmp, result.rows.back().zmp = result.rows[static_cast<std::size_t>(n - 2)].zmp;
  for (int k = 0; k < n; ++k) {
    Row& row = result.rows[static_cast<std::size_t>(k)];
    row.zmp_error = (row.zmp - pattern.sample(k).zmp.head<2>()).norm();
    // Once the start has settled: the robot starts at rest, off the pendulum's ZMP (correct_com).
    if (pattern.settled(row.t) == 1) result.peak_zmp = std::max(result.peak_zmp, row.zmp_error);
  }
  for (const Row& row : result.rows) {
    for (int g = 0; g < kGroups; ++g) result.peak_d[g] = std::min(result.peak_d[g], row.d[g]);
    result.peak_k = std::max(result.peak_k, std::abs(row.k_z));
    result.peak_yaw = std::max(result.peak_yaw, std::abs(row.yaw_torque));
    result.peak_task = std::max(result.peak_task, row.task_error);
    result.peak_mismatch = std::max(result.peak_mismatch, row.wrench_mismatch);
    result.peak_primary = std::max(result.peak_primary, row.primary_residual);
  }
  return result;
}

/// The walk in closed loop on the ground: the simulator (generated backend, RK4 at kServoStep, the
/// scene's contact) and the controller, all on generated code: every millisecond the IK steps
/// its reference configuration along the pattern (as `run` does; the loops re-closed by the
/// generated Newton) and the generated actuator_forces at that reference gives the feed-forward;
/// at every simulator step (4 kHz, a drive's position loop) PD on the actuated coordinates pulls
/// the simulated robot toward the reference (natural frequency `bandwidth` Hz, critically damped,
/// scaled by each coordinate's inertia in the closed system). No balance feedback: the base
/// follows only through the contacts, which the corrected pattern (its full-body ZMP on the
/// stance foot), level feet and a stiff servo make enough. Reports how long it stays up, how far
/// the base gets from its reference, and the CPU time per simulated second (simulator and
/// controller together).
struct SimulationResult {
  double survived = 0, worst_base_error = 0, cpu_per_second = 0, final_height = 0;
  std::string status;
};

SimulationResult simulate(const Model& model, const RunResult& plan, const walking::WalkingPattern& pattern, const Config& config,
                          double bandwidth, bool end_stops) {
  const int nq = robot::nq, nv = robot::nv, ny = robot::ny, na = robot::na;
  robot::Backend backend;
  // Shift the plan so that the lowest contact sphere touches the ground (0.1 mm in).
  std::vector<double> p(3 * robot::num_contact_spheres), Jc(6 * nv * robot::num_contact_spheres);
  backend.contact_points(plan.rows[0].q.data(), p.data(), Jc.data());
  double lowest = 1e9;
  for (int k = 0; k < robot::num_contact_spheres; ++k) lowest = std::min(lowest, p[3 * k + 2] - robot::contact_sphere_radius[k]);
  const double shift = -lowest - 1e-4;
  const int n = static_cast<int>(plan.rows.size());
  // The controller's own state: the IK's configuration, advanced tick by tick as in `run`.
  Planner planner(model, plan.rows[0].q, pattern, config);
  VecX<double> q_ref = plan.rows[0].q, v_ref = VecX<double>::Zero(nv), next(nq), vy(ny), vy_last(ny), ydd(ny), residual(ny),
               feedforward(std::max(na, 1));
  int tick = -1;
  bool controller_failed = false;
  // PD gains from the closed system's inertia at the start: M_y = T^T M T, its diagonal at the
  // actuated coordinates (the knee and ankle nuts feel the leg through their linkages).
  std::vector<double> M(static_cast<std::size_t>(nv * nv)), T(static_cast<std::size_t>(nv * ny));
  robot::mass_matrix(plan.rows[0].q.data(), M.data());
  robot::velocity_map(plan.rows[0].q.data(), T.data());
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const RowMajor My = Eigen::Map<const RowMajor>(T.data(), nv, ny).transpose() * Eigen::Map<const RowMajor>(M.data(), nv, nv) *
                      Eigen::Map<const RowMajor>(T.data(), nv, ny);
  const double w = 2 * M_PI * bandwidth;
  std::vector<double> kp(static_cast<std::size_t>(std::max(na, 1))), kd(kp.size());
  std::vector<int> q_index(kp.size()), column(kp.size());
  for (int i = 0; i < na; ++i) {
    const int v = robot::actuated_v_index[i];
    q_index[static_cast<std::size_t>(i)] = robot::floating_base ? v + 1 : v;  // 1-DoF joints after the base's 7 / 6
    for (int c = 0; c < ny; ++c)
      if (robot::independent_v_index[c] == v) column[static_cast<std::size_t>(i)] = c;
    const double inertia = My(column[static_cast<std::size_t>(i)], column[static_cast<std::size_t>(i)]);
    kp[static_cast<std::size_t>(i)] = w * w * inertia;
    kd[static_cast<std::size_t>(i)] = 2 * w * inertia;
  }
  sim::SimulatorOptions options;
  options.integrator = sim::Integrator::rk4;
  options.step = kServoStep;
  options.control_period = 0;  // the joint PD at every step; the IK and the feed-forward once per kDt (tick)
  options.joint_stops.enabled = end_stops;  // the description's ranges as end stops (sim/joint_stops.hpp)
  sim::Simulator<robot::Backend> simulator(backend, options);
  VecX<double> q0 = plan.rows[0].q;
  q0[2] += shift;
  if (simulator.set_state(q0.data(), plan.rows[0].v.data()) != 0) return {0, 0, 0, 0, "the loops did not close at the start"};
  simulator.set_controller([&](double t, const double* q, const double* v, double* tau) {
    // At each 1 kHz tick (t in [k kDt, (k + 1) kDt) holds tick k): the IK on its reference and
    // the feed-forward at it (ydd by a backward difference of the IK's velocities); at every
    // call, PD from the simulated state toward the reference.
    const int k = std::min(n - 1, static_cast<int>(std::floor(t / kDt + 1e-6)));
    const bool ticks = tick < k;
    while (tick < k) {
      if (tick >= 0) {
        integrate<double>(model, q_ref, v_ref * kDt, next);
        q_ref = next;
        if (backend.closure_positions(q_ref.data()) != 0) controller_failed = true;
      }
      ++tick;
      if (!planner.step(tick, q_ref, v_ref).ok) controller_failed = true;
      vy_last = vy;
      robot::independent_velocities(v_ref.data(), vy.data());
      if (tick == 0) vy_last = vy;
    }
    if (ticks) {
      ydd = (vy - vy_last) / kDt;
      backend.actuator_forces(q_ref.data(), vy.data(), ydd.data(), feedforward.data(), residual.data());
    }
    for (int i = 0; i < nv; ++i) tau[i] = 0;
    for (int i = 0; i < na; ++i) {
      const int a = robot::actuated_v_index[i];
      const int qi = q_index[static_cast<std::size_t>(i)];
      tau[a] = feedforward[i] + kp[static_cast<std::size_t>(i)] * (q_ref[qi] - q[qi]) + kd[static_cast<std::size_t>(i)] * (v_ref[a] - v[a]);
    }
  });
  SimulationResult result;
  const double duration = plan.rows.back().t;
  const auto start = std::chrono::steady_clock::now();
  while (simulator.time() < duration) {
    const sim::StepStatus status = simulator.step();
    if (controller_failed) {
      result.status = "the controller's IK or closure failed";
      break;
    }
    if (status != sim::StepStatus::ok) {
      result.status = sim::to_string(status);
      break;
    }
    const int k = std::min(n - 1, static_cast<int>(std::lround(simulator.time() / kDt)));
    const double base_error = (simulator.q().head<3>() - (plan.rows[static_cast<std::size_t>(k)].q.head<3>() + Vec3<double>(0, 0, shift))).norm();
    result.worst_base_error = std::max(result.worst_base_error, base_error);
    if (base_error > 0.2) {
      result.status = "fell (base 0.2 m off its reference)";
      break;
    }
  }
  const double cpu = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.survived = simulator.time();
  result.cpu_per_second = cpu / std::max(simulator.time(), 1e-9);
  result.final_height = simulator.q()[2] - shift;
  if (result.status.empty()) result.status = "completed";
  return result;
}

/// The walk's poses, for `mbgen view --trajectory` (mbgen/sim/trajectory_csv.hpp).
void write_poses_csv(const std::string& path, const Model& model, const RunResult& r) {
  sim::TrajectoryCsvWriter out(path, model);
  for (const Row& row : r.rows) out.write(row.t, row.q.data());
  if (!out.ok()) throw std::runtime_error(path + ": cannot be written");
}

void write_csv(const std::string& path, const RunResult& r) {
  std::ofstream out(path);
  out << "t,d_legs,d_arms,k_z,yaw_torque,task_error,wrench_mismatch,primary_residual,zmp_x,zmp_y,zmp_error,limit_margin\n";
  for (const Row& row : r.rows)
    out << fmt::format("{:.4f},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.3g},{:.3g},{:.6g},{:.6g},{:.6g},{:.6g}\n", row.t, row.d[kLegs], row.d[kArms],
                       row.k_z, row.yaw_torque, row.task_error, row.wrench_mismatch, row.primary_residual, row.zmp.x(), row.zmp.y(), row.zmp_error,
                       row.limit_margin);
}

/// The start posture: q0 moved (kinematically, by the plain IK) until the CoM stands over the
/// feet's middle, the feet level (their orientation at the assembled, straight-legged pose: the
/// bent knees of q0 pitch them 26 degrees toe down, and a walk on them stands on its toes), the
/// torso's orientation kept: Lola's bent-knee pose has the CoM 18 cm ahead.
VecX<double> balanced(const gen::Description& d, VecX<double> q) {
  robot::Backend backend;
  const std::vector<control::TaskSpec> tasks = Planner::tasks();
  control::BasicDifferentialIk<robot::Backend> ik(backend, tasks);
  Kinematics kin, assembled;
  kin.evaluate(q.data());
  assembled.evaluate(d.assembly.q.data());
  Vec3<double> middle = Vec3<double>::Zero();
  for (int f = 0; f < 2; ++f) {
    const int k = Kinematics::frame(tasks[static_cast<std::size_t>(f)].frame);
    ik.target(f).position = kin.position(k);
    ik.target(f).rotation = assembled.rotation(k);
    middle += 0.5 * kin.position(k);
  }
  ik.target(2).position = Vec3<double>(middle.x(), middle.y(), kin.com[2]);
  ik.target(3).rotation = kin.rotation(Kinematics::frame(tasks[3].frame));
  VecX<double> v(robot::nv), next(robot::nq);
  for (int k = 0; k < 2000; ++k) {
    if (!ik.step(q, v).ok) throw std::runtime_error("balancing the start posture: the IK failed");
    integrate<double>(d.model, q, v * kDt, next);
    q = next;
    if (backend.closure_positions(q.data()) != 0) throw std::runtime_error("balancing the start posture: the loops did not close");
  }
  return q;
}

}  // namespace

int main(int argc, char** argv) {
  std::string out = ".";
  bool plot = true, check = false, simulate_walk = false;
  int steps = 6;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--out" && i + 1 < argc) {
      out = argv[++i];
    } else if (a == "--steps" && i + 1 < argc) {
      steps = std::atoi(argv[++i]);
    } else if (a == "--no-plot") {
      plot = false;
    } else if (a == "--check") {
      check = true;
    } else if (a == "--simulate") {
      simulate_walk = true;
    } else {
      std::fprintf(stderr, "usage: mbgen_walk [--out DIR] [--steps N] [--no-plot] [--check] [--simulate]\n");
      return 2;
    }
  }
  std::filesystem::create_directories(out);
  gen::LoadOptions load;
  load.base = gen::BaseType::Floating;
  load.extras_file = MBGEN_WALK_EXTRAS;
  const gen::Description d = gen::load_description(MBGEN_WALK_DESCRIPTION, load);
  // Bent knees (the straight legs of the assembled pose are singular for the feet tasks).
  VecX<double> q0 = d.assembly.q;
  const double knee_travel = -0.02;  // m of the knee nuts' travel: knees at 0.46 rad
  for (const char* name : {"knee_act_l", "knee_act_r"}) q0[d.model.joint(*d.model.find_joint(name)).idx_q] = knee_travel;
  if (robot::Backend{}.closure_positions(q0.data()) != 0) {
    std::fprintf(stderr, "mbgen_walk: the loops do not close at the bent-knee pose\n");
    return 1;
  }
  q0 = balanced(d, q0);
  // The balanced pose has the elbows 4 mrad past their upper limit (0, straight): start inside
  // every range (the loops closed again after).
  for (int i = 0; i < robot::num_limited_joints; ++i)
    q0[robot::limited_q_index[i]] = std::clamp(q0[robot::limited_q_index[i]], robot::limited_lower[i], robot::limited_upper[i]);
  if (robot::Backend{}.closure_positions(q0.data()) != 0) {
    std::fprintf(stderr, "mbgen_walk: the loops do not close at the start pose\n");
    return 1;
  }
  Kinematics kin;
  kin.evaluate(q0.data());
  const std::vector<double>& com = kin.com;
  const auto frame_position = [&](const char* name) { return kin.position(Kinematics::frame(name)); };
  const Vec3<double> feet_middle = 0.5 * (frame_position("foot_l") + frame_position("foot_r"));
  fmt::print("start: knees {:.3f} rad, feet {:.3f} m apart, CoM {:.3f} m above them and {:.3f} m ahead of their middle\n",
             q0[d.model.joint(*d.model.find_joint("knee_l")).idx_q], (frame_position("foot_l") - frame_position("foot_r")).norm(),
             com[2] - feet_middle.z(), com[0] - feet_middle.x());
  walking::PatternOptions straight;
  straight.steps = steps;
  // The narrow turn: feet 0.9 of the standing width apart (at 0.8 the shanks' SSVs come within
  // 5 mm with both feet down: the QP form held 5 mm only by relaxing the feet's tasks in 904 of
  // 4,101 steps), the swing bent 3 cm outward at mid-swing (its straight path brushes the stance
  // ankle), turning 0.15 rad per step.
  walking::PatternOptions narrow = straight;
  narrow.width_scale = 0.9;
  narrow.swing_bulge = 0.03;
  narrow.turn_per_step = 0.15;
  const Variant variants[] = {{"straight", straight}, {"narrow_turn", narrow}};

  bool ok = true;
  std::string table =
      "| walk | configuration | min distance legs [mm] | min distance arm-body [mm] | min joint-range margin [rad, m] (joint) | peak vertical "
      "angular momentum [kg m^2/s] | peak yaw torque [N m] | peak task error [m, rad] | peak full-body ZMP error [mm] | steps with relaxed tasks "
      "|\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const Variant& variant : variants) {
    walking::WalkingPattern pattern(frame_position("foot_l"), frame_position("foot_r"), Vec3<double>(com[0], com[1], com[2]),
                                    variant.options, kDt);
    walking::WalkingPattern qp_pattern = pattern;  // uncorrected: the QP configuration's own correction starts from it
    // The pendulum leaves out the swing leg, the arms and the trunk's rotation: along the plain
    // LIPM pattern the full-body ZMP leaves the stance foot by up to 25 cm (fast steps), a motion
    // no controller can track on the ground. Each pass runs the IK along the pattern ("both")
    // and moves the CoM by the pendulum's answer to that error (WalkingPattern::correct_com).
    // The last pass's run is the "both" run of the corrected pattern: kept, not run again.
    const auto corrected = [&](walking::WalkingPattern& p, const Config& config, bool held) {
      RunResult last;
      for (int pass = 0;; ++pass) {
        last = run(d, q0, p, config);
        fmt::print("{} ({}): pass {}: full-body ZMP within {:.1f} mm of the reference\n", variant.name, config.name, pass, 1e3 * last.peak_zmp);
        if (last.peak_zmp <= kZmpTolerance) break;
        if (pass == kZmpPasses) {
          if (check && held) ok = false, fmt::print("  check failed: the full-body ZMP is not within {:.1f} mm after {} passes\n", 1e3 * kZmpTolerance, pass);
          break;
        }
        std::vector<Eigen::Vector2d> error(last.rows.size());
        for (std::size_t k = 0; k < error.size(); ++k) error[k] = last.rows[k].zmp - p.sample(static_cast<int>(k)).zmp.head<2>();
        p.correct_com(error);
      }
      return last;
    };
    RunResult both = corrected(pattern, kConfigs[kBoth], true);
    // The QP configuration stands differently (no crouch, its swing pitch released): on the CoM
    // corrected for "both" its full-body ZMP is 0.13 m off the pattern's, and the yaw torque about
    // that centre of pressure reaches 8 N m. It gets its own correction, from the same pendulum
    // pattern; its passes do not reach 3 mm (the stops' dampers change its motion from pass to
    // pass), and --check does not hold them to it.
    RunResult qp_run = corrected(qp_pattern, kConfigs[kQp], false);
    std::vector<double> plain_error;
    double plain_yaw = 0;
    for (const Config& config : kConfigs) {
      const walking::WalkingPattern& used = config.qp ? qp_pattern : pattern;
      const RunResult r = &config == &kConfigs[kBoth] ? std::move(both) : config.qp ? std::move(qp_run) : run(d, q0, used, config);
      write_csv(fmt::format("{}/walk_{}_{}.csv", out, variant.name, config.name), r);
      write_poses_csv(fmt::format("{}/walk_{}_{}_poses.csv", out, variant.name, config.name), d.model, r);
      table += fmt::format("| {} | {} | {:.1f} | {:.1f} | {:.3f} ({}) | {:.3f} | {:.2f} | {:.1e} | {:.1f} | {} |\n", variant.name, config.name,
                           1e3 * r.peak_d[kLegs], 1e3 * r.peak_d[kArms], r.min_limit_margin,
                           r.min_limit_joint >= 0 ? robot::limited_joint_names[r.min_limit_joint] : "-", r.peak_k, r.peak_yaw, r.peak_task,
                           1e3 * r.peak_zmp, config.qp ? std::to_string(r.relaxed_steps) : "-");
      // The simulated robot has end stops at the description's ranges (the simulator's default); a
      // plan that leaves the ranges ("both": the left ankle 0.2 rad past) is also simulated without
      // them, which is what shows the controller tracking it (and what --check holds).
      const bool inside = r.min_limit_margin >= -kLimitTolerance;
      for (const bool end_stops : {true, false}) {
        if (!simulate_walk || !(&config == &kConfigs[kBoth] || config.qp)) break;
        if (!end_stops && inside) break;
        const SimulationResult sr = simulate(d.model, r, used, config, kBandwidth, end_stops);
        fmt::print("  simulated on the ground ({}; RK4 {:.2f} ms; IK + actuator_forces at 1 kHz, joint PD {:.0f} Hz at {:.0f} kHz, all "
                   "generated): {} after {:.3f} s of {:.3f} (walking from {:.1f} s); base off its reference by {:.3f} m at most; {:.3f} s "
                   "CPU per simulated second\n",
                   end_stops ? "end stops at the joint ranges" : "no end stops", 1e3 * kServoStep, kBandwidth, 1e-3 / kServoStep,
                   sr.status, sr.survived, r.rows.back().t, walking::PatternOptions{}.start_time, sr.worst_base_error,
                   sr.cpu_per_second);
        // The whole walk, the base within kBaseTolerance of the plan's (no balance feedback: the
        // corrected pattern and the stiff servo carry it); for a plan inside the ranges (qp) with
        // the stops, for one that leaves them ("both") the run without.
        const bool held = end_stops == inside;
        if (check && held && (sr.status != "completed" || sr.worst_base_error > kBaseTolerance))
          ok = false, fmt::print("  check failed: the simulated walk did not complete with the base within {:.2f} m of its reference\n",
                                 kBaseTolerance);
      }
      if (std::string(config.name) == "plain") {
        for (const Row& row : r.rows) plain_error.push_back(row.task_error);
        plain_yaw = r.peak_yaw;
      }
      // The thesis' claim: tracking the angular momentum keeps the stance foot from being twisted.
      if (check && config.momentum && r.peak_yaw > kYawReduction * plain_yaw)
        ok = false, fmt::print("  check failed: peak yaw torque {:.2f} N m, more than {:.0f} % of the plain run's {:.2f} N m\n", r.peak_yaw,
                               100 * kYawReduction, plain_yaw);
      double task_change = 0;
      for (std::size_t k = 0; k < r.rows.size() && k < plain_error.size(); ++k)
        task_change = std::max(task_change, std::abs(r.rows[k].task_error - plain_error[k]));
      for (int g = 0; g < kGroups; ++g)
        if (r.closest[g] >= 0)
          fmt::print("  closest {}: {} - {} at t = {:.3f} s\n", g == kLegs ? "legs" : "arm-body", robot::distance_pair_names[r.closest[g]][0],
                     robot::distance_pair_names[r.closest[g]][1], r.closest_time[g]);
      if (r.min_limit_joint >= 0)
        fmt::print("  closest to a joint limit (the description's ranges; negative: past it): {} at t = {:.3f} s, margin {:.3f}\n",
                   robot::limited_joint_names[r.min_limit_joint], r.min_limit_time, r.min_limit_margin);
      fmt::print("{:12} {:10} min distance legs {:6.1f} mm, arms {:6.1f} mm; peak |k_z| {:.3f} kg m^2/s; peak |yaw torque| {:6.2f} N m; "
                 "task error {:.1e} (change vs plain {:.1e}); |J v - xd| {:.1e}; ground wrench vs CoM {:.1e}\n",
                 variant.name, config.name, 1e3 * r.peak_d[kLegs], 1e3 * r.peak_d[kArms], r.peak_k, r.peak_yaw, r.peak_task, task_change,
                 r.peak_primary, r.peak_mismatch);
      if (config.qp)
        fmt::print("  QP form: {} of {} steps with the tasks relaxed, at most {} inequalities active\n", r.relaxed_steps, r.rows.size(),
                   r.most_active);
      // The QP configuration's claims: inside every range and the legs apart (its tasks exact
      // only where the inequalities allow: no null-space check for it).
      if (check && config.qp) {
        if (r.min_limit_margin < kLimitMargin - kLimitTolerance)
          ok = false, fmt::print("  check failed: a joint {:.4f} past its range's margin\n", kLimitMargin - r.min_limit_margin);
        if (r.peak_d[kLegs] < kMinDistance - kDistanceTolerance)
          ok = false, fmt::print("  check failed: the legs {:.1f} mm apart, fewer than {:.1f}\n", 1e3 * r.peak_d[kLegs], 1e3 * kMinDistance);
      }
      if (check && !config.qp) {
        if (r.peak_primary > 1e-12) ok = false, fmt::print("  check failed: |J v - xd| / |J||v| = {:.1e} > 1e-12\n", r.peak_primary);
        if (task_change > 1e-3) ok = false, fmt::print("  check failed: the task error changed by {:.1e} m > 1 mm\n", task_change);
        if (r.peak_mismatch > 1e-6) ok = false, fmt::print("  check failed: ground wrench vs CoM acceleration {:.1e} > 1e-6\n", r.peak_mismatch);
      }
    }
    if (plot) {
      const std::string command = fmt::format("gnuplot -e \"dir='{}'; walk='{}'; bound={}\" {}/scripts/plot_walking.gp 2>&1", out, variant.name,
                                              kBound, MBGEN_SOURCE_DIR);
      if (std::system(command.c_str()) != 0) fmt::print("gnuplot failed: the CSV files are in {}\n", out);
    }
  }
  std::ofstream(out + "/walk_peaks.md") << table;
  fmt::print("\n{}", table);
  return ok ? 0 : 1;
}
