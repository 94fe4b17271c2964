// Mesh files through assimp (generator/mesh/read_mesh.cpp) and mesh references through package
// paths (generator/mesh/mesh_path.cpp): each format gives the same tetrahedron, a COLLADA file's
// unit and node transform apply and its up axis does not, and bad files are MeshErrors that name
// the file.
#include "mesh/read_mesh.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#include "mesh/mesh_path.hpp"
#include "mesh_shapes.hpp"

namespace {

namespace fs = std::filesystem;
using mbgen::Vec3;
using namespace mbgen::mesh;

const std::vector<Vec3<double>> kTetrahedron = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 3}};
const int kFaces[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};

fs::path scratch(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "mbgen_test_read_mesh";
  fs::create_directories(dir);
  return dir / name;
}

void write_binary_stl(const fs::path& path, float poison = 0) {
  TriangleMesh tetrahedron;
  tetrahedron.vertices = kTetrahedron;
  for (const auto& f : kFaces) tetrahedron.triangles.push_back({f[0], f[1], f[2]});
  mbgen::test::write_binary_stl(path.string(), tetrahedron, poison);  // NaN poisons the first coordinate
}

std::vector<Vec3<double>> sorted(std::vector<Vec3<double>> v) {
  std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) {
    return std::lexicographical_compare(a.data(), a.data() + 3, b.data(), b.data() + 3);
  });
  v.erase(std::unique(v.begin(), v.end()), v.end());
  return v;
}

void expect_tetrahedron(const TriangleMesh& m, double scale = 1, const Vec3<double>& shift = Vec3<double>::Zero()) {
  EXPECT_EQ(m.triangles.size(), 4u);
  std::vector<Vec3<double>> expected;
  for (const auto& v : kTetrahedron) expected.push_back(scale * v + shift);
  const auto got = sorted(m.vertices), want = sorted(expected);
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i) EXPECT_LE((got[i] - want[i]).norm(), 1e-6) << got[i].transpose();
}

TEST(ReadMesh, BinaryAndAsciiStlObjAndDae) {
  write_binary_stl(scratch("tet_binary.stl"));
  expect_tetrahedron(read_mesh(scratch("tet_binary.stl").string()));

  {
    std::ofstream out(scratch("tet_ascii.stl"));
    out << "solid tet\n";
    for (const auto& f : kFaces) {
      out << " facet normal 0 0 0\n  outer loop\n";
      for (int k : f) out << "   vertex " << kTetrahedron[k].x() << " " << kTetrahedron[k].y() << " " << kTetrahedron[k].z() << "\n";
      out << "  endloop\n endfacet\n";
    }
    out << "endsolid tet\n";
  }
  expect_tetrahedron(read_mesh(scratch("tet_ascii.stl").string()));

  {
    std::ofstream out(scratch("tet.obj"));
    for (const auto& v : kTetrahedron) out << "v " << v.x() << " " << v.y() << " " << v.z() << "\n";
    for (const auto& f : kFaces) out << "f " << f[0] + 1 << " " << f[1] + 1 << " " << f[2] + 1 << "\n";
  }
  expect_tetrahedron(read_mesh(scratch("tet.obj").string()));

  // Millimetres, Z up, and a node that moves the geometry 10 mm along x: metres come out, the
  // translation applies, the axes stay the file's (as ROS tools read a URDF's DAE).
  {
    std::ofstream out(scratch("tet.dae"));
    out << R"(<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="millimeter" meter="0.001"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries>
    <geometry id="g" name="g"><mesh>
      <source id="g-pos">
        <float_array id="g-pos-array" count="12">0 0 0 1000 0 0 0 2000 0 0 0 3000</float_array>
        <technique_common><accessor source="#g-pos-array" count="4" stride="3">
          <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
        </accessor></technique_common>
      </source>
      <vertices id="g-vtx"><input semantic="POSITION" source="#g-pos"/></vertices>
      <triangles count="4"><input semantic="VERTEX" source="#g-vtx" offset="0"/><p>0 2 1 0 1 3 0 3 2 1 2 3</p></triangles>
    </mesh></geometry>
  </library_geometries>
  <library_visual_scenes>
    <visual_scene id="s"><node id="n"><translate>10 0 0</translate><instance_geometry url="#g"/></node></visual_scene>
  </library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
)";
  }
  expect_tetrahedron(read_mesh(scratch("tet.dae").string()), 1.0, Vec3<double>(0.01, 0, 0));
}

TEST(ReadMesh, BadFilesAreMeshErrorsNamingTheFile) {
  const auto message = [](const fs::path& p) {
    try {
      read_mesh(p.string());
    } catch (const MeshError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(scratch("absent.stl")).find("absent.stl: no such file"), std::string::npos);
  { std::ofstream(scratch("empty.stl")); }
  EXPECT_NE(message(scratch("empty.stl")).find("empty.stl"), std::string::npos);
  { std::ofstream(scratch("garbage.obj")) << "this is not a mesh\n"; }
  EXPECT_NE(message(scratch("garbage.obj")).find("garbage.obj"), std::string::npos);
  { std::ofstream(scratch("points.obj")) << "v 0 0 0\nv 1 0 0\nv 0 1 0\n"; }  // vertices, no face
  EXPECT_NE(message(scratch("points.obj")).find("points.obj"), std::string::npos);
  write_binary_stl(scratch("nan.stl"), std::numeric_limits<float>::quiet_NaN());
  EXPECT_NE(message(scratch("nan.stl")).find("is not finite"), std::string::npos) << message(scratch("nan.stl"));
}

TEST(MeshPath, PackagesRosPackagePathFilesAndRelativePaths) {
  PackagePaths packages = {{"robot_data", "/opt/data"}};
  EXPECT_EQ(resolve_mesh_path("package://robot_data/meshes/a.stl", "/d", packages), "/opt/data/meshes/a.stl");
  EXPECT_EQ(resolve_mesh_path("file:///abs/b.stl", "/d", packages), "/abs/b.stl");
  EXPECT_EQ(resolve_mesh_path("meshes/c.stl", "/d", packages), "/d/meshes/c.stl");
  EXPECT_EQ(resolve_mesh_path("/abs/c.stl", "/d", packages), "/abs/c.stl");

  // ROS_PACKAGE_PATH: the first folder holding NAME/rest.
  fs::create_directories(scratch("ros/other_pkg"));
  write_binary_stl(scratch("ros/other_pkg/m.stl"));
  ::setenv("ROS_PACKAGE_PATH", ("/nonexistent:" + scratch("ros").string()).c_str(), 1);
  EXPECT_EQ(resolve_mesh_path("package://other_pkg/m.stl", "/d", packages), scratch("ros/other_pkg/m.stl").string());
  try {
    resolve_mesh_path("package://unknown_pkg/m.stl", "/d", packages);
    FAIL() << "no error";
  } catch (const MeshError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("package 'unknown_pkg' is unknown"), std::string::npos) << what;
    EXPECT_NE(what.find("--package-path unknown_pkg=DIR"), std::string::npos) << what;
    EXPECT_NE(what.find("/nonexistent/unknown_pkg/m.stl"), std::string::npos) << what;
  }
  ::unsetenv("ROS_PACKAGE_PATH");

  EXPECT_EQ(parse_package_path("a=b/c"), (std::pair<std::string, std::string>("a", "b/c")));
  EXPECT_THROW(parse_package_path("no_equals"), std::invalid_argument);
  EXPECT_THROW(parse_package_path("=dir"), std::invalid_argument);
  EXPECT_THROW(parse_package_path("name="), std::invalid_argument);
}

}  // namespace
