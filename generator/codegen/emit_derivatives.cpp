#include "codegen/emit_derivatives.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <utility>
#include <vector>

#include "codegen/emit_batch.hpp"
#include "codegen/emit_cpp.hpp"
#include "codegen/trace_derivatives.hpp"

namespace mbgen::codegen {

namespace {

std::string int_list(const std::vector<int>& values) {
  std::string out;
  for (int x : values) out += (out.empty() ? "" : ", ") + std::to_string(x);
  return out;
}

/// The factor's structure as constant tables and the row solve (L^T z = b from the last row up,
/// D^-1, L x = z from the first down: mass_matrix_factor.hpp's sweeps for a tree,
/// loop_dynamics_derivatives.hpp's factor_chain_solve for a closed system), then the solves of the
/// `solved` outputs in place (row-major, n rows each).
///
/// Each row of the result is gathered, a block of C columns at a time held in C accumulators:
/// z_i = b_i - sum of L(k, i) z_k over i's descendants k, then x_k = z_k / D_k - sum of L(k, i) x_i
/// over k's ancestors i. The scatter form (row_i -= l row_k for each pair) loads and stores a whole
/// row per term; gathered, a term is one load and one multiply-subtract per column: on
/// talos_reduced's 38 x 38 right-hand sides 63,000 instructions a solve against 114,000 (callgrind,
/// -O3, SSE2), the same 25,000 multiply-adds.
/// What the solves function does besides the solves: its extra parameters, the calls before the
/// solves (the inverse dynamics' pairs, which fill the blocks solved) and after them (a function
/// whose solved blocks feed products: rigid contacts).
struct SolvesExtras {
  std::string parameters, before, after;
};

/// The pairs of the inverse dynamics' derivatives as loops (rnea_derivatives.hpp's
/// inverse_dynamics_derivative_pairs): the pairs as constant lists in the runtime's order, and
/// `function`_pairs, which adds each pair's dot products, of the columns' records the trace left
/// (DerivativeColumnRecord), to the row-major nv x nv blocks `dq` and `dv` (those of `has_q`,
/// `has_v`) with the forward dynamics' signs (the inverse dynamics' flipped). Flat lists, not the
/// runtime's walk up each chain: the walk's short loops of varying length cost a tenth more on
/// talos_reduced. One state, or with lanes S (*)[kLanes] arrays summed as GCC vectors, each lane's
/// operations those of the one-state function.
std::string pair_helpers(const std::string& function, const DerivativePairSweep& sweep, int lanes, bool has_q, bool has_v) {
  using R = DerivativeColumnRecord;
  const bool batch = lanes > 0;
  const std::string V = batch ? "typename Lanes<S>::type" : "S";
  const std::string P = batch ? "const S (*{})[kLanes]" : "const S* {}";
  const std::string out = batch ? "S (*{})[kLanes]" : "S* {}";
  const auto ld = [&](const std::string& x) { return batch ? fmt::format("lanes_load<V>({})", x) : x; };
  const auto update = [&](const std::string& target, char op, const std::string& value) {
    return batch ? fmt::format("lanes_store({0}, lanes_load<V>({0}) {1} ({2}))", target, op, value)
                 : fmt::format("{} {}= {}", target, op, value);
  };
  const std::string dot = function + "_dot";
  const auto dot_of = [&](int n, const char* x, int x_offset, const char* y, int y_offset) {
    return fmt::format("{}<S, {}>({} + {}, {} + {})", dot, n, x, x_offset, y, y_offset);
  };
  const auto lists = [](const std::vector<DerivativePairSweep::Pair>& pairs) {
    std::vector<int> row, column, entry, turns;
    for (const auto& pair : pairs) {
      row.push_back(pair.row_column * R::size);
      column.push_back(pair.column * R::size);
      entry.push_back(pair.entry);
      turns.push_back(pair.turns ? 1 : 0);
    }
    return std::array<std::vector<int>, 4>{row, column, entry, turns};
  };
  const auto all_turn = [](const std::vector<DerivativePairSweep::Pair>& pairs) {
    return std::all_of(pairs.begin(), pairs.end(), [](const auto& p) { return p.turns; });
  };
  // rnea_derivatives.hpp: dtau/dq -= a0 . u1 + dV . u23 and dtau/dv += J . u23 - e . u1 (above),
  // dtau/dq += J . w and dtau/dv += J . z (below); here with the signs flipped.
  std::string parameters = fmt::format(fmt::runtime(P), "columns"), tables, above, below;
  if (has_q) parameters += ", " + fmt::format(fmt::runtime(out), "dq");
  if (has_v) parameters += ", " + fmt::format(fmt::runtime(out), "dv");
  for (const auto& [name, pairs] : {std::pair{"above", &sweep.above}, std::pair{"below", &sweep.below}}) {
    const auto l = lists(*pairs);
    const std::size_t count = std::max<std::size_t>(pairs->size(), 1);  // a C++ array is never empty
    const auto table = [&](const char* what, std::vector<int> values) {
      if (values.empty()) values.push_back(0);
      tables += fmt::format("constexpr int {}_pairs_{}_{}[{}] = {{{}}};\n", function, name, what, count, int_list(values));
    };
    table("row", l[0]);
    table("column", l[1]);
    table("entry", l[2]);
    const bool turns = !all_turn(*pairs);
    if (turns) table("turns", l[3]);
    const std::string guard = turns ? fmt::format("if ({}_pairs_{}_turns[t]) ", function, name) : "";
    std::string body;
    const bool is_above = std::string(name) == "above";
    if (has_q)
      body += fmt::format("    {}{};\n", guard,
                          is_above ? update("dq[e]", '+', dot_of(6, "s", R::a0, "u", R::u1) + " + " + dot_of(3, "s", R::dV_angular, "u", R::u23))
                                   : update("dq[e]", '-', dot_of(6, "u", R::J, "s", R::w)));
    if (has_v)
      body += fmt::format("    {};\n", is_above ? update("dv[e]", '-', dot_of(3, "s", R::J + 3, "u", R::u23) + " - " + dot_of(6, "s", R::e, "u", R::u1))
                                               : update("dv[e]", '-', dot_of(6, "u", R::J, "s", R::z)));
    (is_above ? above : below) = fmt::format(
        "  for (int t = 0; t < {3}; ++t) {{\n"
        "    const auto u = columns + {0}_pairs_{1}_row[t];\n"
        "    const auto s = columns + {0}_pairs_{1}_column[t];\n"
        "    const int e = {0}_pairs_{1}_entry[t];\n"
        "{2}"
        "  }}\n",
        function, name, body, pairs->size());
  }
  return fmt::format(
      "// The pairs of the inverse dynamics' derivatives (rnea_derivatives.hpp), in the runtime's order:\n"
      "// above, a row's column (on body i) and a column of i or of an ancestor; below, a row's column on\n"
      "// a strict ancestor b of i and a column of i. Per pair the columns' records (J, a0, dV (angular),\n"
      "// u1, u23, e, w, z from {R_J}, {R_a0}, {R_dV}, {R_u1}, {R_u23}, {R_e}, {R_w}, {R_z} of {R_size}) and the entry\n"
      "// row nv + column of the nv x nv blocks; above, 0 where the column's body is a rotor's.\n"
      "{tables}"
      "\n"
      "template <typename S, int N>\n"
      "inline {V} {dot}({px}, {py}) {{\n"
      "  typedef {V} V;\n"
      "  V sum = {x0} * {y0};\n"
      "  for (int j = 1; j < N; ++j) sum += {xj} * {yj};\n"
      "  return sum;\n"
      "}}\n"
      "\n"
      "// -dtau/dq and -dtau/dv added pair by pair (the blocks hold the rest: zeros, or the ground's).\n"
      "template <typename S>\n"
      "void {f}_pairs({parameters}) {{\n"
      "  typedef {V} V;\n"
      "  (void)sizeof(V);\n"
      "{above}"
      "{below}"
      "}}\n"
      "\n",
      fmt::arg("f", function), fmt::arg("tables", tables), fmt::arg("V", V), fmt::arg("dot", dot),
      fmt::arg("px", fmt::format(fmt::runtime(P), "x")), fmt::arg("py", fmt::format(fmt::runtime(P), "y")),
      fmt::arg("x0", ld("x[0]")), fmt::arg("y0", ld("y[0]")), fmt::arg("xj", ld("x[j]")), fmt::arg("yj", ld("y[j]")),
      fmt::arg("parameters", parameters), fmt::arg("above", above), fmt::arg("below", below), fmt::arg("R_J", R::J),
      fmt::arg("R_a0", R::a0), fmt::arg("R_dV", R::dV_angular), fmt::arg("R_u1", R::u1), fmt::arg("R_u23", R::u23),
      fmt::arg("R_e", R::e), fmt::arg("R_w", R::w), fmt::arg("R_z", R::z), fmt::arg("R_size", R::size));
}

/// The call of `function`_pairs on the columns' record and the blocks of `names` the trace has.
std::string pair_call(const std::string& function, const TracedFunction& f, const std::vector<std::string>& names) {
  std::string arguments = "derivative_columns";
  for (const std::string& name : names)
    if (std::any_of(f.outputs.begin(), f.outputs.end(), [&](const ArraySpec& a) { return a.name == name; })) arguments += ", " + name;
  return fmt::format("  {}_pairs<S>({});\n", function, arguments);
}

std::string solve_helpers(const std::string& function, const std::vector<int>& parent, const TracedFunction& f,
                          const std::vector<std::size_t>& solved, int lanes, const SolvesExtras& extras = {}) {
  const int n = static_cast<int>(parent.size());
  // k's entries L(k, i), i = k's chain of parents from the nearest, from first[k] on.
  std::vector<int> first(static_cast<std::size_t>(n));
  std::vector<std::vector<std::pair<int, int>>> below(static_cast<std::size_t>(n));  // (k, entry of L(k, i)) per i
  int entries = 0;
  for (int k = 0; k < n; ++k) {
    first[static_cast<std::size_t>(k)] = entries;
    for (int i = parent[static_cast<std::size_t>(k)]; i >= 0; i = parent[static_cast<std::size_t>(i)])
      below[static_cast<std::size_t>(i)].emplace_back(k, entries++);
  }
  std::vector<int> below_first, below_row, below_entry;
  for (const auto& row : below) {
    below_first.push_back(static_cast<int>(below_row.size()));
    for (const auto& [k, e] : row) {
      below_row.push_back(k);
      below_entry.push_back(e);
    }
  }
  below_first.push_back(entries);
  if (entries == 0) {  // no parents at all: the tables keep one unused entry (a C++ array is never empty)
    below_row.push_back(0);
    below_entry.push_back(0);
  }
  // One state: S* arrays, B(r, c) at B[r * W + c]. Lanes: S (*)[kLanes] arrays (batch_source.fmt),
  // B(r, c) of state w at B[r * W + c][w], the sums GCC vectors V of the lanes; each lane's sums
  // are the one-state function's, term by term in the same order (the blocks of columns only
  // group them), so each state equals the one-state function bit for bit.
  const bool batch = lanes > 0;
  const auto param = [&](const char* constness, const std::string& name) {
    return fmt::format("{}S{}", constness, fmt::format(fmt::runtime(batch ? " (*{})[kLanes]" : "* {}"), name));
  };
  const std::string sum_type = batch ? "typename Lanes<S>::type" : "S";
  const std::string load = batch ? "lanes_load<V>({})" : "{}";
  const auto ld = [&](const std::string& x) { return fmt::format(fmt::runtime(load), x); };
  const auto entry = [](const std::string& row) { return fmt::format("B[{} * W + c0 + c]", row); };
  const auto store = [&](const std::string& row) {
    return batch ? fmt::format("lanes_store({}, sum[c])", entry(row)) : fmt::format("{} = sum[c]", entry(row));
  };
  // Blocks of C columns whose sums fill eight 16-byte registers.
  const std::string chunk = batch ? "static_cast<int>(128 / (sizeof(S) * kLanes)) > 0 ? static_cast<int>(128 / (sizeof(S) * kLanes)) : 1"
                                  : "static_cast<int>(128 / sizeof(S))";
  std::string parameters, calls, what;
  for (std::size_t o : solved) {
    const ArraySpec& out = f.outputs[o];
    parameters += ", " + param("", out.name);
    calls += fmt::format("  {}_solve<S, {}>(factor_entries, inverse_pivot, {});\n", function, out.size / n, out.name);
    what += (what.empty() ? "" : ", ") + out.name;
  }
  if (solved.empty()) {  // derivatives_wrt without q and v: M^-1 alone, traced; nothing to solve
    calls = "  (void)factor_entries;\n  (void)inverse_pivot;\n";
    what = "nothing";
  }
  parameters += extras.parameters;
  calls = extras.before + calls + extras.after;
  return fmt::format(
      "// The factor's L^T D L structure: each row's parent (-1: none) and where its entries L(k, i),\n"
      "// i = k's chain of parents from the nearest, start in factor_entries; and each row i's\n"
      "// descendants k (the rows whose chain passes through i) with where L(k, i) is.\n"
      "constexpr int {0}_parent[{1}] = {{{2}}};\n"
      "constexpr int {0}_first[{1}] = {{{3}}};\n"
      "constexpr int {0}_below_first[{1} + 1] = {{{7}}};\n"
      "constexpr int {0}_below_row[{8}] = {{{9}}};\n"
      "constexpr int {0}_below_entry[{8}] = {{{10}}};\n"
      "\n"
      "// Columns c0 .. c0 + C - 1 of row i of L^T z = b, in place: z_i = b_i - sum of L(k, i) z_k over\n"
      "// i's descendants k, the C sums held in registers.\n"
      "template <typename S, int W, int C>\n"
      "inline void {0}_gather_below({11}, {12}, int i, int c0) {{\n"
      "  typedef {13} V;\n"
      "  V sum[C];\n"
      "  for (int c = 0; c < C; ++c) sum[c] = {14};\n"
      "  for (int t = {0}_below_first[i]; t < {0}_below_first[i + 1]; ++t) {{\n"
      "    const V l = {15};\n"
      "    const int k = {0}_below_row[t];\n"
      "    for (int c = 0; c < C; ++c) sum[c] -= l * {16};\n"
      "  }}\n"
      "  for (int c = 0; c < C; ++c) {17};\n"
      "}}\n"
      "\n"
      "// The same columns of row k of L x = D^-1 z, in place: x_k = d z_k - sum of L(k, i) x_i over k's\n"
      "// ancestors i.\n"
      "template <typename S, int W, int C>\n"
      "inline void {0}_gather_above({11}, {18}, {12}, int k, int c0) {{\n"
      "  typedef {13} V;\n"
      "  V sum[C];\n"
      "  const V d = {19};\n"
      "  for (int c = 0; c < C; ++c) sum[c] = d * {20};\n"
      "  int e = {0}_first[k];\n"
      "  for (int i = {0}_parent[k]; i >= 0; i = {0}_parent[i], ++e) {{\n"
      "    const V l = {21};\n"
      "    for (int c = 0; c < C; ++c) sum[c] -= l * {22};\n"
      "  }}\n"
      "  for (int c = 0; c < C; ++c) {23};\n"
      "}}\n"
      "\n"
      "// B = A^-1 B in place for a row-major {1} x W matrix B, A the factored matrix: the factor's\n"
      "// sparse solve, row by row, in blocks of C columns (eight 16-byte registers of sums) and the rest.\n"
      "template <typename S, int W>\n"
      "void {0}_solve({11}, {18}, {12}) {{\n"
      "  constexpr int C = W < ({24}) ? W : ({24});\n"
      "  constexpr int R = W % C;\n"
      "  for (int i = {1} - 1; i >= 0; --i) {{\n"
      "    for (int c0 = 0; c0 + C <= W; c0 += C) {0}_gather_below<S, W, C>(factor_entries, B, i, c0);\n"
      "    if (R != 0) {0}_gather_below<S, W, (R != 0 ? R : 1)>(factor_entries, B, i, W - R);\n"
      "  }}\n"
      "  for (int k = 0; k < {1}; ++k) {{\n"
      "    for (int c0 = 0; c0 + C <= W; c0 += C) {0}_gather_above<S, W, C>(factor_entries, inverse_pivot, B, k, c0);\n"
      "    if (R != 0) {0}_gather_above<S, W, (R != 0 ? R : 1)>(factor_entries, inverse_pivot, B, k, W - R);\n"
      "  }}\n"
      "}}\n"
      "\n"
      "// {4}: solved in place.\n"
      "template <typename S>\n"
      "void {0}_solves({11}, {18}{5}) {{\n"
      "{6}"
      "}}\n"
      "\n",
      function, n, int_list(parent), int_list(first), what, parameters, calls, int_list(below_first),
      below_row.size(), int_list(below_row), int_list(below_entry),
      /*11*/ param("const ", "factor_entries"), /*12*/ param("", "B"), /*13*/ sum_type,
      /*14*/ ld(entry("i")), /*15*/ ld("factor_entries[" + function + "_below_entry[t]]"),
      /*16*/ ld(entry("k")), /*17*/ store("i"), /*18*/ param("const ", "inverse_pivot"), /*19*/ ld("inverse_pivot[k]"),
      /*20*/ ld(entry("k")), /*21*/ ld("factor_entries[e]"), /*22*/ ld(entry("i")), /*23*/ store("k"), /*24*/ chunk);
}

}  // namespace

namespace {

/// The entry points of a trace with work outputs: each declares the work arrays (at least one
/// element each: a C++ array is never empty), runs the trace and calls `function`_solves with
/// `solve_arguments`, over one state or, with lanes, over the batch (then `function` is the
/// batch's name).
std::string work_entry_points(const TracedFunction& f, const std::string& function, const std::string& solve_arguments, int lanes,
                              const EmitContext& ctx) {
  const std::size_t count = f.outputs.size(), work = static_cast<std::size_t>(f.work_outputs);
  const std::string per_entry = lanes > 0 ? fmt::format("[{}]", lanes) : "";
  std::string work_declarations;
  for (std::size_t k = count - work; k < count; ++k)
    work_declarations += fmt::format("{}{}[{}]{}", k == count - work ? "" : ", ", f.outputs[k].name, std::max(f.outputs[k].size, 1),
                                     per_entry);
  std::string entry_points;
  for (const std::string& s : scalar_types(ctx.scalars))
    entry_points += ctx.templates.render(
        "solve_entry_point",
        {{"public_name", ctx.public_name(function, s)},
         {"parameters", lanes > 0 ? public_batch_parameters(f, s, lanes) : public_parameters(f, s)},
         {"scalar", s},
         {"work_declarations", work_declarations},
         {"function", function},
         {"robot", ctx.robot},
         {"arguments", call_arguments(f)},
         {"solve_arguments", solve_arguments}});
  return entry_points;
}

/// The entry points of a derivatives trace with M's factor (work outputs factor_entries and
/// inverse_pivot last): the solves of the `solved` outputs in place, then `after_arguments`.
std::string solve_entry_points(const TracedFunction& f, const std::string& function, const std::vector<std::size_t>& solved,
                               int lanes, const EmitContext& ctx, const std::string& after_arguments = "") {
  const std::size_t count = f.outputs.size(), work = static_cast<std::size_t>(f.work_outputs);
  if (work < 2 || count < work + 2 || f.outputs[count - 2].name != "factor_entries" || f.outputs[count - 1].name != "inverse_pivot")
    throw std::logic_error("emit_forward_dynamics_derivatives: " + f.name + " is not a derivatives trace");
  std::string solve_arguments = "factor_entries, inverse_pivot";
  for (std::size_t o : solved) solve_arguments += ", " + f.outputs[o].name;
  return work_entry_points(f, function, solve_arguments + after_arguments, lanes, ctx);
}

}  // namespace

namespace {
/// A forward-dynamics derivatives source, one state (lanes 0) or a batch: the trace, then in the
/// solves function the inverse dynamics' pairs when the trace left them (a tree's), and the solves.
std::string forward_derivatives_source(const TracedFunction& f, const Model& tree, const std::vector<int>& parent,
                                       const std::vector<std::size_t>& solved, int lanes, const EmitContext& ctx) {
  const std::string name = lanes > 0 ? batch_name(f.name) : f.name;
  SolvesExtras extras;
  std::string pairs, arguments;
  if (has_derivative_pairs(f)) {
    const auto has = [&f](const char* block) {
      return std::any_of(f.outputs.begin(), f.outputs.end(), [&](const ArraySpec& a) { return a.name == block; });
    };
    pairs = pair_helpers(name, DerivativePairSweep::of(tree), lanes, has("dqdd_dq"), has("dqdd_dv"));
    extras.parameters = lanes > 0 ? ", const S (*derivative_columns)[kLanes]" : ", const S* derivative_columns";
    extras.before = pair_call(name, f, {"dqdd_dq", "dqdd_dv"});
    arguments = ", derivative_columns";
  }
  const std::string entry_points = solve_entry_points(f, name, solved, lanes, ctx, arguments);
  const std::string helpers = pairs + solve_helpers(name, parent, f, solved, lanes, extras);
  return lanes > 0 ? emit_batch_definition(f, lanes, ctx, helpers, entry_points) : emit_definition(f, ctx, helpers, entry_points);
}

}  // namespace

std::string emit_forward_dynamics_derivatives_definition(const TracedFunction& f, const Model& tree, const std::vector<int>& parent,
                                                        const std::vector<std::size_t>& solved, const EmitContext& ctx) {
  return forward_derivatives_source(f, tree, parent, solved, 0, ctx);
}

std::string emit_forward_dynamics_derivatives_batch_definition(const TracedFunction& f, const Model& tree,
                                                              const std::vector<int>& parent,
                                                              const std::vector<std::size_t>& solved, int lanes,
                                                              const EmitContext& ctx) {
  return forward_derivatives_source(f, tree, parent, solved, lanes, ctx);
}

std::string emit_rigid_contact_derivatives_definition(const TracedFunction& f, const std::vector<int>& parent,
                                                      const std::vector<std::size_t>& solved, const EmitContext& ctx) {
  const auto has = [&f](const char* name) {
    return std::any_of(f.outputs.begin(), f.outputs.end(), [&](const ArraySpec& a) { return a.name == name; });
  };
  const auto size_of = [&f](const char* name) {
    for (const ArraySpec& a : f.outputs)
      if (a.name == name) return a.size;
    throw std::logic_error("emit_rigid_contact_derivatives_definition: " + f.name + " has no " + name);
  };
  const int n = static_cast<int>(parent.size()), m = size_of("lambda");
  if (size_of("J") != m * n || size_of("contact_factor") != m * m || size_of("Y") != n * m)
    throw std::logic_error("emit_rigid_contact_derivatives_definition: " + f.name + " is not a rigid-contact derivatives trace");
  const std::string product = f.name + "_multiply_add", contact_solve = f.name + "_contact_solve";
  SolvesExtras after;
  after.parameters = ", const S* J, const S* contact_factor, const S* Y";
  std::string arguments = ", J, contact_factor, Y";
  // rigid_contact_derivatives.hpp's rigid_contact_derivatives_solves: dlambda = -(J Y)^-1 (dr2 +
  // J (-P)), then da = (-P) + Y dlambda; along tau dlambda = -(J Y)^-1 Y^T, da = M^-1 + Y dlambda.
  for (const char* x : {"q", "v"}) {
    const std::string da = fmt::format("dqdd_d{}", x), dlambda = fmt::format("dlambda_d{}", x);
    if (!has(da.c_str())) continue;
    after.parameters += ", S* " + dlambda;
    arguments += ", " + dlambda;
    after.after += fmt::format(
        "  {0}<S, {2}, {3}, {3}>(J, {4}, {5});\n  {1}<S, {2}, {3}>(contact_factor, {5});\n  {0}<S, {3}, {2}, {3}>(Y, {5}, {4});\n",
        product, contact_solve, m, n, da, dlambda);
  }
  if (has("dqdd_dtau")) {
    after.parameters += ", S* dqdd_dtau, S* dlambda_dtau";
    arguments += ", dqdd_dtau, dlambda_dtau";
    after.after += fmt::format("  {1}<S, {2}, {3}>(contact_factor, dlambda_dtau);\n  {0}<S, {3}, {2}, {3}>(Y, dlambda_dtau, dqdd_dtau);\n",
                               product, contact_solve, m, n);
  }
  if (!has("dqdd_dq") && !has("dqdd_dv")) after.after += "  (void)J;\n";
  if (!has("dqdd_dq") && !has("dqdd_dv") && !has("dqdd_dtau")) after.after += "  (void)contact_factor;\n  (void)Y;\n";
  const std::string helpers = fmt::format(
      "// C += A B for row-major A (R x K), B (K x N) and C (R x N): the products with J and M^-1 J^T\n"
      "// around the solves.\n"
      "template <typename S, int R, int K, int N>\n"
      "inline void {0}(const S* A, const S* B, S* C) {{\n"
      "  for (int r = 0; r < R; ++r)\n"
      "    for (int k = 0; k < K; ++k) {{\n"
      "      const S a = A[r * K + k];\n"
      "      for (int c = 0; c < N; ++c) C[r * N + c] += a * B[k * N + c];\n"
      "    }}\n"
      "}}\n"
      "\n"
      "// X = -(J M^-1 J^T)^-1 X in place for a row-major R x N matrix X, from the operator's factor F\n"
      "// (small_ldlt.hpp's ldlt_factor: L strictly below the diagonal, 1 / d on it), all N columns at\n"
      "// once: L z = x, then z = -D^-1 z, then L^T x = z.\n"
      "template <typename S, int R, int N>\n"
      "inline void {1}(const S* F, S* X) {{\n"
      "  for (int i = 0; i < R; ++i)\n"
      "    for (int k = 0; k < i; ++k) {{\n"
      "      const S l = F[i * R + k];\n"
      "      for (int c = 0; c < N; ++c) X[i * N + c] -= l * X[k * N + c];\n"
      "    }}\n"
      "  for (int i = 0; i < R; ++i) {{\n"
      "    const S d = -F[i * R + i];\n"
      "    for (int c = 0; c < N; ++c) X[i * N + c] *= d;\n"
      "  }}\n"
      "  for (int i = R - 1; i >= 0; --i)\n"
      "    for (int k = i + 1; k < R; ++k) {{\n"
      "      const S l = F[k * R + i];\n"
      "      for (int c = 0; c < N; ++c) X[i * N + c] -= l * X[k * N + c];\n"
      "    }}\n"
      "}}\n"
      "\n",
      product, contact_solve);
  const std::string entry_points = solve_entry_points(f, f.name, solved, 0, ctx, arguments);
  return emit_definition(f, ctx, helpers + solve_helpers(f.name, parent, f, solved, 0, after), entry_points);
}

}  // namespace mbgen::codegen
