#pragma once
// Helpers for mbgen_bench: seeded input pools and a registration helper that names benchmarks
// `<algorithm>/<robot>/<implementation>` and times any callable on the same inputs.
//
// Adding an implementation (e.g. generated code) is one call per algorithm:
//
//   add_benchmark("rnea", robot, "generated", [](const Sample& s) {
//     static Eigen::VectorXd tau(n);
//     iiwa14::inverse_dynamics(s.q.data(), s.v.data(), s.a.data(), tau.data());
//     return tau.data();  // a pointer to the output: kept alive by DoNotOptimize
//   });
#include <benchmark/benchmark.h>

#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "mbgen/mbgen.hpp"
#include "model/load_description.hpp"

namespace mbgen::bench {

/// One input state: configuration, velocity, acceleration and joint forces.
struct Sample {
  VecX<double> q, v, a, tau;
};

/// A robot under test: its model and a pool of seeded random states.
struct Robot {
  std::string name;
  std::string urdf;
  Model model;
  std::shared_ptr<const std::vector<Sample>> pool;
};

/// States cycled through during a benchmark: enough that the branch predictor and the caches
/// cannot learn one input, few enough to stay in L1/L2 (64 states of talos: ~100 KB).
inline constexpr std::size_t kPoolSize = 64;
static_assert((kPoolSize & (kPoolSize - 1)) == 0, "the pool is cycled with a mask");

/// kPoolSize seeded states (the same seed for every robot and implementation): q from
/// random_configuration (within joint limits, random base pose), v in [-2, 2], a in [-5, 5],
/// tau in [-20, 20].
inline std::shared_ptr<const std::vector<Sample>> make_pool(const Model& model, unsigned seed = 2024) {
  std::mt19937_64 rng(seed);
  auto pool = std::make_shared<std::vector<Sample>>();
  for (std::size_t k = 0; k < kPoolSize; ++k) {
    Sample s;
    s.q = random_configuration<double>(model, rng);
    s.v = random_vector<double>(model.nv(), rng, 2.0);
    s.a = random_vector<double>(model.nv(), rng, 5.0);
    s.tau = random_vector<double>(model.nv(), rng, 20.0);
    pool->push_back(std::move(s));
  }
  return pool;
}

/// The robot `name` from ../shared/robots/<relative_path> (its tree, no extras) with its pool.
inline Robot load_robot(const std::string& name, const std::string& relative_path, gen::BaseType base) {
  Robot robot;
  robot.name = name;
  robot.urdf = std::string(MBGEN_SHARED_ROBOTS) + "/" + relative_path;
  gen::LoadOptions options;
  options.base = base;
  options.pick_up_robot_yaml = false;
  robot.model = gen::load_description(robot.urdf, options).model;
  robot.pool = make_pool(robot.model);
  return robot;
}

/// Registers `<algorithm>/<robot>/<implementation>`. `fn(const T&)` does one call on one input
/// of `pool` and returns a pointer to its output (any pointer type); the loop feeds it the pool in
/// turn, passes the pointer to DoNotOptimize and clobbers memory so that the outputs are
/// written. `fn` is copied into the benchmark and may own its work memory (mutable lambda). A
/// peer library that needs its own input types gets a pool of the same states converted
/// beforehand, so that no conversion is timed. `states_per_call` > 1 for a batch function: the
/// items_per_second column counts states, comparable with the one-state benchmarks'.
template <typename T, typename Fn>
benchmark::internal::Benchmark* add_benchmark(const std::string& algorithm, const std::string& robot,
                                              const std::string& implementation,
                                              std::shared_ptr<const std::vector<T>> pool, Fn fn, int states_per_call = 1) {
  const std::string name = algorithm + "/" + robot + "/" + implementation;
  if (pool->size() != kPoolSize) throw std::invalid_argument(name + ": the input pool must hold kPoolSize states");
  return benchmark::RegisterBenchmark(name.c_str(), [pool, fn, states_per_call](benchmark::State& state) mutable {
    const std::vector<T>& inputs = *pool;
    std::size_t k = 0;
    for (auto _ : state) {
      benchmark::DoNotOptimize(fn(inputs[k]));
      benchmark::ClobberMemory();
      k = (k + 1) & (kPoolSize - 1);
    }
    state.SetItemsProcessed(state.iterations() * states_per_call);
  });
}

/// The same on the robot's own pool of Samples.
template <typename Fn>
benchmark::internal::Benchmark* add_benchmark(const std::string& algorithm, const Robot& robot,
                                              const std::string& implementation, Fn fn) {
  return add_benchmark<Sample>(algorithm, robot.name, implementation, robot.pool, std::move(fn));
}

/// Seeded consistent states: the assembled pose with the independent coordinates moved by up to
/// 0.05 rad, loops closed by Newton (states where it fails are drawn again), v = G vy.
inline std::shared_ptr<const std::vector<Sample>> consistent_pool(const Model& model, const VecX<double>& q_closed) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Data<double> data(model);
  const int ny = model.structure().num_independent();
  auto pool = std::make_shared<std::vector<Sample>>();
  for (int attempt = 0; pool->size() < kPoolSize; ++attempt) {
    if (attempt > 100 * static_cast<int>(kPoolSize)) throw std::runtime_error("bench: cannot close the loops of " + model.name);
    Sample s;
    s.q = q_closed;
    for (int y : model.structure().independent_v)
      if (model.q_index_of_v(y) >= 0) s.q[model.q_index_of_v(y)] += 0.05 * unit(rng);
    if (closure_positions<double>(model, data, s.q).status != ClosureStatus::Converged) continue;
    s.v.resize(model.nv());
    full_velocities<double>(model, data, s.q, random_vector<double>(ny, rng), s.v);
    s.a = VecX<double>::Zero(model.nv());
    s.tau = random_vector<double>(model.nv(), rng, 5.0);
    pool->push_back(std::move(s));
  }
  return pool;
}

}  // namespace mbgen::bench
