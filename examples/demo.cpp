// The Quick start demo: what the generated code of the default robot (the Lola-like biped of
// robots/lola: a spanning tree, six loop closures in four sub-systems, harmonic drives, SSV
// compounds) computes, checked against the generic runtime it was traced from and against the
// O(n^3) reference, and how long each takes.
#include <fmt/format.h>

#include <chrono>
#include <random>

#include MBGEN_DEMO_HEADER
#include "mbgen/collision/compound_distance.hpp"
#include "collision/collision_scene.hpp"
#include "model/load_description.hpp"
#include "mbgen/mbgen.hpp"

namespace robot = MBGEN_DEMO_NS;
using namespace mbgen;

namespace {

/// Mean ns per call over enough calls to last ~0.2 s.
template <typename F> double ns_per_call(F&& f) {
  using clock = std::chrono::steady_clock;
  int calls = 100;
  for (;;) {
    const auto start = clock::now();
    for (int i = 0; i < calls; ++i) f();
    const double seconds = std::chrono::duration<double>(clock::now() - start).count();
    if (seconds > 0.2) return 1e9 * seconds / calls;
    calls *= 4;
  }
}

}  // namespace

int main() {
  gen::LoadOptions options;
  if (std::string(MBGEN_DEMO_EXTRAS).size()) options.extras_file = MBGEN_DEMO_EXTRAS;
  const gen::Description description = gen::load_description(MBGEN_DEMO_DESCRIPTION, options);
  const Model& model = description.model;
  Data<double> data(model), reference_data(model);
  fmt::print("robot {}: {} tree joints (nq {}, nv {}), {:.2f} kg, {} base; {} loop closures in {} sub-systems, "
             "{} independent coordinates\n",
             model.name, model.num_joints() - 1, robot::nq, robot::nv, model.total_mass(),
             robot::floating_base ? "floating" : "fixed", model.closures.size(), model.subsystems.size(), robot::ny);
  if (description.assembly.q.size() > 0)
    fmt::print("assembly: closed pose {:.3g} rad from the zero pose, closure residual {:.1e}\n",
               description.assembly.max_joint_change, description.assembly.residual);

  // A consistent state: the closed pose with the independent joints moved, the loops closed again
  // by the generated Newton (checked against the generic one), velocities from the independent ones.
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  VecX<double> q = description.assembly.q.size() ? description.assembly.q : neutral_configuration<double>(model);
  for (int y : model.structure().independent_v) {
    const int i = model.q_index_of_v(y);
    if (i >= 0) q[i] += (model.joint(model.joint_of_v(y)).type == JointType::Prismatic ? 0.002 : 0.05) * unit(rng);
  }
  VecX<double> q_generic = q;
  const robot::ClosureResult<double> closed = robot::closure_positions(q.data());
  const ClosureResult<double> closed_generic = closure_positions<double>(model, data, q_generic);
  fmt::print("closure_positions (generated Newton): {} in {} iterations, residual {:.1e}, pivot ratio {:.2g}; "
             "generic: {} in {}, |q - q_generic| = {:.1e}\n",
             closed.status == robot::ClosureStatus::converged ? "converged" : "FAILED", closed.iterations, closed.residual,
             closed.pivot_ratio, to_string(closed_generic.status), closed_generic.iterations,
             (q - q_generic).cwiseAbs().maxCoeff());
  VecX<double> vy(robot::ny), tau = random_vector<double>(model.nv(), rng, 5.0);
  for (int i = 0; i < robot::ny; ++i) vy[i] = 0.5 * unit(rng);

  // Generated closed-system forward dynamics against the generic O(n) recursion and the O(n^3) KKT reference.
  VecX<double> ydd(robot::ny), qdd_full(robot::nv);
  robot::forward_dynamics(q.data(), vy.data(), tau.data(), ydd.data());
  robot::full_accelerations(q.data(), vy.data(), tau.data(), qdd_full.data());
  forward_dynamics_loops_independent<double>(model, data, q, vy, tau);
  const VecX<double> qdd_generic = data.ddq;
  const VecX<double> v = data.v_full;
  ConstrainedDynamicsWorkspace<double> kkt(model);
  const VecX<double> qdd_reference = forward_dynamics_kkt<double>(model, reference_data, kkt, q, v, tau);
  const double err_generic = (qdd_full - qdd_generic).norm() / qdd_generic.norm();
  const double err_reference = (qdd_full - qdd_reference).norm() / qdd_reference.norm();
  fmt::print("forward dynamics: |ydd| = {:.6g}; generated vs generic O(n) {:.1e}, vs O(n^3) reference {:.1e} (relative)\n",
             ydd.norm(), err_generic, err_reference);
  closure_jacobian<double>(model, data, q);
  fmt::print("closure constraints at those accelerations: |Phi_q qdd - gamma| = {:.1e}\n",
             (data.Phi_q * qdd_full - closure_bias<double>(model, data, q, v)).norm());

  // Self-distances of the scene's pairs, with Jacobians.
  if (robot::num_distance_pairs > 0) {
    std::vector<double> d(robot::num_distance_pairs), n(3 * robot::num_distance_pairs), w(6 * robot::num_distance_pairs),
        J(static_cast<std::size_t>(robot::num_distance_pairs) * robot::nv);
    robot::self_distances(q.data(), d.data(), n.data(), w.data(), J.data());
    int closest = 0;
    for (int k = 1; k < robot::num_distance_pairs; ++k)
      if (d[k] < d[closest]) closest = k;
    fmt::print("self-distances: {} pairs; closest {} - {} at {:.4f} m\n", robot::num_distance_pairs,
               robot::distance_pair_names[closest][0], robot::distance_pair_names[closest][1], d[closest]);
  }

  const double t_generated = ns_per_call([&] { robot::forward_dynamics(q.data(), vy.data(), tau.data(), ydd.data()); });
  const double t_generic = ns_per_call([&] { forward_dynamics_loops<double>(model, data, q, v, tau); });
  const double t_reference = ns_per_call([&] { forward_dynamics_kkt<double>(model, reference_data, kkt, q, v, tau); });
  fmt::print("forward dynamics per call: generated {:.0f} ns, generic O(n) {:.0f} ns ({:.1f}x), O(n^3) reference {:.0f} ns "
             "({:.1f}x)\n",
             t_generated, t_generic, t_generic / t_generated, t_reference, t_reference / t_generated);
  const bool ok = closed.status == robot::ClosureStatus::converged && (q - q_generic).cwiseAbs().maxCoeff() < 1e-12 &&
                  err_generic < 1e-9 && err_reference < 1e-9;
  fmt::print("{}\n", ok ? "demo: OK" : "demo: MISMATCH between generated, generic and reference");
  return ok ? 0 : 1;
}
