#include "codegen/trace_loop_maps.hpp"

#include <stdexcept>

#include "codegen/trace_support.hpp"

namespace mbgen::codegen {

using namespace tracing;

int num_dependent(const Model& model) {
  int n = 0;
  for (const SubSystem& s : model.subsystems) n += s.rank();
  return n;
}

std::vector<int> closure_factor_begin(const Model& model) {
  std::vector<int> begin{0};
  for (const SubSystem& s : model.subsystems) begin.push_back(begin.back() + s.rank() * (s.rank() - 1) + s.rank() * (s.rank() + 1) / 2);
  return begin;
}

TracedFunction trace_closure_newton_step(const Model& model, bool with_velocities) {
  if (model.subsystems.empty()) throw std::logic_error("trace_closure_newton_step: the model has no loops");
  const int r = num_dependent(model);
  TracedFunction f;
  f.name = with_velocities ? "closure_newton_step_velocities" : "closure_newton_step";
  f.doc = "One Newton step of the closure: kept residual rows, Phi_z's R diagonal and the step Phi_z^-1 Phi per "
          "sub-system (runtime: detail::closure_newton_step)";
  f.doc += with_velocities ? ", and the dependent velocities -Phi_z^-1 Phi_y v_y at q from the same factor "
                             "(detail::dependent_velocities_from_factor)."
                           : ", and that factor (the loop's simplified steps reuse it).";
  f.inputs = {q_spec(model)};
  if (with_velocities) f.inputs.push_back(v_spec(model, "v", "joint velocities (the independent entries are read)"));
  f.outputs = {{"residual", r, fmt::format("[{}] kept closure rows, sub-system by sub-system", r)},
               {"pivots", r, fmt::format("[{}] diagonal of each sub-system's R factor of Phi_z", r)},
               {"step", r, fmt::format("[{}] Newton step, to subtract from the dependent coordinates", r)}};
  if (with_velocities) f.outputs.push_back({"vz", r, fmt::format("[{}] dependent velocities, in the step's order", r)});
  else
    f.outputs.push_back({"factor", closure_factor_begin(model).back(),
                         fmt::format("[{}] per sub-system of rank n: the n (n - 1) / 2 Givens cosines, the sines, then R's upper "
                                     "triangle row by row (the simplified step's factor)",
                                     closure_factor_begin(model).back())});
  Recording rec(f.graph);
  Data<Sym> data(model);
  mbgen::detail::closure_newton_step<Sym>(model, data, inputs(0, model.nq()));
  std::vector<int> residual, pivots, step, vz;
  for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
    const SubSystem& sub = model.subsystems[k];
    const SubSystemWork<Sym>& w = data.subsystem[k];
    const int p = static_cast<int>(sub.independent.size());
    for (int i = 0; i < sub.rank(); ++i) {
      residual.push_back(data.Phi[sub.rows[static_cast<std::size_t>(i)]].id());
      pivots.push_back(w.R(i, i).id());
      step.push_back(w.rhs(i, p).id());
    }
  }
  f.output_ids = {residual, pivots, step};
  if (!with_velocities) {
    std::vector<int> factor;
    for (std::size_t k = 0; k < model.subsystems.size(); ++k) {
      const SubSystemWork<Sym>& w = data.subsystem[k];
      const int n = model.subsystems[k].rank(), rotations = n * (n - 1) / 2;
      for (int m = 0; m < rotations; ++m) factor.push_back(w.rotation_c[m].id());
      for (int m = 0; m < rotations; ++m) factor.push_back(w.rotation_s[m].id());
      for (int i = 0; i < n; ++i)
        for (int j = i; j < n; ++j) factor.push_back(w.R(i, j).id());
    }
    f.output_ids.push_back(factor);
  }
  if (with_velocities) {
    SymVec v = inputs(1, model.nv());
    mbgen::detail::dependent_velocities_from_factor<Sym>(model, data, v);
    for (const SubSystem& sub : model.subsystems)
      for (int z : sub.dependent) vz.push_back(v[z].id());
    f.output_ids.push_back(vz);
  }
  return f;
}

TracedFunction trace_closure_residual(const Model& model) {
  if (model.subsystems.empty()) throw std::logic_error("trace_closure_residual: the model has no loops");
  const int r = num_dependent(model);
  TracedFunction f;
  f.name = "closure_residual";
  f.doc = "The kept closure rows at q, sub-system by sub-system (runtime: closure_residual; the Newton step's residual).";
  f.inputs = {q_spec(model)};
  f.outputs = {{"residual", r, fmt::format("[{}] kept closure rows, sub-system by sub-system", r)}};
  Recording rec(f.graph);
  Data<Sym> data(model);
  closure_residual<Sym>(model, data, inputs(0, model.nq()));
  std::vector<int> residual;
  for (const SubSystem& sub : model.subsystems)
    for (int i = 0; i < sub.rank(); ++i) residual.push_back(data.Phi[sub.rows[static_cast<std::size_t>(i)]].id());
  f.output_ids = {residual};
  return f;
}

TracedFunction trace_closure_constraints(const Model& model) {
  const int r = num_dependent(model), nv = model.nv();
  TracedFunction f;
  f.name = "closure_constraints";
  f.doc = "The kept closure rows in full coordinates at (q, v): residual, Jacobian and bias with J qdd = gamma "
          "(runtime: closure_constraints), sub-system by sub-system; what a solver that keeps the loops by "
          "multipliers reads (the simulator's soft span through a dead point). No rows without loops.";
  f.inputs = {q_spec(model), v_spec(model, "v", "joint velocities (every entry is read)")};
  f.outputs = {{"Phi", r, fmt::format("[{}] kept closure rows, sub-system by sub-system", r)},
               {"J", r * nv, fmt::format("[{} x {}, row-major] their Jacobian, joint_names_full columns", r, nv), {r, nv}},
               {"gamma", r, fmt::format("[{}] bias: J qdd = gamma keeps the rows' velocities constant", r)}};
  Recording rec(f.graph);
  Data<Sym> data(model);
  closure_constraints<Sym>(model, data, inputs(0, model.nq()), inputs(1, nv));
  std::vector<int> Phi, J, gamma;
  for (const SubSystem& sub : model.subsystems)
    for (int row : sub.rows) {
      Phi.push_back(data.Phi[row].id());
      gamma.push_back(data.gamma[row].id());
      for (int c = 0; c < nv; ++c) J.push_back(data.Phi_q(row, c).id());
    }
  f.output_ids = {Phi, J, gamma};
  return f;
}

TracedFunction trace_velocity_map(const Model& model) {
  const int ny = num_independent(model);
  TracedFunction f;
  f.name = "velocity_map";
  f.doc = "Velocity map T of the closed system at q: v = T vy gives every tree joint's velocity from the independent "
          "ones (the identity off the loops, each sub-system's G = [I; -Phi_z^-1 Phi_y] on its coordinates).";
  f.inputs = {closed_q_spec(model)};
  f.outputs = {{"T", model.nv() * ny, fmt::format("[{} x {}, row-major] velocity map, joint_names_full rows, "
                                                  "independent_joint_names columns", model.nv(), ny),
                     {model.nv(), ny}}};
  Recording rec(f.graph);
  Data<Sym> data(model);
  MatX<Sym> T(model.nv(), ny);
  velocity_map<Sym>(model, data, inputs(0, model.nq()), T);
  f.output_ids = {ids_of(T)};
  return f;
}

TracedFunction trace_full_velocities(const Model& model) {
  TracedFunction f;
  f.name = "full_velocities";
  f.doc = "Velocities of every tree joint, v = T vy, from the independent ones: the velocity that keeps the loops "
          "closed.";
  f.inputs = {closed_q_spec(model), y_spec(model, "vy", "independent velocities")};
  f.outputs = {v_spec(model, "v", "velocities of every tree joint, joint_names_full order")};
  Recording rec(f.graph);
  Data<Sym> data(model);
  VecX<Sym> v(model.nv());
  full_velocities<Sym>(model, data, inputs(0, model.nq()), inputs(1, num_independent(model)), v);
  f.output_ids = {ids_of(v)};
  return f;
}

TracedFunction trace_acceleration_bias(const Model& model) {
  TracedFunction f;
  f.name = "acceleration_bias";
  f.doc = "Acceleration bias g at (q, vy): qdd = T ydd + g keeps the loops closed (zero at the independent "
          "coordinates).";
  f.inputs = {closed_q_spec(model), y_spec(model, "vy", "independent velocities")};
  f.outputs = {v_spec(model, "g", "acceleration bias of every tree joint, joint_names_full order")};
  Recording rec(f.graph);
  Data<Sym> data(model);
  VecX<Sym> g(model.nv());
  acceleration_bias<Sym>(model, data, inputs(0, model.nq()), inputs(1, num_independent(model)), g);
  f.output_ids = {ids_of(g)};
  return f;
}

}  // namespace mbgen::codegen
