#pragma once
// The collision scene of a description: one SSV compound per body (the extras' `ssv:`, or the
// URDF's sphere and cylinder collisions) and the pairs worth checking, pruned as MoveIt's setup
// assistant builds its collision matrix (DESIGN.md, "Swept-sphere volumes"):
//   adjacent           bodies joined by a joint or a loop closure: they touch by design
//   excluded           named in the scene's `collision: exclude`
//   never_close        over seeded random configurations within the joint limits, never within
//                      the margin of each other
//   always_overlapping overlapping in every sampled configuration (reported: a model error)
// Pairs named in `collision: include` are kept whatever the rules say.
#include <string>
#include <vector>

#include "mbgen/collision/collision_model.hpp"
#include "mbgen/gen/description.hpp"

namespace mbgen::gen {

enum class PairVerdict { Kept, Included, Adjacent, Excluded, NeverClose, AlwaysOverlapping };

const char* to_string(PairVerdict verdict);

/// What became of one pair of compounds, and what the sampling saw of it.
struct PairDecision {
  int first = -1, second = -1;  ///< compound indices, first < second
  PairVerdict verdict = PairVerdict::Kept;
  /// Smallest and largest distance over the samples (a lower bound from the bounding spheres
  /// where those alone showed the pair apart by more than the margin); NaN if not sampled.
  double min_distance = 0.0, max_distance = 0.0;
};

struct CollisionSceneOptions {
  double margin = 0.05;       ///< m; the scene's `collision: margin` when it gives one
  int samples = 10000;        ///< configurations; the scene's `prune_samples` when it gives one
  unsigned seed = 1;          ///< the sampling is seeded: the same description gives the same pairs
  bool progress = false;      ///< draw a progress bar on stderr (only when it is a terminal)
};

struct CollisionScene {
  collision::CollisionModel model;     ///< compounds, and the kept pairs
  std::vector<PairDecision> decisions; ///< every candidate pair, in (first, second) order
  double margin = 0.0;
  int samples = 0;
};

/// Options from the description's scene (margin, prune_samples), defaults otherwise.
CollisionSceneOptions collision_scene_options(const Description& d);

/// Builds the compounds and decides every pair. Throws LoadError for an include/exclude entry
/// that names no link with SSVs.
CollisionScene build_collision_scene(const Description& d, const CollisionSceneOptions& options);

}  // namespace mbgen::gen
