// generator/load/read_description.cpp: which loader a path goes to. The rule is the extension
// alone, in any case, so that ROBOT.XML and robot.World are read as their formats and an
// extension-less or .urdf path as URDF.
#include <gtest/gtest.h>

#include "load/description.hpp"

namespace mbgen {
namespace {

using gen::description_format;
using gen::DescriptionFormat;

TEST(ReadDescription, FormatFollowsTheExtensionInAnyCase) {
  EXPECT_EQ(description_format("robots/cassie/scene.xml"), DescriptionFormat::Mjcf);
  EXPECT_EQ(description_format("ROBOT.XML"), DescriptionFormat::Mjcf);
  EXPECT_EQ(description_format("model.sdf"), DescriptionFormat::Sdf);
  EXPECT_EQ(description_format("arena.World"), DescriptionFormat::Sdf);
  EXPECT_EQ(description_format("lola.urdf"), DescriptionFormat::Urdf);
  EXPECT_EQ(description_format("model.urdf.xacro"), DescriptionFormat::Urdf);
  EXPECT_EQ(description_format("robot"), DescriptionFormat::Urdf);
}

/// A directory named like a format does not make its files that format.
TEST(ReadDescription, OnlyTheFileNameCounts) {
  EXPECT_EQ(description_format("models.xml/robot.urdf"), DescriptionFormat::Urdf);
  EXPECT_EQ(description_format("worlds.sdf/robot.xml"), DescriptionFormat::Mjcf);
}

}  // namespace
}  // namespace mbgen
