// The peer benchmarks, `peer_<function>/<robot>/<implementation>` (README.md here): Pinocchio
// 3.7's algorithm and mbgen's generated function on the same states, in one process.
//
//   peer_aba/<robot>/{pinocchio,generated}              aba / forward_dynamics
//   peer_rnea/<robot>/{pinocchio,generated}             rnea / inverse_dynamics
//   peer_crba/<robot>/{pinocchio,generated}             crba / mass_matrix
//   peer_aba_derivatives/<robot>/{pinocchio,generated}  computeABADerivatives / forward_dynamics_derivatives
//   peer_rnea_derivatives/<robot>/{pinocchio,generated} computeRNEADerivatives / inverse_dynamics_derivatives
//   peer_constraint_dynamics/<robot>/pinocchio          constraintDynamics, ProximalSettings(1e-12, 1e-8, 100)
//                                  /pinocchio_default  constraintDynamics, Pinocchio's default settings
//                                  /generated          full_accelerations (every joint's, the loops held)
//   peer_closed_step/<robot>/pinocchio                 constraintDynamics (tight) again, beside
//                          /generated                 the predictor q + h v (h = 1 ms, every coordinate: how a
//                                                      simulator's step moves q), closure_positions from there,
//                                                      then full_accelerations: what a closed-loop simulator's step
//                                                      needs (Pinocchio's step projects nothing)
//                          /generated_no_predictor    the same from q with only the independent coordinates moved
//                                                      (h vy), the dependent ones held
#include "bench_peers.hpp"

#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "peer_pairs.hpp"

namespace mbgen::bench {
namespace {

using peers::LoopPair;
using peers::LoopState;
using peers::TreePair;
using peers::TreeState;

void require(double error, double tolerance, const std::string& what) {
  if (!(error <= tolerance))
    throw std::runtime_error("peer: " + what + " differs from Pinocchio's by " + std::to_string(error) + " (relative; tolerance " +
                             std::to_string(tolerance) + "): the comparison would time different things");
}

void add_tree(const std::shared_ptr<TreePair>& pair) {
  const peers::TreeAgreement a = peers::check(*pair);
  const std::string& robot = pair->generated.robot;
  require(std::max({a.forward_dynamics, a.inverse_dynamics, a.mass_matrix}), peers::kTreeTolerance, robot + "'s dynamics");
  require(std::max(a.fd_derivatives, a.id_derivatives), peers::kDerivativeTolerance, robot + "'s derivatives");
  const int n = pair->generated.nv;
  const auto states = pair->states;
  peers::PinocchioRobot* pin = pair->pinocchio.get();
  const peers::GeneratedTree* g = &pair->generated;
  struct Out {
    explicit Out(int n) : x(static_cast<std::size_t>(n)), a(static_cast<std::size_t>(n * n)), b(a), c(a) {}
    std::vector<double> x, a, b, c;
  };
  auto out = std::make_shared<Out>(n);
  add_benchmark<TreeState>("peer_aba", robot, "pinocchio", states, [pin, pair](const TreeState& s) {
    return pin->aba(s.pinocchio_q, s.pinocchio_v, s.pinocchio_tau).data();
  });
  add_benchmark<TreeState>("peer_aba", robot, "generated", states, [g, out](const TreeState& s) {
    g->forward_dynamics(s.q.data(), s.v.data(), s.tau.data(), out->x.data());
    return out->x.data();
  });
  add_benchmark<TreeState>("peer_rnea", robot, "pinocchio", states, [pin, pair](const TreeState& s) {
    return pin->rnea(s.pinocchio_q, s.pinocchio_v, s.pinocchio_a).data();
  });
  add_benchmark<TreeState>("peer_rnea", robot, "generated", states, [g, out](const TreeState& s) {
    g->inverse_dynamics(s.q.data(), s.v.data(), s.a.data(), out->x.data());
    return out->x.data();
  });
  // Pinocchio's crba fills M's upper triangle; PinocchioRobot::crba also copies it into a full
  // matrix, which is not timed: the timed call is the bare algorithm (crba_upper below).
  add_benchmark<TreeState>("peer_crba", robot, "pinocchio", states, [pin, pair](const TreeState& s) {
    return pin->crba_upper(s.pinocchio_q).data();
  });
  add_benchmark<TreeState>("peer_crba", robot, "generated", states, [g, out](const TreeState& s) {
    g->mass_matrix(s.q.data(), out->a.data());
    return out->a.data();
  });
  add_benchmark<TreeState>("peer_aba_derivatives", robot, "pinocchio", states, [pin, pair](const TreeState& s) {
    pin->aba_derivatives(s.pinocchio_q, s.pinocchio_v, s.pinocchio_tau);
    return pin->ddq_dq().data();
  });
  add_benchmark<TreeState>("peer_aba_derivatives", robot, "generated", states, [g, out](const TreeState& s) {
    g->forward_dynamics_derivatives(s.q.data(), s.v.data(), s.tau.data(), out->x.data(), out->a.data(), out->b.data(), out->c.data());
    return out->a.data();
  });
  add_benchmark<TreeState>("peer_rnea_derivatives", robot, "pinocchio", states, [pin, pair](const TreeState& s) {
    pin->rnea_derivatives(s.pinocchio_q, s.pinocchio_v, s.pinocchio_a);
    return pin->dtau_dq().data();
  });
  add_benchmark<TreeState>("peer_rnea_derivatives", robot, "generated", states, [g, out](const TreeState& s) {
    g->inverse_dynamics_derivatives(s.q.data(), s.v.data(), s.a.data(), out->x.data(), out->a.data(), out->b.data());
    return out->a.data();
  });
}

void add_loops(const std::shared_ptr<LoopPair>& pair) {
  const peers::LoopAgreement a = peers::check(*pair);
  const std::string& robot = pair->generated.robot;
  require(a.full_accelerations, peers::kLoopTolerance, robot + "'s full_accelerations");
  require(a.forward_dynamics, peers::kTreeTolerance, robot + "'s forward_dynamics against its full_accelerations");
  if (a.warm_closures_converged != static_cast<int>(pair->states->size()) ||
      a.predicted_closures_converged != static_cast<int>(pair->states->size()))
    throw std::runtime_error("peer: " + robot + ": closure_positions failed from a warm or a predicted start");
  const auto states = pair->states;
  peers::PinocchioRobot* pin = pair->pinocchio.get();
  const peers::GeneratedLoops* g = &pair->generated;
  struct Work {
    Eigen::VectorXd q, qdd;
  };
  auto work = std::make_shared<Work>(Work{Eigen::VectorXd(g->nq), Eigen::VectorXd(g->nv)});
  for (const bool tight : {true, false})
    add_benchmark<LoopState>("peer_constraint_dynamics", robot, tight ? "pinocchio" : "pinocchio_default", states,
                             [pin, pair, tight](const LoopState& s) {
                               return pin->constraint_dynamics(s.pinocchio_q, s.pinocchio_v, s.pinocchio_tau, tight).data();
                             });
  add_benchmark<LoopState>("peer_closed_step", robot, "pinocchio", states, [pin, pair](const LoopState& s) {
    return pin->constraint_dynamics(s.pinocchio_q, s.pinocchio_v, s.pinocchio_tau, true).data();
  });
  add_benchmark<LoopState>("peer_constraint_dynamics", robot, "generated", states, [g, work](const LoopState& s) {
    g->full_accelerations(s.q.data(), s.vy.data(), s.tau.data(), work->qdd.data());
    return work->qdd.data();
  });
  // The step from two starts: the simulator's predictor q + h v (every coordinate, timed with the
  // step), and q with only the independent coordinates moved (the shared tool's). Newton works in place.
  for (const bool predictor : {true, false})
    add_benchmark<LoopState>("peer_closed_step", robot, predictor ? "generated" : "generated_no_predictor", states,
                             [g, work, predictor](const LoopState& s) {
                               if (predictor)
                                 peers::predicted_start(s, work->q);
                               else
                                 work->q = s.warm_q;
                               int iterations;
                               g->closure_positions(work->q.data(), &iterations);
                               g->full_accelerations(work->q.data(), s.vy.data(), s.tau.data(), work->qdd.data());
                               return work->qdd.data();
                             });
}

}  // namespace

void add_peer_benchmarks() {
  for (TreePair& pair : peers::tree_pairs()) add_tree(std::make_shared<TreePair>(std::move(pair)));
  for (LoopPair& pair : peers::loop_pairs()) add_loops(std::make_shared<LoopPair>(std::move(pair)));
}

}  // namespace mbgen::bench
