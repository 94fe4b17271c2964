// mbgen_derivative_accuracy: the accuracy of the forward dynamics' derivatives against their cost
// (docs/derivatives.md): for hyq and talos_reduced, dqdd/dq and dqdd/dv by central and forward
// differences of the generated forward_dynamics at steps h = 1e-12 .. 1e-1 (q moved along
// integrate), and by the generated forward_dynamics_derivatives, each against the exact
// derivative (dual numbers through the generic aba, tests/autodiff_reference.hpp), and the time
// of one evaluation of each. Prints CSV for scripts/plot_derivative_accuracy.gp:
//   robot,method,h,error,ns
// error: the largest over 8 states of max|D - D_exact| / max|D_exact| over both matrices;
// ns: the median over 15 repetitions of the mean time of a call (all states in turn).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "autodiff_reference.hpp"
#include "bench_support.hpp"
#include "hyq.hpp"
#include "hyq_derivatives.hpp"
#include "talos.hpp"
#include "talos_derivatives.hpp"

namespace mbgen::bench {
namespace {

using ForwardDynamics = void (*)(const double*, const double*, const double*, double*);
using ForwardDerivatives = void (*)(const double*, const double*, const double*, double*, double*, double*, double*);

struct Exact {
  VecX<double> q, v, tau;
  MatX<double> dq, dv;
};

double relative(const MatX<double>& got, const MatX<double>& want) {
  return (got - want).cwiseAbs().maxCoeff() / want.cwiseAbs().maxCoeff();
}

/// dqdd/dq and dqdd/dv by differences of `fd` at step h: central, or forward.
void differences(const Model& model, ForwardDynamics fd, const Exact& s, double h, bool central, MatX<double>& dq,
                 MatX<double>& dv) {
  const int n = model.nv();
  VecX<double> q(model.nq()), v(n), plus(n), minus(n), e = VecX<double>::Zero(n), base(n);
  fd(s.q.data(), s.v.data(), s.tau.data(), base.data());
  for (int k = 0; k < n; ++k) {
    e[k] = h;
    integrate<double>(model, s.q, e, q);
    fd(q.data(), s.v.data(), s.tau.data(), plus.data());
    if (central) {
      e[k] = -h;
      integrate<double>(model, s.q, e, q);
      fd(q.data(), s.v.data(), s.tau.data(), minus.data());
      dq.col(k) = (plus - minus) / (2 * h);
    } else {
      dq.col(k) = (plus - base) / h;
    }
    e[k] = 0;
    v = s.v;
    v[k] += h;
    fd(s.q.data(), v.data(), s.tau.data(), plus.data());
    if (central) {
      v[k] -= 2 * h;
      fd(s.q.data(), v.data(), s.tau.data(), minus.data());
      dv.col(k) = (plus - minus) / (2 * h);
    } else {
      dv.col(k) = (plus - base) / h;
    }
  }
}

/// Median over repetitions of the mean time of one call of `run(state)` over the states.
double nanoseconds(std::size_t states, const std::function<void(std::size_t)>& run) {
  std::vector<double> t;
  for (int rep = 0; rep < 15; ++rep) {
    int calls = 0;
    const auto start = std::chrono::steady_clock::now();
    do {
      for (std::size_t k = 0; k < states; ++k) run(k);
      calls += static_cast<int>(states);
    } while (std::chrono::steady_clock::now() - start < std::chrono::milliseconds(20));
    t.push_back(std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count() / calls);
  }
  std::nth_element(t.begin(), t.begin() + 7, t.end());
  return t[7];
}

void study(const std::string& name, const char* urdf, ForwardDynamics fd, ForwardDerivatives derivatives) {
  const Robot robot = load_robot(name, urdf, gen::BaseType::Floating);
  const Model& model = robot.model;
  const int n = model.nv();
  std::vector<Exact> states;
  for (std::size_t k = 0; k < 8; ++k) {
    const Sample& s = (*robot.pool)[k];
    const test::DualJacobians J = test::dual_jacobians(model, s.q, s.v, s.a, s.tau);
    states.push_back({s.q, s.v, s.tau, J.dddq_dq, J.dddq_dv});
  }
  MatX<double> dq(n, n), dv(n, n), minv(n, n);
  VecX<double> qdd(n);
  for (bool central : {true, false}) {
    const char* method = central ? "central" : "forward";
    const double ns = nanoseconds(states.size(), [&](std::size_t k) { differences(model, fd, states[k], 1e-6, central, dq, dv); });
    for (int e = -12; e <= -1; ++e) {
      for (double m : {1.0, 3.0}) {
        const double h = m * std::pow(10.0, e);
        if (h > 0.1) continue;
        double error = 0;
        for (const Exact& s : states) {
          differences(model, fd, s, h, central, dq, dv);
          error = std::max({error, relative(dq, s.dq), relative(dv, s.dv)});
        }
        std::printf("%s,%s,%.3g,%.6g,%.1f\n", name.c_str(), method, h, error, ns);
      }
    }
  }
  // The generated derivatives are row-major: read them back transposed into the column-major matrices.
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  RowMajor A(n, n), B(n, n), C(n, n);
  double error = 0;
  for (const Exact& s : states) {
    derivatives(s.q.data(), s.v.data(), s.tau.data(), qdd.data(), A.data(), B.data(), C.data());
    error = std::max({error, relative(MatX<double>(A), s.dq), relative(MatX<double>(B), s.dv)});
  }
  const double ns = nanoseconds(states.size(), [&](std::size_t k) {
    derivatives(states[k].q.data(), states[k].v.data(), states[k].tau.data(), qdd.data(), A.data(), B.data(), C.data());
  });
  std::printf("%s,analytic,0,%.6g,%.1f\n", name.c_str(), error, ns);
}

}  // namespace
}  // namespace mbgen::bench

int main() {
  using namespace mbgen::bench;
  std::printf("robot,method,h,error,ns\n");
  study("hyq", "hyq/hyq_no_sensors.urdf", &hyq::forward_dynamics, &hyq_derivatives::forward_dynamics_derivatives);
  study("talos", "talos/talos_reduced.urdf", &talos::forward_dynamics, &talos_derivatives::forward_dynamics_derivatives);
  return 0;
}
