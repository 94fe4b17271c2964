// Compounds from the description's SSVs and the pruned pair list (collision_scene.hpp).
#include "collision/collision_scene.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <set>

#include "mbgen/collision/compound_distance.hpp"
#include "mbgen/collision/contained_shapes.hpp"
#include "load/load_error.hpp"
#include "mbgen/mbgen.hpp"

namespace mbgen::gen {

const char* to_string(PairVerdict verdict) {
  switch (verdict) {
    case PairVerdict::Kept: return "kept";
    case PairVerdict::Included: return "included";
    case PairVerdict::Adjacent: return "adjacent";
    case PairVerdict::Excluded: return "excluded";
    case PairVerdict::NeverClose: return "never_close";
    case PairVerdict::AlwaysOverlapping: return "always_overlapping";
  }
  return "unknown";
}

namespace {

using collision::Compound;
using collision::Shape;

/// One compound per body that has SSVs, in body order; the links' shapes moved into the body frame.
/// A shape inside another of its body's is left out (contained_shapes.hpp) and listed in `dropped`.
std::vector<Compound> make_compounds(const Description& d, std::vector<DroppedShape>& dropped) {
  const Model& model = d.model;
  std::map<int, Compound> by_body;  // ordered by body index: deterministic
  for (const auto& [link, primitives] : d.ssv) {
    const std::optional<FrameIndex> f = model.find_frame(link);
    if (!f) throw LoadError(d.extras_file.empty() ? d.description_file : d.extras_file, 0, fmt::format("ssv '{}'", link),
                            "names no link of the robot", "use a link name (see `mbgen inspect`)");
    const Frame& frame = model.frame(*f);
    Compound& c = by_body[frame.body.value()];
    c.body = frame.body;
    c.name = model.body(frame.body).name;
    for (const SsvPrimitive& p : primitives) {
      Shape s;
      s.kind = p.kind == SsvPrimitive::Kind::Point ? Shape::Kind::Point
                                                   : (p.kind == SsvPrimitive::Kind::Line ? Shape::Kind::Line : Shape::Kind::Triangle);
      for (std::size_t k = 0; k < p.points.size() && k < 3; ++k) s.points[k] = frame.X_BF.act(p.points[k]);
      s.radius = p.radius;
      s.source = p.source;
      collision::update_bound(s);
      c.shapes.push_back(s);
    }
  }
  std::vector<Compound> out;
  for (auto& [body, c] : by_body) {
    if (c.shapes.empty()) continue;
    const std::vector<Shape> given = c.shapes;
    for (const collision::ContainedShape& x : collision::drop_contained_shapes(c))
      dropped.push_back({c.name, given[static_cast<std::size_t>(x.shape)].source, given[static_cast<std::size_t>(x.container)].source,
                         x.protrusion});
    collision::update_bound(c);
    out.push_back(std::move(c));
  }
  return out;
}

/// Unordered body pairs {min, max}.
using BodyPair = std::pair<int, int>;
BodyPair body_pair(BodyIndex a, BodyIndex b) { return std::minmax(a.value(), b.value()); }

std::set<BodyPair> adjacent_bodies(const Description& d) {
  std::set<BodyPair> out;
  const Model& model = d.model;
  for (int k = 1; k < model.num_bodies(); ++k) out.insert(body_pair(BodyIndex(k), model.body(BodyIndex(k)).parent));
  for (const ClosureSpec& c : d.closures)
    if (c.resolved_a.valid() && c.resolved_b.valid())
      out.insert(body_pair(model.frame(c.resolved_a).body, model.frame(c.resolved_b).body));
  return out;
}

std::set<BodyPair> named_pairs(const Model& model, const std::vector<std::pair<std::string, std::string>>& names) {
  std::set<BodyPair> out;
  for (const auto& [a, b] : names) out.insert(body_pair(model.frame(model.frame_index(a)).body, model.frame(model.frame_index(b)).body));
  return out;
}

/// A progress bar on stderr, redrawn at most 50 times; silent unless stderr is a terminal.
class ProgressBar {
 public:
  ProgressBar(bool wanted, int total) : on_(wanted && total > 0 && isatty(STDERR_FILENO)), total_(total) {}
  void update(int done) {
    if (!on_) return;
    const int step = done * 50 / total_;
    if (step == last_ && done != total_) return;
    last_ = step;
    std::fprintf(stderr, "\rpruning collision pairs [%-50s] %3d%% (%d/%d samples)", std::string(static_cast<std::size_t>(step), '=').c_str(),
                 done * 100 / total_, done, total_);
    if (done == total_) std::fprintf(stderr, "\n");
  }
  /// A line after the bar (same terminal rule).
  void note(const std::string& line) const {
    if (on_) std::fprintf(stderr, "%s\n", line.c_str());
  }

 private:
  bool on_;
  int total_, last_ = -1;
};

}  // namespace

// ------------------------------------------------------------------ sampling (closed poses)

/// What closing the loops of a draw needs: the runtime's Newton and its work memory, the nominal
/// pose, where y and z live in q, and the dependent joints' limits.
struct ConfigurationSampler::Loops {
  explicit Loops(const Description& d) : model(&d.model), data(d.model) {
    const Model& m = d.model;
    nominal = d.assembly.q.size() == m.nq() ? d.assembly.q : neutral_configuration<double>(m);
    if (m.floating_base()) nominal.head<7>() << 0, 0, 0, 0, 0, 0, 1;
    for (int j = 1; j < m.num_joints(); ++j) {
      const Joint& joint = m.joint(JointIndex(j));
      if (joint.nv != 1) continue;
      if (model->structure().column_of_v[static_cast<std::size_t>(joint.idx_v)] >= 0) {
        independent_q.push_back(joint.idx_q);
        // A revolute joint free to turn a full circle walks the short way round.
        const bool turns = !joint.bounded || !(joint.upper > joint.lower) || joint.upper - joint.lower >= 2 * M_PI;
        revolute.push_back(joint.type == JointType::Revolute && turns);
      } else if (joint.bounded && joint.upper > joint.lower) {
        limited.push_back({joint.idx_q, joint.lower, joint.upper});
      }
    }
  }
  /// Newton on the loops from q's dependent coordinates, q's independent ones held.
  bool solve(VecX<double>& q) {
    return closure_positions<double>(*model, data, q).status == ClosureStatus::Converged;
  }
  bool within_limits(const VecX<double>& q) const {
    constexpr double slack = 1e-9;
    for (const Limited& l : limited)
      if (!(q[l.q] >= l.lower - slack && q[l.q] <= l.upper + slack)) return false;
    return true;
  }

  struct Limited {
    int q;
    double lower, upper;
  };
  const Model* model;
  Data<double> data;
  VecX<double> nominal, trial;
  std::vector<int> independent_q;  ///< q indices of the 1-DoF independent coordinates
  std::vector<char> revolute;      ///< per independent_q entry: a revolute joint that turns a full circle
  std::vector<Limited> limited;    ///< the dependent joints with limits
};

ConfigurationSampler::ConfigurationSampler(const Description& d, unsigned seed, bool close_loops) : model_(d.model), rng_(seed) {
  if (close_loops && !d.model.subsystems.empty()) {
    loops_ = std::make_unique<Loops>(d);
    report_.loops = true;
  }
}

ConfigurationSampler::~ConfigurationSampler() = default;

bool ConfigurationSampler::next(VecX<double>& q) {
  ++report_.drawn;
  const VecX<double> drawn = random_configuration<double>(model_, rng_);
  if (!loops_) {  // a tree (or the loops left open): the draw as it is
    q = drawn;
    if (model_.floating_base()) q.head<7>() << 0, 0, 0, 0, 0, 0, 1;
    return true;
  }
  // A walk from the nominal pose to the drawn y, Newton warm-started at each step from the last
  // (continuation: the linkage stays on the nominal pose's branch, where a direct solve from
  // the nominal pose can jump to another assembly mode, e.g. the mirrored slider-crank). A step
  // that does not close is halved, down to 1/kFinestDivision of the way. A revolute joint that
  // turns a full circle takes the short way round (its pose repeats every turn); the drawn
  // values are set last.
  Loops& l = *loops_;
  constexpr int total = kFinestDivision;  // the path in units of the finest step
  static_assert(kFinestDivision % kWalkSteps == 0, "the finest step divides the first steps");
  int at = 0, step = total / kWalkSteps;
  bool refined = false;
  q = l.nominal;
  while (at < total) {
    const int next = std::min(total, at + step);
    const double t = static_cast<double>(next) / total;
    l.trial = q;
    for (std::size_t k = 0; k < l.independent_q.size(); ++k) {
      const int i = l.independent_q[k];
      double delta = drawn[i] - l.nominal[i];
      if (l.revolute[k]) delta = std::remainder(delta, 2 * M_PI);
      l.trial[i] = l.nominal[i] + t * delta;
    }
    if (l.solve(l.trial)) {
      q = l.trial;
      at = next;
    } else if (step > 1) {
      step /= 2;
      refined = true;
    } else {
      ++report_.not_closed;
      return false;
    }
  }
  for (int i : l.independent_q) q[i] = drawn[i];
  if (!l.solve(q)) {
    ++report_.not_closed;
    return false;
  }
  ++report_.closed;
  if (refined) ++report_.refined;
  if (!l.within_limits(q)) ++report_.beyond_limits;
  return true;
}

std::vector<VecX<double>> collision_sample_configurations(const Description& d, const CollisionSceneOptions& options,
                                                          SamplingReport* report) {
  std::vector<VecX<double>> out;
  ConfigurationSampler sampler(d, options.seed, options.close_loops);
  VecX<double> q;
  for (int n = 0; n < options.samples; ++n)
    if (sampler.next(q)) out.push_back(q);
  if (report) *report = sampler.report();
  return out;
}

std::string sampling_summary(const CollisionScene& scene) {
  const SamplingReport& r = scene.sampling;
  if (!r.loops) return fmt::format("{} configurations sampled", r.drawn);
  return fmt::format("{} configurations drawn, loops closed by Newton on a walk from the nominal pose: {} closed ({} "
                     "with finer steps, {} with a passive joint beyond its limits), {} discarded (not closed)",
                     r.drawn, r.closed, r.refined, r.beyond_limits, r.not_closed);
}

CollisionSceneOptions collision_scene_options(const Description& d) {
  CollisionSceneOptions o;
  if (d.scene) {
    if (d.scene->collision_margin > 0) o.margin = d.scene->collision_margin;
    if (d.scene->prune_samples > 0) o.samples = d.scene->prune_samples;
  }
  return o;
}

CollisionScene build_collision_scene(const Description& d, const CollisionSceneOptions& options) {
  const Model& model = d.model;
  CollisionScene scene;
  scene.margin = options.margin;
  scene.samples = options.samples;
  scene.model.compounds = make_compounds(d, scene.dropped_shapes);
  const std::vector<Compound>& compounds = scene.model.compounds;
  const std::set<BodyPair> adjacent = adjacent_bodies(d);
  std::set<BodyPair> excluded, included;
  if (d.scene) {
    excluded = named_pairs(model, d.scene->collision_exclude);
    included = named_pairs(model, d.scene->collision_include);
  }

  // Candidates: every pair of compounds; the rules that need no sampling first.
  std::vector<PairDecision>& decisions = scene.decisions;
  std::vector<std::size_t> sampled;  // indices into decisions
  const double nan = std::numeric_limits<double>::quiet_NaN();
  for (std::size_t i = 0; i < compounds.size(); ++i)
    for (std::size_t j = i + 1; j < compounds.size(); ++j) {
      PairDecision p;
      p.first = static_cast<int>(i);
      p.second = static_cast<int>(j);
      p.min_distance = nan;
      p.max_distance = nan;
      const BodyPair bodies = body_pair(compounds[i].body, compounds[j].body);
      if (included.count(bodies)) p.verdict = PairVerdict::Included;
      else if (excluded.count(bodies)) p.verdict = PairVerdict::Excluded;
      else if (adjacent.count(bodies)) p.verdict = PairVerdict::Adjacent;
      else sampled.push_back(decisions.size());
      decisions.push_back(p);
    }

  // Sampling: seeded configurations within the joint limits, closed where the robot has loops
  // (ConfigurationSampler; the base where it is: relative distances do not depend on it).
  scene.robot = d.robot_name.empty() ? model.name : d.robot_name;
  if (!sampled.empty() && options.samples > 0) {
    const auto start = std::chrono::steady_clock::now();
    for (std::size_t k : sampled) {
      decisions[k].min_distance = std::numeric_limits<double>::infinity();
      decisions[k].max_distance = -std::numeric_limits<double>::infinity();
    }
    ConfigurationSampler sampler(d, options.seed, options.close_loops);
    Data<double> data(model);
    ProgressBar bar(options.progress, options.samples);
    VecX<double> q;
    for (int n = 0; n < options.samples; ++n) {
      if (!sampler.next(q)) {
        bar.update(n + 1);
        continue;
      }
      forward_kinematics<double>(model, data, q);
      for (std::size_t k : sampled) {
        PairDecision& p = decisions[k];
        const Compound& a = compounds[static_cast<std::size_t>(p.first)];
        const Compound& b = compounds[static_cast<std::size_t>(p.second)];
        const SE3<double>& X_Wa = data.X_WB[a.body];
        const SE3<double>& X_Wb = data.X_WB[b.body];
        // The bounding spheres alone settle a pair far apart: it is neither close nor overlapping.
        const double lower = (X_Wb.act(b.bound_center) - X_Wa.act(a.bound_center)).norm() - a.bound_radius - b.bound_radius;
        const double dist =
            lower > options.margin ? lower : collision::compound_distance<double>(a, X_Wa, b, X_Wb).result.distance;
        p.min_distance = std::min(p.min_distance, dist);
        p.max_distance = std::max(p.max_distance, dist);
      }
      bar.update(n + 1);
    }
    scene.sampling = sampler.report();
    scene.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    bar.note(fmt::format("pruning collision pairs: {}, {:.2f} s", sampling_summary(scene), scene.seconds));
    const SamplingReport& r = scene.sampling;
    if (r.used() == 0) {
      // Nothing seen: no pair can be called never close or always overlapping; keep them all.
      for (std::size_t k : sampled) decisions[k].min_distance = decisions[k].max_distance = nan;
      scene.warnings.push_back(fmt::format(
          "collision pruning for robot '{}': none of the {} configurations drawn closed the loops, so no pair was "
          "pruned by sampling; check the actuated joints' limits against the linkages' workspace",
          scene.robot, r.drawn));
    } else {
      for (std::size_t k : sampled) {
        PairDecision& p = decisions[k];
        if (p.min_distance > options.margin) p.verdict = PairVerdict::NeverClose;
        else if (p.max_distance < 0) p.verdict = PairVerdict::AlwaysOverlapping;
      }
      if (r.loops && r.used() < ConfigurationSampler::kWarnUsedFraction * r.drawn)
        scene.warnings.push_back(fmt::format(
            "collision pruning for robot '{}': only {} of the {} configurations drawn ({:.0f} %) closed the loops; the "
            "pruning rests on those {}: raise prune_samples, or narrow the actuated joints' limits to the linkages' "
            "workspace",
            scene.robot, r.used(), r.drawn, 100.0 * r.used() / r.drawn, r.used()));
    }
  }
  for (const PairDecision& p : decisions)
    if (p.verdict == PairVerdict::Kept || p.verdict == PairVerdict::Included) scene.model.pairs.push_back({p.first, p.second});
  return scene;
}

}  // namespace mbgen::gen
