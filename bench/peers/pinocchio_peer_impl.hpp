#pragma once
// What PinocchioRobot holds: Pinocchio's model, data and closures. Included only by this folder's
// translation units, which are compiled against the Pinocchio source tree (CMakeLists.txt).
#include "pinocchio/algorithm/contact-info.hpp"
#include "pinocchio/algorithm/proximal.hpp"
#include "pinocchio/multibody/data.hpp"
#include "pinocchio/multibody/model.hpp"
#include "pinocchio_peer.hpp"

namespace mbgen::peers {

struct PinocchioRobot::Impl {
  pinocchio::Model model;
  std::unique_ptr<pinocchio::Data> data;
  PINOCCHIO_STD_VECTOR_WITH_EIGEN_ALLOCATOR(pinocchio::RigidConstraintModel) closures;
  PINOCCHIO_STD_VECTOR_WITH_EIGEN_ALLOCATOR(pinocchio::RigidConstraintData) closure_data;
  bool constraints_initialised = false;
  pinocchio::ProximalSettings tight{1e-12, 1e-8, 100};
  pinocchio::ProximalSettings defaults;
  int last_iterations = 0;
};

}  // namespace mbgen::peers
