#pragma once
// One test robot's generated code behind a table, so that the tests comparing generated with
// generic code (test_generated.cpp, test_generated_self_distances.cpp) compile once and run on
// every test robot: each test_generated_<robot> links their objects with its own table,
// generated_robot.cpp compiled with that robot's header (tests/CMakeLists.txt). Compiled once
// per robot, the two files took 390 of a clean build's 2,680 CPU seconds on a 2-core VM: the
// same front-end work 22 times over.
//
// The names are the generated header's (generated/README.md): `generated::robot().nv` is the
// robot's `NAME::nv`, `generated::mass_matrix(q, M)` its `NAME::mass_matrix` for the scalar of q.
#include <cstddef>
#include <vector>

#include "mbgen/control/joint_limit_potential.hpp"

namespace mbgen::test::generated {

/// What closure_positions and close_loops return (the generated ClosureResult, read as double).
enum class ClosureStatus { converged = 0, not_converged = 1, singular = 2 };
struct Closure {
  ClosureStatus status;
  int iterations;
  double residual;
  double pivot_ratio;
  int worst_subsystem;  ///< the sub-system nearest a dead point (-1 without loops)
};

/// A list of names or indices of the generated header, with its length.
template <typename E> struct List {
  const E* data;
  std::size_t size;
  const E& operator[](std::size_t i) const { return data[i]; }
  const E* begin() const { return data; }
  const E* end() const { return data + size; }
};

/// The generated functions for one scalar.
template <typename T> struct Functions {
  void (*forward_dynamics)(const T* q, const T* v, const T* tau, T* qdd);
  void (*full_accelerations)(const T* q, const T* v, const T* tau, T* qdd);
  void (*velocity_map)(const T* q, T* T_map);
  void (*full_velocities)(const T* q, const T* vy, T* v);
  void (*acceleration_bias)(const T* q, const T* vy, T* g);
  void (*independent_velocities)(const T* v, T* vy);
  void (*inverse_dynamics)(const T* q, const T* v, const T* qdd, T* tau);
  void (*actuator_forces)(const T* q, const T* vy, const T* ydd, T* tau_a, T* residual);
  void (*mass_matrix)(const T* q, T* M);
  void (*mass_matrix_factor)(const T* M, T* LD);
  void (*mass_matrix_solve)(const T* LD, const T* b, T* x);
  void (*forward_kinematics)(const T* q, T* X_WB);
  void (*frame_poses)(const T* q, T* X_WF);
  void (*frame_jacobians)(const T* q, T* J);
  void (*center_of_mass)(const T* q, T* com);
  void (*centroidal_momentum_matrix)(const T* q, T* Ag);
  void (*task_kinematics)(const T* q, T* X_WF, T* J, T* com, T* Ag);
  Closure (*closure_positions)(T* q);
  Closure (*close_loops)(T* q, T* v);
  void (*closure_constraints)(const T* q, const T* v, T* Phi, T* J, T* gamma);
  void (*self_distances)(const T* q, T* distance, T* normal, T* witness, T* jacobian);
  void (*self_distances_near)(const T* q, T threshold, T* distance, int* near, int* num_near, T* normal, T* witness,
                              T* jacobian);
};

struct Robot {
  // What the robot was generated from (the test loads the same description).
  const char* description;
  const char* extras;  ///< "" without an extras file
  bool load_floating;  ///< loaded with a floating base
  // The header's constants.
  int nq, nv, ny, na, num_bodies, num_frames, num_distance_pairs;
  bool floating_base, has_loops;
  List<const char*> joint_names, joint_names_full, body_names, frame_names, independent_joint_names,
      actuated_joint_names;
  List<int> independent_v_index, actuated_v_index;
  /// The header's position ranges (num_limited_joints, limited_*), read back by the runtime.
  std::vector<JointLimit> limits;
  const char* const (*distance_pair_names)[2];
  Functions<double> f64;
  Functions<float> f32;
};

/// This executable's robot (generated_robot.cpp).
const Robot& robot();

template <typename T> const Functions<T>& functions();
template <> inline const Functions<double>& functions<double>() { return robot().f64; }
template <> inline const Functions<float>& functions<float>() { return robot().f32; }

// The generated functions by their names, for the scalar of their arguments.
template <typename T> void forward_dynamics(const T* q, const T* v, const T* tau, T* qdd) {
  functions<T>().forward_dynamics(q, v, tau, qdd);
}
template <typename T> void full_accelerations(const T* q, const T* v, const T* tau, T* qdd) {
  functions<T>().full_accelerations(q, v, tau, qdd);
}
template <typename T> void velocity_map(const T* q, T* T_map) { functions<T>().velocity_map(q, T_map); }
template <typename T> void full_velocities(const T* q, const T* vy, T* v) { functions<T>().full_velocities(q, vy, v); }
template <typename T> void acceleration_bias(const T* q, const T* vy, T* g) {
  functions<T>().acceleration_bias(q, vy, g);
}
template <typename T> void independent_velocities(const T* v, T* vy) { functions<T>().independent_velocities(v, vy); }
template <typename T> void inverse_dynamics(const T* q, const T* v, const T* qdd, T* tau) {
  functions<T>().inverse_dynamics(q, v, qdd, tau);
}
template <typename T> void actuator_forces(const T* q, const T* vy, const T* ydd, T* tau_a, T* residual) {
  functions<T>().actuator_forces(q, vy, ydd, tau_a, residual);
}
template <typename T> void closure_constraints(const T* q, const T* v, T* Phi, T* J, T* gamma) {
  functions<T>().closure_constraints(q, v, Phi, J, gamma);
}
template <typename T> void mass_matrix(const T* q, T* M) { functions<T>().mass_matrix(q, M); }
template <typename T> void mass_matrix_factor(const T* M, T* LD) { functions<T>().mass_matrix_factor(M, LD); }
template <typename T> void mass_matrix_solve(const T* LD, const T* b, T* x) {
  functions<T>().mass_matrix_solve(LD, b, x);
}
template <typename T> void forward_kinematics(const T* q, T* X_WB) { functions<T>().forward_kinematics(q, X_WB); }
template <typename T> void frame_poses(const T* q, T* X_WF) { functions<T>().frame_poses(q, X_WF); }
template <typename T> void frame_jacobians(const T* q, T* J) { functions<T>().frame_jacobians(q, J); }
template <typename T> void center_of_mass(const T* q, T* com) { functions<T>().center_of_mass(q, com); }
template <typename T> void centroidal_momentum_matrix(const T* q, T* Ag) {
  functions<T>().centroidal_momentum_matrix(q, Ag);
}
template <typename T> void task_kinematics(const T* q, T* X_WF, T* J, T* com, T* Ag) {
  functions<T>().task_kinematics(q, X_WF, J, com, Ag);
}
template <typename T> Closure closure_positions(T* q) { return functions<T>().closure_positions(q); }
template <typename T> Closure close_loops(T* q, T* v) { return functions<T>().close_loops(q, v); }
template <typename T> void self_distances(const T* q, T* distance, T* normal, T* witness, T* jacobian) {
  functions<T>().self_distances(q, distance, normal, witness, jacobian);
}
template <typename T>
void self_distances_near(const T* q, T threshold, T* distance, int* near, int* num_near, T* normal, T* witness,
                         T* jacobian) {
  functions<T>().self_distances_near(q, threshold, distance, near, num_near, normal, witness, jacobian);
}

}  // namespace mbgen::test::generated
