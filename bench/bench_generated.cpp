// The generated implementation of each benchmarked algorithm: `<algorithm>/<robot>/generated`,
// on the same seeded states as `generic` and `kdl` (bench_support.hpp).
//   aba        -> NAME::forward_dynamics          rnea -> NAME::inverse_dynamics
//   crba       -> NAME::mass_matrix               centroidal -> NAME::centroidal_momentum_matrix
//   jacobians  -> NAME::frame_jacobians (the leaf bodies' frames, as the generic benchmark)
#include "bench_generated.hpp"

#include <memory>

#include "hyq.hpp"
#include "iiwa14.hpp"
#include "talos.hpp"

namespace mbgen::bench {

namespace {

/// The double-precision entry points of one generated robot.
struct GeneratedApi {
  void (*forward_dynamics)(const double*, const double*, const double*, double*);
  void (*inverse_dynamics)(const double*, const double*, const double*, double*);
  void (*mass_matrix)(const double*, double*);
  void (*frame_jacobians)(const double*, double*);
  void (*centroidal_momentum_matrix)(const double*, double*);
  int nv, num_frames;
};

#define MBGEN_GENERATED_API(ns)                                                                              \
  GeneratedApi {                                                                                             \
    &ns::forward_dynamics, &ns::inverse_dynamics, &ns::mass_matrix, &ns::frame_jacobians,                    \
        &ns::centroidal_momentum_matrix, ns::nv, ns::num_frames                                              \
  }

void add(const Robot& robot, const GeneratedApi& api) {
  const int n = api.nv;
  auto buffer = [n, &api] { return std::make_shared<std::vector<double>>(6 * n * (n + api.num_frames + 6)); };
  add_benchmark("aba", robot, "generated", [api, out = buffer()](const Sample& s) {
    api.forward_dynamics(s.q.data(), s.v.data(), s.tau.data(), out->data());
    return out->data();
  });
  add_benchmark("rnea", robot, "generated", [api, out = buffer()](const Sample& s) {
    api.inverse_dynamics(s.q.data(), s.v.data(), s.a.data(), out->data());
    return out->data();
  });
  add_benchmark("crba", robot, "generated", [api, out = buffer()](const Sample& s) {
    api.mass_matrix(s.q.data(), out->data());
    return out->data();
  });
  add_benchmark("jacobians", robot, "generated", [api, out = buffer()](const Sample& s) {
    api.frame_jacobians(s.q.data(), out->data());
    return out->data();
  });
  add_benchmark("centroidal", robot, "generated", [api, out = buffer()](const Sample& s) {
    api.centroidal_momentum_matrix(s.q.data(), out->data());
    return out->data();
  });
}

}  // namespace

void add_generated(const Robot& robot) {
  if (robot.name == "iiwa14") add(robot, MBGEN_GENERATED_API(iiwa14));
  if (robot.name == "hyq") add(robot, MBGEN_GENERATED_API(hyq));
  if (robot.name == "talos") add(robot, MBGEN_GENERATED_API(talos));
}

}  // namespace mbgen::bench
