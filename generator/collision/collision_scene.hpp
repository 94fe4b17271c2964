#pragma once
// The collision scene of a description: one SSV compound per body (the extras' `ssv:`, or the
// URDF's sphere and cylinder collisions; a shape inside another of its body's left out) and the
// pairs worth checking, pruned as MoveIt's setup
// assistant builds its collision matrix (DESIGN.md, "Swept-sphere volumes"):
//   adjacent           bodies joined by a joint or a loop closure: they touch by design
//   excluded           named in the scene's `collision: exclude`
//   never_close        over seeded random configurations within the joint limits, never within
//                      the margin of each other
//   always_overlapping overlapping in every sampled configuration (reported: a model error)
// Pairs named in `collision: include` are kept whatever the rules say.
//
// A robot with kinematic loops (Model::subsystems) is sampled in closed poses only: the
// independent coordinates (every coordinate not dependent in a sub-system: actuated joints,
// joints off the loops) are drawn within their limits, the dependent ones start from the
// assembled nominal pose (Description::assembly.q) and are solved by the runtime's Newton
// (closure_positions) on a walk from the nominal pose to the drawn values in a few
// steps, each warm-started at the last (so the linkage stays in the nominal pose's assembly
// mode). Draws that do not close (the actuators outside the linkage's workspace, a dead point
// on the way) are discarded and counted (SamplingReport). Closed poses with a passive
// (dependent) joint beyond its limits are used, and counted: the pruning stays conservative
// (docs/ssv.md, "Which pairs: the pruning", says why). A tree robot's sampling is unchanged.
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "mbgen/collision/collision_model.hpp"
#include "load/description.hpp"

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
  int samples = 10000;        ///< configurations drawn; the scene's `prune_samples` when it gives one
  unsigned seed = 1;          ///< the sampling is seeded: the same description gives the same pairs
  bool progress = false;      ///< draw a progress bar on stderr (only when it is a terminal)
  /// Robots with loops: close every draw (see above). false samples the spanning tree with the
  /// loops open, as mbgen did before: impossible poses of the loop bodies; for comparison only.
  bool close_loops = true;
};

/// What became of the drawn configurations. For a tree robot (or close_loops false) every draw
/// is used as it is.
struct SamplingReport {
  bool loops = false;        ///< the robot has loops and they were closed
  int drawn = 0;             ///< configurations drawn (the options' samples)
  int closed = 0;            ///< closed by the walk from the nominal pose: used
  int refined = 0;           ///< of those, walks that needed steps finer than kWalkSteps
  int beyond_limits = 0;     ///< of those, poses with a dependent joint beyond its limits (used)
  int not_closed = 0;        ///< Newton not converged or singular on the walk, at the finest step: discarded
  int used() const { return loops ? closed : drawn; }
  int discarded() const { return loops ? not_closed : 0; }
};

/// The configurations the pruning evaluates, drawn one at a time (seeded: the same description
/// and seed give the same sequence). The floating base, if any, stays at the origin with the
/// identity orientation: relative distances do not depend on it. Keeps a reference to the
/// description's model: the description must outlive the sampler.
class ConfigurationSampler {
 public:
  ConfigurationSampler(const Description& d, unsigned seed, bool close_loops = true);
  ~ConfigurationSampler();
  ConfigurationSampler(const ConfigurationSampler&) = delete;
  ConfigurationSampler& operator=(const ConfigurationSampler&) = delete;
  /// Draws the next configuration into q (size nq). False if the draw was discarded (q is then
  /// not a pose to use); the report counts it either way.
  bool next(VecX<double>& q);
  const SamplingReport& report() const { return report_; }
  /// Steps of the walk from the nominal pose to a draw, and the finest step a failing step is
  /// halved down to (1/kFinestDivision of the way).
  static constexpr int kWalkSteps = 4;
  static constexpr int kFinestDivision = 64;
  /// Below this fraction of draws used, the scene warns (CollisionScene::warnings).
  static constexpr double kWarnUsedFraction = 0.5;

 private:
  struct Loops;
  const Model& model_;
  std::mt19937_64 rng_;
  std::unique_ptr<Loops> loops_;  // null for a tree robot or with close_loops false
  SamplingReport report_;
};

/// The configurations build_collision_scene uses with these options, in order (discarded draws
/// left out), and optionally the report. For tests and diagnostics.
std::vector<VecX<double>> collision_sample_configurations(const Description& d, const CollisionSceneOptions& options,
                                                          SamplingReport* report = nullptr);

/// A shape left out of its body's compound because another of its shapes holds it
/// (mbgen/collision/contained_shapes.hpp: the compound's volume, and so every distance, is the
/// same without it): a URDF's sphere at the end of a cylinder of its radius, for instance.
struct DroppedShape {
  std::string compound;          ///< the body's name
  std::string source;            ///< where the dropped shape was given
  std::string container_source;  ///< where the shape that holds it was given
  double protrusion = 0.0;       ///< how far it reaches outside the container (<= 0: inside; at most 1e-9 m)
};

struct CollisionScene {
  collision::CollisionModel model;     ///< compounds, and the kept pairs
  std::vector<PairDecision> decisions; ///< every candidate pair, in (first, second) order
  std::vector<DroppedShape> dropped_shapes;  ///< shapes inside another of their body's, left out
  double margin = 0.0;
  int samples = 0;                     ///< configurations drawn (see sampling for how many were used)
  SamplingReport sampling;
  double seconds = 0.0;                ///< wall time of the sampling (not part of the result's identity)
  std::string robot;                   ///< the description's robot name, for messages
  /// Problems worth telling the user: too few draws closed the loops, none did (then nothing
  /// is pruned as never_close or always_overlapping).
  std::vector<std::string> warnings;
};

/// One line on the sampling, e.g. "20000 configurations drawn, loops closed by Newton on a walk
/// from the nominal pose: 19838 closed (12 with finer steps, 17413 with a passive joint beyond
/// its limits), 162 discarded (not closed)"; for a tree "20000 configurations sampled".
std::string sampling_summary(const CollisionScene& scene);

/// Options from the description's scene (margin, prune_samples), defaults otherwise.
CollisionSceneOptions collision_scene_options(const Description& d);

/// Builds the compounds and decides every pair. Throws LoadError for an include/exclude entry
/// that names no link with SSVs.
CollisionScene build_collision_scene(const Description& d, const CollisionSceneOptions& options);

}  // namespace mbgen::gen
