#pragma once
// The simulator's state x = (q, v) as flat arrays, for any backend: a floating base, when there
// is one, is q[0..7) = [p_WB, quaternion (x y z w)] and v[0..6) = [v_B, w_B] (the generated
// headers' convention); every other coordinate is a 1-DoF joint whose position rate is its
// velocity. Integrators work in these ambient coordinates and renormalise the quaternion.
#include <cmath>

#include "mbgen/spatial/types.hpp"

namespace mbgen::sim {

/// dq/dt for velocity v: R_WB v_B and 1/2 quat * (w_B, 0) for the base, v for the rest.
template <typename S> void configuration_rate(bool floating_base, int nq, const S* q, const S* v, S* qdot) {
  int j = 0, k = 0;
  if (floating_base) {
    const S x = q[3], y = q[4], z = q[5], w = q[6];
    const S vx = v[0], vy = v[1], vz = v[2], wx = v[3], wy = v[4], wz = v[5];
    // R(quat) v_B, written out (the quaternion may be slightly off unit inside a step: the same
    // formula as the generated code's rotation keeps the two consistent).
    qdot[0] = (S(1) - S(2) * (y * y + z * z)) * vx + S(2) * (x * y - z * w) * vy + S(2) * (x * z + y * w) * vz;
    qdot[1] = S(2) * (x * y + z * w) * vx + (S(1) - S(2) * (x * x + z * z)) * vy + S(2) * (y * z - x * w) * vz;
    qdot[2] = S(2) * (x * z - y * w) * vx + S(2) * (y * z + x * w) * vy + (S(1) - S(2) * (x * x + y * y)) * vz;
    qdot[3] = S(0.5) * (w * wx + y * wz - z * wy);
    qdot[4] = S(0.5) * (w * wy + z * wx - x * wz);
    qdot[5] = S(0.5) * (w * wz + x * wy - y * wx);
    qdot[6] = S(-0.5) * (x * wx + y * wy + z * wz);
    j = 7, k = 6;
  }
  for (; j < nq; ++j, ++k) qdot[j] = v[k];
}

/// Makes the base quaternion unit again (a no-op without a floating base).
template <typename S> void normalize_quaternion(bool floating_base, S* q) {
  using std::sqrt;
  if (!floating_base) return;
  const S norm = sqrt(q[3] * q[3] + q[4] * q[4] + q[5] * q[5] + q[6] * q[6]);
  for (int i = 3; i < 7; ++i) q[i] /= norm;
}

}  // namespace mbgen::sim
