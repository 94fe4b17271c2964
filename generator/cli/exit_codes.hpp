#pragma once
// The exit codes of every mbgen command, one table (README: "Exit codes"), and the one place that
// turns what a command threw into its code and message.
#include <iostream>
#include <new>
#include <stdexcept>
#include <string>

#include "codegen/output_files.hpp"
#include "load/load_error.hpp"

namespace mbgen::cli {

enum ExitCode : int {
  kSuccess = 0,
  /// The input is wrong: a description, extras, mesh or template file (the message names the file,
  /// the element and the fix).
  kBadInput = 1,
  /// The command line is wrong: an unknown option, a missing argument, a value out of its range, a
  /// file that does not exist.
  kUsage = 2,
  /// An output is in the way: a file there that mbgen did not write, or one it cannot write.
  kOutputRefused = 3,
  /// A bug in mbgen, not in the input: a broken invariant (please report it with the input).
  kInternalError = 4,
};

/// Runs a command's body, printing what it threw to `err` and returning the exit code for it.
template <typename Body> int run_command(const std::string& input, std::ostream& err, Body&& body) {
  try {
    return body();
  } catch (const gen::LoadError& e) {
    err << e.what() << "\n";
    return kBadInput;
  } catch (const codegen::OutputRefused& e) {
    err << e.what() << "\n";
    return kOutputRefused;
  } catch (const std::invalid_argument& e) {  // a value the input gave that the model refuses
    err << input << ": " << e.what() << "\n";
    return kBadInput;
  } catch (const std::logic_error& e) {  // an invariant of mbgen's own
    err << input << ": internal error (a bug in mbgen; please report it with this input): " << e.what() << "\n";
    return kInternalError;
  } catch (const std::exception& e) {  // reading or parsing a file
    err << e.what() << "\n";
    return kBadInput;
  }
}

}  // namespace mbgen::cli
