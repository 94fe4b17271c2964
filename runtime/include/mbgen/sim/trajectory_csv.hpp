#pragma once
// A trajectory as a CSV file, the format `mbgen view --trajectory` plays back (docs/view.md):
//   t,<one column per coordinate of q>[,force:<contact sphere>...]
// q's columns are named after the joints, in q's order: a 1-coordinate joint by its name, a joint
// of several coordinates (the floating base: x y z qx qy qz qw) as name[0] ... name[nq-1]. The
// optional force columns hold each ground-contact sphere's normal force (N), named as the scene
// names its spheres (<link>/<ssv>/<vertex>). Numbers are written with 17 significant digits, so
// that a pose read back is the pose simulated, bit for bit. Host code (examples, tools): it
// writes through a std::ofstream.
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "mbgen/model.hpp"

namespace mbgen::sim {

/// The names of q's columns, in q's order.
inline std::vector<std::string> configuration_columns(const Model& model) {
  std::vector<std::string> names(static_cast<std::size_t>(model.nq()));
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    for (int k = 0; k < joint.nq; ++k)
      names[static_cast<std::size_t>(joint.idx_q + k)] = joint.nq == 1 ? joint.name : joint.name + "[" + std::to_string(k) + "]";
  }
  return names;
}

/// The prefix of a contact sphere's normal-force column.
inline constexpr const char* kForceColumnPrefix = "force:";

/// Writes one row per call: the time, q, and (if contact names were given) one normal force each.
class TrajectoryCsvWriter {
 public:
  TrajectoryCsvWriter(const std::string& path, const Model& model, const std::vector<std::string>& contact_names = {})
      : out_(path), nq_(model.nq()), contacts_(static_cast<int>(contact_names.size())) {
    out_ << "t";
    for (const std::string& name : configuration_columns(model)) out_ << "," << name;
    for (const std::string& name : contact_names) out_ << "," << kForceColumnPrefix << name;
    out_ << "\n";
  }
  /// q: nq values; forces: one per contact name (ignored without contact names).
  void write(double t, const double* q, const double* forces = nullptr) {
    number(t);
    for (int i = 0; i < nq_; ++i) out_ << ",", number(q[i]);
    for (int i = 0; i < contacts_; ++i) out_ << ",", number(forces ? forces[i] : 0.0);
    out_ << "\n";
  }
  /// False if the file could not be opened or written.
  bool ok() const { return static_cast<bool>(out_); }

 private:
  void number(double x) {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", x);
    out_ << text;
  }
  std::ofstream out_;
  int nq_, contacts_;
};

}  // namespace mbgen::sim
