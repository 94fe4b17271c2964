/* The rigid-contact derivatives in the c flavour, from C99 (-Wall -Wextra -Werror -pedantic), linked
 * by the C linker: NAME_rigid_contact_forward_dynamics_derivatives_<S> for double and float on hyq
 * held at lf_foot's frame and at rf_foot's and lh_foot's origins (extras
 * hyq_rigid_contacts_c.yaml), checked against what must hold whatever the implementation, with the
 * same generation's frame Jacobians (world-aligned, of the same frames): a change of tau moves no
 * contact, so the contacts' rows of the Jacobians times dqdd/dtau vanish (the frame's six rows,
 * the points' linear three); and dqdd/dtau = M^-1 - Y (J Y)^-1 Y^T is symmetric. Relative to
 * dqdd/dtau's largest entry: 1e-10 in double, 1e-3 in float. Exit status 0 when all hold.
 * ROBOT and MBGEN_C_HEADER name the robot (tests/CMakeLists.txt). */
#include MBGEN_C_HEADER

#include <math.h>
#include <stdio.h>

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define API(name) CAT(CAT(ROBOT, _), name)
#define N API(nv)
#define M_ROWS 12 /* the frame's 6 rows and the two points' 3 */

/* The rows of frame k's world-aligned Jacobian each contact holds: 6 for the frame, 3 for points. */
static const int held_rows[3] = {6, 3, 3};

/* Defines check_<S>(tolerance): 0 when J dqdd/dtau = 0 and dqdd/dtau is symmetric within tolerance. */
#define DEFINE_CHECK(S)                                                                               \
  static int check_##S(double tolerance) {                                                            \
    S q[API(nq)], v[N], tau[N], qdd[N], lambda[M_ROWS], A[N * N], B[N * N], C[N * N];                 \
    S LA[M_ROWS * N], LB[M_ROWS * N], LC[M_ROWS * N], pivots[2 * M_ROWS], J[3 * 6 * N];               \
    int i, j, k, r, failures = 0;                                                                     \
    double scale = 0, worst_motion = 0, worst_symmetry = 0;                                           \
    for (i = 0; i < API(nq); ++i) q[i] = (S)(0.1 * (i % 5) - 0.2);                                    \
    q[3] = (S)0.5, q[4] = (S)0.5, q[5] = (S)0.5, q[6] = (S)0.5; /* the base's quaternion */            \
    for (i = 0; i < N; ++i) v[i] = (S)(0.3 * (i % 4) - 0.4), tau[i] = (S)(i % 3 - 1);                 \
    API(rigid_contact_forward_dynamics_derivatives_##S)(q, v, tau, qdd, lambda, A, LA, B, LB, C, LC, pivots); \
    API(frame_jacobians_##S)(q, J);                                                                   \
    for (i = 0; i < N * N; ++i)                                                                       \
      if (fabs((double)C[i]) > scale) scale = fabs((double)C[i]);                                     \
    for (k = 0; k < 3; ++k)                                                                           \
      for (r = 0; r < held_rows[k]; ++r)                                                              \
        for (j = 0; j < N; ++j) {                                                                     \
          double x = 0;                                                                               \
          for (i = 0; i < N; ++i) x += (double)J[(k * 6 + r) * N + i] * (double)C[i * N + j];         \
          if (fabs(x) > worst_motion) worst_motion = fabs(x);                                         \
        }                                                                                             \
    for (i = 0; i < N; ++i)                                                                           \
      for (j = 0; j < N; ++j)                                                                         \
        if (fabs((double)C[i * N + j] - (double)C[j * N + i]) > worst_symmetry)                       \
          worst_symmetry = fabs((double)C[i * N + j] - (double)C[j * N + i]);                         \
    if (!(scale > 0) || !(worst_motion <= tolerance * scale)) ++failures;                             \
    if (!(worst_symmetry <= tolerance * scale)) ++failures;                                           \
    printf(#S ": |J dqdd/dtau| = %.3g, asymmetry %.3g, of |dqdd/dtau| %.3g\n", worst_motion, worst_symmetry, scale); \
    return failures;                                                                                  \
  }

DEFINE_CHECK(double)
DEFINE_CHECK(float)

int main(void) { return check_double(1e-10) + check_float(1e-3) == 0 ? 0 : 1; }
