#pragma once
// The integrators the simulator offers, and the Butcher tableaux of its explicit Runge-Kutta
// methods (docs/simulation.md compares them).
#include <cstring>

namespace mbgen::sim {

enum class Integrator {
  explicit_euler,           ///< first order; energy grows (the baseline that fails first)
  symplectic_euler,         ///< first order, v then q with the new v; energy error stays bounded
  rk4,                      ///< classical Runge-Kutta, fourth order, fixed step
  dormand_prince45,         ///< adaptive embedded 5(4) pair: rtol, atol, accepted / rejected steps
  linearly_implicit_euler,  ///< first order, the contact forces implicit: for stiff contact
};

inline const char* to_string(Integrator i) {
  switch (i) {
    case Integrator::explicit_euler: return "explicit_euler";
    case Integrator::symplectic_euler: return "symplectic_euler";
    case Integrator::rk4: return "rk4";
    case Integrator::dormand_prince45: return "dormand_prince45";
    case Integrator::linearly_implicit_euler: return "linearly_implicit_euler";
  }
  return "unknown";
}

/// The integrator named `name` (to_string's spelling); false if there is none.
inline bool parse_integrator(const char* name, Integrator& out) {
  for (Integrator i : {Integrator::explicit_euler, Integrator::symplectic_euler, Integrator::rk4, Integrator::dormand_prince45,
                       Integrator::linearly_implicit_euler})
    if (std::strcmp(name, to_string(i)) == 0) return out = i, true;
  return false;
}

/// Order of accuracy of each integrator (of the solution it advances).
inline int order_of(Integrator i) {
  switch (i) {
    case Integrator::rk4: return 4;
    case Integrator::dormand_prince45: return 5;
    default: return 1;
  }
}

/// An explicit Runge-Kutta method: stage s evaluates f at x + h sum_j a[s][j] k_j.
struct ButcherTableau {
  int stages = 0;
  double a[7][7] = {};
  double b[7] = {};
  double b_embedded[7] = {};  ///< the embedded lower-order weights (error estimate), if any

  static const ButcherTableau& rk4() {
    static const ButcherTableau t = [] {
      ButcherTableau r;
      r.stages = 4;
      r.a[1][0] = 0.5;
      r.a[2][1] = 0.5;
      r.a[3][2] = 1;
      r.b[0] = r.b[3] = 1.0 / 6;
      r.b[1] = r.b[2] = 1.0 / 3;
      return r;
    }();
    return t;
  }

  /// Dormand and Prince (1980), the 5(4) pair of ode45 and DOPRI5.
  static const ButcherTableau& dormand_prince45() {
    static const ButcherTableau t = [] {
      ButcherTableau r;
      r.stages = 7;
      const double a[7][7] = {{0},
                              {1.0 / 5},
                              {3.0 / 40, 9.0 / 40},
                              {44.0 / 45, -56.0 / 15, 32.0 / 9},
                              {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729},
                              {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656},
                              {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84}};
      const double b[7] = {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84, 0};
      const double e[7] = {5179.0 / 57600, 0, 7571.0 / 16695, 393.0 / 640, -92097.0 / 339200, 187.0 / 2100, 1.0 / 40};
      for (int i = 0; i < 7; ++i) {
        for (int j = 0; j < 7; ++j) r.a[i][j] = a[i][j];
        r.b[i] = b[i];
        r.b_embedded[i] = e[i];
      }
      return r;
    }();
    return t;
  }
};

}  // namespace mbgen::sim
