#include "codegen/emit_closure_positions.hpp"

#include <algorithm>

#include <fmt/format.h>

#include "codegen/hoist_invariants.hpp"
#include "codegen/trace_loop_maps.hpp"
#include "mbgen/data.hpp"

namespace mbgen::codegen {

namespace {

std::string int_array(const std::string& name, const std::vector<int>& items) {
  std::string out = fmt::format("constexpr int {}[{}] = {{", name, items.size());
  for (std::size_t i = 0; i < items.size(); ++i) out += fmt::format("{}{}", i ? ", " : "", items[i]);
  return out + "};\n";
}

// The loop of the runtime's closure_positions, on the traced step's outputs; with velocities,
// close_loops': the step also gives the dependent velocities at its q, kept when that q is closed.
// R: the number of dependent coordinates; num_subsystems, subsystem_begin, dependent_q,
// dependent_v, the setup sizes: see the tables above it.
const char* kNewtonLoop = R"(// The step Phi_z^-1 Phi from the kept rows `residual` and the factor of the last Newton step (the
// runtime's detail::step_from_factor, the same operations in the same order): per sub-system its
// Givens rotations on the residual (in place: no copy, which g++ would make a memcpy call), then
// back substitution with R (its upper triangle, row by row; one 1 / R(i, i) per row) into step.
// A column's rotations run up the rows, each on the entry the one before it wrote: that entry
// stays in a register (y) and only the finished lower one is stored. Loading both entries from
// memory made each rotation wait for the store of the one before (a 16-byte load across two
// stores is not forwarded): cassie_like's simplified step took 163 ns, 128 without.
template <typename S> void step_from_factor(const S* factor, S* residual, S* step) {
  for (int k = 0; k < num_subsystems; ++k) {
    const int b = subsystem_begin[k], n = subsystem_begin[k + 1] - b, rotations = n * (n - 1) / 2;
    const S* c = factor + factor_begin[k];
    const S* s = c + rotations;
    const S* r = s + rotations;
    S* x = residual + b;
    int m = 0;
    for (int j = 0; j < n; ++j) {
      S y = x[n - 1];
      for (int i = n - 1; i > j; --i, ++m) {
        const S a = x[i - 1];
        if (s[m] == S(0) && c[m] == S(1)) {  // the identity (an entry already zero): skipped, as the runtime does
          x[i] = y;
          y = a;
          continue;
        }
        x[i] = c[m] * y - s[m] * a;
        y = c[m] * a + s[m] * y;
      }
      x[j] = y;
    }
    S* z = step + b;
    for (int i = n - 1; i >= 0; --i) {
      const S* row = r + i * n - i * (i - 1) / 2;  // R(i, i), then R(i, i + 1) ..
      const S inverse_pivot = S(1) / row[0];
      S v = x[i];
      for (int j = i + 1; j < n; ++j) v -= row[j - i] * z[j];
      z[i] = v * inverse_pivot;
    }
  }
}

// Subtracts each sub-system's step from its dependent coordinates, scaled to max_step in its
// largest entry; returns the largest entry of any, unscaled.
template <typename S> S take_step(S* q, const S* step, const ClosureOptions<S>& options) {
  S largest_step = S(0);
  for (int k = 0; k < num_subsystems; ++k) {
    S largest = S(0);
    for (int i = subsystem_begin[k]; i < subsystem_begin[k + 1]; ++i)
      if (std::fabs(step[i]) > largest) largest = std::fabs(step[i]);
    const S scale = largest > options.max_step ? options.max_step / largest : S(1);
    for (int i = subsystem_begin[k]; i < subsystem_begin[k + 1]; ++i) q[dependent_q[i]] -= scale * step[i];
    if (largest > largest_step) largest_step = largest;
  }
  return largest_step;
}

template <typename S, bool kVelocities>
ClosureResult<S> closure_positions_impl(S* q, S* v, const ClosureOptions<S>& options) {
  // A non-finite coordinate is no pose, closed or not. The step reads only the loops' own
  // coordinates, where Newton finds a NaN and names its sub-system; not one off the loops.
  for (int i = 0; i < num_off_loop_q; ++i)
    if (!std::isfinite(q[off_loop_q[i]])) return {ClosureStatus::not_converged, 0, S(NAN), S(1), S(1), -1, -1};
  S residual[R], pivots[R], step[R], vz[kVelocities ? R : 1], factor[kVelocities ? 1 : factor_size];
  // The step's values that depend only on what the loop does not move (q's independent entries; v).
  S invariants[kVelocities ? closure_newton_step_velocities_setup_size : closure_newton_step_setup_size];
  if constexpr (kVelocities) closure_newton_step_velocities_setup<S>(q, v, invariants);
  else closure_newton_step_setup<S>(q, invariants);
  ClosureResult<S> result{ClosureStatus::converged, 0, S(0), S(1), S(1), -1, -1};
  S previous_residual = S(-1);  // the residual before the last step (-1: no step yet)
  bool residual_check = false;
  bool factor_is_last_steps = false;  // factor holds the Newton step's just taken
  for (;; ++result.iterations) {
    if (residual_check) {  // the iterate by its residual alone; the pivot ratios stay the last factor's
      closure_residual<S>(q, residual);
      bool closed = true, finite = true;
      S largest = S(0);
      for (int i = 0; i < R; ++i) {
        if (!(std::fabs(residual[i]) < options.tolerance)) closed = false;
        if (!std::isfinite(residual[i])) finite = false;
        if (std::fabs(residual[i]) > largest) largest = std::fabs(residual[i]);
      }
      if (closed) return result.residual = largest, result;
      // Not closed yet: one simplified step with the last factor, then the residual again (the
      // runtime's detail::residual_check_predicted); a second failure pays for a full step.
      if (finite && factor_is_last_steps && result.iterations < options.max_iterations) {
        step_from_factor<S>(factor, residual, step);
        take_step<S>(q, step, options);
        factor_is_last_steps = false;
        previous_residual = largest;
        continue;
      }
    }
    if constexpr (kVelocities) closure_newton_step_velocities<S>(q, v, invariants, residual, pivots, step, vz);
    else closure_newton_step<S>(q, invariants, residual, pivots, step, factor);
    bool finite = true;
    int worst_residual = 0, worst_relative = 0;  // the sub-systems a failure is reported in
    result.residual = S(0);
    for (int k = 0; k < num_subsystems; ++k)
      for (int i = subsystem_begin[k]; i < subsystem_begin[k + 1]; ++i) {
        if (!std::isfinite(residual[i]) && finite) finite = false, worst_residual = k;
        if (std::fabs(residual[i]) > result.residual) {
          result.residual = std::fabs(residual[i]);
          if (finite) worst_residual = k;
        }
      }
    // Smallest / largest |R_ii| per sub-system, the worst of them, and the worst of them relative
    // to the sub-system's ratio at the assembled pose; NaN (all pivots 0, or NaN) counts as singular.
    result.pivot_ratio = S(1);
    result.relative_pivot_ratio = S(1);
    for (int k = 0; k < num_subsystems; ++k) {
      S smallest = S(0), largest = S(0);
      for (int i = subsystem_begin[k]; i < subsystem_begin[k + 1]; ++i) {
        const S p = std::fabs(pivots[i]);
        if (i == subsystem_begin[k] || !(p >= smallest)) smallest = p;
        if (p > largest) largest = p;
      }
      const S ratio = largest > S(0) ? smallest / largest : S(NAN);  // all pivots 0 or NaN: NaN, no 0 / 0
      if (!(ratio >= result.pivot_ratio)) result.pivot_ratio = ratio;
      const S relative = ratio / nominal_pivot_ratio<S>[k];
      if (!(relative >= result.relative_pivot_ratio)) result.relative_pivot_ratio = relative, worst_relative = k;
    }
    result.worst_subsystem = worst_relative;
    if (!finite) return result.status = ClosureStatus::not_converged, result.subsystem = worst_residual, result;
    if (!(result.pivot_ratio >= options.singular_tolerance))
      return result.status = ClosureStatus::singular, result.subsystem = worst_relative, result;
    if (result.residual < options.tolerance) {  // closed, but maybe within the tolerance's reach of a dead point
      if (result.relative_pivot_ratio >= options.dead_point_tolerance) {
        if constexpr (kVelocities)
          for (int i = 0; i < R; ++i) v[dependent_v[i]] = vz[i];
        return result;
      }
      return result.status = ClosureStatus::singular, result.subsystem = worst_relative, result;
    }
    if (result.iterations == options.max_iterations)
      return result.status = ClosureStatus::not_converged, result.subsystem = worst_residual, result;
    // The runtime's detail::residual_check_predicted: quadratic convergence, or the step's size
    // (r |step|^2), predicts the residual below the tolerance within a simplified step, far from a
    // dead point; never with velocities (they need the factor at the returned q).
    const S largest_step = take_step<S>(q, step, options);
    const S r = result.residual;
    const bool quadratic = previous_residual > S(0) && r * r * r < options.tolerance * previous_residual * previous_residual;
    const bool small_step = r * largest_step * largest_step < options.tolerance;
    residual_check = !kVelocities && (quadratic || small_step) && result.pivot_ratio >= S(100) * options.singular_tolerance &&
                     result.relative_pivot_ratio >= S(100) * options.dead_point_tolerance;
    factor_is_last_steps = true;
    previous_residual = result.residual;
  }
}
)";

/// The closure's functions write their outputs last. They have few (the step: residual rows,
/// pivots, step), and its residual rows are alike expressions: written as soon as they exist,
/// g++'s SLP vectorizer packs them into vectors through shuffles (cassie_like's
/// closure_positions: 8,101 instructions against 6,802 written last, 8 % slower; 6,719 early
/// without SLP).
/// The Newton step's factor (only the simplified step reads it) is written as it is computed: kept
/// for the end, its ~100 values (cassie_like) were spilled and reloaded, and the step was 11 %
/// slower than without it.
StatementStyle closure_style(const EmitContext& ctx) { return {0, ctx.inline_sincos, /*early_outputs=*/false, {"factor"}}; }

}  // namespace

std::string emit_closure_positions_definition(const Model& model, const EmitContext& ctx) {
  std::string out;
  if (model.subsystems.empty()) {
    out += "// No loops: every configuration is closed.\n"
           "template <typename S, bool kVelocities> ClosureResult<S> closure_positions_impl(S*, S*, const ClosureOptions<S>&) {\n"
           "  return {ClosureStatus::converged, 0, S(0), S(1), S(1), -1, -1};\n}\n";
  } else {
    // The residual check is noinline (as the Newton step's statements are), so that it too has the
    // AVX2 copy chosen at load time (noinline_macro.fmt): from a simulator's predicted start it
    // runs once a call, beside one Newton step (talos_like's closed step 2 % faster, bench/README.md).
    out += ctx.templates.render("noinline_macro", {});
    {
      const TracedFunction residual = trace_closure_residual(model);
      out += fmt::format("// {}\n// {}.\n", residual.doc, describe_operations(count_operations(residual)));
      const SplitStatements split = split_statements(residual, residual.name, ctx.max_statements_per_part, closure_style(ctx));
      out += split.parts;
      out += "template <typename S> MBGEN_GENERATED_NOINLINE void closure_residual(const S* q, S* residual) {\n" + split.body + "}\n\n";
    }
    std::vector<int> begin{0}, dependent_q, dependent_v;
    for (const SubSystem& sub : model.subsystems) {
      begin.push_back(begin.back() + sub.rank());
      for (int z : sub.dependent) dependent_q.push_back(model.q_index_of_v(z)), dependent_v.push_back(z);
    }
    // The loop moves only the dependent coordinates: what the step computes from the others
    // (their sines and cosines, the poses of the bodies above the loops) is computed once per
    // call, by the step's setup, instead of once per iteration.
    std::vector<bool> moves(static_cast<std::size_t>(model.nq()), false);
    for (int i : dependent_q) moves[static_cast<std::size_t>(i)] = true;
    auto varies = [&](int argument, int index) { return argument == 0 && moves[static_cast<std::size_t>(index)]; };
    std::string setup_sizes;
    for (const bool with_velocities : {false, true}) {
      const TracedFunction step = trace_closure_newton_step(model, with_velocities);
      const HoistedFunction hoisted = hoist_invariants(step, varies);
      for (const TracedFunction* f : {&hoisted.setup, &hoisted.body}) {
        out += fmt::format("// {}\n// {}{}.\n", f->doc, describe_operations(count_operations(*f)),
                           f == &hoisted.body ? " per iteration" : "");
        const SplitStatements split = split_statements(*f, f->name, ctx.max_statements_per_part, closure_style(ctx));
        out += split.parts;
        out += fmt::format("template <typename S>\nvoid {}({}) {{\n", f->name, parameters(*f, "S")) + unused_inputs(*f) + split.body + "}\n\n";
      }
      setup_sizes += fmt::format("constexpr int {}_setup_size = {};\n", step.name, std::max(hoisted.setup.outputs[0].size, 1));
    }
    out += "// Sub-system k owns entries [subsystem_begin[k], subsystem_begin[k + 1]) of the step's arrays;\n"
           "// entry i moves q[dependent_q[i]], and its velocity is v[dependent_v[i]]. off_loop_q: the q\n"
           "// entries of the joints on no loop (num_off_loop_q of them; the array has at least one).\n";
    out += fmt::format("constexpr int R = {};\nconstexpr int num_subsystems = {};\n", num_dependent(model), model.subsystems.size());
    // The runtime's test (close_positions): a body of no sub-system is off the loops.
    const IndexedVector<BodyIndex, int> subsystem_of_body = model.structure().subsystem_of_body;
    std::vector<int> off_loop_q;
    for (int k = 1; k < model.num_bodies(); ++k) {
      const Joint& joint = model.joint(model.body(BodyIndex(k)).joint);
      if (subsystem_of_body[BodyIndex(k)] < 0)
        for (int i = 0; i < joint.nq; ++i) off_loop_q.push_back(joint.idx_q + i);
    }
    out += fmt::format("constexpr int num_off_loop_q = {};\n", off_loop_q.size());
    if (off_loop_q.empty()) off_loop_q.push_back(0);
    out += int_array("subsystem_begin", begin) + int_array("dependent_q", dependent_q) + int_array("dependent_v", dependent_v) +
           int_array("off_loop_q", off_loop_q);
    const std::vector<int> factor_begin = closure_factor_begin(model);
    out += "// Sub-system k's factor (the step's last output): entries [factor_begin[k], factor_begin[k + 1]).\n";
    out += fmt::format("constexpr int factor_size = {};\n", factor_begin.back()) + int_array("factor_begin", factor_begin);
    out += "// The sizes of the setups' invariants (at least 1).\n" + setup_sizes;
    // SubSystem::nominal_pivot_ratio holds two significant digits: printed back exactly.
    // (A variable template: the float code converts at compile time, no double arithmetic.)
    out += "// Each sub-system's pivot ratio at the assembled pose (SubSystem::nominal_pivot_ratio).\n";
    out += fmt::format("template <typename S> constexpr S nominal_pivot_ratio[{}] = {{", model.subsystems.size());
    for (std::size_t k = 0; k < model.subsystems.size(); ++k)
      out += fmt::format("{}S({:.1e})", k ? ", " : "", model.subsystems[k].nominal_pivot_ratio);
    out += "};\n\n" + std::string(kNewtonLoop);
  }
  std::string entry_points;
  for (const std::string& s : scalar_types(ctx.scalars))
    entry_points += ctx.templates.render(
        "closure_entry_point", {{"public_name", ctx.public_name("closure_positions", s)},
                                {"close_loops", ctx.public_name("close_loops", s)},
                                {"scalar", s},
                                {"robot", ctx.robot}});
  return ctx.templates.render("closure_positions_source", {{"banner", ctx.banner},
                                                           {"header", ctx.header},
                                                           {"robot", ctx.robot},
                                                           {"sincos", sincos_helper(ctx, !model.subsystems.empty())},
                                                           {"implementation", out},
                                                           {"entry_points", entry_points}});
}

}  // namespace mbgen::codegen
