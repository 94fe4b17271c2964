// mbgen_instructions ROBOT FUNCTION CALLS: calls ROBOT's (iiwa14, hyq, hyq_snapped or talos)
// generated FUNCTION (forward_dynamics, inverse_dynamics or mass_matrix) CALLS times on one seeded
// state, for
// bench/instructions_per_call.sh, which runs it under callgrind twice (CALLS and 2 CALLS) so that
// the difference divided by CALLS is the instruction count of one call alone, free of start-up and
// loading. Instructions, unlike seconds, do not depend on what else the machine is doing.
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "hyq.hpp"
#include "hyq_snapped.hpp"
#include "iiwa14.hpp"
#include "talos.hpp"

namespace {

using Dynamics = void (*)(const double*, const double*, const double*, double*);
using MassMatrix = void (*)(const double*, double*);

struct Functions {
  int nq, nv;
  bool floating;
  Dynamics forward_dynamics, inverse_dynamics;
  MassMatrix mass_matrix;
};

int run(const Functions& f, const std::string& function, long calls) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> q(static_cast<std::size_t>(f.nq)), v(static_cast<std::size_t>(f.nv)),
      tau(static_cast<std::size_t>(f.nv)), out(static_cast<std::size_t>(f.nv * f.nv));
  for (double& x : q) x = uniform(rng);
  for (double& x : v) x = 2.0 * uniform(rng);
  for (double& x : tau) x = 20.0 * uniform(rng);
  if (f.floating) q[3] = 0.0, q[4] = 0.0, q[5] = 0.0, q[6] = 1.0;
  double checksum = 0.0;
  if (function == "forward_dynamics" || function == "inverse_dynamics") {
    const Dynamics call = function == "forward_dynamics" ? f.forward_dynamics : f.inverse_dynamics;
    for (long k = 0; k < calls; ++k) {
      call(q.data(), v.data(), tau.data(), out.data());
      checksum += out[0];
    }
  } else if (function == "mass_matrix") {
    for (long k = 0; k < calls; ++k) {
      f.mass_matrix(q.data(), out.data());
      checksum += out[static_cast<std::size_t>(f.nv) + 1];
    }
  } else {
    std::fprintf(stderr, "mbgen_instructions: unknown function '%s' (forward_dynamics, inverse_dynamics or mass_matrix)\n",
                 function.c_str());
    return 2;
  }
  std::printf("%.17g\n", checksum);  // uses the outputs, so no call is optimised away
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: mbgen_instructions iiwa14|hyq|hyq_snapped|talos forward_dynamics|inverse_dynamics|mass_matrix CALLS\n");
    return 2;
  }
  const std::string robot = argv[1], function = argv[2];
  const long calls = std::atol(argv[3]);
  if (robot == "iiwa14") return run({iiwa14::nq, iiwa14::nv, iiwa14::floating_base, &iiwa14::forward_dynamics, &iiwa14::inverse_dynamics, &iiwa14::mass_matrix},
                                      function, calls);
  if (robot == "hyq") return run({hyq::nq, hyq::nv, hyq::floating_base, &hyq::forward_dynamics, &hyq::inverse_dynamics, &hyq::mass_matrix},
                                      function, calls);
  if (robot == "hyq_snapped")
    return run({hyq_snapped::nq, hyq_snapped::nv, hyq_snapped::floating_base, &hyq_snapped::forward_dynamics, &hyq_snapped::inverse_dynamics,
                &hyq_snapped::mass_matrix},
               function, calls);
  if (robot == "talos") return run({talos::nq, talos::nv, talos::floating_base, &talos::forward_dynamics, &talos::inverse_dynamics, &talos::mass_matrix},
                                      function, calls);
  std::fprintf(stderr, "mbgen_instructions: unknown robot '%s' (iiwa14, hyq, hyq_snapped or talos)\n", robot.c_str());
  return 2;
}
