// mbgen_instructions ROBOT CALLS: calls ROBOT's generated forward_dynamics CALLS times on one
// seeded state, for bench/instructions_per_call.sh, which runs it under callgrind twice (CALLS and
// 2 CALLS) so that the difference divided by CALLS is the instruction count of one call alone,
// free of start-up and loading. Instructions, unlike seconds, do not depend on what else the
// machine is doing.
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "hyq.hpp"
#include "iiwa14.hpp"
#include "talos.hpp"

namespace {

template <int nq, int nv>
void run(void (*forward_dynamics)(const double*, const double*, const double*, double*), bool floating, long calls) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> q(nq), v(nv), tau(nv), qdd(nv);
  for (double& x : q) x = uniform(rng);
  for (double& x : v) x = 2.0 * uniform(rng);
  for (double& x : tau) x = 20.0 * uniform(rng);
  if (floating) q[3] = 0.0, q[4] = 0.0, q[5] = 0.0, q[6] = 1.0;
  double checksum = 0.0;
  for (long k = 0; k < calls; ++k) {
    forward_dynamics(q.data(), v.data(), tau.data(), qdd.data());
    checksum += qdd[0];
  }
  std::printf("%.17g\n", checksum);  // uses the outputs, so no call is optimised away
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: mbgen_instructions iiwa14|hyq|talos CALLS\n");
    return 2;
  }
  const std::string robot = argv[1];
  const long calls = std::atol(argv[2]);
  if (robot == "iiwa14") run<iiwa14::nq, iiwa14::nv>(&iiwa14::forward_dynamics, iiwa14::floating_base, calls);
  else if (robot == "hyq") run<hyq::nq, hyq::nv>(&hyq::forward_dynamics, hyq::floating_base, calls);
  else if (robot == "talos") run<talos::nq, talos::nv>(&talos::forward_dynamics, talos::floating_base, calls);
  else {
    std::fprintf(stderr, "mbgen_instructions: unknown robot '%s' (iiwa14, hyq or talos)\n", robot.c_str());
    return 2;
  }
  return 0;
}
