// mbgen._runtime: a robot description loaded as `mbgen generate` loads it (URDF or MJCF, the
// extras, loops detected and assembled), and the runtime's generic algorithms on it, so that a
// Python user can try a robot before generating it. The functions have the generated module's
// names, arguments and conventions (python/mbgen/__init__.py, docs/python.md): for a robot with
// loops, forward_dynamics and full_accelerations are the closed system's, in its independent
// velocities, and the other functions the spanning tree's, as in the generated header.
//
// One state per call; a Robot holds the runtime's work memory (Data), so its calls are not
// reentrant: the GIL stays held.
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "collision/collision_scene.hpp"
#include "collision/contact_spheres.hpp"
#include "load/load_error.hpp"
#include "mbgen/mbgen.hpp"
#include "mbgen/python/differential_ik_binding.hpp"
#include "mbgen/python/simulator_binding.hpp"
#include "model/actuated_coordinates.hpp"
#include "model/load_description.hpp"
#include "model/topology.hpp"
#include "walking_pattern_binding.hpp"

namespace py = pybind11;

namespace mbgen::python {

namespace {

using Vector = Eigen::Ref<const VecX<double>>;

/// The loaded description, its spanning tree, and the work memory of each.
class Robot {
 public:
  explicit Robot(gen::Description d)
      : description_(std::move(d)), tree_(gen::spanning_tree(description_.model)), closed_data_(model()), tree_data_(tree_) {
    for (int v : model().structure().independent_v) independent_.push_back(v);
    for (int v : gen::description_actuation(description_).actuated_v) actuated_.push_back(v);
  }

  const Model& model() const { return description_.model; }
  const gen::Description& description() const { return description_; }
  const std::vector<int>& independent() const { return independent_; }
  const std::vector<int>& actuated() const { return actuated_; }
  int ny() const { return static_cast<int>(independent_.size()); }
  bool has_loops() const { return !model().subsystems.empty(); }

  VecX<double> forward_dynamics(const Vector& q, const Vector& vy, const Vector& tau) {
    check("forward_dynamics", "q", q, model().nq());
    check("forward_dynamics", "v", vy, ny());
    check("forward_dynamics", "tau", tau, model().nv());
    const VecX<double> full = full_accelerations_of(q, vy, tau);
    VecX<double> ydd(ny());
    for (int i = 0; i < ny(); ++i) ydd[i] = full[independent_[static_cast<std::size_t>(i)]];
    return ydd;
  }

  VecX<double> full_accelerations(const Vector& q, const Vector& vy, const Vector& tau) {
    check("full_accelerations", "q", q, model().nq());
    check("full_accelerations", "v", vy, ny());
    check("full_accelerations", "tau", tau, model().nv());
    return full_accelerations_of(q, vy, tau);
  }

  VecX<double> inverse_dynamics(const Vector& q, const Vector& v, const Vector& a) {
    check("inverse_dynamics", "q", q, tree_.nq());
    check("inverse_dynamics", "v", v, tree_.nv());
    check("inverse_dynamics", "qdd", a, tree_.nv());
    return rnea<double>(tree_, tree_data_, q, v, a);
  }

  MatX<double> mass_matrix(const Vector& q) {
    check("mass_matrix", "q", q, tree_.nq());
    return crba<double>(tree_, tree_data_, q);
  }

  /// Per body (the world left out, as the generated forward_kinematics) the 3 x 4 [R_WB | p_WB].
  py::array_t<double> forward_kinematics(const Vector& q) {
    check("forward_kinematics", "q", q, tree_.nq());
    mbgen::forward_kinematics<double>(tree_, tree_data_, q);
    const int nb = tree_.num_bodies() - 1;
    py::array_t<double> X({nb, 3, 4});
    auto x = X.mutable_unchecked<3>();
    for (int b = 0; b < nb; ++b) {
      const SE3<double>& pose = tree_data_.X_WB[BodyIndex(b + 1)];
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) x(b, r, c) = pose.rotation(r, c);
        x(b, r, 3) = pose.translation[r];
      }
    }
    return X;
  }

  Vec3<double> center_of_mass(const Vector& q) {
    check("center_of_mass", "q", q, tree_.nq());
    return mbgen::center_of_mass<double>(tree_, tree_data_, q);
  }

  MatX<double> centroidal_momentum_matrix(const Vector& q) {
    check("centroidal_momentum_matrix", "q", q, tree_.nq());
    return mbgen::centroidal_momentum_matrix<double>(tree_, tree_data_, q);
  }

  MatX<double> velocity_map(const Vector& q) {
    check("velocity_map", "q", q, model().nq());
    MatX<double> T(model().nv(), ny());
    mbgen::velocity_map<double>(model(), closed_data_, q, T);
    return T;
  }

  VecX<double> full_velocities(const Vector& q, const Vector& vy) {
    check("full_velocities", "q", q, model().nq());
    check("full_velocities", "vy", vy, ny());
    VecX<double> v(model().nv());
    mbgen::full_velocities<double>(model(), closed_data_, q, vy, v);
    return v;
  }

  /// (closed q, result) with the result as a dict: status, iterations, residual, pivot ratios.
  py::tuple closure_positions(const Vector& q) {
    check("closure_positions", "q", q, model().nq());
    VecX<double> closed = q;
    const ClosureResult<double> r = mbgen::closure_positions<double>(model(), closed_data_, closed);
    py::dict result;
    result["status"] = to_string(r.status);
    result["iterations"] = r.iterations;
    result["residual"] = r.residual;
    result["pivot_ratio"] = r.pivot_ratio;
    result["relative_pivot_ratio"] = r.relative_pivot_ratio;
    result["subsystem"] = r.subsystem;
    return py::make_tuple(closed, result);
  }

  /// The scene's collision model (compounds and kept pairs) as `mbgen generate` builds it: the
  /// same deterministic sampling, so the same pairs as the generated self_distances. Built on
  /// first use (it samples the configuration space: seconds for a biped), then kept.
  const collision::CollisionModel& collision_model() {
    if (!collision_) collision_ = gen::build_collision_scene(description_, gen::collision_scene_options(description_)).model;
    return *collision_;
  }

  /// q (+) v: the configuration reached from q moving with v for unit time (the tangent
  /// convention of the derivatives: a floating base moves by the exponential of its body twist).
  VecX<double> integrate(const Vector& q, const Vector& v) const {
    check("integrate", "q", q, model().nq());
    check("integrate", "v", v, model().nv());
    VecX<double> out(model().nq());
    mbgen::integrate<double>(model(), q, v, out);
    return out;
  }

  /// The v that integrate() takes from q0 to q1.
  VecX<double> difference(const Vector& q0, const Vector& q1) const {
    check("difference", "q0", q0, model().nq());
    check("difference", "q1", q1, model().nq());
    VecX<double> out(model().nv());
    mbgen::difference<double>(model(), q0, q1, out);
    return out;
  }

 private:
  static void check(const char* function, const char* name, const Vector& x, int size) {
    if (x.size() != size)
      throw py::value_error(std::string(function) + ": " + name + " must have " + std::to_string(size) + " entries, not " +
                            std::to_string(x.size()));
  }

  VecX<double> full_accelerations_of(const Vector& q, const Vector& vy, const Vector& tau) {
    if (!has_loops()) return aba<double>(model(), closed_data_, q, vy, tau);
    forward_dynamics_loops_independent<double>(model(), closed_data_, q, vy, tau);
    return closed_data_.ddq;
  }

  gen::Description description_;
  Model tree_;
  Data<double> closed_data_, tree_data_;
  std::vector<int> independent_, actuated_;
  std::optional<collision::CollisionModel> collision_;
};

std::unique_ptr<Robot> load(const std::string& description, const std::optional<std::string>& extras,
                            const std::optional<std::string>& base, const std::optional<std::string>& mimic) {
  gen::LoadOptions options;
  options.extras_file = extras;
  if (base) {
    if (*base != "floating" && *base != "fixed")
      throw py::value_error("load: base must be 'floating' or 'fixed', not '" + *base + "'");
    options.base = *base == "floating" ? gen::BaseType::Floating : gen::BaseType::Fixed;
  }
  if (mimic) {
    if (*mimic != "couple" && *mimic != "independent")
      throw py::value_error("load: mimic must be 'couple' or 'independent', not '" + *mimic + "'");
    options.couple_mimics = *mimic == "couple";
  }
  return std::make_unique<Robot>(gen::load_description(description, options));
}

using GenericSimulator = sim::Simulator<sim::GenericBackend<double>>;

/// The simulator on the generic backend, with the scene's ground, contact law and end stops
/// (docs/simulation.md), as mbgen_sim sets it up.
std::unique_ptr<GenericSimulator> make_simulator(const Robot& robot, const std::string& integrator, double step,
                                                 bool contact, bool joint_stops) {
  sim::SimulatorOptions scene_options;
  const auto& scene = robot.description().scene;
  if (scene && scene->contact) {
    scene_options.contact_parameters = scene->contact->parameters;
    scene_options.ground = scene->contact->ground;
  }
  if (scene) scene_options.joint_stops = scene->joint_limits;
  const sim::SimulatorOptions o = simulator_options(scene_options, integrator, step, contact, joint_stops);
  std::vector<ContactSphere> spheres;
  if (contact) spheres = gen::contact_spheres(robot.description());
  return std::make_unique<GenericSimulator>(sim::GenericBackend<double>(robot.model(), std::move(spheres)), o);
}

using GenericIk = control::DifferentialIk<double>;

/// The differential IK on the generic backend of `robot`: its frames the tasks', its pairs the
/// scene's collision model (built when collision_avoidance is on), its ranges the model's.
std::unique_ptr<GenericIk> make_differential_ik(Robot& robot, const py::iterable& tasks, const py::kwargs& kwargs) {
  const std::vector<control::TaskSpec> specs = detail::task_specs(tasks);
  const control::DifferentialIkOptions options = differential_ik_options(kwargs, joint_position_limits(robot.model()));
  const collision::CollisionModel* collision = options.collision_avoidance ? &robot.collision_model() : nullptr;
  return configuration([&] { return std::make_unique<GenericIk>(robot.model(), specs, options, collision); });
}

std::vector<std::string> names_of(const Model& model, const std::vector<int>& coordinates) {
  std::vector<std::string> out;
  for (int v : coordinates) out.push_back(gen::coordinate_name(model, v));
  return out;
}

}  // namespace

}  // namespace mbgen::python

PYBIND11_MODULE(_runtime, m) {
  using mbgen::python::Robot;
  m.doc() = "mbgen's generic runtime on a loaded robot description (import mbgen: python/mbgen/__init__.py).";
  // A description mbgen refuses: its message names the file, the element and the fix.
  py::register_exception<mbgen::gen::LoadError>(m, "LoadError", PyExc_ValueError);
  py::class_<Robot>(m, "Robot", "A loaded description and the generic algorithms on it (one state per call).")
      .def_property_readonly("name", [](const Robot& r) {
        return r.description().robot_name.empty() ? r.model().name : r.description().robot_name;
      })
      .def_property_readonly("nq", [](const Robot& r) { return r.model().nq(); })
      .def_property_readonly("nv", [](const Robot& r) { return r.model().nv(); })
      .def_property_readonly("ny", &Robot::ny)
      .def_property_readonly("na", [](const Robot& r) { return static_cast<int>(r.actuated().size()); })
      .def_property_readonly("num_bodies", [](const Robot& r) { return r.model().num_bodies() - 1; })
      .def_property_readonly("floating_base", [](const Robot& r) { return r.model().floating_base(); })
      .def_property_readonly("has_loops", &Robot::has_loops)
      .def_property_readonly("joint_names", [](const Robot& r) { return r.model().joint_names(); })
      .def_property_readonly("body_names", [](const Robot& r) {
        std::vector<std::string> names;
        for (int k = 1; k < r.model().num_bodies(); ++k) names.push_back(r.model().body(mbgen::BodyIndex(k)).name);
        return names;
      })
      .def_property_readonly("independent_v_index", &Robot::independent)
      .def_property_readonly("independent_joint_names",
                             [](const Robot& r) { return mbgen::python::names_of(r.model(), r.independent()); })
      .def_property_readonly("actuated_v_index", &Robot::actuated)
      .def_property_readonly("actuated_joint_names",
                             [](const Robot& r) { return mbgen::python::names_of(r.model(), r.actuated()); })
      .def_property_readonly(
          "assembled_q",
          [](const Robot& r) {
            const mbgen::VecX<double>& q = r.description().assembly.q;
            return q.size() == r.model().nq() ? q : mbgen::neutral_configuration<double>(r.model());
          },
          "The closed pose the loader assembled the loops at; without loops, the neutral configuration (q = 0, a "
          "floating base's unit quaternion).")
      .def_property_readonly("warnings", [](const Robot& r) { return r.description().warnings; })
      .def_property_readonly("notes", [](const Robot& r) { return r.description().notes; })
      .def("forward_dynamics", &Robot::forward_dynamics, py::arg("q"), py::arg("v"), py::arg("tau"),
           "Independent accelerations (ny) at (q closed, independent velocities v, joint forces tau of every tree "
           "joint); a tree's ABA without loops.")
      .def("full_accelerations", &Robot::full_accelerations, py::arg("q"), py::arg("v"), py::arg("tau"),
           "Every tree joint's acceleration (nv) of the closed system.")
      .def("inverse_dynamics", &Robot::inverse_dynamics, py::arg("q"), py::arg("v"), py::arg("qdd"),
           "The spanning tree's RNEA: tau = M qdd + C v + g.")
      .def("mass_matrix", &Robot::mass_matrix, py::arg("q"), "The spanning tree's CRBA: M(q), nv x nv.")
      .def("forward_kinematics", &Robot::forward_kinematics, py::arg("q"),
           "Per body the 3 x 4 matrix [R_WB | p_WB] (num_bodies x 3 x 4, body_names order).")
      .def("center_of_mass", &Robot::center_of_mass, py::arg("q"), "Centre of mass, world.")
      .def("centroidal_momentum_matrix", &Robot::centroidal_momentum_matrix, py::arg("q"),
           "6 x nv: [linear; angular] momentum about the centre of mass, world axes.")
      .def("velocity_map", &Robot::velocity_map, py::arg("q"), "T (nv x ny): v = T vy at a closed q.")
      .def("full_velocities", &Robot::full_velocities, py::arg("q"), py::arg("vy"), "v = T vy.")
      .def("closure_positions", &Robot::closure_positions, py::arg("q"),
           "Newton on the closures from q (the independent coordinates held): (closed q, result dict).")
      .def("integrate", &Robot::integrate, py::arg("q"), py::arg("v"),
           "q (+) v: the derivatives' tangent convention (a floating base moves by the exponential of its twist).")
      .def("difference", &Robot::difference, py::arg("q0"), py::arg("q1"), "The v with integrate(q0, v) = q1.");
  mbgen::python::bind_simulator<mbgen::sim::GenericBackend<double>>(
      m, "The simulator (docs/simulation.md) on the generic backend of a loaded Robot: the scene's ground, contact "
         "law and end stops; the loops kept closed.")
      .def(py::init(&mbgen::python::make_simulator), py::arg("robot"), py::arg("integrator") = "rk4",
           py::arg("step") = 1e-4, py::arg("contact") = true, py::arg("joint_stops") = true, py::keep_alive<1, 2>(),
           mbgen::python::kSimulatorArguments);
  mbgen::python::bind_differential_ik<mbgen::python::GenericIk>(
      m, "The differential IK (docs/control.md) on the generic backend of a loaded Robot: primary tasks by a damped "
         "pseudo-inverse, joint limits, self-collision avoidance and angular-momentum tracking in their null space, "
         "or all as a QP.")
      .def(py::init(&mbgen::python::make_differential_ik), py::arg("robot"), py::arg("tasks"), py::keep_alive<1, 2>(),
           mbgen::python::kDifferentialIkArguments);
  mbgen::python::bind_walking_pattern(m);
  m.def("load", &mbgen::python::load, py::arg("description"), py::arg("extras") = py::none(),
        py::arg("base") = py::none(), py::arg("mimic") = py::none(),
        "Loads a URDF or MJCF description (and YAML extras; a robot.yaml beside a URDF is picked up) as "
        "`mbgen generate` does: checked, loops detected and assembled. base: 'floating' or 'fixed' (default: "
        "the extras'); mimic: 'couple' or 'independent' (URDF <mimic>). Raises mbgen.LoadError naming the "
        "file, the element and the fix.");
}
