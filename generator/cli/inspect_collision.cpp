#include "cli/inspect_collision.hpp"

#include <fmt/format.h>

#include <cmath>

namespace mbgen::cli {

namespace {
bool kept(gen::PairVerdict v) { return v == gen::PairVerdict::Kept || v == gen::PairVerdict::Included; }

std::string names(const gen::CollisionScene& scene, const gen::PairDecision& p) {
  return fmt::format("{} - {}", scene.model.compounds[static_cast<std::size_t>(p.first)].name,
                     scene.model.compounds[static_cast<std::size_t>(p.second)].name);
}

/// What the sampling saw, for the report.
std::string sampled(const gen::PairDecision& p) {
  if (std::isnan(p.min_distance)) return "";
  return fmt::format(" (sampled distance {:.4g} .. {:.4g} m)", p.min_distance, p.max_distance);
}
}  // namespace

void print_collision_scene(const gen::CollisionScene& scene, std::ostream& out) {
  int n_kept = 0;
  for (const gen::PairDecision& p : scene.decisions) n_kept += kept(p.verdict) ? 1 : 0;
  if (!scene.dropped_shapes.empty()) {
    out << fmt::format("\ncollision shapes left out: {}, each inside another shape of its body (the volume, and every distance, is the same):\n",
                       scene.dropped_shapes.size());
    for (const gen::DroppedShape& s : scene.dropped_shapes) out << fmt::format("  {}: {}\n    inside {}\n", s.compound, s.source, s.container_source);
  }
  if (scene.sampling.loops)  // the draws are closed by Newton: say how many were used
    out << fmt::format("\ncollision pairs: {} kept of {} (margin {:.4g} m; {}):\n", n_kept, scene.decisions.size(), scene.margin,
                       gen::sampling_summary(scene));
  else
    out << fmt::format("\ncollision pairs: {} kept of {} (margin {:.4g} m, {} sampled configurations):\n", n_kept,
                       scene.decisions.size(), scene.margin, scene.samples);
  for (const gen::PairDecision& p : scene.decisions)
    if (kept(p.verdict)) out << fmt::format("  kept    {}{}{}\n", names(scene, p), p.verdict == gen::PairVerdict::Included ? " (included)" : "", sampled(p));
  for (const gen::PairDecision& p : scene.decisions)
    if (!kept(p.verdict)) out << fmt::format("  pruned  {}: {}{}\n", names(scene, p), gen::to_string(p.verdict), sampled(p));
}

nlohmann::ordered_json collision_scene_json(const gen::CollisionScene& scene) {
  using Json = nlohmann::ordered_json;
  Json compounds = Json::array(), kept_pairs = Json::array(), pruned = Json::array();
  for (const collision::Compound& c : scene.model.compounds) compounds.push_back({{"body", c.name}, {"shapes", c.shapes.size()}});
  for (const gen::PairDecision& p : scene.decisions) {
    const Json pair = Json::array({scene.model.compounds[static_cast<std::size_t>(p.first)].name,
                                   scene.model.compounds[static_cast<std::size_t>(p.second)].name});
    if (kept(p.verdict)) {
      kept_pairs.push_back(pair);
    } else {
      pruned.push_back({{"pair", pair},
                        {"reason", gen::to_string(p.verdict)},
                        {"min_distance", std::isnan(p.min_distance) ? Json() : Json(p.min_distance)}});
    }
  }
  Json dropped = Json::array();
  for (const gen::DroppedShape& s : scene.dropped_shapes)
    dropped.push_back({{"body", s.compound}, {"source", s.source}, {"inside", s.container_source}});
  const gen::SamplingReport& r = scene.sampling;
  const Json sampling = {{"loops_closed", r.loops},         {"drawn", r.drawn},
                         {"used", r.used()},                {"closed", r.closed},
                         {"refined", r.refined},            {"not_closed", r.not_closed},
                         {"beyond_limits", r.beyond_limits}};
  return Json{{"margin", scene.margin}, {"samples", scene.samples}, {"sampling", sampling}, {"compounds", compounds},
              {"dropped_shapes", dropped}, {"kept", kept_pairs},     {"pruned", pruned},         {"warnings", scene.warnings}};
}

}  // namespace mbgen::cli
