#pragma once
// mbgen.WalkingPattern (docs/python.md): the walking pattern of mbgen_walk
// (mbgen/control/walking_pattern.hpp) from Python, its samples as arrays over time, so that a
// Python controller can walk a biped with DifferentialIk on the generic or the generated backend.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <string>
#include <vector>

#include "mbgen/control/walking_pattern.hpp"

namespace mbgen::python {

namespace py = pybind11;

/// The options as keyword arguments: PatternOptions' fields, by name.
inline walking::PatternOptions pattern_options(const py::kwargs& kwargs) {
  walking::PatternOptions o;
  const auto number = [&](const char* key, double& field) {
    if (kwargs.contains(key)) field = kwargs[key].cast<double>();
  };
  const auto integer = [&](const char* key, int& field) {
    if (kwargs.contains(key)) field = kwargs[key].cast<int>();
  };
  const char* known[] = {"steps",       "step_length",   "step_time",  "double_support", "step_height", "swing_bulge",
                         "width_scale", "turn_per_step", "com_height", "start_time",     "end_time",    "first_foot"};
  for (const auto& [key, value] : kwargs) {
    (void)value;
    bool found = false;
    for (const char* k : known) found = found || std::string(py::str(key)) == k;
    if (!found) {
      std::string names;
      for (const char* k : known) names += (names.empty() ? "" : ", ") + std::string(k);
      throw py::type_error("WalkingPattern: unknown option '" + std::string(py::str(key)) + "' (the options: " + names + ")");
    }
  }
  integer("steps", o.steps);
  number("step_length", o.step_length);
  number("step_time", o.step_time);
  number("double_support", o.double_support);
  number("step_height", o.step_height);
  number("swing_bulge", o.swing_bulge);
  number("width_scale", o.width_scale);
  number("turn_per_step", o.turn_per_step);
  number("com_height", o.com_height);
  number("start_time", o.start_time);
  number("end_time", o.end_time);
  integer("first_foot", o.first_foot);
  if (o.first_foot != 0 && o.first_foot != 1) throw py::value_error("WalkingPattern: first_foot is 0 (left) or 1 (right)");
  return o;
}

/// Every sample's references as arrays over the samples (the first dimension).
inline py::dict pattern_samples(const walking::WalkingPattern& p) {
  const py::ssize_t n = p.samples();
  py::array_t<double> t(n), com({n, py::ssize_t(3)}), com_velocity({n, py::ssize_t(3)}), zmp({n, py::ssize_t(3)}),
      foot({n, py::ssize_t(2), py::ssize_t(3)}), foot_velocity({n, py::ssize_t(2), py::ssize_t(3)}), foot_yaw({n, py::ssize_t(2)}),
      foot_yaw_rate({n, py::ssize_t(2)}), heading(n), heading_rate(n);
  py::array_t<int> stance(n);
  for (py::ssize_t k = 0; k < n; ++k) {
    const walking::PatternSample& s = p.sample(static_cast<int>(k));
    t.mutable_at(k) = s.t;
    heading.mutable_at(k) = s.heading;
    heading_rate.mutable_at(k) = s.heading_rate;
    stance.mutable_at(k) = s.stance;
    for (py::ssize_t i = 0; i < 3; ++i) {
      com.mutable_at(k, i) = s.com[i];
      com_velocity.mutable_at(k, i) = s.com_velocity[i];
      zmp.mutable_at(k, i) = s.zmp[i];
      for (py::ssize_t f = 0; f < 2; ++f) {
        foot.mutable_at(k, f, i) = s.foot[f][i];
        foot_velocity.mutable_at(k, f, i) = s.foot_velocity[f][i];
      }
    }
    for (py::ssize_t f = 0; f < 2; ++f) {
      foot_yaw.mutable_at(k, f) = s.foot_yaw[f];
      foot_yaw_rate.mutable_at(k, f) = s.foot_yaw_rate[f];
    }
  }
  py::dict out;
  out["t"] = t;
  out["com"] = com;
  out["com_velocity"] = com_velocity;
  out["zmp"] = zmp;
  out["foot"] = foot;
  out["foot_velocity"] = foot_velocity;
  out["foot_yaw"] = foot_yaw;
  out["foot_yaw_rate"] = foot_yaw_rate;
  out["heading"] = heading;
  out["heading_rate"] = heading_rate;
  out["stance"] = stance;
  return out;
}

inline void bind_walking_pattern(py::module_& m) {
  py::class_<walking::WalkingPattern>(
      m, "WalkingPattern",
      "A walking pattern (docs/control.md, \"Walking\"): footsteps, the ZMP they imply, the CoM of the linear inverted "
      "pendulum for it, swing-foot paths and the heading, sampled every dt.")
      .def(py::init([](const Vec3<double>& left, const Vec3<double>& right, const Vec3<double>& com, double dt, const py::kwargs& kwargs) {
             const walking::PatternOptions o = pattern_options(kwargs);
             try {
               return std::make_unique<walking::WalkingPattern>(left, right, com, o, dt);
             } catch (const std::invalid_argument& e) {
               throw py::value_error(e.what());
             }
           }),
           py::arg("left"), py::arg("right"), py::arg("com"), py::arg("dt"),
           "left, right: the feet's frame origins standing (world, m), com: the CoM there; dt: s between samples. "
           "Options (PatternOptions): steps, step_length (m), step_time (s), double_support (s), step_height (m), "
           "swing_bulge (m), width_scale, turn_per_step (rad), com_height (m; 0: standing's), start_time (s), "
           "end_time (s), first_foot (0 left, 1 right).")
      .def_property_readonly("duration", &walking::WalkingPattern::duration, "s")
      .def_property_readonly("dt", &walking::WalkingPattern::dt, "s")
      .def_property_readonly("num_samples", &walking::WalkingPattern::samples)
      .def_property_readonly("omega", &walking::WalkingPattern::omega, "the pendulum's sqrt(g / z_c), 1/s")
      .def_property_readonly(
          "footsteps",
          [](const walking::WalkingPattern& p) {
            py::list out;
            for (const walking::Footstep& f : p.footsteps()) {
              py::dict d;
              d["position"] = Vec3<double>(f.position);
              d["yaw"] = f.yaw;
              d["foot"] = f.foot;
              out.append(d);
            }
            return out;
          },
          "Each footstep: position (m), yaw (rad), foot (0 left, 1 right); the standing feet first.")
      .def("samples", &pattern_samples,
           "The references over time, arrays whose first dimension is the sample: t (s), com, com_velocity, zmp (N x 3), "
           "foot, foot_velocity (N x 2 x 3; 0 left, 1 right), foot_yaw, foot_yaw_rate (N x 2), heading, heading_rate (N), "
           "stance (N: the stance foot in single support, -1 in double support).")
      .def(
          "yaw_free_momentum",
          [](const walking::WalkingPattern& p, double mass) {
            try {
              return p.yaw_free_momentum(mass);
            } catch (const std::invalid_argument& e) {
              throw py::value_error(e.what());
            }
          },
          py::arg("mass"), "Per sample, the vertical angular momentum about the CoM (kg m^2/s) that keeps the ground's yaw torque zero.")
      .def(
          "correct_com",
          [](walking::WalkingPattern& p, const Eigen::Ref<const Eigen::Matrix<double, Eigen::Dynamic, 2, Eigen::RowMajor>>& error) {
            if (error.rows() != p.samples())
              throw py::value_error("WalkingPattern.correct_com: zmp_error must have shape (" + std::to_string(p.samples()) +
                                    ", 2), one (x, y) per sample");
            std::vector<Eigen::Vector2d> e(static_cast<std::size_t>(error.rows()));
            for (Eigen::Index k = 0; k < error.rows(); ++k) e[static_cast<std::size_t>(k)] = error.row(k).transpose();
            p.correct_com(e);
          },
          py::arg("zmp_error"),
          "Moves the CoM so that the whole body keeps the ZMP on its reference: zmp_error (N x 2) = full-body ZMP - "
          "reference of a motion that tracked this pattern.");
}

}  // namespace mbgen::python
