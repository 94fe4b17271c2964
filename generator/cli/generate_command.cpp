// `mbgen generate`: load, trace the runtime's algorithms symbolically, emit, write safely.
#include "cli/generate_command.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>

#include "codegen/emit_batch.hpp"
#include "codegen/generate_robot.hpp"
#include "codegen/output_files.hpp"
#include "codegen/templates.hpp"
#include "cli/description_options.hpp"
#include "cli/exit_codes.hpp"
#include "codegen/function_catalog.hpp"
#include "model/load_description.hpp"

namespace mbgen::cli {

namespace {

struct GenerateOptions {
  DescriptionOptions input;
  std::string out, name, scalar;  ///< scalar: empty = the scene's, else both
  std::string flavour = "cpp", templates;              ///< templates: a user's folder, instead of the flavour's
  std::vector<std::string> frames;
  std::vector<std::string> outputs;  ///< overrides the scene's outputs; {"all"}: everything
  std::vector<std::string> derivatives_wrt;  ///< overrides the scene's derivatives_wrt
  bool quiet = false;
  long max_operations = codegen::kDefaultGraphLimit;
  int batch = 0;  ///< --batch W: states per call of the batch functions, 0 none
  int max_statements = codegen::kMaxStatementsPerPart;
  bool python = false;  ///< --python: also <name>_python.cpp, the robot's Python module
};

int run_generate(const GenerateOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  return run_command(o.input.description, std::cerr, [&] {
    // The Python module calls the cpp flavour's API (namespace, overloads), which the c flavour and
    // a user's templates name and shape otherwise.
    if (o.python && (o.flavour != "cpp" || !o.templates.empty()))
      throw std::invalid_argument(fmt::format("--python binds the cpp flavour's functions, and this run uses {}: generate "
                                              "the Python module from the cpp flavour (no --flavour, no --templates)",
                                              o.templates.empty() ? "--flavour " + o.flavour : "--templates " + o.templates));
    // The templates first: a broken one stops the run before anything is loaded or written.
    const codegen::TemplateSet templates =
        codegen::TemplateSet::load(o.templates.empty() ? codegen::installed_templates_directory(o.flavour) : o.templates);
    const gen::Description d = gen::load_description(o.input.description, o.input.load_options());

    codegen::CodegenOptions options;
    options.name = codegen::sanitize_identifier(!o.name.empty() ? o.name : d.robot_name.empty() ? d.model.name : d.robot_name);
    // --scalar wins; else the scene's `scalar:` (a firmware scene asks for float alone); else both.
    const std::string scalar = !o.scalar.empty() ? o.scalar : d.scene && !d.scene->scalar.empty() ? d.scene->scalar : "both";
    options.scalars = scalar == "double" ? codegen::ScalarChoice::Double
                      : scalar == "float" ? codegen::ScalarChoice::Float
                                          : codegen::ScalarChoice::Both;
    options.frames = o.frames;
    options.max_operations = o.max_operations;
    options.batch = o.batch;
    options.max_statements_per_part = o.max_statements;
    options.outputs = o.outputs;
    options.derivatives_wrt = o.derivatives_wrt;
    options.python = o.python;
    if (options.frames.empty() && d.scene) options.frames = d.scene->jacobian_frames;
    options.inputs.push_back({std::filesystem::path(d.description_file).filename().string(),
                              codegen::sha256_of_file(d.description_file)});
    if (!d.extras_file.empty())
      options.inputs.push_back({std::filesystem::path(d.extras_file).filename().string(),
                                codegen::sha256_of_file(d.extras_file)});
    // A user's templates shape the output as much as the inputs do: the banner names their digest.
    if (!o.templates.empty()) options.inputs.push_back({"templates", templates.digest()});

    std::vector<std::string> notes;
    options.notes = &notes;
    const std::vector<codegen::GeneratedFile> files = codegen::generate_robot(d, options, templates);
    const codegen::WriteReport report = codegen::write_generated_files(o.out, files);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const std::string header = templates.render("header_file", {{"robot", options.name}});
    if (!o.quiet) {
      for (const std::string& w : d.warnings) std::cerr << "warning: " << w << "\n";
      for (const std::string& n : d.notes) std::cout << "note: " << n << "\n";
      for (const std::string& note : notes) (note.rfind("warning: ", 0) == 0 ? std::cerr : std::cout) << note << "\n";
      std::cout << fmt::format("mbgen: {} (nq {}, nv {}) -> {}/{}: {} files written, {} unchanged, {:.2f} s\n",
                               options.name, d.model.nq(), d.model.nv(), o.out, header, report.written.size(),
                               report.unchanged.size(), seconds);
    }
    return static_cast<int>(kSuccess);
  });
}

}  // namespace

void add_generate_command(CLI::App& app, int& status) {
  auto options = std::make_shared<GenerateOptions>();
  CLI::App* cmd = app.add_subcommand("generate", "Emit unrolled, allocation-free C++ for a robot");
  add_description_options(cmd, options->input);
  cmd->add_option("--out", options->out, "output directory (created if missing)")->required();
  cmd->add_option("--name", options->name, "C++ namespace (default: the extras' robot, else the URDF's name)");
  cmd->add_option("--scalar", options->scalar, "scalar types to emit (default: the scene's scalar, else both)")
      ->check(CLI::IsMember({"double", "float", "both"}));
  cmd->add_option("--frames", options->frames, "frames for frame_poses/frame_jacobians (default: scene, else leaf bodies)")
      ->delimiter(',');
  cmd->add_option("--outputs", options->outputs,
                  "scene outputs to generate, overriding the scene's `outputs` (docs/extras.md), or `all`")
      ->delimiter(',')
      ->check([](const std::string& value) -> std::string {
        const std::vector<std::string> known = codegen::scene_outputs();
        if (value == "all" || std::find(known.begin(), known.end(), value) != known.end()) return "";
        return fmt::format("unknown output '{}': the outputs are {} (or all)", value, fmt::join(known, ", "));
      });
  cmd->add_option("--derivatives-wrt", options->derivatives_wrt,
                  "the inputs the derivative outputs are taken with respect to, of q, v, tau (default: the scene's "
                  "derivatives_wrt, else all three); the other blocks are left out of the functions and their signatures")
      ->delimiter(',')
      ->check(CLI::IsMember({"q", "v", "tau"}));
  auto* flavour = cmd->add_option("--flavour", options->flavour,
                                  "output flavour, from mbgen's templates: cpp (namespace, overloads) or c (C99 header, "
                                  "extern \"C\" functions <name>_<function>_<scalar>); default cpp")
                     ->check([](const std::string& value) -> std::string {
                       try {  // a flavour is a folder of the installed templates
                         codegen::installed_templates_directory(value);
                         return "";
                       } catch (const std::exception& e) {
                         return e.what();
                       }
                     });
  cmd->add_option("--templates", options->templates,
                  "a folder of templates to frame the output with (a copy of share/mbgen/templates/<flavour>, edited; "
                  "docs/templates.md)")
      ->check(CLI::ExistingDirectory)
      ->excludes(flavour);
  cmd->add_option("--max-operations", options->max_operations,
                  "largest traced function, in operations, before generation stops with an error (default 10000000; "
                  "a 5,000-link chain stops at its mass matrix after 20 s and 1.8 GB)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--batch", options->batch,
                  "also emit <function>_batch for the dynamics and kinematics over W states per call "
                  "(structure of arrays, q[i][w]; GCC vectors; equal to the one-state functions bit for bit); "
                  "W a power of two from 2 to 16")
      ->check([](const std::string& value) -> std::string {
        int w = 0;
        try {
          w = std::stoi(value);
        } catch (const std::exception&) {
        }
        return codegen::valid_batch_width(w) ? std::string()
                                             : value + " states per call: W must be a power of two from 2 to 16 (4 fills AVX2's registers with double)";
      });
  cmd->add_option("--max-statements", options->max_statements,
                  "statements per part above which a function is split into functions of its own (default 20000): "
                  "g++'s time on one function grows faster than its size, and a split costs a few loads and stores "
                  "(self_distances is split by its own rule: its pairs in parts of at most 48 SSV calls)")
      ->check(CLI::Range(1, 1000000000));
  cmd->add_flag("--python", options->python,
                               "also write <name>_python.cpp: the robot's Python module (pybind11, NumPy) with every "
                               "generated function for double; build it with mbgen_add_robot(... PYTHON) (docs/python.md)");
  cmd->add_flag("--quiet", options->quiet, "print nothing on success");
  cmd->callback([options, &status] { status = run_generate(*options); });
}

}  // namespace mbgen::cli
