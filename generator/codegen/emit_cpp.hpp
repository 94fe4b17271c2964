#pragma once
// Prints traced functions as straight-line C++: one template body per function (instantiated for
// float and double by thin wrappers), temporaries _tN numbered in topological order, constants
// inlined in shortest round-trip form, and the operation count in the doc comment.
#include <string>

#include "codegen/traced_function.hpp"

namespace mbgen::codegen {

enum class ScalarChoice { Double, Float, Both };

/// `S` wrappers wanted by the choice.
std::vector<std::string> scalar_types(ScalarChoice choice);

/// "12 operations: 5 additions, ..." for the doc comment.
std::string describe_operations(const OpCount& count);

/// The declaration(s) for the header: doc comment with argument sizes and op count.
std::string emit_declaration(const TracedFunction& f, ScalarChoice scalars);

/// The straight-line statements of f's body: `const S _tN = ...;` in topological order, then one
/// assignment per output element (`name[i] = ...;`), two-space indented. emit_definition wraps
/// them in a function; emit_self_distances in a function with local output arrays.
std::string emit_statements(const TracedFunction& f);

/// Statements per part above which a function is split (split_statements). g++'s register
/// allocation grows faster than linearly with a function's size: wl16_like's full_accelerations
/// (~39k statements per scalar) took 200 s in one piece at -O3.
inline constexpr int kMaxStatementsPerPart = 20000;

/// A function body split into parts: `parts` defines `template <typename S> void
/// <prefix>_part<k>(inputs..., S* w)` (marked noinline, see noinline_macro), each computing
/// one run of consecutive statements and storing at its end the values later parts or the
/// outputs need into the workspace w; `body` declares w, calls the parts in order and assigns
/// the outputs. Functions of at most max_statements statements are not split: parts is empty
/// and body is emit_statements(f). Deterministic: slots are reused lowest first.
struct SplitStatements {
  std::string parts;
  std::string body;
};
SplitStatements split_statements(const TracedFunction& f, const std::string& prefix, int max_statements);

/// Defines MBGEN_GENERATED_NOINLINE (GCC and Clang: noinline; else nothing), for files with parts.
std::string noinline_macro();

/// `S(value)` in shortest round-trip form.
std::string literal(double value);

/// A .cpp body (without banner) defining the function in namespace `ns`; includes `header`.
std::string emit_definition(const TracedFunction& f, const std::string& ns, const std::string& header,
                            ScalarChoice scalars);

/// A .cpp body defining `f` as a selection of `source`'s single output (same inputs): it calls
/// `source` into a local array and copies the entries `selection` (one per output element of f).
/// The closed system's forward_dynamics is full_accelerations read at the independent
/// coordinates: one copy of the unrolled code, not two.
std::string emit_selection_definition(const TracedFunction& f, const TracedFunction& source, const std::vector<int>& selection,
                                      const std::string& ns, const std::string& header, ScalarChoice scalars);

/// A .cpp body defining `f` (inputs: source's inputs, then a vector x; one output y) as the
/// product y = A x of `source`'s single output A (row-major, f's output size x x's size): it
/// calls `source` into a local array and sums only A's entries that are not structural zeros
/// (an entry that is the constant 1 adds x itself). full_velocities is velocity_map times vy:
/// one copy of the unrolled maps, not two.
std::string emit_product_definition(const TracedFunction& f, const TracedFunction& source, const std::string& ns,
                                    const std::string& header, ScalarChoice scalars);

}  // namespace mbgen::codegen
