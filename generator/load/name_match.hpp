#pragma once
// Close-match suggestions for names the user mistyped ("did you mean ...?").
#include <optional>
#include <string>
#include <vector>

namespace mbgen::gen {

/// Levenshtein distance counted in Unicode code points (UTF-8 input), so that one accented
/// letter in place of a plain one is one edit, not two.
int edit_distance(const std::string& a, const std::string& b);

/// The candidate closest to `name`, if it is close enough to be a plausible typo (at most a
/// third of the name's length, and at least 1 edit allowed). Ties go to the first candidate.
std::optional<std::string> closest_name(const std::string& name, const std::vector<std::string>& candidates);

/// "did you mean 'x'?" or, with no close match, an empty string.
std::string did_you_mean(const std::string& name, const std::vector<std::string>& candidates);

}  // namespace mbgen::gen
