// self_distances: traced placement and Jacobian columns, unrolled shape pairs (emit_self_distances.hpp).
#include "codegen/emit_self_distances.hpp"

#include <fmt/format.h>

#include <map>
#include <set>

#include "codegen/symbolic.hpp"
#include "mbgen/mbgen.hpp"

namespace mbgen::codegen {

namespace {

using collision::CollisionModel;
using collision::Compound;
using collision::Shape;
using collision::vertex_count;

/// Where each placed point lives in P (offsets of 3 numbers), per compound and shape.
struct Placement {
  std::vector<int> points;  ///< offset of each core point
  int bound = -1;           ///< offset of the bounding-sphere centre (-1: no pair needs it)
};

/// What the straight-line part computes: placed points and Jacobian columns, and where.
struct Plan {
  std::map<int, std::vector<Placement>> shapes;  ///< per used compound, per shape
  std::map<int, int> compound_bound;             ///< per used compound, the offset of its bounding-sphere centre
  std::vector<int> columns;                      ///< velocity columns needed, ascending
  std::map<int, int> column_slot;                ///< column -> its 6 numbers in J at 6 * slot
  std::map<int, std::set<int>> support;          ///< per used compound, the columns moving its body
  int num_p = 0;
};

std::set<int> supporting_columns(const Model& model, BodyIndex body) {
  std::set<int> out;
  for (BodyIndex b = body; b != kWorldBody; b = model.body(b).parent) {
    const Joint& joint = model.joint(model.body(b).joint);
    for (int col = 0; col < joint.nv; ++col) out.insert(joint.idx_v + col);
  }
  return out;
}

Plan make_plan(const Model& model, const CollisionModel& scene) {
  Plan plan;
  std::set<int> needs_bounds;  // compounds in a pair of more than one shape pair
  for (const collision::CollisionPair& p : scene.pairs) {
    const Compound& a = scene.compounds[static_cast<std::size_t>(p.first)];
    const Compound& b = scene.compounds[static_cast<std::size_t>(p.second)];
    plan.shapes[p.first];
    plan.shapes[p.second];
    if (a.shapes.size() * b.shapes.size() > 1) {
      needs_bounds.insert(p.first);
      needs_bounds.insert(p.second);
    }
  }
  std::set<int> columns;
  for (auto& [c, placements] : plan.shapes) {
    const Compound& compound = scene.compounds[static_cast<std::size_t>(c)];
    for (const Shape& s : compound.shapes) {
      Placement pl;
      for (int k = 0; k < vertex_count(s); ++k, plan.num_p += 3) pl.points.push_back(plan.num_p);
      if (needs_bounds.count(c)) {
        pl.bound = plan.num_p;
        plan.num_p += 3;
      }
      placements.push_back(pl);
    }
    plan.compound_bound[c] = plan.num_p;  // the near set's test
    plan.num_p += 3;
    plan.support[c] = supporting_columns(model, compound.body);
    columns.insert(plan.support[c].begin(), plan.support[c].end());
  }
  plan.columns.assign(columns.begin(), columns.end());
  for (std::size_t k = 0; k < plan.columns.size(); ++k) plan.column_slot[plan.columns[k]] = static_cast<int>(k);
  return plan;
}

/// The branch-free part: P (placed points) and J (world joint-Jacobian columns, [linear; angular]
/// of the motion at the world origin, as data.J), traced from the runtime.
TracedFunction trace_placement(const Model& model, const CollisionModel& scene, const Plan& plan) {
  TracedFunction f;
  f.name = "self_distances";
  f.inputs = {{"q", model.nq(), ""}};
  f.outputs = {{"P", plan.num_p, ""}, {"J", 6 * static_cast<int>(plan.columns.size()), ""}};
  Recording rec(f.graph);
  Data<Sym> data(model);
  VecX<Sym> q(model.nq());
  for (int i = 0; i < model.nq(); ++i) q[i] = Sym::input(0, i);
  compute_joint_jacobians<Sym>(model, data, q);
  std::vector<int> p_ids, j_ids;
  auto place = [&](const SE3<Sym>& X, const Vec3<double>& p) {
    // The same expression as collision::detail::place: X.act(p cast to the scalar).
    const Vec3<Sym> w = X.act(p.cast<Sym>());
    for (int r = 0; r < 3; ++r) p_ids.push_back(w[r].id());
  };
  for (const auto& [c, placements] : plan.shapes) {
    const Compound& compound = scene.compounds[static_cast<std::size_t>(c)];
    const SE3<Sym>& X = data.X_WB[compound.body];
    for (std::size_t s = 0; s < placements.size(); ++s) {
      const Shape& shape = compound.shapes[s];
      for (int k = 0; k < vertex_count(shape); ++k) place(X, shape.points[static_cast<std::size_t>(k)]);
      if (placements[s].bound >= 0) place(X, shape.bound_center);
    }
    place(X, compound.bound_center);
  }
  for (int col : plan.columns)
    for (int r = 0; r < 6; ++r) j_ids.push_back(data.J(r, col).id());
  f.output_ids = {p_ids, j_ids};
  return f;
}

const char* kind_name(Shape::Kind k) {
  return k == Shape::Kind::Point ? "PointSsv" : (k == Shape::Kind::Line ? "LineSsv" : "TriangleSsv");
}

std::string volume(const Shape& s, const Placement& pl) {
  std::string args;
  for (int o : pl.points) args += fmt::format("at(P + {}), ", o);
  return fmt::format("{}<S>{{{}{}}}", kind_name(s.kind), args, literal(s.radius));
}

/// ssv_distance for shapes a (volume 1) and b (volume 2): the primitives take the lower kind first
/// (point < line < triangle), so higher-vs-lower is computed the other way round and reversed,
/// as collision::detail::shape_distance does.
std::string shape_call(const Shape& a, const Placement& pa, const Shape& b, const Placement& pb) {
  if (static_cast<int>(a.kind) <= static_cast<int>(b.kind))
    return fmt::format("ssv_distance({}, {})", volume(a, pa), volume(b, pb));
  return fmt::format("reversed(ssv_distance({}, {}))", volume(b, pb), volume(a, pa));
}

std::string pair_block(const Model& model, const CollisionModel& scene, const Plan& plan, std::size_t k) {
  const collision::CollisionPair& p = scene.pairs[k];
  const Compound& a = scene.compounds[static_cast<std::size_t>(p.first)];
  const Compound& b = scene.compounds[static_cast<std::size_t>(p.second)];
  const std::vector<Placement>& pa = plan.shapes.at(p.first);
  const std::vector<Placement>& pb = plan.shapes.at(p.second);
  std::string out = fmt::format("  {{  // pair {}: {} ({} shapes) - {} ({} shapes)\n", k, a.name, a.shapes.size(), b.name,
                                b.shapes.size());
  // The near set (collision::compute_near_distances): the compounds' bounding spheres first.
  // The bounding spheres' test, in a block of its own that only the near set enters.
  const std::string bound = fmt::format("sphere_lower_bound(at(P + {}), {}, at(P + {}), {})", plan.compound_bound.at(p.first),
                                        literal(a.bound_radius), plan.compound_bound.at(p.second), literal(b.bound_radius));
  out += fmt::format("    bool far = false;\n    if (compact) {{\n      const S bound = {};\n"
                     "      if (bound >= threshold) {{\n        distance[{}] = bound;\n        far = true;\n      }}\n    }}\n"
                     "    if (!far) {{\n", bound, k);
  // The near set's threshold is the shape pairs' limit too (ClosestShapes: a shape pair whose
  // spheres are that far apart is skipped); the full set computes at least the first pair. A
  // single shape pair has no spheres of its own: its compounds' spheres were the test.
  out += "      ClosestShapes<S> best(compact, threshold);\n";
  const bool single = a.shapes.size() * b.shapes.size() == 1;
  for (std::size_t i = 0; i < a.shapes.size(); ++i)
    for (std::size_t j = 0; j < b.shapes.size(); ++j) {
      const std::string call = fmt::format("best.take({}, {}, {});", shape_call(a.shapes[i], pa[i], b.shapes[j], pb[j]), i, j);
      if (single) {
        out += "      " + call + "\n";
      } else {
        out += fmt::format("      if (best.worth(at(P + {}), {}, at(P + {}), {})) {}\n", pa[i].bound,
                           literal(a.shapes[i].bound_radius), pb[j].bound, literal(b.shapes[j].bound_radius), call);
      }
    }
  // Near only if the distance itself is below the threshold: the rows are the expensive part.
  out += fmt::format("      if (compact && !best.within_limit()) {{\n        distance[{}] = best.lower_bound();\n"
                     "      }} else {{\n", k);
  out += fmt::format("      store(best.result, {}, m, distance, normal, witness);\n", k);
  out += fmt::format("      if (near) near[m] = {};\n", k);
  // Row m = n^T (J_p2 - J_p1); per column c: n . v_c + w_c . (p x n) for the body's witness p.
  // Columns moving both bodies keep w_c . ((p2 - p1) x n) (n . v_c cancels).
  const std::set<int>& s1 = plan.support.at(p.first);
  const std::set<int>& s2 = plan.support.at(p.second);
  out += "      const SsvVec3<S> n = best.result.normal;\n";
  out += "      const SsvVec3<S> p1n = best.result.point1.cross(n), p2n = best.result.point2.cross(n), dn = p2n - p1n;\n";
  out += "      (void)p1n;\n      (void)p2n;\n      (void)dn;\n";
  out += fmt::format("      S* row = jacobian + m * {};\n", model.nv());
  for (int c = 0; c < model.nv(); ++c) {
    const bool in1 = s1.count(c) > 0, in2 = s2.count(c) > 0;
    if (!in1 && !in2) {
      out += fmt::format("      row[{}] = S(0);\n", c);
      continue;
    }
    const int j = 6 * plan.column_slot.at(c);
    if (in1 && in2) out += fmt::format("      row[{}] = dot3(dn, J + {});\n", c, j + 3);
    else if (in2) out += fmt::format("      row[{}] = dot3(n, J + {}) + dot3(p2n, J + {});\n", c, j, j + 3);
    else out += fmt::format("      row[{}] = -(dot3(n, J + {}) + dot3(p1n, J + {}));\n", c, j, j + 3);
  }
  return out + "      ++m;\n      }\n    }\n  }\n";
}

/// SSV calls per noinline part of distances_impl (its own rule: --max-statements counts traced
/// statements, and an inlined SSV call weighs many). g++'s time on one function grows faster than
/// its size: Lola's 711 calls in one function took 60.7 s at -O3 (68 s for a Cortex-M7 at -O2),
/// in parts of at most 48 calls 26.1 s (35 s), for a full set 6 % slower (placed points read from
/// memory instead of registers) and a near set 1 % slower (docs/ssv.md).
constexpr int kSsvCallsPerPart = 48;

int ssv_calls(const CollisionModel& scene, std::size_t k) {
  const collision::CollisionPair& p = scene.pairs[k];
  return static_cast<int>(scene.compounds[static_cast<std::size_t>(p.first)].shapes.size() *
                          scene.compounds[static_cast<std::size_t>(p.second)].shapes.size());
}

/// The pair blocks, in parts of at most kSsvCallsPerPart SSV calls (a pair is never cut) when
/// the scene has more calls than one part holds; else in distances_impl itself.
struct PairCode {
  std::string parts;  ///< the parts' definitions, or nothing
  std::string body;   ///< distances_impl's statements after the placement: the blocks or the parts' calls
};

PairCode pair_code(const Model& model, const CollisionModel& scene, const Plan& plan, int total_calls) {
  PairCode code;
  const std::size_t np = scene.pairs.size();
  if (total_calls <= kSsvCallsPerPart) {
    for (std::size_t k = 0; k < np; ++k) code.body += pair_block(model, scene, plan, k);
    return code;
  }
  for (std::size_t first = 0; first < np;) {
    std::size_t last = first;
    int calls = ssv_calls(scene, first);
    while (last + 1 < np && calls + ssv_calls(scene, last + 1) <= kSsvCallsPerPart) calls += ssv_calls(scene, ++last);
    const std::string name = fmt::format("pairs_{}_to_{}", first, last);
    code.parts += fmt::format("// Pairs {} to {} of distances_impl ({} SSV calls).\n"
                              "template <typename S, bool compact>\nMBGEN_GENERATED_NOINLINE void {}(const S* P, const S* J, S threshold, "
                              "S* distance, int* near, S* normal, S* witness, S* jacobian, int& m) {{\n",
                              first, last, calls, name);
    for (std::size_t k = first; k <= last; ++k) code.parts += pair_block(model, scene, plan, k);
    code.parts += "}\n\n";
    code.body += fmt::format("  {}<S, compact>(P, J, threshold, distance, near, normal, witness, jacobian, m);\n", name);
    first = last + 1;
  }
  return code;
}

std::string arguments(const std::string& scalar) {
  return fmt::format("const {0}* q, {0}* distance, {0}* normal, {0}* witness, {0}* jacobian", scalar);
}

std::string near_arguments(const std::string& scalar) {
  return fmt::format("const {0}* q, {0} threshold, {0}* distance, int* near, int* num_near, {0}* normal, {0}* witness, {0}* jacobian",
                     scalar);
}

/// The implementation both entry points share, a template on compact (the near set,
/// self_distances_near): each entry point gets its own copy, the full set's without the near
/// set's branches (Lola's full set on 64 standing poses: 185k instructions per call with them,
/// 174k without; docs/ssv.md).
std::string impl_arguments() {
  return "const S* q, S threshold, S* distance, int* near, int* num_near, S* normal, S* witness, S* jacobian";
}

}  // namespace

SelfDistanceCode emit_self_distances(const Model& model, const CollisionModel& scene, const EmitContext& ctx) {
  const Plan plan = make_plan(model, scene);
  const TracedFunction traced = trace_placement(model, scene, plan);
  const std::size_t np = scene.pairs.size();
  int shape_pairs = 0;
  for (std::size_t k = 0; k < np; ++k) shape_pairs += ssv_calls(scene, k);
  const std::string cost = np == 0 ? "nothing (the scene keeps no pair)"
                                   : fmt::format("straight-line placement and Jacobian columns: {}; then at most {} SSV "
                                                 "distance calls ({} pair{}; bounding spheres skip the rest)",
                                                 describe_operations(count_operations(traced)), shape_pairs, np,
                                                 np == 1 ? "" : "s");

  // C++ and C have no empty arrays: one empty row when there is no pair.
  std::string pair_names = np == 0 ? "{\"\", \"\"}" : "";
  for (std::size_t k = 0; k < np; ++k)
    pair_names += fmt::format("{}{{\"{}\", \"{}\"}}", k ? ", " : "", scene.compounds[static_cast<std::size_t>(scene.pairs[k].first)].name,
                              scene.compounds[static_cast<std::size_t>(scene.pairs[k].second)].name);
  std::string prototypes, near_prototypes;
  for (const std::string& s : scalar_types(ctx.scalars)) {
    prototypes += ctx.templates.render("prototype", {{"public_name", ctx.public_name("self_distances", s)},
                                                     {"parameters", arguments(s)},
                                                     {"scalar", s},
                                                     {"function", "self_distances"},
                                                     {"robot", ctx.robot}});
    near_prototypes += ctx.templates.render("prototype", {{"public_name", ctx.public_name("self_distances_near", s)},
                                                          {"parameters", near_arguments(s)},
                                                          {"scalar", s},
                                                          {"function", "self_distances_near"},
                                                          {"robot", ctx.robot}});
  }

  std::string body;
  PairCode pairs;
  if (np == 0) {
    body = "  (void)q;\n  (void)threshold;\n  (void)compact;\n  (void)distance;\n  (void)near;\n  (void)normal;\n"
           "  (void)witness;\n  (void)jacobian;\n  if (num_near) *num_near = 0;\n";
  } else {
    body += "  int m = 0;  // rows written: the near pairs so far (every pair when !compact)\n";
    body += fmt::format("  S P[{}];  // shapes' points placed in the world\n", plan.num_p);
    body += fmt::format("  S J[{}];  // world joint-Jacobian columns {{", 6 * plan.columns.size());
    for (std::size_t k = 0; k < plan.columns.size(); ++k) body += fmt::format("{}{}", k ? ", " : "", plan.columns[k]);
    body += "}, 6 each\n";
    body += emit_statements(traced, {0, ctx.inline_sincos});
    pairs = pair_code(model, scene, plan, shape_pairs);
    body += pairs.body;
    body += "  if (num_near) *num_near = m;\n";
  }

  SelfDistanceCode code;
  code.header_fields = {{"num_distance_pairs", std::to_string(np)},
                        {"distance_pair_rows", std::to_string(np == 0 ? 1 : np)},
                        {"distance_pair_names", pair_names},
                        {"distance_declarations", ctx.templates.render("distance_declarations",
                                                                       {{"nq", std::to_string(model.nq())},
                                                                        {"nv", std::to_string(model.nv())},
                                                                        {"num_distance_pairs", std::to_string(np)},
                                                                        {"distance_cost", cost},
                                                                        {"distance_prototypes", prototypes},
                                                                        {"near_prototypes", near_prototypes}})}};
  code.source = ctx.templates.render(
      "self_distances_source",
      {{"banner", ctx.banner},
       {"header", ctx.header},
       {"robot", ctx.robot},
       {"cost", cost},
       {"sincos", sincos_helper(ctx, np > 0 && uses_trig(traced))},
       {"noinline", pairs.parts.empty() ? std::string() : ctx.templates.render("noinline_macro", {})},
       {"parts", pairs.parts},
       {"impl_parameters", impl_arguments()},
       {"full_parameters", arguments("S")},
       {"near_parameters", near_arguments("S")},
       {"body", body},
       {"entry_points", emit_entry_points("self_distances", "q, distance, normal, witness, jacobian", arguments, ctx) +
                            emit_entry_points("self_distances_near", "q, threshold, distance, near, num_near, normal, witness, jacobian",
                                              near_arguments, ctx)}});
  return code;
}

}  // namespace mbgen::codegen
