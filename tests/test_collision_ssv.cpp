// SSVs from URDF collision geometry (generator/load/collision_ssv.cpp): spheres become point-SSVs,
// cylinders line-SSVs along their axis; boxes and meshes are counted, not modelled; the extras'
// `ssv:` replaces a link's compound. Expected endpoints are worked out by hand from the files.
#include <gtest/gtest.h>

#include "test_support.hpp"

namespace mbgen::test {
namespace {

using Kind = gen::SsvPrimitive::Kind;
const std::string kData = MBGEN_TEST_DATA;

gen::Description load(const std::string& urdf, const std::string& extras = "") {
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  if (!extras.empty()) options.extras_file = extras;
  return gen::load_description(urdf, options);
}

TEST(CollisionSsv, SpheresAndCylindersBecomePointAndLineSsvs) {
  const gen::Description d = load(kData + "/collision_shapes.urdf");
  ASSERT_EQ(d.ssv.count("base"), 1u);
  const auto& base = d.ssv.at("base");
  ASSERT_EQ(base.size(), 2u);
  EXPECT_EQ(base[0].kind, Kind::Point);
  EXPECT_LT((base[0].points[0] - Vec3<double>(0.1, 0.2, 0.3)).norm(), 1e-15);
  EXPECT_EQ(base[0].radius, 0.05);
  // Pitch +90 deg turns the cylinder's z axis into +x: ends at x = -0.1 and +0.1, z = 0.5.
  EXPECT_EQ(base[1].kind, Kind::Line);
  EXPECT_LT((base[1].points[0] - Vec3<double>(-0.1, 0, 0.5)).norm(), 1e-15);
  EXPECT_LT((base[1].points[1] - Vec3<double>(0.1, 0, 0.5)).norm(), 1e-15);
  EXPECT_EQ(base[1].radius, 0.04);
  EXPECT_NE(base[1].source.find("collision_shapes.urdf:4: <collision> 2 of link 'base'"), std::string::npos) << base[1].source;
  EXPECT_EQ(d.collision_geometry_not_modelled.at("box"), 1);
  EXPECT_EQ(d.collision_geometry_not_modelled.at("mesh"), 1);
  ASSERT_EQ(d.ssv.at("arm").size(), 1u);
  EXPECT_EQ(d.ssv.at("arm")[0].radius, 0.07);
}

TEST(CollisionSsv, ExtrasReplaceALinksCompound) {
  const gen::Description d = load(kData + "/collision_shapes.urdf", kData + "/extras/arm_ssv.yaml");
  const auto& arm = d.ssv.at("arm");
  ASSERT_EQ(arm.size(), 1u);
  EXPECT_EQ(arm[0].kind, Kind::Line);
  EXPECT_EQ(arm[0].radius, 0.03);
  EXPECT_NE(arm[0].source.find("arm_ssv.yaml:4"), std::string::npos) << arm[0].source;
  EXPECT_EQ(d.ssv.at("base").size(), 2u);  // untouched
}

TEST(CollisionSsv, Iiwa14PrimitiveCollisionModel) {
  const gen::Description d = load(shared_robot("iiwa14/iiwa14_primitive_collision.urdf"));
  EXPECT_EQ(d.ssv.size(), 6u);  // links 0..5 carry one cylinder each; 6 and 7 none
  // link 0: cylinder at (-0.015, 0, 0.07), length 0.17, radius 0.139, along z.
  const auto& l0 = d.ssv.at("iiwa_link_0").at(0);
  EXPECT_LT((l0.points[0] - Vec3<double>(-0.015, 0, 0.07 - 0.085)).norm(), 1e-15);
  EXPECT_LT((l0.points[1] - Vec3<double>(-0.015, 0, 0.07 + 0.085)).norm(), 1e-15);
  EXPECT_EQ(l0.radius, 0.139);
  // link 2: roll +90 deg turns z into -y; at (0, 0.056, 0.035), length 0.29.
  const auto& l2 = d.ssv.at("iiwa_link_2").at(0);
  EXPECT_LT((l2.points[0] - Vec3<double>(0, 0.056 + 0.145, 0.035)).norm(), 1e-12);
  EXPECT_LT((l2.points[1] - Vec3<double>(0, 0.056 - 0.145, 0.035)).norm(), 1e-12);
}

}  // namespace
}  // namespace mbgen::test
