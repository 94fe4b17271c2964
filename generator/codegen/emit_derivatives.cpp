#include "codegen/emit_derivatives.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>
#include <utility>
#include <vector>

#include "codegen/emit_batch.hpp"
#include "codegen/emit_cpp.hpp"

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
/// `after` holds what the solves function does after the solves (its extra parameters, then
/// the calls), for a function whose solved blocks feed products (rigid contacts).
struct AfterSolves {
  std::string parameters, calls;
};

std::string solve_helpers(const std::string& function, const std::vector<int>& parent, const TracedFunction& f,
                          const std::vector<std::size_t>& solved, int lanes, const AfterSolves& after = {}) {
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
  parameters += after.parameters;
  calls += after.calls;
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

/// The entry points of a derivatives trace (work outputs factor_entries and inverse_pivot last):
/// each declares the work arrays, runs the trace and solves the `solved` outputs in place, over one
/// state or, with lanes, over the batch (then `function` is the batch's name).
std::string solve_entry_points(const TracedFunction& f, const std::string& function, const std::vector<std::size_t>& solved,
                               int lanes, const EmitContext& ctx, const std::string& after_arguments = "") {
  const std::size_t count = f.outputs.size(), work = static_cast<std::size_t>(f.work_outputs);
  if (work < 2 || count < work + 2 || f.outputs[count - 2].name != "factor_entries" || f.outputs[count - 1].name != "inverse_pivot")
    throw std::logic_error("emit_forward_dynamics_derivatives: " + f.name + " is not a derivatives trace");
  const ArraySpec& entries = f.outputs[count - 2];
  const ArraySpec& pivots = f.outputs[count - 1];
  const std::string per_entry = lanes > 0 ? fmt::format("[{}]", lanes) : "";
  std::string work_declarations;
  for (std::size_t k = count - work; k < count - 2; ++k)
    work_declarations += fmt::format("{}[{}]{}, ", f.outputs[k].name, f.outputs[k].size, per_entry);
  work_declarations += fmt::format("{}[{}]{}, {}[{}]{}", entries.name, std::max(entries.size, 1), per_entry, pivots.name,
                                   pivots.size, per_entry);
  std::string solve_arguments = fmt::format("{}, {}", entries.name, pivots.name);
  for (std::size_t o : solved) solve_arguments += ", " + f.outputs[o].name;
  solve_arguments += after_arguments;
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

}  // namespace

std::string emit_forward_dynamics_derivatives_definition(const TracedFunction& f, const std::vector<int>& parent,
                                                        const std::vector<std::size_t>& solved, const EmitContext& ctx) {
  const std::string entry_points = solve_entry_points(f, f.name, solved, 0, ctx);
  return emit_definition(f, ctx, solve_helpers(f.name, parent, f, solved, 0), entry_points);
}

std::string emit_forward_dynamics_derivatives_batch_definition(const TracedFunction& f, const std::vector<int>& parent,
                                                              const std::vector<std::size_t>& solved, int lanes,
                                                              const EmitContext& ctx) {
  const std::string name = batch_name(f.name);
  const std::string entry_points = solve_entry_points(f, name, solved, lanes, ctx);
  return emit_batch_definition(f, lanes, ctx, solve_helpers(name, parent, f, solved, lanes), entry_points);
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
  AfterSolves after;
  after.parameters = ", const S* J, const S* contact_factor, const S* Y";
  std::string arguments = ", J, contact_factor, Y";
  // rigid_contact_derivatives.hpp's rigid_contact_derivatives_solves: dlambda = -(J Y)^-1 (dr2 +
  // J (-P)), then da = (-P) + Y dlambda; along tau dlambda = -(J Y)^-1 Y^T, da = M^-1 + Y dlambda.
  for (const char* x : {"q", "v"}) {
    const std::string da = fmt::format("dqdd_d{}", x), dlambda = fmt::format("dlambda_d{}", x);
    if (!has(da.c_str())) continue;
    after.parameters += ", S* " + dlambda;
    arguments += ", " + dlambda;
    after.calls += fmt::format(
        "  {0}<S, {2}, {3}, {3}>(J, {4}, {5});\n  {1}<S, {2}, {3}>(contact_factor, {5});\n  {0}<S, {3}, {2}, {3}>(Y, {5}, {4});\n",
        product, contact_solve, m, n, da, dlambda);
  }
  if (has("dqdd_dtau")) {
    after.parameters += ", S* dqdd_dtau, S* dlambda_dtau";
    arguments += ", dqdd_dtau, dlambda_dtau";
    after.calls += fmt::format("  {1}<S, {2}, {3}>(contact_factor, dlambda_dtau);\n  {0}<S, {3}, {2}, {3}>(Y, dlambda_dtau, dqdd_dtau);\n",
                               product, contact_solve, m, n);
  }
  if (!has("dqdd_dq") && !has("dqdd_dv")) after.calls += "  (void)J;\n";
  if (!has("dqdd_dq") && !has("dqdd_dv") && !has("dqdd_dtau")) after.calls += "  (void)contact_factor;\n  (void)Y;\n";
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
