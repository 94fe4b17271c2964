/* The C flavour's batch functions from C: tiny_arm's forward kinematics over 2 states per call
   equals the one-state function on each state, bit for bit, in double and in float. */
#include <stdio.h>
#include <string.h>

#include "tiny_arm_batch.h"

#define W tiny_arm_batch_batch_width
#define NQ tiny_arm_batch_nq
#define NX (tiny_arm_batch_num_bodies * 12)

/* One checker per scalar (C has no templates): S the scalar, the entry points' suffix. */
#define DEFINE_CHECK(S)                                                                   \
  static int check_##S(void) {                                                            \
    S q[NQ][W], X[NX][W], one[NX];                                                        \
    int differing = 0;                                                                    \
    for (int trial = 0; trial < 100; ++trial) {                                           \
      for (int i = 0; i < NQ; ++i)                                                        \
        for (int w = 0; w < W; ++w) q[i][w] = (S)(0.37 * trial - 0.91 * i + 1.3 * w);     \
      tiny_arm_batch_forward_kinematics_batch_##S((const S(*)[W])q, X);                   \
      for (int w = 0; w < W; ++w) {                                                       \
        S qw[NQ];                                                                         \
        for (int i = 0; i < NQ; ++i) qw[i] = q[i][w];                                     \
        tiny_arm_batch_forward_kinematics_##S(qw, one);                                   \
        for (int i = 0; i < NX; ++i) differing += memcmp(&one[i], &X[i][w], sizeof(S)) != 0; \
      }                                                                                   \
    }                                                                                     \
    return differing;                                                                     \
  }
DEFINE_CHECK(double)
DEFINE_CHECK(float)

int main(void) {
  const int d = check_double(), f = check_float();
  printf("tiny_arm batch against one state: %d double and %d float entries differ\n", d, f);
  return d == 0 && f == 0 ? 0 : 1;
}
