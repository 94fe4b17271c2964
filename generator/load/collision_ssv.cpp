// Swept-sphere volumes from a URDF's primitive collision geometry (issue 5, item 2):
//   <sphere radius="r">                 -> point-SSV at the collision origin, radius r;
//   <cylinder radius="r" length="l">    -> line-SSV along the collision frame's z axis, from -l/2 to
//                                          +l/2, radius r (a capsule: it covers the cylinder and
//                                          adds two caps of height r, a conservative bound).
// Boxes and meshes have no SSV counterpart here: they are counted and kept in `link_meshes` (a
// link without <collision> gives its <visual> meshes instead), for `fit-ssv` and `scene:
// collision: fit` to enclose (fit_link_ssvs.hpp); the extras' `ssv:` is the other way to model them. A link that the extras give an `ssv:` compound keeps only that one: the
// scene says what it needs (load_extras.cpp replaces the compound).
#include <fmt/format.h>

#include <algorithm>

#include "load/description.hpp"
#include "load/load_error.hpp"
#include "load/parse_urdf.hpp"

namespace mbgen::gen {

namespace {

SE3<double> to_se3(const urdf::Pose& pose) {
  double x, y, z, w;
  pose.rotation.getQuaternion(x, y, z, w);
  SE3<double> X;
  X.rotation = Eigen::Quaterniond(w, x, y, z).toRotationMatrix();
  X.translation = Vec3<double>(pose.position.x, pose.position.y, pose.position.z);
  return X;
}

}  // namespace

void add_collision_ssvs(const std::string& path, Description& d) {
  urdf::ModelInterfaceSharedPtr urdf = parse_urdf_file(path);
  std::vector<urdf::LinkSharedPtr> links;
  urdf->getLinks(links);
  // Document order is not kept by urdfdom's map; sort by name so that output is deterministic.
  std::sort(links.begin(), links.end(), [](const auto& a, const auto& b) { return a->name < b->name; });
  for (const urdf::LinkSharedPtr& link : links) {
    if (!d.model.find_frame(link->name)) continue;
    int index = 0;
    for (const urdf::CollisionSharedPtr& collision : link->collision_array) {
      ++index;
      if (!collision || !collision->geometry) continue;
      const SE3<double> X_LC = to_se3(collision->origin);
      SsvPrimitive p;
      p.source = fmt::format("{}:{}: <collision> {} of link '{}'", path, d.urdf_lines.line_of_link(link->name), index, link->name);
      switch (collision->geometry->type) {
        case urdf::Geometry::SPHERE: {
          const auto& sphere = static_cast<const urdf::Sphere&>(*collision->geometry);
          p.kind = SsvPrimitive::Kind::Point;
          p.points = {X_LC.translation};
          p.radius = sphere.radius;
          break;
        }
        case urdf::Geometry::CYLINDER: {
          const auto& cylinder = static_cast<const urdf::Cylinder&>(*collision->geometry);
          p.kind = SsvPrimitive::Kind::Line;
          const Vec3<double> half = X_LC.rotation.col(2) * (cylinder.length / 2);
          p.points = {X_LC.translation - half, X_LC.translation + half};
          p.radius = cylinder.radius;
          break;
        }
        case urdf::Geometry::BOX: {
          ++d.collision_geometry_not_modelled["box"];
          const auto& box = static_cast<const urdf::Box&>(*collision->geometry);
          d.link_meshes[link->name].push_back({"", true, Vec3<double>(box.dim.x, box.dim.y, box.dim.z), X_LC, p.source});
          continue;
        }
        case urdf::Geometry::MESH: {
          ++d.collision_geometry_not_modelled["mesh"];
          const auto& mesh = static_cast<const urdf::Mesh&>(*collision->geometry);
          d.link_meshes[link->name].push_back(
              {mesh.filename, false, Vec3<double>(mesh.scale.x, mesh.scale.y, mesh.scale.z), X_LC, p.source});
          continue;
        }
        default: ++d.collision_geometry_not_modelled["other"]; continue;
      }
      if (!(p.radius >= 0))
        throw LoadError(path, d.urdf_lines.line_of_link(link->name), fmt::format("link '{}'", link->name),
                        fmt::format("<collision> {} has a negative radius ({})", index, p.radius),
                        "give the sphere or cylinder a radius >= 0");
      d.ssv[link->name].push_back(p);
    }
    if (!link->collision_array.empty()) continue;
    index = 0;
    for (const urdf::VisualSharedPtr& visual : link->visual_array) {
      ++index;
      if (!visual || !visual->geometry || visual->geometry->type != urdf::Geometry::MESH) continue;
      const auto& mesh = static_cast<const urdf::Mesh&>(*visual->geometry);
      d.link_meshes[link->name].push_back(
          {mesh.filename, false, Vec3<double>(mesh.scale.x, mesh.scale.y, mesh.scale.z), to_se3(visual->origin),
           fmt::format("{}:{}: <visual> {} of link '{}'", path, d.urdf_lines.line_of_link(link->name), index, link->name)});
    }
  }
}

}  // namespace mbgen::gen
