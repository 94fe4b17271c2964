// The generated implementation of each benchmarked algorithm: `<algorithm>/<robot>/generated`,
// on the same seeded states as `generic` and `kdl` (bench_support.hpp).
//   aba        -> NAME::forward_dynamics          rnea -> NAME::inverse_dynamics
//   crba       -> NAME::mass_matrix               centroidal -> NAME::centroidal_momentum_matrix
//   jacobians  -> NAME::frame_jacobians (the leaf bodies' frames, as the generic benchmark)
//   minv       -> M^-1 tau: NAME::mass_matrix + mass_matrix_factor + mass_matrix_solve (`generated`) against
//                 NAME::mass_matrix + Eigen's dense LLT and its solve (`eigen`)
//   aba_batch/<robot>/<W> -> NAME_batch<W>::forward_dynamics_batch, W states per call (x86-64-v3; hyq
//                 and talos): items_per_second counts states, to compare with aba/<robot>/generated_v3
#include "bench_generated.hpp"

#include <Eigen/Cholesky>
#include <array>
#include <memory>

#include "hyq.hpp"
#include "hyq_snapped.hpp"
#include "iiwa14.hpp"
#include "talos.hpp"
#if MBGEN_BENCH_V3
#include "hyq_v3.hpp"
#include "iiwa14_v3.hpp"
#include "talos_v3.hpp"
#include "hyq_batch4.hpp"
#include "talos_batch4.hpp"
#endif

namespace mbgen::bench {

namespace {

/// The double-precision entry points of one generated robot.
struct GeneratedApi {
  void (*forward_dynamics)(const double*, const double*, const double*, double*);
  void (*inverse_dynamics)(const double*, const double*, const double*, double*);
  void (*mass_matrix)(const double*, double*);
  void (*mass_matrix_factor)(const double*, double*);
  void (*mass_matrix_solve)(const double*, const double*, double*);
  void (*frame_jacobians)(const double*, double*);
  void (*centroidal_momentum_matrix)(const double*, double*);
  int nv, num_frames;
};

#define MBGEN_GENERATED_API(ns)                                                                              \
  GeneratedApi {                                                                                             \
    &ns::forward_dynamics, &ns::inverse_dynamics, &ns::mass_matrix, &ns::mass_matrix_factor,                 \
        &ns::mass_matrix_solve, &ns::frame_jacobians, &ns::centroidal_momentum_matrix, ns::nv, ns::num_frames \
  }

/// `implementation`: generated (the build's flags) or generated_v3 (the same code for x86-64-v3).
void add(const Robot& robot, const GeneratedApi& api, const std::string& implementation) {
  const int n = api.nv;
  auto buffer = [n, &api] { return std::make_shared<std::vector<double>>(6 * n * (n + api.num_frames + 6)); };
  add_benchmark("aba", robot, implementation, [api, out = buffer()](const Sample& s) {
    api.forward_dynamics(s.q.data(), s.v.data(), s.tau.data(), out->data());
    return out->data();
  });
  add_benchmark("rnea", robot, implementation, [api, out = buffer()](const Sample& s) {
    api.inverse_dynamics(s.q.data(), s.v.data(), s.a.data(), out->data());
    return out->data();
  });
  add_benchmark("crba", robot, implementation, [api, out = buffer()](const Sample& s) {
    api.mass_matrix(s.q.data(), out->data());
    return out->data();
  });
  add_benchmark("minv", robot, implementation, [api, factor = buffer(), out = buffer()](const Sample& s) {
    api.mass_matrix(s.q.data(), out->data());
    api.mass_matrix_factor(out->data(), factor->data());
    api.mass_matrix_solve(factor->data(), s.tau.data(), out->data());
    return out->data();
  });
  // Eigen's dense Cholesky of the same (generated) mass matrix, its storage allocated up front.
  struct Dense {
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> M;
    Eigen::LLT<MatX<double>> llt;
    VecX<double> x;
  };
  auto dense = std::make_shared<Dense>(Dense{decltype(Dense::M)(n, n), Eigen::LLT<MatX<double>>(n), VecX<double>(n)});
  if (implementation == "generated") {
    add_benchmark("minv", robot, "eigen", [api, dense](const Sample& s) {
      api.mass_matrix(s.q.data(), dense->M.data());
      dense->llt.compute(dense->M);
      dense->x = dense->llt.solve(Eigen::Map<const VecX<double>>(s.tau.data(), dense->x.size()));
      return dense->x.data();
    });
  }
  add_benchmark("jacobians", robot, implementation, [api, out = buffer()](const Sample& s) {
    api.frame_jacobians(s.q.data(), out->data());
    return out->data();
  });
  add_benchmark("centroidal", robot, implementation, [api, out = buffer()](const Sample& s) {
    api.centroidal_momentum_matrix(s.q.data(), out->data());
    return out->data();
  });
}

/// aba_batch/<robot>/<W>: the batch forward dynamics on the robot's pool, W consecutive states
/// per call, packed beforehand (q[i][w]) so that no packing is timed.
template <int W, int nq, int nv>
void add_batch(const Robot& robot,
               void (*forward_dynamics_batch)(const double (*)[W], const double (*)[W], const double (*)[W], double (*)[W])) {
  struct Batch {
    std::array<double, nq * W> q;
    std::array<double, nv * W> v, tau;
  };
  auto pool = std::make_shared<std::vector<Batch>>(kPoolSize);
  for (std::size_t k = 0; k < kPoolSize; ++k)
    for (int w = 0; w < W; ++w) {
      const Sample& s = (*robot.pool)[(k * W + static_cast<std::size_t>(w)) % kPoolSize];
      for (int i = 0; i < nq; ++i) (*pool)[k].q[static_cast<std::size_t>(i * W + w)] = s.q[i];
      for (int i = 0; i < nv; ++i) {
        (*pool)[k].v[static_cast<std::size_t>(i * W + w)] = s.v[i];
        (*pool)[k].tau[static_cast<std::size_t>(i * W + w)] = s.tau[i];
      }
    }
  auto lanes = [](const auto& a) { return reinterpret_cast<const double(*)[W]>(a.data()); };
  add_benchmark<Batch>(
      "aba_batch", robot.name, std::to_string(W), pool,
      [forward_dynamics_batch, lanes, out = std::make_shared<std::array<double, nv * W>>()](const Batch& b) {
        forward_dynamics_batch(lanes(b.q), lanes(b.v), lanes(b.tau), reinterpret_cast<double(*)[W]>(out->data()));
        return out->data();
      },
      W);
}

}  // namespace

void add_generated(const Robot& robot) {
  if (robot.name == "iiwa14") add(robot, MBGEN_GENERATED_API(iiwa14), "generated");
  if (robot.name == "hyq") add(robot, MBGEN_GENERATED_API(hyq), "generated");
  // The same robot with its quarter turns exact (bench/data/hyq_quarter_turns.yaml): its mass
  // matrix within 1e-13 of the literal one's (test LoadUrdf.SnapQuarterTurns*), a quarter fewer operations.
  if (robot.name == "hyq") add(robot, MBGEN_GENERATED_API(hyq_snapped), "generated_snapped");
  if (robot.name == "talos") add(robot, MBGEN_GENERATED_API(talos), "generated");
#if MBGEN_BENCH_V3
  // x86-64-v3 code on a CPU without AVX2 and FMA would stop at its first instruction.
  __builtin_cpu_init();
  if (!__builtin_cpu_supports("avx2") || !__builtin_cpu_supports("fma") || !__builtin_cpu_supports("bmi2")) return;
  if (robot.name == "iiwa14") add(robot, MBGEN_GENERATED_API(iiwa14_v3), "generated_v3");
  if (robot.name == "hyq") add(robot, MBGEN_GENERATED_API(hyq_v3), "generated_v3");
  if (robot.name == "talos") add(robot, MBGEN_GENERATED_API(talos_v3), "generated_v3");
  if (robot.name == "hyq") add_batch<hyq_batch4::batch_width, hyq_batch4::nq, hyq_batch4::nv>(robot, &hyq_batch4::forward_dynamics_batch);
  if (robot.name == "talos")
    add_batch<talos_batch4::batch_width, talos_batch4::nq, talos_batch4::nv>(robot, &talos_batch4::forward_dynamics_batch);
#endif
}

}  // namespace mbgen::bench
