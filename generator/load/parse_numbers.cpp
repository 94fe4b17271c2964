#include "load/parse_numbers.hpp"

#include <fmt/format.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace mbgen::gen {

ParsedNumbers parse_numbers(const std::string& text) {
  ParsedNumbers out;
  std::istringstream in(text);
  std::string token;
  while (in >> token) {
    char* end = nullptr;
    errno = 0;
    const double x = std::strtod(token.c_str(), &end);
    if (end == token.c_str() || *end != '\0') {
      out.problem = fmt::format("'{}' is not a number", token);
    } else if (std::isnan(x) || (std::isinf(x) && errno != ERANGE)) {
      out.problem = fmt::format("'{}' is not a finite number", token);
    } else if (errno == ERANGE && std::isinf(x)) {
      out.problem = fmt::format("'{}' overflows a double", token);
    } else if (token.find_first_not_of("0123456789+-.eE") != std::string::npos) {
      out.problem = fmt::format("'{}' is not a decimal number", token);  // strtod reads hex: 0x10
    }
    // (An underflow, 1e-400, reads as 0 or a subnormal: a value, if an odd one.)
    if (!out.problem.empty()) return out;
    out.values.push_back(x);
  }
  return out;
}

}  // namespace mbgen::gen
