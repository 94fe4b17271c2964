#include "codegen/scene_functions.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <filesystem>
#include <map>
#include <stdexcept>

namespace mbgen::codegen {

const std::vector<std::string>& all_functions() {
  static const std::vector<std::string> functions = {
      "forward_dynamics", "full_accelerations", "inverse_dynamics", "actuator_forces", "mass_matrix", "mass_matrix_factor",
      "mass_matrix_solve", "forward_kinematics", "frame_poses",
      "frame_jacobians", "center_of_mass", "centroidal_momentum_matrix", "task_kinematics", "velocity_map", "full_velocities",
      "acceleration_bias", "closure_positions", "self_distances", "contact_points", "contact_accelerations"};
  return functions;
}

namespace {

/// What each scene output brings. The closed system's dynamics come with the maps between its
/// coordinate sets (without them a user cannot make a state for it); the simulation brings every
/// function NAME::Backend calls.
const std::map<std::string, std::vector<std::string>>& output_functions() {
  static const std::map<std::string, std::vector<std::string>> table = {
      {"forward_dynamics", {"forward_dynamics", "full_accelerations", "velocity_map", "full_velocities", "acceleration_bias"}},
      {"inverse_dynamics", {"inverse_dynamics", "actuator_forces"}},
      {"mass_matrix", {"mass_matrix", "mass_matrix_factor", "mass_matrix_solve"}},
      {"forward_kinematics", {"forward_kinematics", "frame_poses"}},
      {"jacobians", {"frame_poses", "frame_jacobians"}},
      {"center_of_mass", {"center_of_mass"}},
      {"centroidal_momentum", {"centroidal_momentum_matrix"}},
      {"distances", {"self_distances"}},
      {kSimulationOutput,
       {"full_accelerations", "velocity_map", "full_velocities", "inverse_dynamics", "actuator_forces", "mass_matrix", "center_of_mass",
        "contact_points", "contact_accelerations"}},
  };
  return table;
}

/// One copy of the unrolled dynamics (generate_robot.cpp): forward_dynamics and
/// full_accelerations are each other's selection, full_velocities is velocity_map's product, and
/// a contact-free contact_accelerations calls full_accelerations.
const std::vector<std::pair<std::string, std::string>>& needs() {
  static const std::vector<std::pair<std::string, std::string>> pairs = {{"forward_dynamics", "full_accelerations"},
                                                                         {"full_accelerations", "forward_dynamics"},
                                                                         {"full_velocities", "velocity_map"},
                                                                         {"contact_accelerations", "full_accelerations"}};
  return pairs;
}

}  // namespace

FunctionSelection select_functions(const std::vector<std::string>& outputs, bool contact) {
  FunctionSelection s;
  if (outputs.empty()) {
    s.emitted.insert(all_functions().begin(), all_functions().end());
  } else {
    std::vector<std::string> wanted = outputs;
    if (contact) wanted.push_back(kSimulationOutput);
    for (const std::string& output : wanted) {
      const auto it = output_functions().find(output);
      if (it == output_functions().end()) {
        std::vector<std::string> known;
        for (const auto& [name, functions] : output_functions()) known.push_back(name);
        throw std::invalid_argument(fmt::format("unknown output '{}': the outputs are {} (or all)", output, fmt::join(known, ", ")));
      }
      s.emitted.insert(it->second.begin(), it->second.end());
    }
    s.emitted.insert("closure_positions");
    for (const auto& [function, needed] : needs())
      if (s.emits(function)) s.emitted.insert(needed);
    // A scene with the four parts of a controller's kinematics gets them in one pass too.
    if (s.emits("frame_poses") && s.emits("frame_jacobians") && s.emits("center_of_mass") && s.emits("centroidal_momentum_matrix"))
      s.emitted.insert("task_kinematics");
  }
  for (const std::string& f : all_functions())
    if (!s.emits(f)) s.left_out.push_back(f);
  s.backend = true;
  for (const std::string& f : output_functions().at(kSimulationOutput)) s.backend = s.backend && s.emits(f);
  return s;
}

FunctionSelection select_functions(const gen::Description& description, const std::vector<std::string>& outputs,
                                   std::string* reason) {
  const bool contact = description.scene && description.scene->contact;
  if (outputs.size() == 1 && outputs[0] == "all") return select_functions(std::vector<std::string>{}, contact);
  if (!outputs.empty()) {
    if (reason) *reason = fmt::format("not among --outputs {}, nor needed by them", fmt::join(outputs, ","));
    return select_functions(outputs, contact);
  }
  const std::vector<std::string> scene = description.scene ? description.scene->outputs : std::vector<std::string>{};
  if (reason)
    *reason = fmt::format("not among the outputs of {}'s scene, nor needed by them",
                          std::filesystem::path(description.extras_file).filename().string());
  return select_functions(scene, contact);
}

}  // namespace mbgen::codegen
