#pragma once
// The one reader of numbers written as text (URDF and MJCF attributes, YAML scalars): plain
// decimal numbers separated by white space, each finite. strtod alone accepts "nan", "inf",
// "0x10" and "1e400" (as infinity), and reports "1.5abc" only through its end pointer; each of
// those is a problem here, named.
#include <string>
#include <vector>

namespace mbgen::gen {

struct ParsedNumbers {
  std::vector<double> values;
  /// Empty when every token is a finite number; else what is wrong with the first bad token,
  /// e.g. "'nan' is not a finite number", "'1e400' overflows a double", "'abc' is not a number".
  std::string problem;
};

ParsedNumbers parse_numbers(const std::string& text);

}  // namespace mbgen::gen
