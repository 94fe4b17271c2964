#pragma once
// The collision part of `mbgen inspect`: compounds, kept and pruned pairs with the reason.
#include <nlohmann/json.hpp>
#include <ostream>

#include "collision/collision_scene.hpp"

namespace mbgen::cli {

/// "collision pairs (...)": one line per candidate pair, kept ones first.
void print_collision_scene(const gen::CollisionScene& scene, std::ostream& out);

/// {margin, samples, compounds, kept: [[a, b], ...], pruned: [{pair, reason, min_distance}, ...]}.
nlohmann::ordered_json collision_scene_json(const gen::CollisionScene& scene);

}  // namespace mbgen::cli
