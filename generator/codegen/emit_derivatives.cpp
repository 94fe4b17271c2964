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

/// The factor's structure as constant tables and the row solve of mass_matrix_factor.hpp
/// (L^T z = b from the leaves up, D^-1, L x = z from the root down), each step on whole rows.
std::string solve_helpers(const std::string& function, const Model& tree) {
  const int n = tree.nv();
  std::vector<int> parent(static_cast<std::size_t>(n)), first(static_cast<std::size_t>(n));
  int entries = 0;
  for (int k = 0; k < n; ++k) {
    parent[static_cast<std::size_t>(k)] = tree.velocity_parent(k);
    first[static_cast<std::size_t>(k)] = entries;
    for (int i = tree.velocity_parent(k); i >= 0; i = tree.velocity_parent(i)) ++entries;
  }
  return fmt::format(
      "// The mass matrix's L^T D L factor: each coordinate's parent coordinate (-1: none) and where its\n"
      "// entries L(k, i), i = k's ancestors from the nearest, start in factor_entries.\n"
      "constexpr int {0}_parent[{1}] = {{{2}}};\n"
      "constexpr int {0}_first[{1}] = {{{3}}};\n"
      "\n"
      "// B = M^-1 B in place for a row-major {1} x {1} matrix B: the factor's sparse solve\n"
      "// (mass_matrix_factor.hpp), each step an operation on two whole rows.\n"
      "template <typename S>\n"
      "void {0}_solve(const S* factor_entries, const S* inverse_pivot, S* B) {{\n"
      "  for (int k = {1} - 1; k >= 0; --k) {{\n"
      "    const S* bk = B + k * {1};\n"
      "    int e = {0}_first[k];\n"
      "    for (int i = {0}_parent[k]; i >= 0; i = {0}_parent[i], ++e) {{\n"
      "      S* bi = B + i * {1};\n"
      "      const S l = factor_entries[e];\n"
      "      for (int c = 0; c < {1}; ++c) bi[c] -= l * bk[c];\n"
      "    }}\n"
      "  }}\n"
      "  for (int k = 0; k < {1}; ++k) {{\n"
      "    S* bk = B + k * {1};\n"
      "    const S d = inverse_pivot[k];\n"
      "    for (int c = 0; c < {1}; ++c) bk[c] *= d;\n"
      "  }}\n"
      "  for (int k = 0; k < {1}; ++k) {{\n"
      "    S* bk = B + k * {1};\n"
      "    int e = {0}_first[k];\n"
      "    for (int i = {0}_parent[k]; i >= 0; i = {0}_parent[i], ++e) {{\n"
      "      const S* bi = B + i * {1};\n"
      "      const S l = factor_entries[e];\n"
      "      for (int c = 0; c < {1}; ++c) bk[c] -= l * bi[c];\n"
      "    }}\n"
      "  }}\n"
      "}}\n"
      "\n"
      "// dqdd/dq = M^-1 (-dtau/dq) and dqdd/dv = M^-1 (-dtau/dv), in place.\n"
      "template <typename S>\n"
      "void {0}_solves(const S* factor_entries, const S* inverse_pivot, S* dqdd_dq, S* dqdd_dv) {{\n"
      "  {0}_solve<S>(factor_entries, inverse_pivot, dqdd_dq);\n"
      "  {0}_solve<S>(factor_entries, inverse_pivot, dqdd_dv);\n"
      "}}\n"
      "\n",
      function, n, int_list(parent), int_list(first));
}

}  // namespace

std::string emit_forward_dynamics_derivatives_definition(const TracedFunction& f, const Model& tree, const EmitContext& ctx) {
  if (f.work_outputs != 2 || f.outputs.size() != 6)
    throw std::logic_error("emit_forward_dynamics_derivatives_definition: " + f.name + " is not its trace");
  const ArraySpec& entries = f.outputs[4];
  const ArraySpec& pivots = f.outputs[5];
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
         {"solve_arguments", fmt::format("{}, {}, {}, {}", entries.name, pivots.name, f.outputs[1].name, f.outputs[2].name)}});
  return emit_definition(f, ctx, solve_helpers(f.name, tree), entry_points);
}

}  // namespace mbgen::codegen
