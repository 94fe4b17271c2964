// The Quick start demo: what the generated code of the default robot computes, checked against
// the generic runtime it was traced from, and how long each takes.
#include <fmt/format.h>

#include <chrono>
#include <random>

#include MBGEN_DEMO_HEADER
#include "mbgen/gen/description.hpp"
#include "mbgen/mbgen.hpp"

namespace robot = MBGEN_DEMO_NS;
using namespace mbgen;

namespace {

/// Median-free, simple timing: mean ns per call over enough calls to last ~0.2 s.
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
  options.base = gen::BaseType::Floating;
  const gen::Description description = gen::load_description(MBGEN_DEMO_DESCRIPTION, options);
  const Model& model = description.model;
  Data<double> data(model);
  fmt::print("robot {}: nq {}, nv {}, {} bodies, {:.3f} kg, {} base\n", model.name, robot::nq, robot::nv,
             robot::num_bodies, model.total_mass(), robot::floating_base ? "floating" : "fixed");

  // A standing robot held by gravity-compensating torques does not accelerate.
  VecX<double> q = neutral_configuration<double>(model);
  VecX<double> v = VecX<double>::Zero(model.nv()), zero = VecX<double>::Zero(model.nv());
  VecX<double> tau(model.nv()), qdd(model.nv());
  robot::inverse_dynamics(q.data(), v.data(), zero.data(), tau.data());
  robot::forward_dynamics(q.data(), v.data(), tau.data(), qdd.data());
  fmt::print("gravity compensation at the neutral pose: |tau| = {:.4g} N(m), then |qdd| = {:.2e} (0 expected)\n",
             tau.norm(), qdd.norm());

  // A random state: generated against generic.
  std::mt19937_64 rng(1);
  q = random_configuration<double>(model, rng);
  v = random_vector<double>(model.nv(), rng, 1.0);
  tau = random_vector<double>(model.nv(), rng, 10.0);
  robot::forward_dynamics(q.data(), v.data(), tau.data(), qdd.data());
  const VecX<double> qdd_generic = aba<double>(model, data, q, v, tau);
  MatX<double> M(model.nv(), model.nv());
  robot::mass_matrix(q.data(), M.data());  // row-major; M is symmetric
  double com[3];
  robot::center_of_mass(q.data(), com);
  fmt::print("random state: |qdd| = {:.6g}, generated vs generic difference {:.2e} (relative)\n", qdd.norm(),
             (qdd - qdd_generic).norm() / qdd_generic.norm());
  fmt::print("mass matrix: trace {:.6g}, symmetric to {:.1e}; centre of mass ({:.4f}, {:.4f}, {:.4f}) m\n", M.trace(),
             (M - M.transpose()).norm(), com[0], com[1], com[2]);
  if (robot::num_frames > 0) {
    double X[12 * robot::num_frames];
    robot::frame_poses(q.data(), X);
    for (int f = 0; f < robot::num_frames; ++f)
      fmt::print("frame {:<12} at ({:+.4f}, {:+.4f}, {:+.4f}) m\n", robot::frame_names[f], X[12 * f + 3],
                 X[12 * f + 7], X[12 * f + 11]);
  }

  const double t_generated = ns_per_call([&] { robot::forward_dynamics(q.data(), v.data(), tau.data(), qdd.data()); });
  const double t_generic = ns_per_call([&] { aba<double>(model, data, q, v, tau); });
  fmt::print("forward dynamics: generated {:.0f} ns, generic {:.0f} ns per call ({:.1f}x)\n", t_generated, t_generic,
             t_generic / t_generated);
  const bool ok = (qdd - qdd_generic).norm() <= 1e-9 * (1 + qdd_generic.norm());
  fmt::print("{}\n", ok ? "demo: OK" : "demo: MISMATCH between generated and generic code");
  return ok ? 0 : 1;
}
