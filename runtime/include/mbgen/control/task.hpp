#pragma once
// Primary tasks of the differential IK (differential_ik.hpp, which writes their rows): Jacobian
// rows and a desired task velocity  xd_des = xd_ff + gain * error(pose_ref, pose).
//
// Every task is expressed in world axes (LocalWorldAligned): linear velocity of the frame origin
// (or of the centre of mass) and angular velocity of the frame. The orientation error is
// log(R_ref R^T) in world axes, so that the angular velocity gain * error turns R towards R_ref
// along the shortest arc (pose error in task space as in the thesis, Appendix C).
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "mbgen/algorithm/jacobian.hpp"

namespace mbgen::control {

enum class TaskKind {
  FramePose,         ///< 6 rows: [linear; angular] velocity of a frame
  FramePosition,     ///< 3 rows: linear velocity of a frame's origin
  FrameOrientation,  ///< 3 rows: angular velocity of a frame
  CenterOfMass,      ///< 3 rows: velocity of the centre of mass
};

inline int task_rows(TaskKind kind) { return kind == TaskKind::FramePose ? 6 : 3; }
inline const char* to_string(TaskKind kind) {
  switch (kind) {
    case TaskKind::FramePose: return "frame pose";
    case TaskKind::FramePosition: return "frame position";
    case TaskKind::FrameOrientation: return "frame orientation";
    case TaskKind::CenterOfMass: return "centre of mass";
  }
  return "unknown";
}

/// What a task is (constant): given by the user, resolved against the model at construction.
struct TaskSpec {
  std::string name;    ///< for messages and lookup
  TaskKind kind = TaskKind::FramePose;
  std::string frame;   ///< model frame name (ignored for CenterOfMass)
  double gain = 0.0;   ///< feedback gain on the pose error, 1/s (0: pure feed-forward)
  /// The QP form of the step (QpStepOptions): the weight of this task's rows, relative to the
  /// other tasks', when the inequalities leave no velocity that achieves every task exactly (the
  /// task with the smallest weight gives most). > 0.
  double weight = 1.0;
};

/// Where a task should be and how fast it should move (set every step), world axes.
template <typename S> struct TaskTarget {
  Vec3<S> position = Vec3<S>::Zero();         ///< frame origin or centre of mass
  Mat3<S> rotation = Mat3<S>::Identity();     ///< R_WF_ref (orientation tasks)
  Vec6<S> velocity = Vec6<S>::Zero();         ///< feed-forward [linear; angular] (the relevant half is used)
  /// Rows of the task released from the primary stack for this step (world axes; FramePose:
  /// linear x, y, z then angular x, y, z; the 3-row tasks use the first three): a released row
  /// constrains nothing, so its direction joins the null space the secondary objectives use (the
  /// thesis' swing foot turning about the vertical to make room for avoidance). The QP form still
  /// tracks it, softly (QpStepOptions::released_weight); the potential form leaves it free.
  std::array<bool, 6> released{};
};

/// A TaskSpec resolved: the task's first row in the stack, its frame among the backend's
/// (slot) and, when resolved against a model (the generic DifferentialIk), the model's frame.
struct Task {
  TaskSpec spec;
  FrameIndex frame;
  int slot = -1;
  int row = 0;
  int rows() const { return task_rows(spec.kind); }
};

/// Rotation error e (world axes) with exp([e]) R = R_ref: the axis-angle of R_ref R^T.
template <typename S> Vec3<S> orientation_error(const Mat3<S>& R_ref, const Mat3<S>& R) {
  const Mat3<S> R_err = R_ref * R.transpose();
  const Eigen::AngleAxis<S> aa(R_err);
  return aa.angle() * aa.axis();
}

/// Resolves a TaskSpec (throws std::invalid_argument naming the task and what is wrong).
inline Task resolve_task(const Model& model, const TaskSpec& spec, int row) {
  Task task;
  task.spec = spec;
  task.row = row;
  if (!(spec.gain >= 0) || !std::isfinite(spec.gain))
    throw std::invalid_argument("task '" + spec.name + "': gain must be finite and >= 0, got " + std::to_string(spec.gain));
  if (spec.kind != TaskKind::CenterOfMass) {
    const auto f = model.find_frame(spec.frame);
    if (!f)
      throw std::invalid_argument("task '" + spec.name + "': no frame named '" + spec.frame + "' in model '" + model.name +
                                  "' (a URDF link or fixed joint name)");
    task.frame = *f;
  }
  return task;
}

}  // namespace mbgen::control
