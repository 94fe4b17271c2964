// Forward dynamics of closed-loop robots (bench/README.md):
//   fd/<robot>/generic     O(n): loop maps (G, g) + the articulated-body algorithm with
//                          sub-systems as aggregate bodies (forward_dynamics_loops)
//   fd/<robot>/reference   O(n^3): full coordinates with Lagrange multipliers (forward_dynamics_kkt)
//   fd/<robot>/generated   the generated closed-system forward_dynamics (independent velocities)
//   fd/lola_legs_transmission/{generic,generated}   the legs-only scene with the drive linkages
//                          replaced by their transmissions (scene: loops): a tree, what the
//                          reduction buys against fd/lola/*
//   closure/<robot>/{generic,generated}   closure_positions: Newton for the dependent coordinates
//                          from a pose whose dependent coordinates were moved by up to 1e-3
//                          each (a tick without a predictor, as an actuator-to-joint map's), to
//                          the 1e-12 tolerance
//   project/<robot>/{generic,generated}   the simulator's projection: close_loops (positions and
//                          velocities) on the state one simulator step leaves (RK4, its default
//                          step, before it projects), to its closure_tolerance (1e-11)
// on Lola, Cassie (MJCF), cassie_like and digit_like_2legs, and the scaling series
//   fd_chain/<k>/{generic,reference}   a chain of k four-bar modules (loop_chain.hpp), k = 1 .. 64.
// Inputs: 64 seeded consistent states per robot (loops closed by Newton, v = G vy) with random
// joint forces, the same for both implementations.
#include "bench_loops.hpp"

#include <filesystem>
#include <memory>
#include <random>

#include "cassie_mjcf.hpp"
#include "lola.hpp"
#include "lola_legs_transmission.hpp"
#include "loop_chain.hpp"
#include "mbgen/sim/backend.hpp"
#include "mbgen/sim/simulator.hpp"
#include "model/load_description.hpp"
#include "pl_cassie_like.hpp"
#include "pl_digit_like_2legs.hpp"

namespace mbgen::bench {

namespace {

/// The generated closed-system forward dynamics of one robot: q (nq), independent velocities, tau (nv).
using GeneratedForwardDynamics = void (*)(const double*, const double*, const double*, double*);

/// One state for the generated code: the independent velocities only.
struct IndependentSample {
  VecX<double> q, vy, tau;
};

/// A warm start for Newton: the dependent coordinates of a closed q moved by up to 1e-3.
struct ClosureSample {
  VecX<double> q;
};

/// The tolerance of the simulator's projection (SimulatorOptions::closure_tolerance, 1e-11).
const double kProjection = sim::SimulatorOptions{}.closure_tolerance;

/// The state a simulator step hands its projection.
struct ProjectionSample {
  VecX<double> q, v;
};

/// Per state of the pool, the state one step of the simulator leaves before it projects: its
/// default integrator and step (RK4, 1e-4 s) on the generic backend, no contact, no controller
/// (gravity and the pool's velocities), projection off. What Simulator::project() then closes.
std::shared_ptr<const std::vector<ProjectionSample>> projection_starts(const Model& model, const std::vector<Sample>& pool) {
  sim::SimulatorOptions options;
  options.project = false;
  options.contact = false;
  auto starts = std::make_shared<std::vector<ProjectionSample>>();
  for (const Sample& sample : pool) {
    sim::Simulator<sim::GenericBackend<double>> simulator(sim::GenericBackend<double>(model), options);
    if (simulator.set_state(sample.q.data(), sample.v.data()) != 0 || simulator.step() != sim::StepStatus::ok)
      throw std::runtime_error("bench: cannot step " + model.name);
    starts->push_back({simulator.q(), simulator.v()});
  }
  return starts;
}

/// No generated closure_positions (the scaling chain).
struct NoClosure {
  void operator()(double*) const {}
};

/// A generated close_loops as the simulator's projection calls it: the robot's default options
/// with the projection's tolerance (what the generated Backend's close_loops does).
template <typename Options, typename Result>
auto projection(Result (*close_loops)(double*, double*, const Options&), Options options) {
  options.tolerance = kProjection;
  return [close_loops, options](double* q, double* v) { close_loops(q, v, options); };
}

/// No generated close_loops.
struct NoProjection {
  void operator()(double*, double*) const {}
};

template <typename GeneratedClosure = NoClosure, typename GeneratedProjection = NoProjection>
void add_closed_loop_robot(const std::string& name, const std::string& urdf, const std::string& extras,
                           GeneratedForwardDynamics generated = nullptr, GeneratedClosure generated_closure = {},
                           GeneratedProjection generated_projection = {}) {
  static std::vector<std::unique_ptr<Robot>> robots;  // live as long as the benchmarks
  gen::LoadOptions options;
  if (!extras.empty()) options.extras_file = extras;
  const gen::Description d = gen::load_description(urdf, options);
  auto robot = std::make_unique<Robot>();
  robot->name = name;
  robot->urdf = urdf;
  robot->model = d.model;
  robot->pool = consistent_pool(robot->model, d.model.closures.empty() ? neutral_configuration<double>(d.model) : d.assembly.q);
  const Model* model = &robot->model;
  struct Generic {  // forward_dynamics_loops computes the sub-systems' maps in Data itself
    explicit Generic(const Model& m) : data(m) {}
    Data<double> data;
  };
  struct Reference {
    explicit Reference(const Model& m) : data(m), ws(m) {}
    Data<double> data;
    ConstrainedDynamicsWorkspace<double> ws;
  };
  const std::string algorithm = name.rfind("chain_", 0) == 0 ? "fd_chain" : "fd";
  const std::string label = algorithm == "fd_chain" ? name.substr(6) : name;
  add_benchmark<Sample>(algorithm, label, "generic", robot->pool, [model, w = std::make_shared<Generic>(*model)](const Sample& s) {
    forward_dynamics_loops<double>(*model, w->data, s.q, s.v, s.tau);
    return w->data.ddq.data();
  });
  add_benchmark<Sample>(algorithm, label, "reference", robot->pool, [model, w = std::make_shared<Reference>(*model)](const Sample& s) {
    return forward_dynamics_kkt<double>(*model, w->data, w->ws, s.q, s.v, s.tau).data();
  });
  if (generated) {
    auto pool = std::make_shared<std::vector<IndependentSample>>();
    for (const Sample& sample : *robot->pool) {
      IndependentSample x{sample.q, VecX<double>(static_cast<int>(model->structure().independent_v.size())), sample.tau};
      for (std::size_t i = 0; i < model->structure().independent_v.size(); ++i) x.vy[static_cast<int>(i)] = sample.v[model->structure().independent_v[i]];
      pool->push_back(std::move(x));
    }
    add_benchmark<IndependentSample>(algorithm, label, "generated", pool,
                                     [generated, out = std::make_shared<std::vector<double>>(model->nv())](const IndependentSample& x) {
                                       generated(x.q.data(), x.vy.data(), x.tau.data(), out->data());
                                       return out->data();
                                     });
  }
  if (generated && !model->closures.empty()) {
    std::mt19937_64 rng(77);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    auto pool = std::make_shared<std::vector<ClosureSample>>();
    for (const Sample& sample : *robot->pool) {
      ClosureSample x{sample.q};
      for (const SubSystem& sub : model->subsystems)
        for (int z : sub.dependent) x.q[model->q_index_of_v(z)] += 1e-3 * unit(rng);
      pool->push_back(std::move(x));
    }
    // Both copy the warm start first (Newton works in place).
    add_benchmark<ClosureSample>("closure", label, "generic", pool,
                                 [model, w = std::make_shared<Generic>(*model), q = std::make_shared<VecX<double>>()](const ClosureSample& x) {
                                   *q = x.q;
                                   closure_positions<double>(*model, w->data, *q);
                                   return q->data();
                                 });
    add_benchmark<ClosureSample>("closure", label, "generated", pool,
                                 [generated_closure, q = std::make_shared<VecX<double>>()](const ClosureSample& x) {
                                   *q = x.q;
                                   generated_closure(q->data());
                                   return q->data();
                                 });
    const auto starts = projection_starts(*model, *robot->pool);
    ClosureOptions to_projection;
    to_projection.tolerance = kProjection;
    add_benchmark<ProjectionSample>("project", label, "generic", starts,
                                    [model, to_projection, w = std::make_shared<Generic>(*model), x = std::make_shared<ProjectionSample>()](
                                        const ProjectionSample& start) {
                                      *x = start;
                                      close_loops<double>(*model, w->data, x->q, x->v, to_projection);
                                      return x->q.data();
                                    });
    add_benchmark<ProjectionSample>("project", label, "generated", starts,
                                    [generated_projection, x = std::make_shared<ProjectionSample>()](const ProjectionSample& start) {
                                      *x = start;
                                      generated_projection(x->q.data(), x->v.data());
                                      return x->q.data();
                                    });
  }
  robots.push_back(std::move(robot));
}

}  // namespace

void add_loop_benchmarks() {
  const std::string source = MBGEN_SOURCE_DIR, shared = MBGEN_SHARED_ROBOTS;
  // The generated closure_positions, and close_loops as the simulator's projection calls it.
  add_closed_loop_robot("lola", source + "/robots/lola/lola.urdf", source + "/robots/lola/lola.yaml", &lola::forward_dynamics,
                        [](double* q) { lola::closure_positions(q); },
                        projection(&lola::close_loops, lola::closure_options_double));
  add_closed_loop_robot("lola_legs_transmission", source + "/robots/lola/lola.urdf", source + "/robots/lola/lola_legs_transmission.yaml",
                        &lola_legs_transmission::forward_dynamics);
  add_closed_loop_robot("cassie", shared + "/cassie_mjcf/cassie.xml", "", &cassie_mjcf::forward_dynamics,
                        [](double* q) { cassie_mjcf::closure_positions(q); },
                        projection(&cassie_mjcf::close_loops, cassie_mjcf::closure_options_double));
  add_closed_loop_robot("cassie_like", shared + "/parallel_legs/cassie_like/robot.urdf", "", &pl_cassie_like::forward_dynamics,
                        [](double* q) { pl_cassie_like::closure_positions(q); },
                        projection(&pl_cassie_like::close_loops, pl_cassie_like::closure_options_double));
  add_closed_loop_robot("digit_like_2legs", shared + "/parallel_legs/digit_like_2legs/robot.urdf", "",
                        &pl_digit_like_2legs::forward_dynamics, [](double* q) { pl_digit_like_2legs::closure_positions(q); },
                        projection(&pl_digit_like_2legs::close_loops, pl_digit_like_2legs::closure_options_double));
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "mbgen_bench_loop_chain";
  std::filesystem::create_directories(dir);
  for (int k : {1, 2, 4, 8, 16, 32, 64}) {
    const std::string urdf = write_loop_chain(dir.string(), k);
    add_closed_loop_robot("chain_" + std::to_string(k), urdf, urdf.substr(0, urdf.size() - 5) + ".yaml");
  }
}

}  // namespace mbgen::bench
