// Controller-side costs (runtime/include/mbgen/control/, docs/control.md):
//   dls/<m>x<n>/svd      damped least-squares solve + null-space projection of one vector from
//                        Eigen's JacobiSVD (thin U, V): the scheme DampedLeastSquares used before;
//   dls/<m>x<n>/qr_eig   the same with DampedLeastSquares (column-pivoted QR of A^T and the
//                        eigen-decomposition of R R^T);
//   ik_step/talos/generic one DifferentialIk::step on TALOS (talos_reduced): feet poses, CoM and
//                        torso orientation (18 rows, 38 coordinates), angular-momentum objective
//                        on, as tests/test_differential_ik.cpp sets it up.
//   ik_step/lola/{generic,generated}  the full controller step on Lola with its loops (18 rows,
//                        30 independent velocities): the same tasks, self-collision avoidance over
//                        the scene's 178 pairs and angular-momentum tracking
//                        (bench/lola_ik_scenario.hpp), on DifferentialIk (the generic runtime) and
//                        on BasicDifferentialIk<lola::Backend> (the generated functions), over the
//                        same 64 poses of the controller's own motion from the bent-knee pose.
//   ik_step/lola/generated/qp  the same step in the QP form (QpStepOptions, dense_qp.hpp): the
//                        description's joint ranges (activation 0.1), velocity limits (3 rad/s or
//                        m/s) and a 15 mm smallest distance (activation 5 cm: the arms start 20 mm
//                        from the body) as inequalities, smoothing 30 (the walk's), on the
//                        generated backend.
// Both dls implementations run on the same 64 seeded random matrices (entries uniform in
// [-1, 1]) with the differential IK's damping (singular region 0.01, max damping 0.01);
// registration checks that they agree on every sample. Sizes: m = 12 .. 24 task rows,
// n = 30 .. 50 coordinates, the range of walking robots.
#include <Eigen/SVD>
#include <cstdio>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "bench_support.hpp"
#include "lola.hpp"
#include "lola_ik_scenario.hpp"
#include "talos_ik_scenario.hpp"
#include "mbgen/control/differential_ik.hpp"
#include "model/load_description.hpp"

namespace mbgen::bench {
namespace {

using control::DampedLeastSquares;
using control::DampingOptions;

const DampingOptions kDamping{0.0, 1e-2, 1e-2, 1e-10};  // DifferentialIkOptions' default

struct DlsInput {
  MatX<double> A;
  VecX<double> e, v;  // right-hand side, vector to project
};

std::shared_ptr<const std::vector<DlsInput>> dls_pool(int m, int n) {
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(-1, 1);
  auto pool = std::make_shared<std::vector<DlsInput>>();
  for (std::size_t k = 0; k < kPoolSize; ++k) {
    DlsInput in{MatX<double>(m, n), VecX<double>(m), VecX<double>(n)};
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < m; ++i) in.A(i, j) = u(rng);
    for (int i = 0; i < m; ++i) in.e[i] = u(rng);
    for (int j = 0; j < n; ++j) in.v[j] = u(rng);
    pool->push_back(std::move(in));
  }
  return pool;
}

/// The SVD scheme: x = V diag(s / (s^2 + lambda(s)^2)) U^T e, N v = v - V_r V_r^T v.
struct SvdWork {
  SvdWork(int m, int n)
      : svd(m, n, Eigen::ComputeThinU | Eigen::ComputeThinV), damping(m, n, kDamping), tmp(std::min(m, n)), coeffs(std::min(m, n)),
        x(n), y(n) {}
  Eigen::JacobiSVD<MatX<double>> svd;
  DampedLeastSquares<double> damping;  // only for damping_squared (the same schedule)
  VecX<double> tmp, coeffs, x, y;
  const double* run(const DlsInput& in) {
    svd.compute(in.A);
    const auto& s = svd.singularValues();
    int rank = 0;
    for (int i = 0; i < s.size(); ++i)
      if (s[i] > kDamping.rank_tolerance * s[0] && s[i] > 0) rank = i + 1;
    tmp.noalias() = svd.matrixU().transpose() * in.e;
    for (int i = 0; i < s.size(); ++i) {
      const double denom = s[i] * s[i] + damping.damping_squared(s[i]);
      tmp[i] = denom > 0 ? tmp[i] * s[i] / denom : 0;
    }
    x.noalias() = svd.matrixV() * tmp;
    y = in.v;
    auto c = coeffs.head(rank);
    c.noalias() = svd.matrixV().leftCols(rank).transpose() * y;
    y.noalias() -= svd.matrixV().leftCols(rank) * c;
    return x.data();
  }
};

struct QrEigWork {
  QrEigWork(int m, int n) : dls(m, n, kDamping), x(n), y(n) {}
  DampedLeastSquares<double> dls;
  VecX<double> x, y;
  const double* run(const DlsInput& in) {
    dls.compute(in.A);
    dls.solve(in.e, x);
    y = in.v;
    dls.project_to_null(y);
    return x.data();
  }
};

void add_dls(int m, int n) {
  const auto pool = dls_pool(m, n);
  const std::string size = std::to_string(m) + "x" + std::to_string(n);
  // Agreement on every sample: solutions to 1e-12 relative, projections to 1e-12 (random
  // matrices of this size are well conditioned, sigma_min > 0.1).
  SvdWork svd(m, n);
  QrEigWork qr(m, n);
  for (const DlsInput& in : *pool) {
    svd.run(in);
    qr.run(in);
    if ((svd.x - qr.x).norm() > 1e-12 * svd.x.norm() || (svd.y - qr.y).norm() > 1e-12 * in.v.norm())
      throw std::runtime_error("dls/" + size + ": the SVD and QR + eigen schemes disagree");
  }
  add_benchmark<DlsInput>("dls", size, "svd", pool,
                          [w = std::make_shared<SvdWork>(m, n)](const DlsInput& in) { return w->run(in); });
  add_benchmark<DlsInput>("dls", size, "qr_eig", pool,
                          [w = std::make_shared<QrEigWork>(m, n)](const DlsInput& in) { return w->run(in); });
}

/// TALOS with its controller, loaded on the first run of the benchmark (not at static
/// initialisation: the loader's own statics may not be constructed yet) and kept for the others.
struct IkFixture {
  Model model;
  std::unique_ptr<control::DifferentialIk<double>> ik;
  std::vector<VecX<double>> poses;
  VecX<double> v;

  IkFixture() {
    gen::LoadOptions options;
    options.base = gen::BaseType::Floating;
    options.pick_up_robot_yaml = false;
    model = gen::load_description(std::string(MBGEN_SHARED_ROBOTS) + "/talos/talos_reduced.urdf", options).model;
    // The scenario tests/test_differential_ik.cpp checks (bench/talos_ik_scenario.hpp).
    for (unsigned seed = 0; seed < kPoolSize; ++seed) poses.push_back(scenario::talos_pose(model, seed));
    control::DifferentialIkOptions ik_options;
    ik_options.angular_momentum.enabled = true;
    ik_options.angular_momentum.weight = 50.0;
    ik = std::make_unique<control::DifferentialIk<double>>(model, scenario::talos_tasks(10.0), ik_options);
    scenario::set_targets_near(*ik, model, poses[0], 7);
    ik->angular_momentum_target = Vec3<double>(4.0, -3.0, 2.0);
    v = VecX<double>::Zero(model.nv());
    for (const VecX<double>& q : poses)
      if (!ik->step(q, v).ok) throw std::runtime_error("ik_step/talos/generic: a step failed");
  }
};

void ik_step(benchmark::State& state) {
  static std::unique_ptr<IkFixture> fixture;
  if (!fixture) {
    try {
      fixture = std::make_unique<IkFixture>();
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      return;
    }
  }
  IkFixture& f = *fixture;
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(f.ik->step(f.poses[k], f.v));
    benchmark::DoNotOptimize(f.v.data());
    benchmark::ClobberMemory();
    k = (k + 1) & (kPoolSize - 1);
  }
  state.SetItemsProcessed(state.iterations());
}

/// Lola's controller on both backends, and 64 poses along the generic controller's own motion
/// (1 ms steps from the bent-knee pose, loops re-closed): realistic states with pairs switching
/// in and out of the activation distance.
struct LolaIkFixture {
  gen::Description d;
  collision::CollisionModel cm;
  std::unique_ptr<control::DifferentialIk<double>> generic;
  std::unique_ptr<control::BasicDifferentialIk<lola::Backend>> generated, qp;
  std::vector<VecX<double>> poses, qp_poses;  ///< along the potential form's motion, along the QP form's
  VecX<double> v;

  LolaIkFixture() : d(scenario::lola_description(MBGEN_SOURCE_DIR)), cm(scenario::generated_collision_scene(d)) {
    const Model& model = d.model;
    const control::DifferentialIkOptions options = scenario::lola_ik_options();
    generic = std::make_unique<control::DifferentialIk<double>>(model, scenario::lola_tasks(), options, &cm);
    generated = std::make_unique<control::BasicDifferentialIk<lola::Backend>>(lola::Backend{}, scenario::lola_tasks(), options);
    control::DifferentialIkOptions qp_options = options;
    qp_options.qp.enabled = true;
    qp_options.joint_limits.limits = joint_position_limits(lola::num_limited_joints, lola::limited_joint_names, lola::limited_q_index,
                                                           lola::limited_v_index, lola::limited_lower, lola::limited_upper);
    qp_options.velocity_limits.assign(static_cast<std::size_t>(lola::ny), 3.0);
    qp_options.collision.activation_distance = 0.05;  // as tests/test_differential_ik_qp.cpp: rows bind as the arms swing
    qp_options.qp.min_distance = 0.015;
    qp_options.qp.smoothing = 30.0;  // as mbgen_walk's qp configuration
    qp = std::make_unique<control::BasicDifferentialIk<lola::Backend>>(lola::Backend{}, scenario::lola_tasks(), qp_options);
    VecX<double> q = scenario::lola_bent_pose(d), next(model.nq());
    scenario::set_targets_near(*generic, model, q, 11);
    for (int i = 0; i < generic->num_tasks(); ++i) qp->target(i) = generated->target(i) = generic->target(i);
    generic->angular_momentum_target = generated->angular_momentum_target = qp->angular_momentum_target = Vec3<double>(0.5, 0.2, -0.3);
    v = VecX<double>::Zero(model.nv());
    Data<double> data(model);
    for (std::size_t k = 0; k < kPoolSize; ++k) {
      poses.push_back(q);
      if (!generated->step(q, v).ok || !generic->step(q, v).ok) throw std::runtime_error("ik_step/lola: a step failed");
      integrate<double>(model, q, v * 1e-3, next);
      q = next;
      if (closure_positions<double>(model, data, q).status != ClosureStatus::Converged)
        throw std::runtime_error("ik_step/lola: the loops did not close along the motion");
    }
    // The QP form along its own motion: the potential form's leaves the joint ranges, where the
    // QP's inequalities would ask more than the velocity limits allow.
    q = scenario::lola_bent_pose(d);
    for (std::size_t k = 0; k < kPoolSize; ++k) {
      qp_poses.push_back(q);
      const control::StepReport r = qp->step(q, v);
      if (!r.ok) throw std::runtime_error(std::string("ik_step/lola/generated/qp: a step failed: ") + control::to_string(r.qp_status));
      integrate<double>(model, q, v * 1e-3, next);
      q = next;
      if (closure_positions<double>(model, data, q).status != ClosureStatus::Converged)
        throw std::runtime_error("ik_step/lola/generated/qp: the loops did not close along the motion");
    }
  }
};

enum class LolaStep { generic, generated, generated_qp };

template <LolaStep Which> void ik_step_lola(benchmark::State& state) {
  static std::unique_ptr<LolaIkFixture> fixture;
  if (!fixture) {
    try {
      fixture = std::make_unique<LolaIkFixture>();
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      return;
    }
  }
  LolaIkFixture& f = *fixture;
  std::size_t k = 0;
  for (auto _ : state) {
    if constexpr (Which == LolaStep::generated) {
      benchmark::DoNotOptimize(f.generated->step(f.poses[k], f.v));
    } else if constexpr (Which == LolaStep::generated_qp) {
      benchmark::DoNotOptimize(f.qp->step(f.qp_poses[k], f.v));
    } else {
      benchmark::DoNotOptimize(f.generic->step(f.poses[k], f.v));
    }
    benchmark::DoNotOptimize(f.v.data());
    benchmark::ClobberMemory();
    k = (k + 1) & (kPoolSize - 1);
  }
  state.SetItemsProcessed(state.iterations());
}

/// Registered at static initialisation, as bench_ssv.cpp does, so that main (bench_dynamics.cpp)
/// need not know this file.
const bool registered = [] {
  add_dls(12, 30);
  add_dls(18, 38);
  add_dls(24, 50);
  benchmark::RegisterBenchmark("ik_step/talos/generic", ik_step);
  benchmark::RegisterBenchmark("ik_step/lola/generic", ik_step_lola<LolaStep::generic>);
  benchmark::RegisterBenchmark("ik_step/lola/generated", ik_step_lola<LolaStep::generated>);
  benchmark::RegisterBenchmark("ik_step/lola/generated/qp", ik_step_lola<LolaStep::generated_qp>);
  return true;
}();

}  // namespace
}  // namespace mbgen::bench
