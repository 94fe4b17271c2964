// mbgen_bench: dynamics algorithms per robot and implementation, named
// `<algorithm>/<robot>/<implementation>` (see bench/README.md).
//
//   algorithms       aba, rnea, crba, jacobians (the leaf frames' Jacobians), centroidal
//                    (centroidal_momentum_matrix)
//   robots           iiwa14 (fixed base, nv 7), hyq (floating, nv 18), talos (floating, talos_reduced, nv 38)
//   implementations  generic (mbgen's runtime instantiated with double),
//                    generated (the code `mbgen generate` emits, bench_generated.cpp),
//                    kdl (orocos-kdl: every algorithm on the iiwa14 chain; rnea on hyq and talos
//                    as a tree with six virtual base joints)
//
// Every implementation of one robot runs on the same seeded states (bench_support.hpp).
#include <cstdio>
#include <exception>
#include <map>

#include <kdl/chain.hpp>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfdsolver_recursive_newton_euler.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/jntspaceinertiamatrix.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include "bench_derivatives.hpp"
#include "bench_generated.hpp"
#include "bench_loops.hpp"
#ifdef MBGEN_BENCH_PEERS
#include "peers/bench_peers.hpp"
#endif
#include "bench_sim.hpp"
#include "bench_rotor.hpp"
#include "bench_self_distance.hpp"
#include "bench_support.hpp"
#include "kdl_from_urdf.hpp"
#include "model/load_description.hpp"

namespace mbgen::bench {
namespace {

/// The generic runtime: every algorithm on every robot, each benchmark with its own Data.
void add_generic(const Robot& robot) {
  const Model* model = &robot.model;  // robots outlive the benchmarks (see main)
  add_benchmark("aba", robot, "generic", [model, data = std::make_shared<Data<double>>(*model)](const Sample& s) {
    return aba<double>(*model, *data, s.q, s.v, s.tau).data();
  });
  add_benchmark("rnea", robot, "generic", [model, data = std::make_shared<Data<double>>(*model)](const Sample& s) {
    return rnea<double>(*model, *data, s.q, s.v, s.a).data();
  });
  add_benchmark("crba", robot, "generic", [model, data = std::make_shared<Data<double>>(*model)](const Sample& s) {
    return crba<double>(*model, *data, s.q).data();
  });
  // The leaf bodies' frame Jacobians (LocalWorldAligned): the generated code's default output.
  auto leaves = std::make_shared<std::vector<FrameIndex>>();
  for (int k = 1; k < model->num_bodies(); ++k)
    if (model->body(BodyIndex(k)).children.empty()) leaves->push_back(model->frame_index(model->body(BodyIndex(k)).name));
  add_benchmark("jacobians", robot, "generic",
                [model, leaves, data = std::make_shared<Data<double>>(*model),
                 J = std::make_shared<Mat6X<double>>(6, model->nv())](const Sample& s) {
                  compute_joint_jacobians<double>(*model, *data, s.q);
                  for (FrameIndex f : *leaves) frame_jacobian<double>(*model, *data, f, ReferenceFrame::LocalWorldAligned, *J);
                  return J->data();
                });
  add_benchmark("centroidal", robot, "generic",
                [model, data = std::make_shared<Data<double>>(*model)](const Sample& s) {
                  return centroidal_momentum_matrix<double>(*model, *data, s.q).data();
                });
}

/// One state in KDL's types, joints in chain order.
struct KdlSample {
  KDL::JntArray q, v, a, tau;
};

/// Work memory of the KDL solvers for one chain (the solvers keep a reference to the chain).
struct KdlSolvers {
  explicit KdlSolvers(KDL::Chain c, const Vec3<double>& g)
      : chain(std::move(c)),
        grav(g.x(), g.y(), g.z()),
        id(chain, grav),
        fd(chain, grav),
        dyn(chain, grav),
        jac(chain),
        f_ext(chain.getNrOfSegments(), KDL::Wrench::Zero()),
        out(chain.getNrOfJoints()),
        H(chain.getNrOfJoints()),
        J(chain.getNrOfJoints()) {}
  KDL::Chain chain;
  KDL::Vector grav;
  KDL::ChainIdSolver_RNE id;
  KDL::ChainFdSolver_RNE fd;
  KDL::ChainDynParam dyn;
  KDL::ChainJntToJacSolver jac;
  KDL::Wrenches f_ext;
  KDL::JntArray out;
  KDL::JntSpaceInertiaMatrix H;
  KDL::Jacobian J;
};

/// orocos-kdl on a fixed-base robot: the chain root -> tip built from the URDF through urdfdom.
///   aba       = ChainFdSolver_RNE::CartToJnt   (KDL's forward dynamics: JntToMass + RNE + LDL, O(n^3))
///   rnea      = ChainIdSolver_RNE::CartToJnt
///   crba      = ChainDynParam::JntToMass
///   jacobians = ChainJntToJacSolver::JntToJac  (the tip's 6 x n Jacobian; mbgen's computes every
///               joint column in the world frame, the same O(n) work)
void add_kdl(const Robot& robot, const std::string& root, const std::string& tip) {
  const KDL::Tree tree = peer::kdl_tree_from_urdf_file(robot.urdf);
  KDL::Chain chain = peer::kdl_chain_with_welded_branches(tree, root, tip);
  std::vector<int> index;  // mbgen v index of each chain joint
  for (const std::string& name : peer::kdl_chain_joint_names(chain)) {
    auto j = robot.model.find_joint(name);
    if (!j) throw std::runtime_error("KDL chain joint '" + name + "' is not in mbgen's model of " + robot.name);
    index.push_back(robot.model.joint(*j).idx_v);
  }
  if (static_cast<int>(index.size()) != robot.model.nv())
    throw std::runtime_error("the KDL chain of " + robot.name + " does not cover every joint");
  auto to_kdl = [&](const VecX<double>& x) {
    KDL::JntArray out(index.size());
    for (std::size_t k = 0; k < index.size(); ++k) out(k) = x[index[k]];
    return out;
  };
  auto pool = std::make_shared<std::vector<KdlSample>>();
  for (const Sample& s : *robot.pool) pool->push_back({to_kdl(s.q), to_kdl(s.v), to_kdl(s.a), to_kdl(s.tau)});
  std::shared_ptr<const std::vector<KdlSample>> inputs = pool;
  const Vec3<double> g = robot.model.gravity;

  add_benchmark<KdlSample>("aba", robot.name, "kdl", inputs,
                           [w = std::make_shared<KdlSolvers>(chain, g)](const KdlSample& s) {
                             w->fd.CartToJnt(s.q, s.v, s.tau, w->f_ext, w->out);
                             return w->out.data.data();
                           });
  add_benchmark<KdlSample>("rnea", robot.name, "kdl", inputs,
                           [w = std::make_shared<KdlSolvers>(chain, g)](const KdlSample& s) {
                             w->id.CartToJnt(s.q, s.v, s.a, w->f_ext, w->out);
                             return w->out.data.data();
                           });
  add_benchmark<KdlSample>("crba", robot.name, "kdl", inputs,
                           [w = std::make_shared<KdlSolvers>(chain, g)](const KdlSample& s) {
                             w->dyn.JntToMass(s.q, w->H);
                             return w->H.data.data();
                           });
  add_benchmark<KdlSample>("jacobians", robot.name, "kdl", inputs,
                           [w = std::make_shared<KdlSolvers>(chain, g)](const KdlSample& s) {
                             w->jac.JntToJac(s.q, w->J);
                             return w->J.data.data();
                           });
}

/// orocos-kdl's inverse dynamics on a floating-base robot: TreeIdSolver_RNE on the tree with six
/// virtual joints (x, y, z, roll, pitch, yaw) under the root link (kdl_floating_tree_from_urdf_file,
/// checked against mbgen in test_peer_kdl's PeerKdlFloating), the way KDL users model a floating
/// base. The same nv as mbgen's floating joint; the virtual joints take the sample's base entries
/// (positions from q[0..5], so the quaternion's x, y, z serve as angles).
void add_kdl_floating_rnea(const Robot& robot) {
  const KDL::Tree tree = peer::kdl_floating_tree_from_urdf_file(robot.urdf);
  const std::map<std::string, unsigned> tree_index = peer::kdl_tree_joint_indices(tree);
  const Model& model = robot.model;
  if (static_cast<int>(tree_index.size()) != model.nv())
    throw std::runtime_error("the floating KDL tree of " + robot.name + " does not match mbgen's nv");
  const char* base_joints[] = {"floating_x", "floating_y", "floating_z", "floating_rx", "floating_ry", "floating_rz"};
  std::vector<unsigned> kdl_of_v(model.nv());
  for (int k = 0; k < 6; ++k) kdl_of_v[k] = tree_index.at(base_joints[k]);
  for (int j = 2; j < model.num_joints(); ++j) kdl_of_v[model.joint(JointIndex(j)).idx_v] = tree_index.at(model.joint(JointIndex(j)).name);
  auto to_kdl = [&](const VecX<double>& x, int offset) {  // offset: where the joints start in x (q: 7, v: 6)
    KDL::JntArray out(model.nv());
    for (int k = 0; k < 6; ++k) out(kdl_of_v[k]) = x[k];
    for (int k = 6; k < model.nv(); ++k) out(kdl_of_v[k]) = x[offset + k - 6];
    return out;
  };
  auto pool = std::make_shared<std::vector<KdlSample>>();
  for (const Sample& s : *robot.pool) pool->push_back({to_kdl(s.q, 7), to_kdl(s.v, 6), to_kdl(s.a, 6), to_kdl(s.tau, 6)});
  std::shared_ptr<const std::vector<KdlSample>> inputs = pool;
  const Vec3<double> g = model.gravity;
  struct Work {
    Work(const KDL::Tree& t, const Vec3<double>& g, int n) : tree(t), solver(tree, KDL::Vector(g.x(), g.y(), g.z())), out(n) {}
    KDL::Tree tree;
    KDL::TreeIdSolver_RNE solver;
    KDL::JntArray out;
  };
  add_benchmark<KdlSample>("rnea", robot.name, "kdl", inputs,
                           [w = std::make_shared<Work>(tree, g, model.nv())](const KdlSample& s) {
                             w->solver.CartToJnt(s.q, s.v, s.a, KDL::WrenchMap(), w->out);
                             return w->out.data.data();
                           });
}

}  // namespace
}  // namespace mbgen::bench

int main(int argc, char** argv) {
  using namespace mbgen;
  using namespace mbgen::bench;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  // The robots live until the benchmarks have run: the registered callables point into them.
  std::vector<Robot> robots;
  try {
    robots.push_back(load_robot("iiwa14", "iiwa14/iiwa14_primitive_collision.urdf", gen::BaseType::Fixed));
    robots.push_back(load_robot("hyq", "hyq/hyq_no_sensors.urdf", gen::BaseType::Floating));
    robots.push_back(load_robot("talos", "talos/talos_reduced.urdf", gen::BaseType::Floating));
    for (const Robot& robot : robots) add_generic(robot);
    for (const Robot& robot : robots) add_generated(robot);
    for (const Robot& robot : robots) add_derivative_benchmarks(robot);
    add_rotor_benchmarks();
    add_self_distance_benchmarks();
    add_loop_benchmarks();
    add_loop_derivative_benchmarks();
    add_sim_benchmarks();
    add_kdl(robots[0], "base", "iiwa_link_ee");
    add_kdl_floating_rnea(robots[1]);
    add_kdl_floating_rnea(robots[2]);
#ifdef MBGEN_BENCH_PEERS
    add_peer_benchmarks();
#endif
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mbgen_bench: %s\n", e.what());
    return 1;
  }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
