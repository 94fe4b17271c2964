#pragma once
// The stability map of the study (docs/study.md): for each integrator and contact stiffness, the
// largest step on a geometric ladder with which the drop runs to its end with status ok (no
// divergence, energy bounded, loops closed, penetration bounded), found by bisection on the
// ladder under the assumption that stability is monotonic in the step (each run says which
// status ended it, so a non-monotonic case shows in the report's failures).
#include <cmath>
#include <functional>
#include <vector>

#include "mbgen/sim/simulator.hpp"

namespace mbgen::study {

/// The ladder: 10^(k/4) s, four steps per decade, from `smallest` to `largest`.
inline std::vector<double> step_ladder(double smallest, double largest) {
  std::vector<double> ladder;
  for (int k = static_cast<int>(std::lround(4 * std::log10(smallest))); k <= std::lround(4 * std::log10(largest)); ++k)
    ladder.push_back(std::pow(10.0, k / 4.0));
  return ladder;
}

struct StabilityResult {
  double stable = 0;    ///< s: the largest step of the ladder that ran to the end (0: none did)
  double unstable = 0;  ///< s: the smallest that failed (0: none did, the ladder's top was stable)
  sim::StepStatus failure = sim::StepStatus::ok;  ///< how the run at `unstable` ended
  double failure_time = 0;                        ///< s: when
  int runs = 0;
};

/// `ok(h, status, time)` runs the scenario with step h and returns whether it reached its end,
/// writing the status and the time it stopped.
inline StabilityResult largest_stable_step(const std::vector<double>& ladder,
                                           const std::function<bool(double, sim::StepStatus&, double&)>& ok) {
  StabilityResult r;
  sim::StepStatus status = sim::StepStatus::ok;
  double time = 0;
  int lo = -1, hi = static_cast<int>(ladder.size());  // lo: known stable (-1: none yet), hi: known unstable
  const auto record_failure = [&](int i) {
    hi = i;
    r.unstable = ladder[static_cast<std::size_t>(i)], r.failure = status, r.failure_time = time;
  };
  ++r.runs;
  if (!ok(ladder.back(), status, time)) record_failure(hi - 1);
  else lo = hi - 1;
  if (lo < 0) {
    ++r.runs;
    if (ok(ladder.front(), status, time)) lo = 0;
    else record_failure(0);
  }
  while (lo >= 0 && hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    ++r.runs;
    if (ok(ladder[static_cast<std::size_t>(mid)], status, time)) lo = mid;
    else record_failure(mid);
  }
  r.stable = lo >= 0 ? ladder[static_cast<std::size_t>(lo)] : 0;
  return r;
}

}  // namespace mbgen::study
