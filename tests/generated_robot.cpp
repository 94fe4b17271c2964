// The table of generated_robot.hpp for one robot: compiled once per test robot with
// MBGEN_GENERATED_HEADER, MBGEN_GENERATED_NS, MBGEN_DESCRIPTION, MBGEN_EXTRAS (empty: none) and
// MBGEN_FLOATING defined (tests/CMakeLists.txt). Only this file sees the robot's header.
#include "generated_robot.hpp"

#include <iterator>

#include MBGEN_GENERATED_HEADER

namespace mbgen::test::generated {
namespace {

namespace ns = MBGEN_GENERATED_NS;

template <typename E, std::size_t N> List<E> list(const E (&array)[N]) { return {array, N}; }

template <typename T> Closure closure_of(const ns::ClosureResult<T>& r) {
  return {static_cast<ClosureStatus>(static_cast<int>(r.status)), r.iterations, static_cast<double>(r.residual),
          static_cast<double>(r.pivot_ratio), r.worst_subsystem};
}
template <typename T> Closure closure_positions_of(T* q) { return closure_of(ns::closure_positions(q)); }
template <typename T> Closure close_loops_of(T* q, T* v) { return closure_of(ns::close_loops(q, v)); }

// Each member takes the generated overload of its own type.
template <typename T> Functions<T> functions_of() {
  Functions<T> f{};
  f.forward_dynamics = ns::forward_dynamics;
  f.full_accelerations = ns::full_accelerations;
  f.velocity_map = ns::velocity_map;
  f.full_velocities = ns::full_velocities;
  f.acceleration_bias = ns::acceleration_bias;
  f.independent_velocities = ns::independent_velocities<T>;
  f.inverse_dynamics = ns::inverse_dynamics;
  f.actuator_forces = ns::actuator_forces;
  f.mass_matrix = ns::mass_matrix;
  f.mass_matrix_factor = ns::mass_matrix_factor;
  f.mass_matrix_solve = ns::mass_matrix_solve;
  f.forward_kinematics = ns::forward_kinematics;
  f.frame_poses = ns::frame_poses;
  f.frame_jacobians = ns::frame_jacobians;
  f.center_of_mass = ns::center_of_mass;
  f.centroidal_momentum_matrix = ns::centroidal_momentum_matrix;
  f.task_kinematics = ns::task_kinematics;
  f.closure_positions = closure_positions_of<T>;
  f.close_loops = close_loops_of<T>;
  f.closure_constraints = ns::closure_constraints;
  f.self_distances = ns::self_distances;
  f.self_distances_near = ns::self_distances_near;
  return f;
}

Robot make_robot() {
  Robot r{};
  r.description = MBGEN_DESCRIPTION;
  r.extras = MBGEN_EXTRAS;
  r.load_floating = MBGEN_FLOATING != 0;
  r.nq = ns::nq;
  r.nv = ns::nv;
  r.ny = ns::ny;
  r.na = ns::na;
  r.num_bodies = ns::num_bodies;
  r.num_frames = ns::num_frames;
  r.num_distance_pairs = ns::num_distance_pairs;
  r.floating_base = ns::floating_base;
  r.has_loops = ns::has_loops;
  r.joint_names = list(ns::joint_names);
  r.joint_names_full = list(ns::joint_names_full);
  r.body_names = list(ns::body_names);
  r.frame_names = list(ns::frame_names);
  r.independent_joint_names = list(ns::independent_joint_names);
  r.actuated_joint_names = list(ns::actuated_joint_names);
  r.independent_v_index = list(ns::independent_v_index);
  r.actuated_v_index = list(ns::actuated_v_index);
  r.distance_pair_names = ns::distance_pair_names;
  r.limits = joint_position_limits(ns::num_limited_joints, ns::limited_joint_names, ns::limited_q_index, ns::limited_v_index,
                                            ns::limited_lower, ns::limited_upper);
  r.f64 = functions_of<double>();
  r.f32 = functions_of<float>();
  return r;
}

}  // namespace

const Robot& robot() {
  static const Robot r = make_robot();
  return r;
}

}  // namespace mbgen::test::generated
