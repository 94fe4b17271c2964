#pragma once
// The actuated set of a description: which velocity coordinates carry an actuator. It decides
// what the generated actuator_forces returns (the closed system's inverse dynamics for the
// actuators, runtime algorithm/actuator_forces.hpp) and the header's actuated_joint_names.
#include <string>
#include <vector>

#include "load/description.hpp"
#include "mbgen/algorithm/actuator_forces.hpp"

namespace mbgen::gen {

/// The coordinates of the description's actuated joints (robot.yaml's name_mot, the extras'
/// `independent:` hints, MJCF actuators), in the order named; when it names none, every
/// independent coordinate except a floating base. Throws a LoadError naming the joint for a
/// name the model does not have (a joint a reduction removed is dropped from the set with it),
/// a floating joint, or a set make_actuation refuses.
std::vector<int> actuated_coordinates(const Description& d);

/// make_actuation for the description's actuated set. An actuated joint that the loops made a
/// dependent coordinate (a load warning says so) is solved for through its sub-system only when
/// that sub-system has exactly as many actuators as independent coordinates and they move them
/// at the assembled pose (a regular block); otherwise, e.g. redundant actuators or idle spins no
/// actuator moves, the sub-system's dependent actuators are left out (their share stays in the
/// residual), each with a line in *notes when given.
Actuation description_actuation(const Description& d, std::vector<std::string>* notes = nullptr);

}  // namespace mbgen::gen
