#include "peer_pairs.hpp"

#include <algorithm>
#include <iterator>
#include <stdexcept>

#include "bench_support.hpp"
#include "hyq.hpp"
#include "hyq_derivatives.hpp"
#include "iiwa14.hpp"
#include "iiwa14_derivatives.hpp"
#include "model/load_description.hpp"
#include "pl_cassie_like.hpp"
#include "pl_digit_like_2legs.hpp"
#include "pl_talos_like.hpp"
#include "talos.hpp"
#include "talos_derivatives.hpp"

namespace mbgen::peers {
namespace {

const std::string kShared = MBGEN_SHARED_ROBOTS;

// The functions of generated robot NS (trees: its tree outputs, NS_derivatives its derivatives).
#define MBGEN_PEER_TREE(label, NS, path)                                                                         \
  GeneratedTree {                                                                                                \
    label, path, NS::floating_base, NS::nq, NS::nv, {std::begin(NS::joint_names), std::end(NS::joint_names)},   \
        &NS::forward_dynamics, &NS::inverse_dynamics, &NS::mass_matrix, &NS##_derivatives::forward_dynamics_derivatives, \
        &NS##_derivatives::inverse_dynamics_derivatives                                                          \
  }
#define MBGEN_PEER_LOOPS(label, NS, path)                                                                             \
  GeneratedLoops {                                                                                                    \
    label, path, NS::nq, NS::nv, NS::ny, {std::begin(NS::joint_names), std::end(NS::joint_names)},                  \
        {std::begin(NS::independent_v_index), std::end(NS::independent_v_index)}, &NS::forward_dynamics,            \
        &NS::full_accelerations, [](double* q, int* iterations) {          \
          const auto r = NS::closure_positions(q);                                                                   \
          *iterations = r.iterations;                                                                                \
          return static_cast<int>(r.status);                                                                         \
        }       \
  }

}  // namespace

std::vector<TreePair> tree_pairs() {
  std::vector<GeneratedTree> trees = {
      MBGEN_PEER_TREE("iiwa14", iiwa14, "iiwa14/iiwa14_primitive_collision.urdf"),
      MBGEN_PEER_TREE("hyq", hyq, "hyq/hyq_no_sensors.urdf"),
      MBGEN_PEER_TREE("talos", talos, "talos/talos_reduced.urdf"),
  };
  std::vector<TreePair> pairs;
  for (GeneratedTree& g : trees) {
    TreePair p;
    p.pinocchio = std::make_unique<PinocchioRobot>(kShared + "/" + g.urdf, g.floating);
    p.map = std::make_unique<JointMap>(*p.pinocchio, g.joint_names, g.floating, g.nq, g.nv);
    // The bench's states of this robot (bench_support.hpp: the same seed as every other benchmark).
    const bench::Robot robot = bench::load_robot(g.robot, g.urdf, g.floating ? gen::BaseType::Floating : gen::BaseType::Fixed);
    if (robot.model.nq() != g.nq || robot.model.nv() != g.nv) throw std::runtime_error("peer: " + g.robot + ": model and generated code differ");
    auto states = std::make_shared<std::vector<TreeState>>();
    for (const bench::Sample& s : *robot.pool) {
      TreeState x{s.q, s.v, s.a, s.tau, p.map->q_to_pinocchio(s.q), p.map->v_to_pinocchio(s.v), p.map->v_to_pinocchio(s.a),
                  p.map->v_to_pinocchio(s.tau)};
      states->push_back(std::move(x));
    }
    p.states = std::move(states);
    p.generated = std::move(g);
    pairs.push_back(std::move(p));
  }
  return pairs;
}

std::vector<LoopPair> loop_pairs() {
  std::vector<GeneratedLoops> robots = {
      MBGEN_PEER_LOOPS("cassie_like", pl_cassie_like, "parallel_legs/cassie_like/robot.urdf"),
      MBGEN_PEER_LOOPS("talos_like", pl_talos_like, "parallel_legs/talos_like/robot.urdf"),
      MBGEN_PEER_LOOPS("digit_like_2legs", pl_digit_like_2legs, "parallel_legs/digit_like_2legs/robot.urdf"),
  };
  std::vector<LoopPair> pairs;
  for (GeneratedLoops& g : robots) {
    const std::string urdf = kShared + "/" + g.urdf;
    const gen::Description d = gen::load_description(urdf, gen::LoadOptions{});
    if (d.model.nq() != g.nq || d.model.nv() != g.nv) throw std::runtime_error("peer: " + g.robot + ": model and generated code differ");
    if (g.nq != g.nv) throw std::runtime_error("peer: " + g.robot + ": a closed-loop robot here has a fixed base (predicted_start adds v to q)");
    // Pinocchio's model from what mbgen read of the robot.yaml beside the URDF: the revolute
    // joints standing for ball (SPHERICAL) and universal (UJOINT_XY) joints, and the frame pairs.
    std::vector<RevoluteChain> chains;
    for (const auto& [joint, type] : d.joint_type_overrides) chains.push_back({joint, type == "SPHERICAL" ? 3 : 2});
    LoopPair p;
    p.pinocchio = std::make_unique<PinocchioRobot>(urdf, false, chains);
    for (const gen::ClosureSpec& c : d.closures) p.pinocchio->add_closure(c.frame_a, c.frame_b);
    p.map = std::make_unique<JointMap>(*p.pinocchio, g.joint_names, false, g.nq, g.nv);
    // The bench's closed states of this robot (bench_loops.cpp's pool).
    const auto pool = bench::consistent_pool(d.model, d.assembly.q);
    auto states = std::make_shared<std::vector<LoopState>>();
    for (const bench::Sample& s : *pool) {
      LoopState x;
      x.q = s.q;
      x.v = s.v;
      x.tau = s.tau;
      x.vy.resize(g.ny);
      for (int k = 0; k < g.ny; ++k) x.vy[k] = s.v[g.independent_v_index[static_cast<std::size_t>(k)]];
      x.warm_q = s.q;
      for (int k = 0; k < g.ny; ++k) x.warm_q[g.independent_v_index[static_cast<std::size_t>(k)]] += kStep * x.vy[k];
      x.pinocchio_q = p.map->q_to_pinocchio(s.q);
      x.pinocchio_v = p.map->v_to_pinocchio(s.v);
      x.pinocchio_tau = p.map->v_to_pinocchio(s.tau);
      states->push_back(std::move(x));
    }
    p.states = std::move(states);
    p.generated = std::move(g);
    pairs.push_back(std::move(p));
  }
  return pairs;
}

TreeAgreement check(TreePair& pair) {
  const GeneratedTree& g = pair.generated;
  PinocchioRobot& pin = *pair.pinocchio;
  const JointMap& map = *pair.map;
  const int n = g.nv;
  TreeAgreement worst;
  Eigen::VectorXd out(n);
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  RowMajor m1(n, n), m2(n, n), m3(n, n);
  for (const TreeState& s : *pair.states) {
    g.forward_dynamics(s.q.data(), s.v.data(), s.tau.data(), out.data());
    worst.forward_dynamics = std::max(worst.forward_dynamics, relative_error(out, map.v_from_pinocchio(pin.aba(s.pinocchio_q, s.pinocchio_v, s.pinocchio_tau))));
    g.inverse_dynamics(s.q.data(), s.v.data(), s.a.data(), out.data());
    worst.inverse_dynamics = std::max(worst.inverse_dynamics, relative_error(out, map.v_from_pinocchio(pin.rnea(s.pinocchio_q, s.pinocchio_v, s.pinocchio_a))));
    g.mass_matrix(s.q.data(), m1.data());
    worst.mass_matrix = std::max(worst.mass_matrix, relative_error(m1, map.matrix_from_pinocchio(pin.crba(s.pinocchio_q))));

    g.forward_dynamics_derivatives(s.q.data(), s.v.data(), s.tau.data(), out.data(), m1.data(), m2.data(), m3.data());
    pin.aba_derivatives(s.pinocchio_q, s.pinocchio_v, s.pinocchio_tau);
    worst.fd_derivatives = std::max({worst.fd_derivatives, relative_error(out, map.v_from_pinocchio(pin.ddq())),
                                     relative_error(m1, map.matrix_from_pinocchio(pin.ddq_dq())),
                                     relative_error(m2, map.matrix_from_pinocchio(pin.ddq_dv())),
                                     relative_error(m3, map.matrix_from_pinocchio(pin.minv()))});
    g.inverse_dynamics_derivatives(s.q.data(), s.v.data(), s.a.data(), out.data(), m1.data(), m2.data());
    pin.rnea_derivatives(s.pinocchio_q, s.pinocchio_v, s.pinocchio_a);
    worst.id_derivatives = std::max({worst.id_derivatives, relative_error(m1, map.matrix_from_pinocchio(pin.dtau_dq())),
                                     relative_error(m2, map.matrix_from_pinocchio(pin.dtau_dv()))});
  }
  return worst;
}

LoopAgreement check(LoopPair& pair) {
  const GeneratedLoops& g = pair.generated;
  PinocchioRobot& pin = *pair.pinocchio;
  LoopAgreement worst;
  Eigen::VectorXd full(g.nv), independent(g.ny);
  for (const LoopState& s : *pair.states) {
    g.full_accelerations(s.q.data(), s.vy.data(), s.tau.data(), full.data());
    const Eigen::VectorXd reference = pair.map->v_from_pinocchio(pin.constraint_dynamics(s.pinocchio_q, s.pinocchio_v, s.pinocchio_tau, true));
    worst.full_accelerations = std::max(worst.full_accelerations, relative_error(full, reference));
    g.forward_dynamics(s.q.data(), s.vy.data(), s.tau.data(), independent.data());
    for (int k = 0; k < g.ny; ++k)
      worst.forward_dynamics = std::max(worst.forward_dynamics, std::abs(independent[k] - full[g.independent_v_index[static_cast<std::size_t>(k)]]) /
                                                                    std::max(1.0, full.cwiseAbs().maxCoeff()));
    worst.pinocchio_closure = std::max(worst.pinocchio_closure, pin.closure_error(s.pinocchio_q));
    Eigen::VectorXd start = s.warm_q;
    int iterations = 0;
    if (g.closure_positions(start.data(), &iterations) == 0) ++worst.warm_closures_converged;
    worst.warm_iterations += iterations;
    predicted_start(s, start);
    if (g.closure_positions(start.data(), &iterations) == 0) ++worst.predicted_closures_converged;
    worst.predicted_iterations += iterations;
  }
  return worst;
}

}  // namespace mbgen::peers
