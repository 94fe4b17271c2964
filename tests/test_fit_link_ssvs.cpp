// Each link's meshes and boxes fitted with SSVs (generator/load/fit_link_ssvs.cpp): TALOS from its
// own meshes, a URDF the test writes (box, scaled and mirrored mesh, visual-only mesh, missing
// mesh, zero scale), `scene: collision: fit`, and the extras' compounds left alone.
#include "load/fit_link_ssvs.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "collision/collision_scene.hpp"
#include "load/load_error.hpp"
#include "mesh/read_mesh.hpp"
#include "mesh_shapes.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

namespace fs = std::filesystem;

const std::string kTalos = shared_robot("talos/talos_reduced.urdf");
const std::string kTalosMeshes = shared_robot("talos/meshes/example-robot-data");

/// Every vertex of every mesh of the link, placed in the link's frame as the fit placed it, lies
/// inside the link's compound in d.ssv (after the YAML-sized rounding): largest excess returned.
double largest_vertex_outside(const gen::Description& d, const gen::LinkFit& fit) {
  std::vector<mesh::FittedPrimitive> compound;
  for (const gen::SsvPrimitive& p : d.ssv.at(fit.link)) compound.push_back({p.points, p.radius});
  double worst = -1e300;
  std::size_t k = 0;
  for (const gen::MeshGeometry& g : d.link_meshes.at(fit.link)) {
    mesh::TriangleMesh m;
    if (g.box)
      mesh::append_transformed(mesh::box_mesh(g.scale), Vec3<double>::Ones(), g.X_LG, m);
    else
      mesh::append_transformed(mesh::read_mesh(fit.sources.at(k)), g.scale, g.X_LG, m);
    ++k;
    for (const auto& v : m.vertices) worst = std::max(worst, mesh::distance_to_compound(v, compound));
  }
  return worst;
}

TEST(FitLinkSsvs, TalosGetsACompleteModelFromItsOwnMeshes) {
  gen::LoadOptions options;
  options.base = gen::BaseType::Floating;
  gen::Description d = gen::load_description(kTalos, options);
  ASSERT_EQ(d.link_meshes.size(), 48u);  // every link with collision geometry
  const std::vector<gen::LinkFit> fits = gen::fit_link_ssvs(d, {{"example-robot-data", kTalosMeshes}}, mesh::FitOptions{});
  ASSERT_EQ(fits.size(), 48u);
  for (const std::string& w : d.warnings) EXPECT_EQ(w.find("gets no fitted SSV"), std::string::npos) << w;
  int primitives = 0;
  for (const gen::LinkFit& f : fits) {
    EXPECT_LE(largest_vertex_outside(d, f), 0.0) << f.link;
    EXPECT_LE(f.compound.primitives.size(), 4u) << f.link;
    // Stated factor on a real robot: no compound more than 2.5 times its meshes' convex hull.
    EXPECT_LE(f.compound.report.volume, 2.5 * f.compound.report.hull_volume) << f.link;
    primitives += static_cast<int>(f.compound.primitives.size());
  }
  EXPECT_LE(primitives, 4 * 48);
  // The collision scene takes the compounds: TALOS now has pairs to keep and prune.
  gen::CollisionSceneOptions collision;
  collision.samples = 500;
  const gen::CollisionScene scene = gen::build_collision_scene(d, collision);
  int kept = 0, pruned = 0;
  for (const gen::PairDecision& p : scene.decisions) (p.verdict == gen::PairVerdict::Kept ? kept : pruned)++;
  EXPECT_GT(kept, 100);
  EXPECT_GT(pruned, 10);
}

/// A small URDF with one link per case, and a tetrahedron STL in a package folder.
struct Written {
  fs::path urdf, package;
};

Written write_robot() {
  const fs::path dir = fs::temp_directory_path() / "mbgen_test_fit_link_ssvs";
  fs::create_directories(dir / "pkg" / "meshes");
  {
    std::ofstream out(dir / "pkg" / "meshes" / "tet.obj");
    out << "v 0 0 0\nv 0.1 0 0\nv 0 0.2 0\nv 0 0 0.3\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";
  }
  const auto link = [](const std::string& name, const std::string& body) {
    return "  <link name=\"" + name + "\">\n    <inertial><mass value=\"1\"/><inertia ixx=\"0.01\" iyy=\"0.01\" izz=\"0.01\" ixy=\"0\" ixz=\"0\" iyz=\"0\"/></inertial>\n" + body + "  </link>\n";
  };
  const auto joint = [](const std::string& parent, const std::string& child) {
    return "  <joint name=\"" + child + "_joint\" type=\"revolute\"><parent link=\"" + parent + "\"/><child link=\"" + child +
           "\"/><origin xyz=\"0 0 0.5\"/><axis xyz=\"0 1 0\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>\n";
  };
  const std::string mesh = "package://pkg/meshes/tet.obj";
  std::string urdf = "<?xml version=\"1.0\"?>\n<robot name=\"fit\">\n";
  urdf += link("base", "    <collision><origin xyz=\"0 0 0.1\"/><geometry><box size=\"0.2 0.1 0.05\"/></geometry></collision>\n");
  urdf += link("scaled", "    <collision><origin xyz=\"0.01 0 0\" rpy=\"0 0 1.5707963267948966\"/><geometry><mesh filename=\"" + mesh +
                             "\" scale=\"2 -1 1\"/></geometry></collision>\n");
  urdf += link("visual_only", "    <visual><geometry><mesh filename=\"" + mesh + "\"/></geometry></visual>\n");
  urdf += link("missing", "    <collision><geometry><mesh filename=\"package://pkg/meshes/absent.stl\"/></geometry></collision>\n");
  urdf += link("flat", "    <collision><geometry><mesh filename=\"" + mesh + "\" scale=\"1 0 1\"/></geometry></collision>\n");
  urdf += link("both", "    <collision><geometry><cylinder radius=\"0.02\" length=\"0.2\"/></geometry></collision>\n"
                       "    <collision><origin xyz=\"0 0 0.3\"/><geometry><box size=\"0.05 0.05 0.05\"/></geometry></collision>\n");
  urdf += joint("base", "scaled") + joint("scaled", "visual_only") + joint("visual_only", "missing") + joint("missing", "flat") +
          joint("flat", "both");
  urdf += "</robot>\n";
  std::ofstream(dir / "fit.urdf") << urdf;
  return {dir / "fit.urdf", dir / "pkg"};
}

TEST(FitLinkSsvs, BoxesScaledMirroredAndVisualMeshesAndWarningsForBadOnes) {
  const Written w = write_robot();
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  gen::Description d = gen::read_description(w.urdf.string(), options);
  const std::vector<gen::LinkFit> fits = gen::fit_link_ssvs(d, {{"pkg", w.package.string()}}, mesh::FitOptions{});
  std::vector<std::string> fitted;
  for (const gen::LinkFit& f : fits) {
    fitted.push_back(f.link);
    EXPECT_LE(largest_vertex_outside(d, f), 0.0) << f.link;
  }
  EXPECT_EQ(fitted, (std::vector<std::string>{"base", "both", "scaled", "visual_only"}));
  // The cylinder of `both` stays and the box's compound comes after it.
  ASSERT_GE(d.ssv.at("both").size(), 2u);
  EXPECT_EQ(d.ssv.at("both")[0].kind, gen::SsvPrimitive::Kind::Line);
  EXPECT_NE(d.ssv.at("both")[1].source.find("fitted to box"), std::string::npos);
  // The mirrored, scaled, rotated mesh: its far corner (0.1 * 2, 0, 0) -> rotated 90 deg about z
  // -> (0, 0.2, 0) + (0.01, 0, 0) lies on the compound's surface within the 1 um rounding.
  std::vector<mesh::FittedPrimitive> scaled;
  for (const auto& p : d.ssv.at("scaled")) scaled.push_back({p.points, p.radius});
  EXPECT_NEAR(mesh::distance_to_compound(Vec3<double>(0.01, 0.2, 0), scaled), 0.0, 0.2);  // inside
  EXPECT_LE(mesh::distance_to_compound(Vec3<double>(0.01, 0.2, 0), scaled), 0.0);
  // Warnings name the link and the file, and say how to fix it.
  int missing = 0, flat = 0;
  for (const std::string& warning : d.warnings) {
    if (warning.find("link 'missing'") != std::string::npos && warning.find("absent.stl: no such file") != std::string::npos) ++missing;
    if (warning.find("link 'flat'") != std::string::npos && warning.find("must be finite and not zero") != std::string::npos) ++flat;
  }
  EXPECT_EQ(missing, 1);
  EXPECT_EQ(flat, 1);
  EXPECT_EQ(d.ssv.count("missing"), 0u);
  EXPECT_EQ(d.ssv.count("flat"), 0u);
  EXPECT_THROW(gen::fit_link_ssvs(d, {}, mesh::FitOptions{0, 0.05}), std::invalid_argument);
}

fs::path write_extras(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / "mbgen_test_fit_link_ssvs" / name;
  std::ofstream(p) << text;
  return p;
}

TEST(FitLinkSsvs, SceneFitOnLoadWithItsBudgetAndTheExtrasCompoundsLeftAlone) {
  const Written w = write_robot();
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  options.package_paths = {{"pkg", w.package.string()}};
  options.extras_file = write_extras("fit.yaml", "ssv:\n  base: [{point: [0, 0, 0], radius: 0.3}]\n"
                                                 "scene:\n  collision: {fit: true, fit_budget: 1}\n").string();
  const gen::Description d = gen::read_description(w.urdf.string(), options);
  ASSERT_EQ(d.ssv.at("base").size(), 1u);
  EXPECT_EQ(d.ssv.at("base")[0].radius, 0.3);  // the extras' own
  ASSERT_EQ(d.ssv.at("scaled").size(), 1u);     // budget 1
  ASSERT_EQ(d.ssv.at("visual_only").size(), 1u);
  int notes = 0;
  for (const std::string& n : d.notes) notes += n.find("SSV primitives fitted to") != std::string::npos;
  EXPECT_EQ(notes, 3);  // scaled, visual_only, both

  options.apply_scene_fit = false;  // what fit-ssv does: no fit on load
  EXPECT_EQ(gen::read_description(w.urdf.string(), options).ssv.count("scaled"), 0u);

  for (const char* bad : {"fit_budget: 0", "fit_budget: 2.5", "fit: maybe"}) {
    options.extras_file = write_extras("bad.yaml", std::string("scene:\n  collision: {") + bad + "}\n").string();
    try {
      gen::read_description(w.urdf.string(), options);
      ADD_FAILURE() << bad << ": no error";
    } catch (const gen::LoadError& e) {
      EXPECT_NE(std::string(e.what()).find("bad.yaml:2"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("scene: collision: fit"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace mbgen::test
