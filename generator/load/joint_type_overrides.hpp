#pragma once
// The parallel_legs convention's joint types (robot.yaml `joint_type`): URDF revolute joints that
// stand for spherical or universal joints become real chains of revolute joints, before the
// description is validated (the chains' joints must move mass too).
#include "load/description.hpp"

namespace mbgen::gen {

/// Replaces every revolute joint named in d.joint_type_overrides by a chain of revolute joints
/// at the joint's origin: SPHERICAL -> `<joint>_x`, `<joint>_y`, `<joint>_z` (axes x, y, z of
/// the joint frame), UJOINT_XY -> `<joint>_x`, `<joint>_y` (rotation about x, then about the
/// turned y). The intermediate bodies `<joint>_x_link`(, `<joint>_y_link`) are massless; the
/// last joint moves the original child body. Frame indices are kept (the intermediate bodies'
/// frames are appended), so resolved closure frames stay valid.
/// Caveat: the chain is a gimbal; it loses one freedom where two of its axes align (for
/// SPHERICAL at <joint>_y = +-pi/2; for UJOINT_XY never, as x and the turned y stay
/// perpendicular). There the mass matrix stays regular but Phi_z or the ABA's D of the
/// massless links can become singular; the loop solver reports it as `singular`.
void apply_joint_type_overrides(Description& d);

}  // namespace mbgen::gen
