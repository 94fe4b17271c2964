#include "view/view_scene.hpp"

#include <fmt/format.h>

#include <cstring>
#include <filesystem>

#include "collision/collision_scene.hpp"
#include "collision/contact_spheres.hpp"
#include "mbgen/algorithm/configuration.hpp"
#include "mbgen/algorithm/kinematics.hpp"
#include "mbgen/collision/compound_distance.hpp"
#include "mesh/mesh_path.hpp"
#include "mesh/read_mesh.hpp"
#include "mesh/triangle_mesh.hpp"
#include "view/base64.hpp"

namespace mbgen::view {

namespace {

using Json = nlohmann::json;

Json point(const Vec3<double>& p) { return Json::array({p.x(), p.y(), p.z()}); }

const char* kind_name(collision::Shape::Kind k) {
  return k == collision::Shape::Kind::Point ? "point" : k == collision::Shape::Kind::Line ? "line" : "triangle";
}

/// Each link's meshes and boxes gathered in its body's frame; a mesh that cannot be read leaves
/// its link out, with a warning.
Json meshes(const gen::Description& d, const ViewOptions& options, std::vector<std::string>& warnings) {
  Json out = Json::array();
  const std::string folder = std::filesystem::path(d.description_file).parent_path().string();
  for (const auto& [link, geometries] : d.link_meshes) {
    const auto frame = d.model.find_frame(link);
    if (!frame || d.model.frame(*frame).body.value() == 0) continue;  // a link welded to the world: nothing moves it
    const Frame& f = d.model.frame(*frame);
    mesh::TriangleMesh gathered;
    bool usable = true;
    for (const gen::MeshGeometry& g : geometries) {
      try {
        if (g.box) {
          mesh::append_transformed(mesh::box_mesh(g.scale), Vec3<double>::Ones(), f.X_BF * g.X_LG, gathered);
          continue;
        }
        const std::string path = mesh::resolve_mesh_path(g.reference, folder, options.package_paths);
        mesh::append_transformed(mesh::read_mesh(path), g.scale, f.X_BF * g.X_LG, gathered);
      } catch (const mesh::MeshError& e) {
        warnings.push_back(fmt::format("{}: {}; link '{}' is drawn with its SSVs only", g.source, e.what(), link));
        usable = false;
        break;
      }
    }
    if (!usable || gathered.triangles.empty()) continue;
    std::vector<float> positions;
    positions.reserve(3 * gathered.vertices.size());
    for (const Vec3<double>& v : gathered.vertices)
      for (int k = 0; k < 3; ++k) positions.push_back(static_cast<float>(v[k]));
    std::vector<std::uint32_t> indices;
    indices.reserve(3 * gathered.triangles.size());
    for (const auto& t : gathered.triangles)
      for (int k : t) indices.push_back(static_cast<std::uint32_t>(k));
    out.push_back({{"body", f.body.value() - 1},
                   {"link", link},
                   {"positions", base64(positions.data(), positions.size() * sizeof(float))},
                   {"indices", base64(indices.data(), indices.size() * sizeof(std::uint32_t))}});
  }
  return out;
}

}  // namespace

VecX<double> nominal_pose(const gen::Description& d) {
  return d.assembly.q.size() == d.model.nq() ? d.assembly.q : neutral_configuration<double>(d.model);
}

Json view_scene(const gen::Description& d, const Trajectory* trajectory, const ViewOptions& options, std::vector<std::string>& warnings) {
  const Model& model = d.model;
  Json scene;
  scene["format"] = "mbgen-view 1";
  scene["robot"] = model.name;
  scene["description"] = std::filesystem::path(d.description_file).filename().string();
  Json bodies = Json::array();
  for (int b = 1; b < model.num_bodies(); ++b) bodies.push_back(model.body(BodyIndex(b)).name);
  scene["bodies"] = bodies;

  // The SSVs the distances use: the collision scene's compounds and its kept pairs.
  const gen::CollisionScene collision = gen::build_collision_scene(d, gen::collision_scene_options(d));
  for (const std::string& w : collision.warnings) warnings.push_back(w);
  Json ssv = Json::array();
  for (const collision::Compound& c : collision.model.compounds)
    for (const collision::Shape& s : c.shapes) {
      Json points = Json::array();
      for (int k = 0; k < collision::vertex_count(s); ++k) points.push_back(point(s.points[static_cast<std::size_t>(k)]));
      ssv.push_back({{"body", c.body.value() - 1}, {"kind", kind_name(s.kind)}, {"points", points}, {"radius", s.radius}});
    }
  scene["ssv"] = ssv;
  Json pairs = Json::array();
  for (const collision::CollisionPair& p : collision.model.pairs)
    pairs.push_back({collision.model.compounds[static_cast<std::size_t>(p.first)].body.value() - 1,
                     collision.model.compounds[static_cast<std::size_t>(p.second)].body.value() - 1});
  scene["pairs"] = pairs;
  scene["near_threshold"] = options.near_threshold;
  scene["meshes"] = options.meshes ? meshes(d, options, warnings) : Json::array();

  // The closures' two frames (a coupling of two joints has no point to mark).
  Json closures = Json::array();
  for (const LoopClosure& c : model.closures) {
    if (c.type == ClosureType::Coupling) continue;
    closures.push_back({{"name", c.name}, {"body_a", c.body_a.value() - 1}, {"point_a", point(c.X_ACa.translation)},
                        {"body_b", c.body_b.value() - 1}, {"point_b", point(c.X_BCb.translation)}});
  }
  scene["closures"] = closures;
  const std::vector<ContactSphere> spheres = gen::contact_spheres(d);
  Json contacts = Json::array();
  for (const ContactSphere& s : spheres)
    contacts.push_back({{"name", s.name}, {"body", s.body.value() - 1}, {"center", point(s.center)}, {"radius", s.radius}});
  scene["contacts"] = contacts;

  // The frames: poses, near pairs, forces.
  std::vector<VecX<double>> poses;
  std::vector<double> times;
  std::vector<int> rows;
  if (trajectory) {
    rows = resample(trajectory->t, options.fps);
    for (int r : rows) poses.push_back(trajectory->q[static_cast<std::size_t>(r)]), times.push_back(trajectory->t[static_cast<std::size_t>(r)]);
  } else {
    poses.push_back(nominal_pose(d));
    times.push_back(0.0);
  }
  Data<double> data(model);
  collision::CollisionData<double> distances(model, collision.model);
  Json t = Json::array(), X_WB = Json::array(), near = Json::array(), forces = Json::array();
  for (std::size_t k = 0; k < poses.size(); ++k) {
    forward_kinematics<double>(model, data, poses[k]);
    Json X = Json::array();
    for (int b = 1; b < model.num_bodies(); ++b) {
      const SE3<double>& pose = data.X_WB[BodyIndex(b)];
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) X.push_back(pose.rotation(i, j));
        X.push_back(pose.translation[i]);
      }
    }
    X_WB.push_back(std::move(X));
    t.push_back(times[k]);
    collision::compute_near_distances<double>(model, data, collision.model, options.near_threshold, distances);
    Json frame_near = Json::array();
    for (int n = 0; n < distances.num_near; ++n) {
      const int pair = distances.near[static_cast<std::size_t>(n)];
      const auto& r = distances.distances[static_cast<std::size_t>(pair)].result;
      frame_near.push_back({pair, r.distance, r.point1[0], r.point1[1], r.point1[2], r.point2[0], r.point2[1], r.point2[2]});
    }
    near.push_back(std::move(frame_near));
    if (trajectory && !trajectory->forces.empty()) {
      // The file's force columns in the scene's sphere order; a sphere without a column has none.
      const std::vector<double>& row = trajectory->forces[static_cast<std::size_t>(rows[k])];
      Json f = Json::array();
      for (const ContactSphere& s : spheres) {
        const auto it = std::find(trajectory->force_names.begin(), trajectory->force_names.end(), s.name);
        f.push_back(it == trajectory->force_names.end() ? 0.0 : row[static_cast<std::size_t>(it - trajectory->force_names.begin())]);
      }
      forces.push_back(std::move(f));
    }
  }
  scene["frames"] = {{"t", t}, {"X_WB", X_WB}, {"near", near}, {"forces", forces.empty() ? Json(nullptr) : forces}};
  if (d.scene && d.scene->contact)
    scene["ground"] = {{"normal", point(d.scene->contact->ground.normal)}, {"offset", d.scene->contact->ground.offset}};
  return scene;
}

}  // namespace mbgen::view
