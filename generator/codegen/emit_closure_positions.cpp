#include "codegen/emit_closure_positions.hpp"

#include <fmt/format.h>

#include "codegen/trace_loop_maps.hpp"

namespace mbgen::codegen {

namespace {

std::string int_array(const std::string& name, const std::vector<int>& items) {
  std::string out = fmt::format("constexpr int {}[{}] = {{", name, items.size());
  for (std::size_t i = 0; i < items.size(); ++i) out += fmt::format("{}{}", i ? ", " : "", items[i]);
  return out + "};\n";
}

// The loop of the runtime's closure_positions, on the traced step's outputs. R: the number of
// dependent coordinates; num_subsystems, subsystem_begin, dependent_q: see the tables above it.
const char* kNewtonLoop = R"(template <typename S> ClosureResult<S> closure_positions_impl(S* q, const ClosureOptions<S>& options) {
  S residual[R], pivots[R], step[R];
  ClosureResult<S> result{ClosureStatus::converged, 0, S(0), S(1), S(1)};
  for (;; ++result.iterations) {
    closure_newton_step<S>(q, residual, pivots, step);
    bool finite = true;
    result.residual = S(0);
    for (int i = 0; i < R; ++i) {
      finite = finite && std::isfinite(residual[i]);
      if (std::fabs(residual[i]) > result.residual) result.residual = std::fabs(residual[i]);
    }
    // Smallest / largest |R_ii| per sub-system, the worst of them, and the worst of them relative
    // to the sub-system's ratio at the assembled pose; NaN (0 / 0) counts as singular.
    result.pivot_ratio = S(1);
    result.relative_pivot_ratio = S(1);
    for (int k = 0; k < num_subsystems; ++k) {
      S smallest = S(0), largest = S(0);
      for (int i = subsystem_begin[k]; i < subsystem_begin[k + 1]; ++i) {
        const S p = std::fabs(pivots[i]);
        if (i == subsystem_begin[k] || !(p >= smallest)) smallest = p;
        if (p > largest) largest = p;
      }
      const S ratio = smallest / largest;
      if (!(ratio >= result.pivot_ratio)) result.pivot_ratio = ratio;
      const S relative = ratio / nominal_pivot_ratio<S>[k];
      if (!(relative >= result.relative_pivot_ratio)) result.relative_pivot_ratio = relative;
    }
    if (!finite) return result.status = ClosureStatus::not_converged, result;
    if (!(result.pivot_ratio >= options.singular_tolerance)) return result.status = ClosureStatus::singular, result;
    if (result.residual < options.tolerance)  // closed, but maybe within the tolerance's reach of a dead point
      return result.status = result.relative_pivot_ratio >= options.dead_point_tolerance ? ClosureStatus::converged : ClosureStatus::singular,
             result;
    if (result.iterations == options.max_iterations) return result.status = ClosureStatus::not_converged, result;
    // Steps limited to max_step in their largest entry, per sub-system.
    for (int k = 0; k < num_subsystems; ++k) {
      S largest = S(0);
      for (int i = subsystem_begin[k]; i < subsystem_begin[k + 1]; ++i)
        if (std::fabs(step[i]) > largest) largest = std::fabs(step[i]);
      const S scale = largest > options.max_step ? options.max_step / largest : S(1);
      for (int i = subsystem_begin[k]; i < subsystem_begin[k + 1]; ++i) q[dependent_q[i]] -= scale * step[i];
    }
  }
}
)";

}  // namespace

std::string emit_closure_positions_declaration(ScalarChoice scalars) {
  std::string out = R"(
/// What closure_positions ended with.
enum class ClosureStatus : int {
  converged = 0,      ///< max |Phi| below the tolerance
  not_converged = 1,  ///< iteration cap reached, or a non-finite residual (q holds the last finite iterate)
  singular = 2,       ///< a linkage at a dead point, or closer to one than the tolerance can tell: z is not a function of y there
};
template <typename S> struct ClosureResult {
  ClosureStatus status;
  int iterations;   ///< Newton steps taken
  S residual;       ///< max |Phi| over the kept closure rows at the returned q (m, rad)
  S pivot_ratio;    ///< smallest / largest |R_ii| of Phi_z's QR, the worst sub-system (1 without loops)
  S relative_pivot_ratio;  ///< each sub-system's pivot ratio over its ratio at the assembled pose, the worst (1 without loops)
};
/// Newton settings, those of the runtime's ClosureOptions (mbgen/algorithm/closure_positions.hpp).
template <typename S> struct ClosureOptions {
  S tolerance;           ///< max |Phi| over the kept rows
  int max_iterations;
  S max_step;            ///< steps scaled down to at most this in their largest entry (rad or m)
  S singular_tolerance;  ///< pivot ratio below this, at any step: singular
  S dead_point_tolerance;  ///< relative pivot ratio below this at the closed pose: singular
};
/// double: the runtime's defaults. float: residuals are known to ~1e-7 m here (unit round-off
/// times the loops' size), so 2e-6; regular poses of the shipped and parallel_legs models have
/// pivot ratios above 1e-3 (robot_delta's ~4e-3, wl16_like's down to ~1.5e-3), so 1e-3 stops
/// Newton where no step can be trusted. A dead point itself shows only in relative terms in
/// float: Newton stops a residual r <= 2e-6 short of it, where the pivot ratio squared is ~2 h r
/// (h the linkage's curvature), ~2e-3 for the slider-crank, no lower than some regular poses of
/// other robots. Each sub-system's ratio over its ratio at the assembled pose (a residual
/// D >= 5e-3 from any dead point) cancels h: below sqrt(tolerance / D) the converged pose is
/// within the tolerance's reach of a dead point, status singular; sqrt(1e-12 / 5e-3) = 1.4e-5,
/// sqrt(2e-6 / 5e-3) = 2e-2 (the runtime's ClosureOptions::dead_point_tolerance says more).
inline constexpr ClosureOptions<double> closure_options_double{1e-12, 20, 0.1, 1e-5, 1.4e-5};
inline constexpr ClosureOptions<float> closure_options_float{2e-6f, 20, 0.1f, 1e-3f, 2e-2f};
/// Closes the loops: Newton on the closures for the dependent coordinates (their entries of q are
/// the warm start), the independent ones held; q (nq) is updated in place. Deterministic, no
/// allocation. Call it after every change of the independent coordinates (a simulation step):
/// forward_dynamics and the maps need a closed q, and a status other than converged means they
/// must not be used there.
)";
  for (const std::string& s : scalar_types(scalars))
    out += fmt::format("ClosureResult<{0}> closure_positions({0}* q, const ClosureOptions<{0}>& options = closure_options_{0});\n", s);
  return out;
}

std::string emit_closure_positions_definition(const Model& model, const std::string& ns, const std::string& header,
                                              ScalarChoice scalars) {
  std::string out = fmt::format("#include \"{}\"\n\n#include <cmath>\n\nnamespace {} {{\n\nnamespace {{\n\n", header, ns);
  if (model.subsystems.empty()) {
    out += "// No loops: every configuration is closed.\n"
           "template <typename S> ClosureResult<S> closure_positions_impl(S*, const ClosureOptions<S>&) {\n"
           "  return {ClosureStatus::converged, 0, S(0), S(1), S(1)};\n}\n";
  } else {
    const TracedFunction step = trace_closure_newton_step(model);
    out += fmt::format("// {}\n// {}.\n", step.doc, describe_operations(count_operations(step)));
    const SplitStatements split = split_statements(step, "closure_newton_step", kMaxStatementsPerPart);
    if (!split.parts.empty()) out += noinline_macro();
    out += split.parts;
    out += "template <typename S> void closure_newton_step(const S* q, S* residual, S* pivots, S* step) {\n";
    out += split.body + "}\n\n";
    std::vector<int> begin{0}, dependent_q;
    for (const SubSystem& sub : model.subsystems) {
      begin.push_back(begin.back() + sub.rank());
      for (int z : sub.dependent) dependent_q.push_back(model.q_index_of_v(z));
    }
    out += "// Sub-system k owns entries [subsystem_begin[k], subsystem_begin[k + 1]) of the step's arrays;\n"
           "// entry i moves q[dependent_q[i]].\n";
    out += fmt::format("constexpr int R = {};\nconstexpr int num_subsystems = {};\n", num_dependent(model), model.subsystems.size());
    out += int_array("subsystem_begin", begin) + int_array("dependent_q", dependent_q);
    // SubSystem::nominal_pivot_ratio holds two significant digits: printed back exactly.
    // (A variable template: the float code converts at compile time, no double arithmetic.)
    out += "// Each sub-system's pivot ratio at the assembled pose (SubSystem::nominal_pivot_ratio).\n";
    out += fmt::format("template <typename S> constexpr S nominal_pivot_ratio[{}] = {{", model.subsystems.size());
    for (std::size_t k = 0; k < model.subsystems.size(); ++k)
      out += fmt::format("{}S({:.1e})", k ? ", " : "", model.subsystems[k].nominal_pivot_ratio);
    out += "};\n\n" + std::string(kNewtonLoop);
  }
  out += "\n}  // namespace\n\n";
  for (const std::string& s : scalar_types(scalars))
    out += fmt::format("ClosureResult<{0}> closure_positions({0}* q, const ClosureOptions<{0}>& options) {{ return closure_positions_impl<{0}>(q, options); }}\n\n", s);
  out += fmt::format("}}  // namespace {}\n", ns);
  return out;
}

}  // namespace mbgen::codegen
