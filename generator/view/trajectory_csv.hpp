#pragma once
// Reading a trajectory CSV (the format of mbgen/sim/trajectory_csv.hpp, which mbgen_sim and
// mbgen_walk write) for `mbgen view`, checked against the robot it is shown on.
#include <string>
#include <vector>

#include "mbgen/model.hpp"

namespace mbgen::view {

struct Trajectory {
  std::vector<double> t;                  ///< s, non-decreasing
  std::vector<VecX<double>> q;            ///< nq each
  std::vector<std::string> force_names;   ///< the contact spheres of the force columns (the prefix removed)
  std::vector<std::vector<double>> forces;  ///< per row, one normal force (N) per force column; empty without them
};

/// Reads `path`. Throws gen::LoadError naming the file, the line and the column when a column
/// does not match the robot (q's columns must be `configuration_columns(model)` in order, then
/// only force columns whose spheres are in `contact_names`), when a row has the wrong number of
/// fields, a value is not a finite number, time goes backwards, or a base quaternion is not
/// unit (within 1e-6; it is normalised to round-off). An empty file or one without rows is refused.
Trajectory read_trajectory_csv(const std::string& path, const Model& model, const std::vector<std::string>& contact_names);

/// The rows to show at `fps` frames per second: for each multiple of 1/fps from the first time to
/// the last, the first row at or after it (each row at most once); every row for fps <= 0.
std::vector<int> resample(const std::vector<double>& t, double fps);

}  // namespace mbgen::view
