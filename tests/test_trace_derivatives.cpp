// The traced derivatives (generator/codegen/trace_derivatives.cpp) and the axes their sweep runs in
// (SweepAxes, rnea_derivatives.hpp): a floating base's translation columns of dtau/dq are exact
// zeros in the trace (tau does not depend on where the robot stands), and in the root's axes the
// trace is shorter than in the world's. That both axes give the same numbers is test_rnea_derivatives'.
#include <gtest/gtest.h>

#include "codegen/trace_derivatives.hpp"
#include "codegen/trace_support.hpp"
#include "mbgen/algorithm/rnea_derivatives.hpp"
#include "test_support.hpp"

namespace mbgen::codegen {
namespace {

using namespace tracing;

/// The inverse dynamics' derivatives traced in `axes`: the function with tau, dtau/dq and dtau/dv.
TracedFunction traced_in(const Model& tree, SweepAxes axes) {
  TracedFunction f;
  Recording rec(f.graph);
  Data<Sym> data(tree);
  DynamicsDerivatives<Sym> d(tree, axes);
  inverse_dynamics_derivatives<Sym>(tree, data, d, inputs(0, tree.nq()), inputs(1, tree.nv()), inputs(2, tree.nv()));
  const int n = tree.nv();
  f.outputs = {{"tau", n, ""}, {"dtau_dq", n * n, ""}, {"dtau_dv", n * n, ""}};
  f.output_ids = {ids_of(d.tau), ids_of(d.dtau_dq), ids_of(d.dtau_dv)};
  return f;
}

const std::string kTalos = test::shared_robot("talos/talos_reduced.urdf");

TEST(TraceDerivatives, FloatingBasesTranslationColumnsAreZeros) {
  const Model tree = test::load_tree(kTalos, gen::BaseType::Floating);
  const TracedFunction f = trace_inverse_dynamics_derivatives(tree);
  const int nv = tree.nv();
  for (int r = 0; r < nv; ++r)
    for (int c = 0; c < 3; ++c) EXPECT_TRUE(f.graph.is_constant(f.output_ids[1][static_cast<std::size_t>(r * nv + c)], 0.0)) << r << ", " << c;
  // The rotations' columns are not: turning the base turns the gravity.
  for (int c = 3; c < 6; ++c) EXPECT_FALSE(f.graph.is_constant(f.output_ids[1][static_cast<std::size_t>(6 * nv + c)])) << c;
}

TEST(TraceDerivatives, RootAxesTraceFewerOperations) {
  // talos_reduced: 33,184 against 40,331 (-18 %); iiwa14 on its fixed base: its first joint's
  // column is constant too.
  for (const auto& [path, base, at_most] :
       {std::tuple{kTalos, gen::BaseType::Floating, 0.85},
        std::tuple{test::shared_robot("iiwa14/iiwa14_primitive_collision.urdf"), gen::BaseType::Fixed, 0.97}}) {
    SCOPED_TRACE(path);
    const Model tree = test::load_tree(path, base);
    const int root = count_operations(traced_in(tree, SweepAxes::root)).total();
    const int world = count_operations(traced_in(tree, SweepAxes::world)).total();
    EXPECT_LT(root, at_most * world) << root << " against " << world;
    EXPECT_EQ(root, count_operations(trace_inverse_dynamics_derivatives(tree)).total());  // the generated one's
  }
}

TEST(TraceDerivatives, SeveralBodiesOnTheWorldSweepInItsAxes) {
  const Model tree = test::load_tree(kTalos, gen::BaseType::Floating);
  EXPECT_TRUE(DynamicsDerivatives<double>(tree, SweepAxes::root).root_axes);
  EXPECT_FALSE(DynamicsDerivatives<double>(tree, SweepAxes::world).root_axes);
  Model two_roots = tree;
  Joint hinge;
  hinge.name = "second_root_joint";
  hinge.axis = Vec3<double>::UnitZ();
  Inertia<double> I;
  I.mass = 1;
  I.inertia_com = Mat3<double>::Identity() * 0.01;
  two_roots.add_body(kWorldBody, hinge, "second_root", I);
  EXPECT_FALSE(DynamicsDerivatives<double>(two_roots, SweepAxes::root).root_axes);
}

}  // namespace
}  // namespace mbgen::codegen
