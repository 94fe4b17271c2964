/* The c flavour from C (templates/c): calls every function of a robot's generated C API, for
 * double and float, and lays the results out in one array in a fixed order, which
 * test_c_flavour.cpp rebuilds from the cpp flavour and compares bit for bit. Compiled as C99 with
 * -Wall -Wextra -Werror -pedantic: the header must be plain C. ROBOT and MBGEN_C_HEADER name the
 * robot; with MBGEN_C_MAIN it is a C program of its own, linked by the C linker (no libstdc++). */
#include MBGEN_C_HEADER

#include <stddef.h>
#include <string.h>

#define CAT_(a, b) a##b
#define CAT(a, b) CAT_(a, b)
#define API(name) CAT(CAT(ROBOT, _), name)
#define STR_(x) #x
#define STR(x) STR_(x)
#define NUM_PAIRS (API(num_distance_pairs) > 0 ? API(num_distance_pairs) : 1)

enum {
  probe_size = API(nq) + 5 + API(ny) + API(nv) + API(nv) * API(ny) + 3 * API(nv) + API(ny) + API(nv) * API(nv) +
               12 * API(num_bodies) + 12 * API(num_frames) + 6 * API(num_frames) * API(nv) + 3 + 6 * API(nv) +
               API(num_distance_pairs) * (1 + 3 + 6 + API(nv)) + API(nq) + 1 + API(nv)
};

int c_probe_size(void) { return probe_size; }

/* Defines c_probe_<S>(q0, vy, tau, out): closes the loops from q0, then every function. */
#define DEFINE_PROBE(S)                                                                                   \
  int c_probe_##S(const S* q0, const S* vy, const S* tau, S* out) {                                        \
    S q[API(nq)], qdd_y[API(ny)], qdd[API(nv)], T[API(nv) * API(ny)], v[API(nv)], g[API(nv)], vy2[API(ny)]; \
    S tau_out[API(nv)], M[API(nv) * API(nv)], X[12 * API(num_bodies)], XF[12 * API(num_frames)];           \
    S JF[6 * API(num_frames) * API(nv)], com[3], Ag[6 * API(nv)];                                          \
    S d[NUM_PAIRS], n[3 * NUM_PAIRS], w[6 * NUM_PAIRS], Jd[NUM_PAIRS * API(nv)];                           \
    S q2[API(nq)], v2[API(nv)];                                                                           \
    S* at = out;                                                                                          \
    int i;                                                                                                \
    API(closure_result_##S) r, r2;                                                                        \
    memcpy(q, q0, sizeof q);                                                                              \
    r = API(closure_positions_##S)(q, NULL);                                                              \
    API(forward_dynamics_##S)(q, vy, tau, qdd_y);                                                         \
    API(full_accelerations_##S)(q, vy, tau, qdd);                                                         \
    API(velocity_map_##S)(q, T);                                                                          \
    API(full_velocities_##S)(q, vy, v);                                                                   \
    API(acceleration_bias_##S)(q, vy, g);                                                                 \
    API(independent_velocities_##S)(v, vy2);                                                              \
    API(inverse_dynamics_##S)(q, v, qdd, tau_out);                                                        \
    API(mass_matrix_##S)(q, M);                                                                           \
    API(forward_kinematics_##S)(q, X);                                                                    \
    API(frame_poses_##S)(q, XF);                                                                          \
    API(frame_jacobians_##S)(q, JF);                                                                      \
    API(center_of_mass_##S)(q, com);                                                                      \
    API(centroidal_momentum_matrix_##S)(q, Ag);                                                           \
    API(self_distances_##S)(q, d, n, w, Jd);                                                              \
    memcpy(q2, q0, sizeof q2);                                                                            \
    for (i = 0; i < API(nv); ++i) v2[i] = (S)1;                                                           \
    for (i = 0; i < API(ny); ++i) v2[API(independent_v_index)[i]] = vy[i];                                \
    r2 = API(close_loops_##S)(q2, v2, NULL);                                                              \
    memcpy(at, q, sizeof q), at += API(nq);                                                               \
    *at++ = (S)r.status, *at++ = (S)r.iterations, *at++ = r.residual, *at++ = r.pivot_ratio;              \
    *at++ = r.relative_pivot_ratio;                                                                       \
    memcpy(at, qdd_y, sizeof qdd_y), at += API(ny);                                                       \
    memcpy(at, qdd, sizeof qdd), at += API(nv);                                                           \
    memcpy(at, T, sizeof T), at += API(nv) * API(ny);                                                     \
    memcpy(at, v, sizeof v), at += API(nv);                                                               \
    memcpy(at, g, sizeof g), at += API(nv);                                                               \
    memcpy(at, vy2, sizeof vy2), at += API(ny);                                                           \
    memcpy(at, tau_out, sizeof tau_out), at += API(nv);                                                   \
    memcpy(at, M, sizeof M), at += API(nv) * API(nv);                                                     \
    memcpy(at, X, sizeof X), at += 12 * API(num_bodies);                                                  \
    memcpy(at, XF, sizeof XF), at += 12 * API(num_frames);                                                \
    memcpy(at, JF, sizeof JF), at += 6 * API(num_frames) * API(nv);                                       \
    memcpy(at, com, sizeof com), at += 3;                                                                 \
    memcpy(at, Ag, sizeof Ag), at += 6 * API(nv);                                                         \
    memcpy(at, d, API(num_distance_pairs) * sizeof(S)), at += API(num_distance_pairs);                    \
    memcpy(at, n, 3 * API(num_distance_pairs) * sizeof(S)), at += 3 * API(num_distance_pairs);            \
    memcpy(at, w, 6 * API(num_distance_pairs) * sizeof(S)), at += 6 * API(num_distance_pairs);            \
    memcpy(at, Jd, API(num_distance_pairs) * API(nv) * sizeof(S)), at += API(num_distance_pairs) * API(nv); \
    memcpy(at, q2, sizeof q2), at += API(nq);                                                             \
    *at++ = (S)r2.iterations;                                                                             \
    memcpy(at, v2, sizeof v2), at += API(nv);                                                             \
    return (int)(at - out);                                                                               \
  }

DEFINE_PROBE(double)
DEFINE_PROBE(float)

#ifdef MBGEN_C_MAIN
#include <stdio.h>

/* At q = 0 (a unit quaternion for a floating base), zero velocities and forces: the closure
 * converges, every output is finite, and the sizes add up. */
int main(void) {
  static double q[API(nq)], vy[API(ny)], tau[API(nv)], out[probe_size];
  int i, written;
  if (API(floating_base)) q[6] = 1.0;
  written = c_probe_double(q, vy, tau, out);
  if (written != probe_size) return printf("wrote %d of %d values\n", written, probe_size), 1;
  if (out[API(nq)] != (double)API(closure_converged)) return printf("closure status %g\n", out[API(nq)]), 1;
  for (i = 0; i < probe_size; ++i)
    if (!(out[i] == out[i])) return printf("value %d is NaN\n", i), 1;
  printf("%s: %d values from the C API, closure converged in %g iterations\n", STR(ROBOT), probe_size, out[API(nq) + 1]);
  return 0;
}
#endif
