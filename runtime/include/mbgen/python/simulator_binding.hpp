#pragma once
// The Python class Simulator of both Python modules (docs/python.md): mbgen._runtime's runs the
// generic backend of a loaded Robot, a generated robot's module (--python) its own Backend. One
// binding of the runtime's sim::Simulator for both: state in and out as NumPy arrays, a step and a
// run with their status by name, the contact reports as arrays, and a controller written in
// Python. A Simulator keeps state and work memory: its calls hold the GIL (a Python controller
// runs inside them).
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <functional>
#include <string>
#include <utility>

#include "mbgen/sim/simulator.hpp"

namespace mbgen::python {

namespace py = pybind11;

/// The options the constructors share, over `base` (the scene's ground, law and end stops).
inline sim::SimulatorOptions simulator_options(sim::SimulatorOptions base, const std::string& integrator, double step,
                                               bool contact, bool joint_stops) {
  if (!sim::parse_integrator(integrator.c_str(), base.integrator))
    throw py::value_error("Simulator: unknown integrator '" + integrator +
                          "' (explicit_euler, symplectic_euler, rk4, dormand_prince45, linearly_implicit_euler)");
  if (!(step > 0)) throw py::value_error("Simulator: step must be positive (s), not " + std::to_string(step));
  base.step = step;
  base.contact = contact;
  if (!joint_stops) base.joint_stops.enabled = false;
  return base;
}

/// The constructor's keyword arguments and what they mean, for its docstring.
inline constexpr const char* kSimulatorArguments =
    "integrator: explicit_euler, symplectic_euler, rk4, dormand_prince45 or linearly_implicit_euler; step: s (the "
    "adaptive one's first); contact: the ground acts on the contact spheres; joint_stops: end stops at the joint "
    "ranges.";

namespace detail {
inline py::array_t<double> to_array(const VecX<double>& x) {
  py::array_t<double> out(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) out.mutable_at(i) = x[i];
  return out;
}
}  // namespace detail

/// The class Simulator on `Backend` in module m, without a constructor (each module adds its own).
template <typename Backend> py::class_<sim::Simulator<Backend>> bind_simulator(py::module_& m, const char* doc) {
  using Simulator = sim::Simulator<Backend>;
  using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
  py::class_<Simulator> c(m, "Simulator", doc);
  c.def(
       "set_state",
       [](Simulator& s, const Array& q, const Array& v, double t) {
         const int nq = s.backend().nq(), nv = s.backend().nv();
         if (q.ndim() != 1 || v.ndim() != 1 || q.shape(0) != nq || v.shape(0) != nv)
           throw py::value_error("Simulator.set_state: q must have shape (" + std::to_string(nq) + ",) and v (" +
                                 std::to_string(nv) + ",) (every tree joint's velocity)");
         return std::string(s.set_state(q.data(), v.data(), t) == 0 ? "converged" : "not_converged");
       },
       py::arg("q"), py::arg("v"), py::arg("t") = 0.0,
       "Sets the state (q: nq, v: nv) and the time; closes the loops and projects v first, and returns that "
       "closure's status.")
      .def("step", [](Simulator& s) { return std::string(sim::to_string(s.step())); },
           "One step; its status (ok, step_rejected, closure_lost, diverged, penetration, continued).")
      .def("run_until", [](Simulator& s, double t) { return std::string(sim::to_string(s.run_until(t))); },
           py::arg("t"), "Steps until the time t (s); the status of the last step (ok when it got there).")
      .def_property_readonly("q", [](const Simulator& s) { return detail::to_array(s.q()); }, "positions (nq), a copy")
      .def_property_readonly("v", [](const Simulator& s) { return detail::to_array(s.v()); }, "velocities (nv), a copy")
      .def_property_readonly("time", &Simulator::time, "s")
      .def_property_readonly("accepted_steps", [](const Simulator& s) { return s.statistics().accepted_steps; })
      .def("energy", [](Simulator& s) { return double(s.energy()); },
           "Kinetic + gravity + the contact springs' energy, J.")
      .def(
          "contacts",
          [](Simulator& s) {
            const auto& reports = s.contacts();
            const py::ssize_t n = static_cast<py::ssize_t>(reports.size());
            py::array_t<double> penetration(n), point({n, py::ssize_t(3)}), force({n, py::ssize_t(3)}),
                slip({n, py::ssize_t(3)});
            py::array_t<bool> active(n);
            for (py::ssize_t k = 0; k < n; ++k) {
              const auto& r = reports[static_cast<std::size_t>(k)];
              penetration.mutable_at(k) = r.penetration;
              active.mutable_at(k) = r.active;
              for (py::ssize_t i = 0; i < 3; ++i) {
                point.mutable_at(k, i) = r.point[i];
                force.mutable_at(k, i) = r.force[i];
                slip.mutable_at(k, i) = r.slip_velocity[i];
              }
            }
            py::dict out;
            out["penetration"] = penetration;
            out["point"] = point;
            out["force"] = force;
            out["slip_velocity"] = slip;
            out["active"] = active;
            return out;
          },
          "Per contact sphere at the current state: penetration (m, > 0 in contact), point, force (N, on the robot, "
          "world), slip_velocity (m/s), active.")
      .def(
          "set_controller",
          [](Simulator& s, std::function<Array(double, Array, Array)> f) {
            const int nq = s.backend().nq(), nv = s.backend().nv();
            s.set_controller([f = std::move(f), nq, nv](double t, const double* q, const double* v, double* tau) {
              Array q_now(nq, q), v_now(nv, v);
              const Array out = f(t, q_now, v_now);
              if (out.ndim() != 1 || out.shape(0) != nv)
                throw py::value_error("Simulator controller: it must return " + std::to_string(nv) + " joint forces, not " +
                                      std::to_string(out.size()));
              for (int i = 0; i < nv; ++i) tau[i] = out.data()[i];
            });
          },
          py::arg("controller"),
          "controller(t, q, v) -> tau (nv joint forces), called at the control period (1 ms) and held between calls.");
  return c;
}

}  // namespace mbgen::python
