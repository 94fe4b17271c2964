#include "codegen/emit_derivatives.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

#include "codegen/emit_cpp.hpp"

namespace mbgen::codegen {

namespace {

std::string int_list(const std::vector<int>& values) {
  std::string out;
  for (int x : values) out += (out.empty() ? "" : ", ") + std::to_string(x);
  return out;
}

/// The factor's structure as constant tables and the row solve (L^T z = b from the last row up,
/// D^-1, L x = z from the first down, each step on whole rows: mass_matrix_factor.hpp's sweeps for a
/// tree, loop_dynamics_derivatives.hpp's factor_chain_solve for a closed system), then the solves
/// of the `solved` outputs in place (row-major, n rows each).
std::string solve_helpers(const std::string& function, const std::vector<int>& parent, const TracedFunction& f,
                          const std::vector<std::size_t>& solved) {
  const int n = static_cast<int>(parent.size());
  std::vector<int> first(static_cast<std::size_t>(n));
  int entries = 0;
  for (int k = 0; k < n; ++k) {
    first[static_cast<std::size_t>(k)] = entries;
    for (int i = parent[static_cast<std::size_t>(k)]; i >= 0; i = parent[static_cast<std::size_t>(i)]) ++entries;
  }
  std::string parameters, calls, what;
  for (std::size_t o : solved) {
    const ArraySpec& out = f.outputs[o];
    parameters += fmt::format(", S* {}", out.name);
    calls += fmt::format("  {}_solve<S, {}>(factor_entries, inverse_pivot, {});\n", function, out.size / n, out.name);
    what += (what.empty() ? "" : ", ") + out.name;
  }
  return fmt::format(
      "// The factor's L^T D L structure: each row's parent (-1: none) and where its entries L(k, i),\n"
      "// i = k's chain of parents from the nearest, start in factor_entries.\n"
      "constexpr int {0}_parent[{1}] = {{{2}}};\n"
      "constexpr int {0}_first[{1}] = {{{3}}};\n"
      "\n"
      "// B = A^-1 B in place for a row-major {1} x W matrix B, A the factored matrix: the factor's\n"
      "// sparse solve, each step an operation on two whole rows.\n"
      "template <typename S, int W>\n"
      "void {0}_solve(const S* factor_entries, const S* inverse_pivot, S* B) {{\n"
      "  for (int k = {1} - 1; k >= 0; --k) {{\n"
      "    const S* bk = B + k * W;\n"
      "    int e = {0}_first[k];\n"
      "    for (int i = {0}_parent[k]; i >= 0; i = {0}_parent[i], ++e) {{\n"
      "      S* bi = B + i * W;\n"
      "      const S l = factor_entries[e];\n"
      "      for (int c = 0; c < W; ++c) bi[c] -= l * bk[c];\n"
      "    }}\n"
      "  }}\n"
      "  for (int k = 0; k < {1}; ++k) {{\n"
      "    S* bk = B + k * W;\n"
      "    const S d = inverse_pivot[k];\n"
      "    for (int c = 0; c < W; ++c) bk[c] *= d;\n"
      "  }}\n"
      "  for (int k = 0; k < {1}; ++k) {{\n"
      "    S* bk = B + k * W;\n"
      "    int e = {0}_first[k];\n"
      "    for (int i = {0}_parent[k]; i >= 0; i = {0}_parent[i], ++e) {{\n"
      "      const S* bi = B + i * W;\n"
      "      const S l = factor_entries[e];\n"
      "      for (int c = 0; c < W; ++c) bk[c] -= l * bi[c];\n"
      "    }}\n"
      "  }}\n"
      "}}\n"
      "\n"
      "// {4}: solved in place.\n"
      "template <typename S>\n"
      "void {0}_solves(const S* factor_entries, const S* inverse_pivot{5}) {{\n"
      "{6}"
      "}}\n"
      "\n",
      function, n, int_list(parent), int_list(first), what, parameters, calls);
}

}  // namespace

std::string emit_forward_dynamics_derivatives_definition(const TracedFunction& f, const std::vector<int>& parent,
                                                        const std::vector<std::size_t>& solved, const EmitContext& ctx) {
  // Outputs: the results, then the two work arrays (the factor's entries and inverse pivots).
  const std::size_t count = f.outputs.size();
  if (f.work_outputs != 2 || count < 4 || f.outputs[count - 2].name != "factor_entries" ||
      f.outputs[count - 1].name != "inverse_pivot")
    throw std::logic_error("emit_forward_dynamics_derivatives_definition: " + f.name + " is not a derivatives trace");
  const ArraySpec& entries = f.outputs[count - 2];
  const ArraySpec& pivots = f.outputs[count - 1];
  std::string solve_arguments = fmt::format("{}, {}", entries.name, pivots.name);
  for (std::size_t o : solved) solve_arguments += ", " + f.outputs[o].name;
  std::string entry_points;
  for (const std::string& s : scalar_types(ctx.scalars))
    entry_points += ctx.templates.render(
        "solve_entry_point",
        {{"public_name", ctx.public_name(f.name, s)},
         {"parameters", public_parameters(f, s)},
         {"scalar", s},
         {"work_declarations", fmt::format("{}[{}], {}[{}]", entries.name, std::max(entries.size, 1), pivots.name, pivots.size)},
         {"function", f.name},
         {"robot", ctx.robot},
         {"arguments", call_arguments(f)},
         {"solve_arguments", solve_arguments}});
  return emit_definition(f, ctx, solve_helpers(f.name, parent, f, solved), entry_points);
}

}  // namespace mbgen::codegen
