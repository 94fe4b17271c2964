// Swept-sphere volumes from an SDFormat model's collision geometry, with URDF's conventions
// (collision_ssv.cpp): a sphere is a point-SSV; a cylinder a line-SSV along its z axis from -l/2
// to +l/2 (a capsule that covers it, a conservative bound); a capsule is exactly a line-SSV. Boxes
// and meshes are counted and kept in `link_meshes` for `fit-ssv` and `scene: collision: fit` (a
// link without <collision> gives its <visual> meshes); a mesh's model:// or package:// URI is
// resolved there (--package-path NAME=DIR). Planes, heightmaps and ellipsoids have no SSV and are
// counted as "other". Points are in the link's frame.
#include <fmt/format.h>

#include "load/load_error.hpp"
#include "load/sdf_support.hpp"

namespace mbgen::gen::sdformat {

namespace {

MeshGeometry mesh_of(const sdf::Mesh& mesh, const SE3<double>& X_LG, const std::string& source) {
  return {mesh.Uri(), false, to_vec3(mesh.Scale()), X_LG, source};
}

}  // namespace

void add_sdf_collisions(const std::string& path, const sdf::Model& model, Description& d) {
  for (uint64_t l = 0; l < model.LinkCount(); ++l) {
    const sdf::Link& link = *model.LinkByIndex(l);
    if (!d.model.find_frame(link.Name())) continue;
    for (uint64_t i = 0; i < link.CollisionCount(); ++i) {
      const sdf::Collision& collision = *link.CollisionByIndex(i);
      const int line = line_of(collision.Element());
      const std::string element = fmt::format("<collision> '{}' of link '{}'", collision.Name(), link.Name());
      const SE3<double> X_LG = resolve(path, collision.SemanticPose(), link.Name(), element, line);
      SsvPrimitive p;
      p.source = fmt::format("{}:{}: {}", path, line, element);
      const sdf::Geometry& g = *collision.Geom();
      switch (g.Type()) {
        case sdf::GeometryType::SPHERE:
          p.kind = SsvPrimitive::Kind::Point;
          p.points = {X_LG.translation};
          p.radius = g.SphereShape()->Radius();
          break;
        case sdf::GeometryType::CYLINDER:
        case sdf::GeometryType::CAPSULE: {
          const bool cylinder = g.Type() == sdf::GeometryType::CYLINDER;
          const double length = cylinder ? g.CylinderShape()->Length() : g.CapsuleShape()->Length();
          p.kind = SsvPrimitive::Kind::Line;
          const Vec3<double> half = X_LG.rotation.col(2) * (length / 2);
          p.points = {X_LG.translation - half, X_LG.translation + half};
          p.radius = cylinder ? g.CylinderShape()->Radius() : g.CapsuleShape()->Radius();
          break;
        }
        case sdf::GeometryType::BOX:
          ++d.collision_geometry_not_modelled["box"];
          d.link_meshes[link.Name()].push_back({"", true, to_vec3(g.BoxShape()->Size()), X_LG, p.source});
          continue;
        case sdf::GeometryType::MESH:
          ++d.collision_geometry_not_modelled["mesh"];
          d.link_meshes[link.Name()].push_back(mesh_of(*g.MeshShape(), X_LG, p.source));
          continue;
        default: ++d.collision_geometry_not_modelled["other"]; continue;
      }
      if (!(p.radius >= 0))
        throw LoadError(path, line, element, fmt::format("has a negative radius ({})", p.radius), "give a radius >= 0");
      d.ssv[link.Name()].push_back(p);
    }
    if (link.CollisionCount() > 0) continue;
    for (uint64_t i = 0; i < link.VisualCount(); ++i) {
      const sdf::Visual& visual = *link.VisualByIndex(i);
      if (!visual.Geom() || visual.Geom()->Type() != sdf::GeometryType::MESH) continue;
      const int line = line_of(visual.Element());
      const std::string element = fmt::format("<visual> '{}' of link '{}'", visual.Name(), link.Name());
      const SE3<double> X_LG = resolve(path, visual.SemanticPose(), link.Name(), element, line);
      d.link_meshes[link.Name()].push_back(mesh_of(*visual.Geom()->MeshShape(), X_LG, fmt::format("{}:{}: {}", path, line, element)));
    }
  }
}

}  // namespace mbgen::gen::sdformat
