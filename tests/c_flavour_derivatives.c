/* The derivatives in the c flavour, from C99 (-Wall -Wextra -Werror -pedantic), linked by the C
 * linker: NAME_forward_dynamics_derivatives_<S> for double and float on a floating robot, checked
 * against the same generation's mass matrix: M^-1 M = 1 (1e-10 double, 1e-3 float), and dqdd/dv
 * zero at v = 0 (the velocity terms are quadratic in v; 1e-12 double, 1e-5 float). Exit status 0
 * when all hold.
 * ROBOT and MBGEN_C_HEADER name the robot (tests/CMakeLists.txt). */
#include MBGEN_C_HEADER

#include <math.h>
#include <stdio.h>

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define API(name) CAT(CAT(ROBOT, _), name)
#define N API(nv)

/* Defines check_<S>(tolerance): 0 when M^-1 M = 1 within tolerance and dqdd/dv vanishes at v = 0. */
#define DEFINE_CHECK(S)                                                                     \
  static int check_##S(double tolerance) {                                                  \
    S q[API(nq)], v[N], tau[N], qdd[N], A[N * N], B[N * N], Minv[N * N], M[N * N];           \
    int i, j, k, failures = 0;                                                              \
    double worst = 0, worst_dv = 0;                                                         \
    for (i = 0; i < API(nq); ++i) q[i] = (S)(0.1 * (i % 5) - 0.2);                          \
    q[3] = (S)0.5, q[4] = (S)0.5, q[5] = (S)0.5, q[6] = (S)0.5; /* the base's quaternion */  \
    for (i = 0; i < N; ++i) v[i] = (S)0, tau[i] = (S)(i % 3 - 1);                           \
    API(forward_dynamics_derivatives_##S)(q, v, tau, qdd, A, B, Minv);                      \
    API(mass_matrix_##S)(q, M);                                                             \
    for (i = 0; i < N; ++i)                                                                 \
      for (j = 0; j < N; ++j) {                                                             \
        double x = i == j ? -1.0 : 0.0;                                                     \
        for (k = 0; k < N; ++k) x += (double)Minv[i * N + k] * (double)M[k * N + j];        \
        if (fabs(x) > worst) worst = fabs(x);                                               \
        if (fabs((double)B[i * N + j]) > worst_dv) worst_dv = fabs((double)B[i * N + j]);   \
      }                                                                                     \
    if (worst > tolerance) ++failures;                                                      \
    if (worst_dv > tolerance * 1e-2) ++failures;                                            \
    printf(#S ": |M^-1 M - 1| = %.3g, |dqdd/dv| at v = 0: %.3g\n", worst, worst_dv);        \
    return failures;                                                                        \
  }

DEFINE_CHECK(double)
DEFINE_CHECK(float)

int main(void) { return check_double(1e-10) + check_float(1e-3) == 0 ? 0 : 1; }
