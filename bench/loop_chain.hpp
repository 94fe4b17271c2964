#pragma once
// A chain of k identical loop modules, for the scaling benchmark of closed-loop forward dynamics
// (fd_chain/<k>/...): module i is a parallelogram four-bar (crank and rocker 0.2 m, coupler and
// ground 0.3 m, axes along y) whose ground is the rocker of module i - 1 (the world for i = 1),
// closed by a revolute closure at the coupler-rocker joint. Each loop is one sub-system of three
// bodies with one independent coordinate (the crank); nested: module i + 1 hangs from module i.
// Closed at the zero pose, far from the parallelogram's singular poses (crank along the ground).
#include <string>

namespace mbgen::bench {

/// Writes loop_chain_<k>.urdf and loop_chain_<k>.yaml (mbgen extras) into `directory` and
/// returns the URDF's path (the extras beside it: same name, .yaml).
std::string write_loop_chain(const std::string& directory, int k);

}  // namespace mbgen::bench
