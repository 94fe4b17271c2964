#pragma once
// `scene: loops: transmission` (docs/extras.md, "Model reductions"): every sub-system of loops is
// replaced by the kinematic map from its actuators to its output joints. The thesis' knee and
// ankle drive kinematics: a controller commands the actuators, the dynamics sees the outputs.
//
// For each closure of a sub-system, the tree path from its root to one closure body holds an
// actuator (an independent coordinate of the exact model) and the path to the other does not:
// the first is the linkage (Lola's knee: nut and rod; its ankle: the actuators' U-joint crosses,
// housings and rods), the second ends at the output (the knee; the foot's pitch and roll). The
// reduced model keeps the output joints as ordinary tree joints and welds the linkage at the
// reference pose, its mass lumped into the parents. The map and its Jacobian live on in
// Description::transmission_model: the whole robot with the same loops, partitioned with the
// outputs as independent coordinates.
#include <map>
#include <string>

#include "load/description.hpp"

namespace mbgen::gen {

/// Plans the transmissions of d (loops as read): fills d.transmissions and
/// d.transmission_model, removes the replaced closures from d.closures, makes the outputs the
/// actuated joints in place of the actuators, and returns the linkage joints to weld with their
/// values at the assembled reference pose (d.model itself is left for reduce_model to weld).
/// Throws a LoadError (the extras' `loops:` line) for a loop with actuators on both sides or on
/// neither, a linkage body that carries a body outside the linkage, outputs that do not match
/// the actuators in number, or outputs that cannot serve as the loops' coordinates.
std::map<std::string, double> plan_transmissions(Description& d);

}  // namespace mbgen::gen
