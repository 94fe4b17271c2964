#pragma once
// Topology (docs/extras.md, "Loops: assembly and sub-systems"; docs/loops.md). load_description
// validates the description as read (load/, with parallel_legs joint types already turned into
// chains), then build_topology composes three steps, each a function of the description that
// changes nothing (callable on its own):
//   closures_of                 ClosureSpec -> LoopClosure (frames, axes, row offsets)
//   assemble_closures           Levenberg-Marquardt from the zero pose to a closed pose
//   choose_subsystems           fundamental cycles, grouping, ranks, independent coordinates
// Failures are LoadErrors naming the closure.
#include "load/description.hpp"

namespace mbgen::gen {

/// Each ClosureSpec as a LoopClosure of d.model: bodies and closure frames from the
/// resolved frames composed with the spec's origins; types revolute, prismatic, universal,
/// weld, spherical -> Point, 6d -> Weld, 3d -> Point. A universal closure's second axis (in Cb)
/// is the first vector of closure_axis_basis(axis): perpendicular to `axis`.
std::vector<LoopClosure> closures_of(const Description& d);

/// Options of the assembly solve.
struct AssemblyOptions {
  double tolerance = 1e-12;         ///< max |Phi| of a closed pose
  int max_iterations = 400;         ///< per seed
  int max_seeds = 24;               ///< the zero pose, then perturbed seeds
  /// A closed pose is well conditioned when, with the sub-systems' independent coordinates
  /// chosen there (actuated joints first), every dependent block Phi_z has its smallest singular
  /// value at least this fraction of its largest (condition <= 100): the actuators then move
  /// the loops with no fold (dead point) close by. wl16_like at condition 724 had one within
  /// 0.002 rad of its motors. Seeds are tried until one is (or max_seeds); the best is kept, and
  /// a warning is given below a tenth of it.
  double conditioning = 1e-2;
  int min_seeds = 4;                ///< closed poses compared before the first well-conditioned one is taken
  /// Rank tolerance (docs/extras.md, "Loops: assembly and sub-systems"): singular values below rank_tolerance * max(1, sigma_max) are zero.
  double rank_tolerance = 1e-7;
};

/// Closes every loop of d.model from the zero pose (neutral configuration) by damped least
/// squares over all tree joints; restarts from perturbed seeds when it stalls; among closed
/// poses prefers full rank, then the fewest actuated joints forced dependent, then a
/// well-conditioned one (`conditioning`), then the nearest. Revolute coordinates are wrapped to
/// (-pi, pi] (or a turn away, into their limits). d.model must hold the closures (closures_of).
/// Throws a LoadError naming each closure that stays open and by how much.
struct Assembled {
  AssemblyReport report;
  std::vector<std::string> warnings;  ///< joints outside their limits, a poorly conditioned pose
};
Assembled assemble_closures(const Description& d, const AssemblyOptions& options = {});

/// Sub-systems at a pose q (build_topology at the assembled pose, and the assembly's choice of
/// pose, use it): the sub-systems, the total rank, the warnings it would give, and the worst
/// conditioning (smallest / largest singular value) of the sub-systems' dependent blocks Phi_z.
/// At q: the fundamental cycle of each closure (tree path body_a -> common ancestor ->
/// body_b); closures whose cycles share a moving joint are one sub-system (loops that only
/// meet at a body, e.g. both rooted at the pelvis, stay apart: their coordinates are disjoint
/// and their rows decouple). Per sub-system: rank of its rows, the kept independent rows
/// (column-pivoted QR of Phi_s^T), dependent coordinates z picked by column-pivoted QR among the
/// joints that are not actuated / hinted first (so actuated joints end up independent whenever
/// the rank allows), independent y = the rest (idle spins included). A hinted joint that must be
/// dependent gets a warning.
struct SubSystemChoice {
  std::vector<SubSystem> subsystems;
  int total_rank = 0;
  int dependent_actuated = 0;  ///< actuated joints the rank forced into z
  double worst_conditioning = 1.0;
  std::vector<std::string> warnings;
};
SubSystemChoice choose_subsystems(const Description& d, const VecX<double>& q, const AssemblyOptions& options = {});

/// The fundamental cycle of a closure as a path of bodies: body_a up to the common ancestor,
/// the ancestor (the cycle's root), then down to body_b.
std::vector<BodyIndex> cycle_path(const Model& model, const LoopClosure& closure);

/// The spanning tree of a closed model: the same bodies and joints without closures or
/// sub-systems (the tree functions of a generation, and the Python runtime's, run on it).
Model spanning_tree(const Model& closed);

/// Name of the joint a velocity index belongs to (with the axis suffix `[k]` inside a floating joint).
std::string coordinate_name(const Model& model, int v_index);

/// The description with its loops: the closures in d.model, the assembled pose (d.assembly), the
/// sub-systems at it (d.model.subsystems), d.closed_dof and the steps' warnings. Without closures
/// only d.closed_dof = nv.
Description build_topology(Description d);

}  // namespace mbgen::gen
