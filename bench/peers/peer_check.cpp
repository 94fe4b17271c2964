// mbgen_peer_check: does mbgen's generated code compute what Pinocchio 3.7 computes, on the peer
// benchmark's robots and states? Prints one line per robot and exits 1 when a quantity differs
// by more than its tolerance (peer_pairs.hpp); ctest runs it as peer.pinocchio_agreement.
#include <algorithm>
#include <cstdio>
#include <exception>

#include "peer_pairs.hpp"

int main() {
  using namespace mbgen::peers;
  bool ok = true;
  const auto verdict = [&ok](double error, double tolerance) {
    ok = ok && error <= tolerance;
    return error <= tolerance ? "" : " FAIL";
  };
  try {
    for (TreePair& pair : tree_pairs()) {
      const TreeAgreement a = check(pair);
      const double dynamics = std::max({a.forward_dynamics, a.inverse_dynamics, a.mass_matrix});
      std::printf("%-18s nv %2d  aba %.1e  rnea %.1e  crba %.1e%s  aba derivatives %.1e  rnea derivatives %.1e%s\n",
                  pair.generated.robot.c_str(), pair.generated.nv, a.forward_dynamics, a.inverse_dynamics, a.mass_matrix,
                  verdict(dynamics, kTreeTolerance), a.fd_derivatives, a.id_derivatives,
                  verdict(std::max(a.fd_derivatives, a.id_derivatives), kDerivativeTolerance));
    }
    for (LoopPair& pair : loop_pairs()) {
      const LoopAgreement a = check(pair);
      const int states = static_cast<int>(pair.states->size());
      std::printf("%-18s nv %2d  full_accelerations vs constraintDynamics %.1e%s  forward_dynamics %.1e%s  "
                  "Pinocchio's closure error %.1e  closures from warm starts %d/%d%s (%.2f steps), from predicted ones %d/%d%s (%.2f steps)\n",
                  pair.generated.robot.c_str(), pair.generated.nv, a.full_accelerations, verdict(a.full_accelerations, kLoopTolerance),
                  a.forward_dynamics, verdict(a.forward_dynamics, kTreeTolerance), a.pinocchio_closure, a.warm_closures_converged,
                  states, verdict(states - a.warm_closures_converged, 0), static_cast<double>(a.warm_iterations) / states,
                  a.predicted_closures_converged, states, verdict(states - a.predicted_closures_converged, 0),
                  static_cast<double>(a.predicted_iterations) / states);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mbgen_peer_check: %s\n", e.what());
    return 1;
  }
  std::printf("%s (tolerances, relative: dynamics %.0e, derivatives %.0e, loops %.0e)\n", ok ? "agree" : "DISAGREE", kTreeTolerance,
              kDerivativeTolerance, kLoopTolerance);
  return ok ? 0 : 1;
}
