/* The c flavour of an installed mbgen (mbgen_add_robot(... FLAVOUR c)), called from C99: the
 * gravity torques of tests/data/tiny_arm.urdf against the closed forms of main.cpp. Exit 0 when
 * all agree. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "tiny_arm_c.h"

static int joint_index(const char* name) {
  int i;
  for (i = 0; i < tiny_arm_c_nv; ++i)
    if (strcmp(tiny_arm_c_joint_names[i], name) == 0) return i;
  return -1;
}

int main(void) {
  const double g = 9.81, q1 = 0.3, q2 = -0.7;
  const int shoulder = joint_index("shoulder"), elbow = joint_index("elbow"), knee = joint_index("knee");
  double q[tiny_arm_c_nq] = {0}, zero[tiny_arm_c_nv] = {0}, tau[tiny_arm_c_nv], expected[3];
  int i, failures = 0;
  if (shoulder < 0 || elbow < 0 || knee < 0) return printf("FAIL: joint names\n"), 1;
  q[shoulder] = q1;
  q[elbow] = q2;
  q[knee] = 0.05;
  tiny_arm_c_inverse_dynamics_double(q, zero, zero, tau);
  expected[0] = -g * (0.6 * sin(q1) + 0.18 * sin(q1 + q2));
  expected[1] = -g * 0.18 * sin(q1 + q2);
  expected[2] = g * 1.0;
  for (i = 0; i < 3; ++i) {
    const double actual = tau[i == 0 ? shoulder : i == 1 ? elbow : knee];
    if (!(fabs(actual - expected[i]) <= 1e-12 * (1.0 + fabs(expected[i])))) {
      printf("FAIL c flavour inverse_dynamics %d: %.17g, expected %.17g\n", i, actual, expected[i]);
      ++failures;
    }
  }
  if (failures == 0) printf("c flavour consumer: inverse_dynamics agrees with the closed form\n");
  return failures == 0 ? 0 : 1;
}
