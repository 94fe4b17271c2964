#pragma once
// The Python class DifferentialIk of both Python modules (docs/python.md): mbgen._runtime's runs
// the controller on the generic backend of a loaded Robot, a generated robot's module (--python)
// on its own Backend. One binding of control::BasicDifferentialIk for both, as the simulator's
// (simulator_binding.hpp): tasks as dicts, the options as keyword arguments (every field of
// DifferentialIkOptions, checked: an unknown keyword is a TypeError naming the known ones), the
// targets set by task name, a step returning the velocity and the report as a dict.
//
// No pybind11 class of the runtime's is registered (TaskSpec, StepReport): two modules that both
// registered one could not be imported together.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "mbgen/control/differential_ik.hpp"

namespace mbgen::python {

namespace py = pybind11;

namespace detail {

inline control::TaskKind task_kind(const std::string& task, const std::string& kind) {
  if (kind == "pose") return control::TaskKind::FramePose;
  if (kind == "position") return control::TaskKind::FramePosition;
  if (kind == "orientation") return control::TaskKind::FrameOrientation;
  if (kind == "com") return control::TaskKind::CenterOfMass;
  throw py::value_error("DifferentialIk: task '" + task + "' has kind '" + kind + "': pose, position, orientation or com");
}

/// A task given as a dict: name, kind (pose, position, orientation, com), frame (but for com),
/// gain (1/s, default 0), weight (default 1).
inline control::TaskSpec task_spec(const py::handle& item) {
  if (!py::isinstance<py::dict>(item))
    throw py::type_error("DifferentialIk: a task is a dict (name, kind, frame, gain, weight), not " +
                         std::string(py::str(py::type::handle_of(item).attr("__name__"))));
  const py::dict d = py::reinterpret_borrow<py::dict>(item);
  static const std::set<std::string> known{"name", "kind", "frame", "gain", "weight"};
  for (const auto& [key, value] : d) {
    (void)value;
    if (!known.count(py::str(key)))
      throw py::type_error("DifferentialIk: a task has no key '" + std::string(py::str(key)) + "' (name, kind, frame, gain, weight)");
  }
  control::TaskSpec spec;
  if (!d.contains("name")) throw py::value_error("DifferentialIk: a task needs a name");
  spec.name = d["name"].cast<std::string>();
  spec.kind = task_kind(spec.name, d.contains("kind") ? d["kind"].cast<std::string>() : "pose");
  if (spec.kind != control::TaskKind::CenterOfMass) {
    if (!d.contains("frame")) throw py::value_error("DifferentialIk: task '" + spec.name + "' needs a frame");
    spec.frame = d["frame"].cast<std::string>();
  }
  if (d.contains("gain")) spec.gain = d["gain"].cast<double>();
  if (d.contains("weight")) spec.weight = d["weight"].cast<double>();
  return spec;
}

inline std::vector<control::TaskSpec> task_specs(const py::iterable& tasks) {
  std::vector<control::TaskSpec> specs;
  for (const py::handle item : tasks) specs.push_back(task_spec(item));
  return specs;
}

template <typename T> std::vector<T> numbers(const py::handle& x) {
  std::vector<T> out;
  for (const py::handle item : x) out.push_back(item.cast<T>());
  return out;
}

}  // namespace detail

/// The keywords DifferentialIk's constructor takes, with what each sets (its docstring).
inline constexpr const char* kDifferentialIkArguments = R"doc(tasks: a list of dicts, each {name, kind: pose | position | orientation | com, frame (a frame of the
  backend: a generated robot's frame_names), gain: 1/s (default 0), weight (the QP form's, default 1)}.
Options (control/differential_ik.hpp, DifferentialIkOptions; defaults as in C++):
  weights, velocity_limits: per solved coordinate (nv for a tree, ny with loops)
  damping_constant, singular_region, max_damping: the primary stack's damped least squares
  joint_limits: True descends the robot's joint-range potential (its limited joints)
  limit_activation (rad or m), limit_stiffness (1/s)
  collision_avoidance: True descends the self-collision potential
  activation_distance (m), collision_stiffness (1/(m s))
  angular_momentum: True tracks angular_momentum_target; momentum_weight, momentum_axis_weights (x, y, z)
  qp: True solves the step as a QP with the limits and distances hard; limit_horizon (s), limit_margin,
  collision_horizon (s), min_distance (m), relaxation_weight, released_weight, smoothing)doc";

/// DifferentialIkOptions from keyword arguments; `limits` is the backend's joint ranges (taken
/// when joint_limits=True).
inline control::DifferentialIkOptions differential_ik_options(const py::kwargs& kwargs, std::vector<JointLimit> limits) {
  control::DifferentialIkOptions o;
  static const std::set<std::string> known{
      "weights",           "velocity_limits",     "damping_constant", "singular_region",      "max_damping",
      "joint_limits",      "limit_activation",    "limit_stiffness",  "collision_avoidance",  "activation_distance",
      "collision_stiffness", "angular_momentum",  "momentum_weight",  "momentum_axis_weights", "qp",
      "limit_horizon",     "limit_margin",        "collision_horizon", "min_distance",        "relaxation_weight",
      "released_weight",   "smoothing"};
  for (const auto& [key, value] : kwargs) {
    (void)value;
    if (!known.count(py::str(key))) {
      std::string names;
      for (const std::string& k : known) names += (names.empty() ? "" : ", ") + k;
      throw py::type_error("DifferentialIk: unknown option '" + std::string(py::str(key)) + "' (the options: " + names + ")");
    }
  }
  const auto number = [&](const char* key, double& field) {
    if (kwargs.contains(key)) field = kwargs[key].cast<double>();
  };
  const auto flag = [&](const char* key) { return kwargs.contains(key) && kwargs[key].cast<bool>(); };
  if (kwargs.contains("weights")) o.weights = detail::numbers<double>(kwargs["weights"]);
  if (kwargs.contains("velocity_limits")) o.velocity_limits = detail::numbers<double>(kwargs["velocity_limits"]);
  number("damping_constant", o.damping.constant);
  number("singular_region", o.damping.singular_region);
  number("max_damping", o.damping.max_damping);
  if (flag("joint_limits")) {
    if (limits.empty()) throw py::value_error("DifferentialIk: joint_limits=True, but the robot has no joint with a range");
    o.joint_limits.limits = std::move(limits);
  }
  number("limit_activation", o.joint_limits.activation);
  number("limit_stiffness", o.joint_limits.stiffness);
  o.collision_avoidance = flag("collision_avoidance");
  number("activation_distance", o.collision.activation_distance);
  number("collision_stiffness", o.collision.stiffness);
  o.angular_momentum.enabled = flag("angular_momentum");
  number("momentum_weight", o.angular_momentum.weight);
  if (kwargs.contains("momentum_axis_weights")) {
    const std::vector<double> w = detail::numbers<double>(kwargs["momentum_axis_weights"]);
    if (w.size() != 3) throw py::value_error("DifferentialIk: momentum_axis_weights takes 3 numbers (x, y, z), not " + std::to_string(w.size()));
    for (std::size_t i = 0; i < 3; ++i) o.angular_momentum.axis_weights[i] = w[i];
  }
  o.qp.enabled = flag("qp");
  number("limit_horizon", o.qp.limit_horizon);
  number("limit_margin", o.qp.limit_margin);
  number("collision_horizon", o.qp.collision_horizon);
  number("min_distance", o.qp.min_distance);
  number("relaxation_weight", o.qp.relaxation_weight);
  number("released_weight", o.qp.released_weight);
  number("smoothing", o.qp.smoothing);
  return o;
}

/// The joint ranges a backend lists (num_limited_joints, limited_*), as JointLimitOptions takes them.
template <typename Backend> std::vector<JointLimit> backend_limits(const Backend& b) {
  std::vector<JointLimit> limits;
  for (int k = 0; k < b.num_limited_joints(); ++k)
    limits.push_back({b.limited_joint_name(k), b.limited_q_index()[k], b.limited_v_index()[k], b.limited_lower()[k], b.limited_upper()[k]});
  return limits;
}

/// Runs f, turning the controller's configuration errors (std::invalid_argument) into ValueError.
template <typename F> auto configuration(F&& f) -> decltype(f()) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw py::value_error(e.what());
  }
}

/// The class DifferentialIk (an Ik derived from BasicDifferentialIk) in module m, without a
/// constructor (each module adds its own).
template <typename Ik> py::class_<Ik> bind_differential_ik(py::module_& m, const char* doc) {
  using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
  using S = typename Ik::S;
  static_assert(std::is_same_v<S, double>, "the Python binding runs the controller in double");
  const auto check = [](const char* what, const Array& a, std::vector<py::ssize_t> shape) {
    bool ok = static_cast<std::size_t>(a.ndim()) == shape.size();
    for (std::size_t i = 0; ok && i < shape.size(); ++i) ok = a.shape(static_cast<py::ssize_t>(i)) == shape[i];
    if (!ok) {
      std::string s;
      for (py::ssize_t d : shape) s += (s.empty() ? "" : ", ") + std::to_string(d);
      throw py::value_error(std::string("DifferentialIk: ") + what + " must have shape (" + s + (shape.size() == 1 ? ",)" : ")"));
    }
  };
  const auto task_of = [](Ik& ik, const py::handle& task) {
    if (py::isinstance<py::int_>(task)) {
      const int i = task.cast<int>();
      if (i < 0 || i >= ik.num_tasks())
        throw py::index_error("DifferentialIk: task " + std::to_string(i) + " of " + std::to_string(ik.num_tasks()));
      return i;
    }
    try {
      return ik.task_index(task.cast<std::string>());
    } catch (const std::out_of_range& e) {
      throw py::key_error(e.what());
    }
  };
  const auto matrix = [](const auto& x) {
    py::array_t<double> out({static_cast<py::ssize_t>(x.rows()), static_cast<py::ssize_t>(x.cols())});
    for (Eigen::Index r = 0; r < x.rows(); ++r)
      for (Eigen::Index c = 0; c < x.cols(); ++c) out.mutable_at(r, c) = x(r, c);
    return out;
  };
  const auto vector = [](const S* x, Eigen::Index n) {
    py::array_t<double> out(n);
    std::copy(x, x + n, out.mutable_data());
    return out;
  };
  py::class_<Ik> c(m, "DifferentialIk", doc);
  c.def(
       "set_target",
       [check, task_of](Ik& ik, const py::handle& task, const py::object& position, const py::object& rotation,
                        const py::object& velocity, const py::object& released) {
         control::TaskTarget<S>& t = ik.target(task_of(ik, task));
         if (!position.is_none()) {
           const Array p = Array::ensure(position);
           check("position", p, {3});
           t.position = Eigen::Map<const Vec3<S>>(p.data());
         }
         if (!rotation.is_none()) {
           const Array r = Array::ensure(rotation);
           check("rotation", r, {3, 3});
           t.rotation = Eigen::Map<const Eigen::Matrix<S, 3, 3, Eigen::RowMajor>>(r.data());
         }
         if (!velocity.is_none()) {
           const Array v = Array::ensure(velocity);
           if (v.ndim() == 1 && v.shape(0) == 3) {  // a 3-row task's: the linear or angular half it uses
             t.velocity.setZero();
             if (ik.task(task_of(ik, task)).spec.kind == control::TaskKind::FrameOrientation)
               t.velocity.template tail<3>() = Eigen::Map<const Vec3<S>>(v.data());
             else
               t.velocity.template head<3>() = Eigen::Map<const Vec3<S>>(v.data());
           } else {
             check("velocity", v, {6});
             t.velocity = Eigen::Map<const Vec6<S>>(v.data());
           }
         }
         if (!released.is_none()) {
           const std::vector<bool> rows = detail::numbers<bool>(released);
           if (rows.size() != 6) throw py::value_error("DifferentialIk: released takes 6 flags (linear x, y, z, angular x, y, z)");
           for (std::size_t i = 0; i < 6; ++i) t.released[i] = rows[i];
         }
       },
       py::arg("task"), py::arg("position") = py::none(), py::arg("rotation") = py::none(), py::arg("velocity") = py::none(),
       py::arg("released") = py::none(),
       "Sets the reference of a task (its name or index), world axes: position (3,) of the frame's origin or the CoM, m; "
       "rotation (3, 3) R_WF; velocity (6,) feed-forward [linear; angular], or (3,) for a 3-row task, m/s and rad/s; "
       "released: 6 flags, rows left out of the primary stack for the next steps. Arguments not given keep their value.")
      .def_property(
          "angular_momentum_target", [vector](const Ik& ik) { return vector(ik.angular_momentum_target.data(), 3); },
          [check](Ik& ik, const Array& k) {
            check("angular_momentum_target", k, {3});
            ik.angular_momentum_target = Eigen::Map<const Vec3<S>>(k.data());
          },
          "k_des (3,), kg m^2/s about the CoM, world axes: the momentum objective's target.")
      .def(
          "step",
          [check](Ik& ik, const Array& q) {
            const int nq = ik.backend().nq(), nv = ik.backend().nv();
            check("q", q, {nq});
            VecX<S> v(nv);
            const control::StepReport r = ik.step(Eigen::Map<const VecX<S>>(q.data(), nq), v);
            py::dict report;
            report["ok"] = r.ok;
            report["rank"] = r.rank;
            report["smallest_singular_value"] = r.smallest_singular_value;
            report["active_pairs"] = r.active_pairs;
            report["near_pairs"] = r.near_pairs;
            report["active_limits"] = r.active_limits;
            report["limit_scale"] = r.limit_scale;
            report["qp_status"] = control::to_string(r.qp_status);
            report["inequalities"] = r.inequalities;
            report["active_inequalities"] = r.active_inequalities;
            report["qp_iterations"] = r.qp_iterations;
            report["tasks_relaxed"] = r.tasks_relaxed;
            py::array_t<double> out(nv);
            std::copy(v.data(), v.data() + nv, out.mutable_data());
            return py::make_tuple(out, report);
          },
          py::arg("q"),
          "One step at q (nq, the loops closed): (v, report). v (nv) the joint velocities (T vy with loops; zero when "
          "the step fails); report: ok, rank, smallest_singular_value, active_pairs, near_pairs, active_limits, "
          "limit_scale, qp_status, inequalities, active_inequalities, qp_iterations, tasks_relaxed.")
      .def("restart", &Ik::restart, "Forgets the last command (the QP form's smoothing pulls toward it).")
      .def_property_readonly("task_names",
                             [](const Ik& ik) {
                               py::list names;
                               for (int i = 0; i < ik.num_tasks(); ++i) names.append(ik.task(i).spec.name);
                               return names;
                             })
      .def_property_readonly("num_coordinates", &Ik::num_coordinates, "nv for a tree, ny with loops: what the step solves for.")
      .def_property_readonly("primary_rows", &Ik::primary_rows)
      .def_property_readonly("primary_jacobian", [matrix](const Ik& ik) { return matrix(ik.primary_jacobian()); },
                             "The last step's stacked task Jacobian J (rows x nv), world axes.")
      .def_property_readonly("primary_velocity", [vector](const Ik& ik) { return vector(ik.primary_velocity().data(), ik.primary_velocity().size()); },
                             "The last step's desired task velocity xd (feed-forward + gain * error).")
      .def_property_readonly("coordinates_velocity", [vector](const Ik& ik) { return vector(ik.coordinates_velocity().data(), ik.coordinates_velocity().size()); },
                             "The last step's solved velocity c (num_coordinates).")
      .def_property_readonly("secondary_velocity", [vector](const Ik& ik) { return vector(ik.secondary_velocity().data(), ik.secondary_velocity().size()); },
                             "The last step's null-space part of c.")
      .def_property_readonly("center_of_mass", [vector](const Ik& ik) { return vector(ik.center_of_mass().data(), 3); }, "At the last step's q, m.")
      .def_property_readonly("centroidal_momentum_matrix", [matrix](const Ik& ik) { return matrix(ik.centroidal_momentum_matrix()); },
                             "At the last step's q (6 x nv).")
      .def_property_readonly("distances", [vector](const Ik& ik) { return vector(ik.distances(), ik.num_pairs()); },
                             "The last step's pair distances (collision avoidance on), m: exact below the activation distance.");
  return c;
}

}  // namespace mbgen::python
