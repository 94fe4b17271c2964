#include "view/trajectory_csv.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "load/load_error.hpp"
#include "mbgen/sim/trajectory_csv.hpp"

namespace mbgen::view {

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> fields;
  std::stringstream in(line);
  std::string field;
  while (std::getline(in, field, ',')) fields.push_back(field);
  if (!line.empty() && line.back() == ',') fields.emplace_back();
  return fields;
}

std::string trimmed(std::string s) {
  while (!s.empty() && (s.back() == '\r' || s.back() == ' ')) s.pop_back();
  while (!s.empty() && s.front() == ' ') s.erase(s.begin());
  return s;
}

}  // namespace

Trajectory read_trajectory_csv(const std::string& path, const Model& model, const std::vector<std::string>& contact_names) {
  std::ifstream in(path);
  if (!in) throw gen::LoadError(path, 0, "the trajectory", "cannot be read", "check the path (mbgen_sim and mbgen_walk write one with --trajectory)");
  std::string line;
  if (!std::getline(in, line))
    throw gen::LoadError(path, 1, "the header", "is missing: the file is empty", "write `t,<q columns>` first (docs/view.md)");
  const std::vector<std::string> expected = sim::configuration_columns(model);
  std::vector<std::string> header = split(line);
  for (std::string& h : header) h = trimmed(h);
  const auto column = [&](std::size_t k) { return fmt::format("column {} ('{}')", k + 1, header[k]); };
  if (header.empty() || header[0] != "t")
    throw gen::LoadError(path, 1, header.empty() ? "column 1" : column(0), "is not `t`", "the first column is the time, named t");
  if (header.size() < expected.size() + 1)
    throw gen::LoadError(path, 1, "the header", fmt::format("has {} columns of q; robot '{}' has nq = {}", header.size() - 1, model.name, expected.size()),
                         fmt::format("write one column per coordinate of q, named {} ... (docs/view.md)", expected.front()));
  for (std::size_t k = 0; k < expected.size(); ++k)
    if (header[k + 1] != expected[k])
      throw gen::LoadError(path, 1, column(k + 1), fmt::format("should be q[{}] of robot '{}', named '{}'", k, model.name, expected[k]),
                           "the columns after t are q's coordinates in q's order (mbgen inspect lists the joints); was the "
                           "trajectory written for another robot or another --extras?");
  Trajectory trajectory;
  const std::string prefix = sim::kForceColumnPrefix;
  for (std::size_t k = expected.size() + 1; k < header.size(); ++k) {
    if (header[k].rfind(prefix, 0) != 0)
      throw gen::LoadError(path, 1, column(k), "is neither a coordinate of q nor a contact force", "after q, only `force:<contact sphere>` columns may follow");
    const std::string name = header[k].substr(prefix.size());
    if (std::find(contact_names.begin(), contact_names.end(), name) == contact_names.end())
      throw gen::LoadError(path, 1, column(k), "names no contact sphere of the scene",
                           contact_names.empty() ? std::string("the scene has no `contact:`; give the extras that the simulation used")
                                                 : fmt::format("the scene's spheres are {} ...", contact_names.front()));
    trajectory.force_names.push_back(name);
  }
  int number = 1;
  std::vector<int> quaternions;  // the first q index of each floating joint's quaternion
  for (int j = 1; j < model.num_joints(); ++j)
    if (model.joint(JointIndex(j)).type == JointType::Floating) quaternions.push_back(model.joint(JointIndex(j)).idx_q + 3);
  while (std::getline(in, line)) {
    ++number;
    if (trimmed(line).empty()) continue;
    const std::vector<std::string> fields = split(line);
    if (fields.size() != header.size())
      throw gen::LoadError(path, number, "the row", fmt::format("has {} fields; the header has {}", fields.size(), header.size()), "");
    std::vector<double> values(fields.size());
    for (std::size_t k = 0; k < fields.size(); ++k) {
      const std::string f = trimmed(fields[k]);
      std::size_t used = 0;
      try {
        values[k] = std::stod(f, &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != f.size() || !std::isfinite(values[k]))
        throw gen::LoadError(path, number, column(k), fmt::format("holds '{}', not a finite number", f), "");
    }
    if (!trajectory.t.empty() && values[0] < trajectory.t.back())
      throw gen::LoadError(path, number, column(0), fmt::format("goes back in time ({} after {})", values[0], trajectory.t.back()),
                           "sort the rows by time");
    VecX<double> q = Eigen::Map<const VecX<double>>(values.data() + 1, model.nq());
    for (int i : quaternions) {
      const double norm = q.segment<4>(i).norm();
      if (std::abs(norm - 1) > 1e-6)
        throw gen::LoadError(path, number, column(static_cast<std::size_t>(i) + 1),
                             fmt::format("starts a base quaternion of norm {:.9g}, not 1", norm), "write unit quaternions (x y z w)");
      q.segment<4>(i) /= norm;
    }
    trajectory.t.push_back(values[0]);
    trajectory.q.push_back(std::move(q));
    if (!trajectory.force_names.empty())
      trajectory.forces.emplace_back(values.begin() + 1 + model.nq(), values.end());
  }
  if (trajectory.t.empty()) throw gen::LoadError(path, number, "the file", "has a header and no rows", "");
  return trajectory;
}

std::vector<int> resample(const std::vector<double>& t, double fps) {
  std::vector<int> rows;
  if (t.empty()) return rows;
  if (!(fps > 0)) {
    for (std::size_t k = 0; k < t.size(); ++k) rows.push_back(static_cast<int>(k));
    return rows;
  }
  const double period = 1 / fps;
  std::size_t k = 0;
  for (long i = 0;; ++i) {
    const double target = t.front() + static_cast<double>(i) * period;
    while (k < t.size() && t[k] < target - 1e-9 * period) ++k;
    if (k == t.size()) break;
    if (rows.empty() || rows.back() != static_cast<int>(k)) rows.push_back(static_cast<int>(k));
  }
  if (rows.back() != static_cast<int>(t.size()) - 1) rows.push_back(static_cast<int>(t.size()) - 1);  // the end is always shown
  return rows;
}

}  // namespace mbgen::view
