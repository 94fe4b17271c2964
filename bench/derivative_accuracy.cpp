// mbgen_derivative_accuracy: the accuracy of the forward dynamics' derivatives against their cost
// (docs/derivatives.md): for hyq and talos_reduced, dqdd/dq and dqdd/dv by central and forward
// differences of the generated forward_dynamics at steps h = 1e-12 .. 1e-1 (q moved along
// integrate), and by the generated forward_dynamics_derivatives, each against the exact
// derivative (dual numbers through the generic aba, tests/autodiff_reference.hpp), and the time
// of one evaluation of each; for Lola (closed loops) the same in its independent coordinates:
// dydd/dy and dydd/dyd, y moved by integrate and the loops closed again by the generated
// closure_positions on each side, the exact derivative by dual numbers through the generic
// forward_dynamics_loops_independent along the closed set. Prints CSV for
// scripts/plot_derivative_accuracy.gp:
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
#include "lola.hpp"
#include "lola_derivatives.hpp"
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

/// dqdd/dq and dqdd/dv by differences of `fd` at step h: central, or forward. With loops
/// (`close` given) the columns are the independent coordinates' (s.v the independent velocities):
/// each moved configuration is closed again before the call.
void differences(const Model& model, ForwardDynamics fd, const Exact& s, double h, bool central, MatX<double>& dq,
                 MatX<double>& dv, void (*close)(double*) = nullptr) {
  const int n = static_cast<int>(s.v.size()), nv = model.nv();
  VecX<double> q(model.nq()), v(n), plus(n), minus(n), e = VecX<double>::Zero(nv), base(n);
  const auto column = [&](int k) { return close ? model.structure().independent_v[static_cast<std::size_t>(k)] : k; };
  fd(s.q.data(), s.v.data(), s.tau.data(), base.data());
  for (int k = 0; k < n; ++k) {
    e[column(k)] = h;
    integrate<double>(model, s.q, e, q);
    if (close) close(q.data());
    fd(q.data(), s.v.data(), s.tau.data(), plus.data());
    if (central) {
      e[column(k)] = -h;
      integrate<double>(model, s.q, e, q);
      if (close) close(q.data());
      fd(q.data(), s.v.data(), s.tau.data(), minus.data());
      dq.col(k) = (plus - minus) / (2 * h);
    } else {
      dq.col(k) = (plus - base) / h;
    }
    e[column(k)] = 0;
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

/// The rows of one robot: both differences at every step, then the analytic derivatives (the
/// generated function, row-major, its third matrix of nv or ny rows and `tau_columns` columns).
void print_rows(const std::string& name, const Model& model, const std::vector<Exact>& states, ForwardDynamics fd,
                ForwardDerivatives derivatives, int tau_columns, void (*close)(double*) = nullptr) {
  const int n = static_cast<int>(states.front().v.size());
  MatX<double> dq(n, n), dv(n, n);
  VecX<double> qdd(n);
  for (bool central : {true, false}) {
    const char* method = central ? "central" : "forward";
    const double ns =
        nanoseconds(states.size(), [&](std::size_t k) { differences(model, fd, states[k], 1e-6, central, dq, dv, close); });
    for (int e = -12; e <= -1; ++e) {
      for (double m : {1.0, 3.0}) {
        const double h = m * std::pow(10.0, e);
        if (h > 0.1) continue;
        double error = 0;
        for (const Exact& s : states) {
          differences(model, fd, s, h, central, dq, dv, close);
          error = std::max({error, relative(dq, s.dq), relative(dv, s.dv)});
        }
        std::printf("%s,%s,%.3g,%.6g,%.1f\n", name.c_str(), method, h, error, ns);
      }
    }
  }
  // The generated derivatives are row-major: read them back transposed into the column-major matrices.
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  RowMajor A(n, n), B(n, n), C(n, tau_columns);
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

void study(const std::string& name, const char* urdf, ForwardDynamics fd, ForwardDerivatives derivatives) {
  const Robot robot = load_robot(name, urdf, gen::BaseType::Floating);
  const Model& model = robot.model;
  std::vector<Exact> states;
  for (std::size_t k = 0; k < 8; ++k) {
    const Sample& s = (*robot.pool)[k];
    const test::DualJacobians J = test::dual_jacobians(model, s.q, s.v, s.a, s.tau);
    states.push_back({s.q, s.v, s.tau, J.dddq_dq, J.dddq_dv});
  }
  print_rows(name, model, states, fd, derivatives, model.nv());
}

/// Lola in its independent coordinates: the exact dydd/dy (q along the closed set, T e_c) and
/// dydd/dyd by dual numbers through the generic forward_dynamics_loops_independent.
void study_lola() {
  gen::LoadOptions options;
  options.extras_file = MBGEN_SOURCE_DIR "/robots/lola/lola.yaml";
  const gen::Description d = gen::load_description(MBGEN_SOURCE_DIR "/robots/lola/lola.urdf", options);
  const Model& model = d.model;
  const int ny = model.structure().num_independent();
  const auto pool = consistent_pool(model, d.assembly.q);
  Data<double> data(model);
  Data<test::Dual> dual(model);
  MatX<double> T(model.nv(), ny);
  std::vector<Exact> states;
  for (std::size_t k = 0; k < 8; ++k) {
    const Sample& s = (*pool)[k];
    VecX<double> vy(ny);
    for (int i = 0; i < ny; ++i) vy[i] = s.v[model.structure().independent_v[static_cast<std::size_t>(i)]];
    velocity_map<double>(model, data, s.q, T);
    MatX<double> dq(ny, ny), dv(ny, ny);
    const auto independent = [&](const VecX<test::Dual>& full) {
      VecX<double> out(ny);
      for (int i = 0; i < ny; ++i) out[i] = full[model.structure().independent_v[static_cast<std::size_t>(i)]].derivatives()[0];
      return out;
    };
    for (int c = 0; c < ny; ++c) {
      forward_dynamics_loops_independent<test::Dual>(model, dual, test::seeded_configuration_along(model, s.q, T.col(c)),
                                                      test::seeded_vector(vy), test::seeded_vector(s.tau));
      dq.col(c) = independent(dual.ddq);
      forward_dynamics_loops_independent<test::Dual>(model, dual, test::seeded_vector(s.q), test::seeded_vector(vy, c),
                                                      test::seeded_vector(s.tau));
      dv.col(c) = independent(dual.ddq);
    }
    states.push_back({s.q, vy, s.tau, dq, dv});
  }
  print_rows("lola", model, states, &lola::forward_dynamics, &lola_derivatives::forward_dynamics_derivatives, model.nv(),
             [](double* q) { lola::closure_positions(q); });
}

}  // namespace
}  // namespace mbgen::bench

int main() {
  using namespace mbgen::bench;
  std::printf("robot,method,h,error,ns\n");
  study("hyq", "hyq/hyq_no_sensors.urdf", &hyq::forward_dynamics, &hyq_derivatives::forward_dynamics_derivatives);
  study("talos", "talos/talos_reduced.urdf", &talos::forward_dynamics, &talos_derivatives::forward_dynamics_derivatives);
  study_lola();
  return 0;
}
