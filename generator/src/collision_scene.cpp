// Compounds from the description's SSVs and the pruned pair list (collision_scene.hpp).
#include "mbgen/gen/collision_scene.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <set>

#include "mbgen/collision/compound_distance.hpp"
#include "mbgen/gen/load_error.hpp"
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
std::vector<Compound> make_compounds(const Description& d) {
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

 private:
  bool on_;
  int total_, last_ = -1;
};

}  // namespace

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
  scene.model.compounds = make_compounds(d);
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

  // Sampling: seeded configurations within the joint limits (the base where it is: relative
  // distances do not depend on it).
  if (!sampled.empty() && options.samples > 0) {
    for (std::size_t k : sampled) {
      decisions[k].min_distance = std::numeric_limits<double>::infinity();
      decisions[k].max_distance = -std::numeric_limits<double>::infinity();
    }
    std::mt19937_64 rng(options.seed);
    Data<double> data(model);
    ProgressBar bar(options.progress, options.samples);
    for (int n = 0; n < options.samples; ++n) {
      VecX<double> q = random_configuration<double>(model, rng);
      if (model.floating_base()) q.head<7>() << 0, 0, 0, 0, 0, 0, 1;
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
    for (std::size_t k : sampled) {
      PairDecision& p = decisions[k];
      if (p.min_distance > options.margin) p.verdict = PairVerdict::NeverClose;
      else if (p.max_distance < 0) p.verdict = PairVerdict::AlwaysOverlapping;
    }
  }
  for (const PairDecision& p : decisions)
    if (p.verdict == PairVerdict::Kept || p.verdict == PairVerdict::Included) scene.model.pairs.push_back({p.first, p.second});
  return scene;
}

}  // namespace mbgen::gen
