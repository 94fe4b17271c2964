#include "load/load_error.hpp"

#include <fmt/format.h>

namespace mbgen::gen {

namespace {
std::string compose(const std::string& file, int line, const std::string& element, const std::string& problem,
                    const std::string& fix) {
  std::string where = line > 0 ? fmt::format("{}:{}", file, line) : file;
  std::string text = element.empty() ? fmt::format("{}: error: {}", where, problem)
                                     : fmt::format("{}: error: {}: {}", where, element, problem);
  if (!fix.empty()) text += fmt::format("\n  fix: {}", fix);
  return text;
}
}  // namespace

LoadError::LoadError(std::string file, int line, std::string element, std::string problem, std::string fix)
    : std::runtime_error(compose(file, line, element, problem, fix)),
      file_(std::move(file)),
      element_(std::move(element)),
      problem_(std::move(problem)),
      fix_(std::move(fix)),
      line_(line) {}

}  // namespace mbgen::gen
