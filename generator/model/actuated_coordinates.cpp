#include "model/actuated_coordinates.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "load/load_error.hpp"
#include "model/topology.hpp"

namespace mbgen::gen {

namespace {
const std::string& source_file(const Description& d) { return d.extras_file.empty() ? d.description_file : d.extras_file; }
}  // namespace

std::vector<int> actuated_coordinates(const Description& d) {
  const Model& model = d.model;
  if (d.actuated_joints.empty()) return default_actuated_v(model);
  std::vector<int> out;
  for (const std::string& name : d.actuated_joints) {
    const auto j = model.find_joint(name);
    if (!j)
      throw LoadError(source_file(d), 0, fmt::format("actuated joint '{}'", name), "is not a joint of the model",
                      "name a moving joint of the description (see `mbgen inspect`)");
    const Joint& joint = model.joint(*j);
    if (joint.type == JointType::Floating)
      throw LoadError(source_file(d), 0, fmt::format("actuated joint '{}'", name), "is the floating base: no joint actuator moves it",
                      "leave it out of the actuated joints; its forces are the residual the contacts supply");
    for (int k = 0; k < joint.nv; ++k) out.push_back(joint.idx_v + k);
  }
  return out;
}

Actuation description_actuation(const Description& d, std::vector<std::string>* notes) {
  const Model& model = d.model;
  std::vector<int> actuated = actuated_coordinates(d);
  Data<double> data(model);
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& s = model.subsystems[k];
    std::vector<int> inside, dependent;
    for (int v : actuated) {
      const bool in = std::find(s.coordinates.begin(), s.coordinates.end(), v) != s.coordinates.end();
      if (in) inside.push_back(v);
      if (in && std::find(s.dependent.begin(), s.dependent.end(), v) != s.dependent.end()) dependent.push_back(v);
    }
    if (dependent.empty()) continue;
    bool solvable = inside.size() == s.independent.size();
    if (solvable) {  // regular at the assembled pose?
      const Actuation block = make_actuation(model, inside);
      const int ny = model.structure().num_independent();
      VecX<double> f(static_cast<int>(inside.size())), r(ny);
      const VecX<double> zero = VecX<double>::Zero(ny);
      solvable = actuator_forces<double>(model, data, block, d.assembly.q, zero, zero, f, r);
    }
    if (solvable) continue;
    for (int v : dependent) {
      actuated.erase(std::remove(actuated.begin(), actuated.end(), v), actuated.end());
      if (notes)
        notes->push_back(fmt::format(
            "actuator_forces: actuated joint '{}' is a dependent coordinate of its loops, whose {} actuator(s) cannot be solved for "
            "their {} independent coordinate(s) at the assembled pose (redundant, or idle spins no actuator moves): left out of "
            "the actuated set, its share stays in the residual",
            coordinate_name(model, v), inside.size(), s.independent.size()));
    }
  }
  try {
    return make_actuation(model, actuated);
  } catch (const std::invalid_argument& e) {
    throw LoadError(source_file(d), 0, "actuated joints", e.what(), "name each actuated joint once, and no floating base");
  }
}

}  // namespace mbgen::gen
