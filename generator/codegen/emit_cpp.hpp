#pragma once
// Prints traced functions as straight-line C++: one template body per function (instantiated for
// float and double by thin wrappers), temporaries _tN numbered in topological order, constants
// inlined in shortest round-trip form, and the operation count in the doc comment.
// The files' frame (includes, namespaces, entry points, doc comments) comes from the templates
// (EmitContext, templates/<flavour>/); this file computes what goes in it.
#include <functional>
#include <string>
#include <vector>

#include "codegen/emit_context.hpp"
#include "codegen/traced_function.hpp"

namespace mbgen::codegen {

/// "12 operations: 5 additions, ..." for the doc comment.
std::string describe_operations(const OpCount& count);

/// f's parameter list for `scalar`: `const S* in..., S* out...`.
std::string parameters(const TracedFunction& f, const std::string& scalar);
/// The same without f's work outputs (TracedFunction::work_outputs): its public signature.
std::string public_parameters(const TracedFunction& f, const std::string& scalar);

/// sincos.fmt rendered when the source computes a sin or cos (uses_trig) or ctx.inline_sincos,
/// else nothing: the {sincos} of the source templates.
std::string sincos_helper(const EmitContext& ctx, bool uses_trig);

/// Whether f's outputs depend on a sin or cos.
bool uses_trig(const TracedFunction& f);

/// f's parameter names, inputs then outputs: `q, v, qdd`.
std::string call_arguments(const TracedFunction& f);

/// `(void)name;` for every input (a function may read none of them) and every empty output.
std::string unused_inputs(const TracedFunction& f);

/// function_declaration.fmt for f: doc comment with argument sizes and op count, the prototypes.
std::string emit_declaration(const TracedFunction& f, const EmitContext& ctx);

/// f's source file (function_source.fmt) with `helpers` printed before its impl (in the impl's
/// unnamed namespace) and the given entry points: for a row whose public functions do more than
/// call the impl (forward_dynamics_derivatives: the solves after it).
std::string emit_definition(const TracedFunction& f, const EmitContext& ctx, const std::string& helpers,
                            const std::string& entry_points);

/// entry_point.fmt per scalar: `function`'s public entry points calling <function>_impl<scalar>
/// with `arguments`, their parameter lists given per scalar.
std::string emit_entry_points(const std::string& function, const std::string& arguments,
                              const std::function<std::string(const std::string&)>& parameters_for, const EmitContext& ctx);

/// How statements are printed: for one state or for `lanes` states at once (lanes > 0, batch
/// functions). For one state, the sines and cosines of inputs (every joint angle) come first, all
/// at once (`sincos_all`, sincos.fmt); other sines and cosines by libm (std::sin, std::cos) or,
/// with inline_sincos, by sincos_of<S> (arithmetic alone, the same for one state and for lanes;
/// always so in a batch).
struct StatementStyle {
  int lanes = 0;
  bool inline_sincos = false;
  /// Outputs written as soon as their values exist (emit_statements); false: all at the end.
  bool early_outputs = true;
  /// With early_outputs false, these outputs (by name) are still written as soon as they exist.
  std::vector<std::string> early_anyway = {};
  /// The constant output entries are left out (split_statements writes them by a function of
  /// their own: set there, for one state, from 256 such entries on).
  bool constants_apart = false;
  /// The statements read the prologue's sines and cosines through pointers into its arrays
  /// (`_sin[slot - bias]`): they are in a function of their own (split_statements sets it).
  bool angles_by_pointer = false;
};

/// f's parameter list over `lanes` states at once (batch functions): `const S (*in)[lanes]...,
/// S (*out)[lanes]...` (in[i][w]: entry i of state w); lanes 0 gives parameters(f, scalar).
std::string batch_parameters(const TracedFunction& f, const std::string& scalar, int lanes);
/// The same without f's work outputs (TracedFunction::work_outputs): the entry points' parameters.
std::string public_batch_parameters(const TracedFunction& f, const std::string& scalar, int lanes);

/// The straight-line statements of f's body: for one state, the prologue computing the sines
/// and cosines of its inputs (`_angle`, `_sin`, `_cos`: StatementStyle), then `const S _tN = ...;` in topological order, with one
/// assignment per output element (`name[i] = ...;`) as soon as its value exists, but after the
/// last statement reading an input (so inputs are all read before any output is written), or
/// all at the end without style.early_outputs; two-space indented. emit_definition wraps
/// them in a function; emit_self_distances in a function with local output arrays.
/// With style.lanes > 0, the same operations in the same order on `V`, a GCC vector of `lanes` S
/// (`const V _tN = ...;`, inputs read by lanes_load, outputs written by lanes_store, sqrt and pow
/// lane by lane: the helpers of batch_source.fmt; sin and cos by sincos_of), so that every lane
/// equals the one-state function printed with inline_sincos bit for bit under the same flags.
std::string emit_statements(const TracedFunction& f, StatementStyle style = {});


/// From this many statements on, an unsplit function with a prologue keeps its statements in a
/// function of their own that reads the sines through pointers (split_statements). Below it the
/// frame is small, and the call is all it would add: iiwa14's inverse dynamics (790 statements)
/// and mass matrix (369) ran the same either way, hyq's (2,451 and 1,337) faster apart.
constexpr int kStatementsApartFrom = 1000;

/// A function body split into parts: `parts` defines `template <typename S> void
/// <prefix>_part<k>(inputs..., [_sin, _cos,] S* w)` (marked noinline, see noinline_macro; the
/// body's prologue computes _sin and _cos once for all parts), each computing
/// one run of consecutive statements and storing at its end the values later parts or the
/// outputs need into the workspace w; `body` declares w, calls the parts in order and assigns
/// the outputs. Functions of at most max_statements statements are not split: parts is empty
/// and body is emit_statements(f, style), except that one with a prologue (one state, sines and
/// cosines of its inputs) and at least kStatementsApartFrom statements keeps its statements in `<prefix>_statements<S>(inputs..., outputs...,
/// _sin, _cos)` (noinline): the body computes the sines and passes pointers into its arrays, which
/// the statements address in fewer instruction bytes than their own frame (angle_pointer_bias in
/// emit_cpp.cpp). Parts, too, read the sines through such pointers. With style.lanes > 0 the workspace holds vectors. Deterministic: slots are reused lowest first.
/// For one state, a function with at least 256 constant output entries (structural zeros of a
/// mass matrix or a Jacobian, a velocity map's identity) writes them last by a function of their
/// own, `<prefix>_constants<S>(outputs...)` in parts (noinline): in a small function g++ packs
/// them into vector stores, in the function's single large basic block it does not.
struct SplitStatements {
  std::string parts;
  std::string body;
};
SplitStatements split_statements(const TracedFunction& f, const std::string& prefix, int max_statements, StatementStyle style = {});

/// `S(value)` in shortest round-trip form.
std::string literal(double value);

/// function_source.fmt for f: its source file, banner included.
std::string emit_definition(const TracedFunction& f, const EmitContext& ctx);

/// selection_source.fmt: the source file defining `f` as a selection of `source`'s single output (same inputs): it calls
/// `source` into a local array and copies the entries `selection` (one per output element of f).
/// The closed system's forward_dynamics is full_accelerations read at the independent
/// coordinates: one copy of the unrolled code, not two.
std::string emit_selection_definition(const TracedFunction& f, const TracedFunction& source, const std::vector<int>& selection,
                                      const EmitContext& ctx);

/// product_source.fmt: the source file defining `f` (inputs: source's inputs, then a vector x; one output y) as the
/// product y = A x of `source`'s single output A (row-major, f's output size x x's size): it
/// calls `source` into a local array and sums only A's entries that are not structural zeros
/// (an entry that is the constant 1 adds x itself). full_velocities is velocity_map times vy:
/// one copy of the unrolled maps, not two.
std::string emit_product_definition(const TracedFunction& f, const TracedFunction& source, const EmitContext& ctx);

/// contact_free_source.fmt: contact_accelerations of a scene without contact spheres, as a call of
/// full_accelerations (`source`) at the independent velocities of v: its unrolled twin would be
/// a second copy of the dynamics that computes nothing more.
std::string emit_contact_free_definition(const TracedFunction& f, const TracedFunction& source, const std::vector<int>& independent,
                                         const EmitContext& ctx);

}  // namespace mbgen::codegen
