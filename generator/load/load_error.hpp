#pragma once
// The one error type of loading: where (file, line when the format gives one), which element,
// what is wrong, and how to fix it. The CLI prints what() and exits with status 1 (bad input:
// generator/cli/exit_codes.hpp).
#include <stdexcept>
#include <string>

namespace mbgen::gen {

class LoadError : public std::runtime_error {
 public:
  /// line <= 0 when unknown. `element` reads like "joint 'knee'"; `fix` may be empty.
  LoadError(std::string file, int line, std::string element, std::string problem, std::string fix);

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& element() const { return element_; }
  const std::string& problem() const { return problem_; }
  const std::string& fix() const { return fix_; }

 private:
  std::string file_, element_, problem_, fix_;
  int line_;
};

}  // namespace mbgen::gen
