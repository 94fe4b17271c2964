// What the rotor models cost: `aba|rnea/iiwa14_rotors_<model>/{generic,generated}` for the
// armature model (reflected inertia on the diagonal) and the rotor-body model (gyroscopic
// coupling), beside the plain `aba|rnea/iiwa14/...`. Drives: bench/data/iiwa14_rotors_*.yaml.
#include "bench_rotor.hpp"

#include <memory>

#include "iiwa14_rotors_armature.hpp"
#include "iiwa14_rotors_body.hpp"
#include "model/load_description.hpp"

namespace mbgen::bench {

namespace {

template <typename ForwardDynamics, typename InverseDynamics>
void add_rotor_robot(const std::string& model_name, ForwardDynamics fd, InverseDynamics id) {
  // The robots live as long as the process: the benchmarks point into them.
  static std::vector<std::unique_ptr<Robot>> robots;
  auto robot = std::make_unique<Robot>();
  robot->name = "iiwa14_rotors_" + model_name;
  robot->urdf = std::string(MBGEN_SHARED_ROBOTS) + "/iiwa14/iiwa14_primitive_collision.urdf";
  gen::LoadOptions options;
  options.extras_file = std::string(MBGEN_BENCH_DATA) + "/" + robot->name + ".yaml";
  robot->model = gen::load_description(robot->urdf, options).model;
  robot->pool = make_pool(robot->model);
  const Model* model = &robot->model;
  const int nv = model->nv();
  add_benchmark("aba", *robot, "generic", [model, data = std::make_shared<Data<double>>(*model)](const Sample& s) {
    return aba<double>(*model, *data, s.q, s.v, s.tau).data();
  });
  add_benchmark("rnea", *robot, "generic", [model, data = std::make_shared<Data<double>>(*model)](const Sample& s) {
    return rnea<double>(*model, *data, s.q, s.v, s.a).data();
  });
  add_benchmark("aba", *robot, "generated", [fd, out = std::make_shared<std::vector<double>>(nv)](const Sample& s) {
    fd(s.q.data(), s.v.data(), s.tau.data(), out->data());
    return out->data();
  });
  add_benchmark("rnea", *robot, "generated", [id, out = std::make_shared<std::vector<double>>(nv)](const Sample& s) {
    id(s.q.data(), s.v.data(), s.a.data(), out->data());
    return out->data();
  });
  robots.push_back(std::move(robot));
}

}  // namespace

void add_rotor_benchmarks() {
  using Fn = void (*)(const double*, const double*, const double*, double*);
  add_rotor_robot("armature", static_cast<Fn>(&iiwa14_rotors_armature::forward_dynamics),
                  static_cast<Fn>(&iiwa14_rotors_armature::inverse_dynamics));
  add_rotor_robot("body", static_cast<Fn>(&iiwa14_rotors_body::forward_dynamics),
                  static_cast<Fn>(&iiwa14_rotors_body::inverse_dynamics));
}

}  // namespace mbgen::bench
