// mbgen_study: speed against accuracy (docs/study.md). Runs a grid of backend x integrator x step
// on the simulation scenarios, measures each run's error against a reference solution and its
// CPU time per simulated second, and writes a CSV of every run, a Markdown report and, with
// gnuplot, one error-against-cost chart per scenario (scripts/plot_study.gp) with the Pareto
// front marked.
//
//   mbgen_study [--grid full|small] [--out DIR] [--no-plot] [--check]
//
// The reference is the issue's: the generic O(n) backend in double with Dormand-Prince 5(4) at
// rtol 1e-10; its own error is estimated by running it again at half that tolerance. --check
// exits 1 unless the study's invariants hold (the reference's self-error below every run's
// error; in the smooth scenario, error falling with the step at the integrator's order).
#include <fmt/format.h>
#include <fmt/os.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include MBGEN_STUDY_HEADER
#include "codegen/trace_dynamics.hpp"
#include "codegen/trace_loop_maps.hpp"
#include "codegen/traced_function.hpp"
#include "collision/contact_spheres.hpp"
#include "examples/study/stability_map.hpp"
#include "examples/study/trajectory.hpp"
#include "load/load_error.hpp"
#include "mbgen/algorithm/transmission_map.hpp"
#include "model/load_description.hpp"

namespace robot = MBGEN_STUDY_NS;
using namespace mbgen;
using sim::Integrator;

namespace {

constexpr const char* kUsage = R"(usage: mbgen_study [options]
  --grid full|small   the grid (default full: minutes; small: seconds, what the test suite runs)
  --out DIR           where study.csv, study.md and the charts go (default: study)
  --scenario NAME     only this part: swing_four_bar, drop_lola, push_lola, stability (the map), drift, dead_point or
                      reductions
  --backends A,B,...  only these backends (generated, generic, float, independent, kkt)
  --no-plot           no charts
  --check             exit 1 unless the study's invariants hold
)";

/// One configuration of the grid.
struct Config {
  std::string backend;  ///< generated, generic, float (the generic O(n) in float), kkt, independent
  Integrator integrator = Integrator::rk4;
  double step = 1e-4;   ///< s: fixed step (dormand_prince45: its first step)
  double rtol = 0;      ///< dormand_prince45 only
  std::string curve() const { return fmt::format("{} {}", backend, sim::to_string(integrator)); }
};

struct Point {
  Config config;
  study::Trajectory run;
  study::Deviation error;
  double energy_error = 0;  ///< J: |energy balance - the reference's| at the end
  bool finished = false;
};

struct Scenario {
  std::string name;      ///< drop_lola, swing_four_bar, ...
  std::string title;
  simulate::ScenarioOptions options;
  gen::Description description;
  std::vector<ContactSphere> spheres;
  double duration = 0;
  bool generated = false;  ///< the compiled-in robot: the generated backend runs too
  bool smooth = false;     ///< contact-free: the integrators' orders show
};

/// Samples every 10 ms: every step of the grid divides it (run_until shortens a step to end on a
/// sample, which would make the larger steps equal).
constexpr double kSamplePeriod = 1e-2;
constexpr double kReferenceRtol = 1e-10;
/// The contact-free swing's reference is cheap (0.012 CPU s per simulated s at 1e-10) and the
/// grid's best runs come within its own error there (KKT with Dormand-Prince at 1e-9: 3e-9
/// against 4.4e-9): two decades tighter.
constexpr double kSmoothReferenceRtol = 1e-12;

/// `extras`: the YAML extras; empty: the URDF's name with .yaml, if there is one.
Scenario make_scenario(const std::string& name, simulate::Scenario kind, const std::string& urdf, double duration,
                       std::string extras = "") {
  Scenario s;
  s.name = name;
  s.options.scenario = kind;
  gen::LoadOptions load;
  if (extras.empty()) extras = std::filesystem::path(urdf).replace_extension(".yaml").string();
  if (std::filesystem::exists(extras)) load.extras_file = extras;
  s.description = gen::load_description(urdf, load);
  s.spheres = gen::contact_spheres(s.description);
  if (s.description.scene && s.description.scene->contact) {
    s.options.simulator.contact_parameters = s.description.scene->contact->parameters;
    s.options.simulator.ground = s.description.scene->contact->ground;
  }
  if (s.description.scene) s.options.simulator.joint_stops = s.description.scene->joint_limits;
  s.duration = duration;
  s.generated = urdf == MBGEN_STUDY_DESCRIPTION && s.description.model.nq() == robot::nq;
  s.smooth = kind == simulate::Scenario::swing;
  const char* kind_name = kind == simulate::Scenario::swing ? "swing" : kind == simulate::Scenario::push ? "push" : "drop";
  s.title = fmt::format("{} {} for {:g} s", kind_name, s.description.model.name, duration);
  return s;
}

/// The push: Lola standing (its lowest sphere 2 mm above the ground, settling for 0.1 s), then
/// pushed at the base by 4 N s along +x over 0.05 s, 0.3 s in all: the stance's response to a
/// disturbance, where the drop is an impact.
Scenario push_scenario() {
  Scenario s = make_scenario("push_lola", simulate::Scenario::push, MBGEN_STUDY_DESCRIPTION, 0.3);
  s.options.height = 0.002;
  s.options.settle = 0.1;
  return s;
}

study::Trajectory run(const Scenario& s, const Config& c) {
  simulate::ScenarioOptions o = s.options;
  o.simulator.integrator = c.integrator;
  o.simulator.step = c.step;
  if (c.integrator == Integrator::dormand_prince45) o.simulator.rtol = c.rtol, o.simulator.atol = c.rtol * 1e-2;
  const Model& m = s.description.model;
  if (c.backend == "generated")
    return study::run_trajectory(robot::Backend{}, robot::Backend{}, s.description, o, s.duration, kSamplePeriod);
  if (c.backend == "generic")
    return study::run_trajectory(sim::GenericBackend<double>(m, s.spheres), sim::GenericBackend<double>(m), s.description, o, s.duration,
                                 kSamplePeriod);
  if (c.backend == "float")  // the same O(n) recursion in single precision: float's error floor
    return study::run_trajectory(sim::GenericBackend<float>(m, s.spheres), sim::GenericBackend<float>(m), s.description, o, s.duration,
                                 kSamplePeriod);
  if (c.backend == "kkt") {
    const BaumgarteGains gains{o.baumgarte, o.baumgarte};
    return study::run_trajectory(sim::KktBackend<double>(m, gains, s.spheres), sim::KktBackend<double>(m, gains), s.description, o,
                                 s.duration, kSamplePeriod);
  }
  return study::run_trajectory(sim::IndependentBackend<double>(m, s.spheres), sim::IndependentBackend<double>(m), s.description, o,
                               s.duration, kSamplePeriod);
}

/// The grid: every backend with each fixed-step integrator over `steps`, and Dormand-Prince over
/// `rtols`. The contact-free swing skips linearly implicit Euler (without contact forces it is
/// symplectic Euler).
std::vector<Config> grid(const Scenario& s, const std::vector<double>& steps, const std::vector<double>& rtols,
                         const std::vector<std::string>& backends) {
  std::vector<Config> configs;
  for (const std::string& b : backends) {
    if (b == "generated" && !s.generated) continue;
    for (Integrator i : {Integrator::explicit_euler, Integrator::symplectic_euler, Integrator::linearly_implicit_euler, Integrator::rk4}) {
      if (s.smooth && i == Integrator::linearly_implicit_euler) continue;
      for (double h : steps)  // a controlled scenario's steps end at each controller call: no longer than its period
        if (s.smooth || h <= s.options.simulator.control_period * (1 + 1e-9)) configs.push_back({b, i, h, 0});
    }
    // float's round-off (6e-8 relative) puts tolerances below 1e-5 out of its reach: the step
    // controller shrinks the step until round-off passes the test by chance (the drop's float
    // runs below 1e-5 had not finished after twelve minutes of CPU).
    for (double r : rtols)
      if (b != "float" || r >= 1e-5) configs.push_back({b, Integrator::dormand_prince45, 1e-4, r});
  }
  return configs;
}

/// Runs one of the project's gnuplot scripts with its variables (`name=value; ...`); says where
/// the chart went, or that gnuplot failed (the data files stay).
void run_gnuplot(const std::string& variables, const std::string& script, const std::string& png) {
  const std::string command = fmt::format("gnuplot -e \"{}; png='{}'\" {}/scripts/{} 2>&1", variables, png, MBGEN_SOURCE_DIR, script);
  if (std::system(command.c_str()) == 0) fmt::print("  chart: {}\n", png);
  else fmt::print(stderr, "mbgen_study: gnuplot failed (apt-get install gnuplot-nox); the data are written\n");
}

/// How many backends ran (the chart colours curves by integrator and marks them by backend).
std::size_t backends_of(const std::vector<Point>& points) {
  std::vector<std::string> seen;
  for (const Point& p : points)
    if (std::find(seen.begin(), seen.end(), p.config.backend) == seen.end()) seen.push_back(p.config.backend);
  return seen.size();
}

/// The points no other finished point beats in both cost and error, cheapest first.
std::vector<const Point*> pareto_front(const std::vector<Point>& points) {
  std::vector<const Point*> finished;
  for (const Point& p : points)
    if (p.finished) finished.push_back(&p);
  std::sort(finished.begin(), finished.end(), [](const Point* a, const Point* b) {
    return a->run.cpu_seconds != b->run.cpu_seconds ? a->run.cpu_seconds < b->run.cpu_seconds : a->error.largest() < b->error.largest();
  });
  std::vector<const Point*> front;
  for (const Point* p : finished)
    if (front.empty() || p->error.largest() < front.back()->error.largest()) front.push_back(p);
  return front;
}

/// The name of the joint that q index i belongs to ("" for none).
std::string joint_at_q(const Model& model, int i) {
  for (int j = 0; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    if (i >= joint.idx_q && i < joint.idx_q + joint.nq) return joint.name;
  }
  return "";
}

double cost_of(const Point& p, double duration) { return p.run.cpu_seconds / duration; }

std::string parameter(const Config& c) {
  return c.integrator == Integrator::dormand_prince45 ? fmt::format("rtol {:g}", c.rtol) : fmt::format("h {:g} s", c.step);
}

/// The measured order of each fixed-step curve: the least-squares slope of log error against
/// log step over its points in the asymptotic range (error at least 100x the reference's own, and
/// below 0.5: the first-order methods' errors are large at every step of the grid). NaN with fewer than two such points.
std::map<std::string, double> measured_orders(const std::vector<Point>& points, double floor) {
  std::map<std::string, std::vector<const Point*>> curves;
  for (const Point& p : points)
    if (p.config.integrator != Integrator::dormand_prince45 && p.finished && p.error.largest() >= 100 * floor && p.error.largest() < 0.5)
      curves[p.config.curve()].push_back(&p);
  std::map<std::string, double> orders;
  for (const auto& [name, curve] : curves) {
    double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
    for (const Point* p : curve) {
      const double x = std::log(p->config.step), y = std::log(p->error.largest());
      n += 1, sx += x, sy += y, sxx += x * x, sxy += x * y;
    }
    orders[name] = n >= 2 ? (n * sxy - sx * sy) / (n * sxx - sx * sx) : NAN;
  }
  return orders;
}

/// Where the study writes, and what it has found so far: the report's Markdown and the
/// invariants that failed.
struct Study {
  std::filesystem::path out;
  bool plot = true;
  bool full = true;  ///< the full grid (minutes); else the small one (seconds)
  std::string report;
  std::vector<std::string> failures;
};

/// One scenario's grid against its reference: a CSV row per run, the chart's data and chart, the
/// report's Pareto front, failures and measured orders, and the invariants.
void compare_methods(Study& study, const Scenario& s, const std::vector<Config>& configs, fmt::ostream& csv) {
  const std::filesystem::path& out = study.out;
  const bool plot = study.plot;
  std::string& report = study.report;
  std::vector<std::string>& failures = study.failures;
  const double reference_rtol = s.smooth ? kSmoothReferenceRtol : kReferenceRtol;
  fmt::print("{}: the reference (generic, dormand_prince45, rtol {:g})...\n", s.title, reference_rtol);
  std::fflush(stdout);
  const Config reference_config{"generic", Integrator::dormand_prince45, 1e-4, reference_rtol};
  const study::Trajectory reference = run(s, reference_config);
  Config half = reference_config;
  half.rtol = reference_rtol / 2;
  const study::Trajectory check_run = run(s, half);
  if (!reference.finished(s.duration) || !check_run.finished(s.duration))
    throw std::runtime_error(fmt::format("{}: the reference run stopped with {} at t = {:g} s", s.name,
                                         sim::to_string(reference.status), reference.end_time));
  const bool floating = s.description.model.floating_base();
  const double self_error = study::deviation(reference, check_run, floating).largest();
  fmt::print("  reference: {} steps, CPU {:.3g} s per simulated s; its own error {:.2g} (rtol {:g} against {:g})\n",
             reference.statistics.accepted_steps, reference.cpu_seconds / s.duration, self_error, reference_rtol, reference_rtol / 2);

  std::vector<Point> points;
  for (const Config& c : configs) {
    Point p;
    p.config = c;
    p.run = run(s, c);
    p.finished = p.run.finished(s.duration);
    p.error = study::deviation(p.run, reference, floating);
    p.energy_error = std::abs(p.run.energy_balance - reference.energy_balance);
    const double simulated = std::max(p.run.end_time, 1e-12);
    csv.print("{},{},{},{:g},{:g},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{},{:.6g},{},{},{}\n", s.name, c.backend,
              sim::to_string(c.integrator), c.step, c.rtol, sim::to_string(p.run.status), p.run.end_time, p.run.cpu_seconds / simulated,
              p.finished ? p.error.largest() : NAN, p.error.base_position, p.error.base_orientation, p.error.joints,
              joint_at_q(s.description.model, p.error.worst_joint_q), p.finished ? p.energy_error : NAN, p.run.statistics.accepted_steps, p.run.statistics.rejected_steps,
              p.run.statistics.evaluations);
    points.push_back(std::move(p));
  }

  // The chart's data: one block per curve (cost, error, parameter), the Pareto front, the
  // failures (cost up to the failure, its time).
  auto dat = fmt::output_file((out / (s.name + ".dat")).string());
  std::vector<std::string> curves;
  for (const Point& p : points)
    if (std::find(curves.begin(), curves.end(), p.config.curve()) == curves.end()) curves.push_back(p.config.curve());
  for (const std::string& curve : curves) {
    if (curve != curves.front()) dat.print("\n\n");  // blocks apart, none after the last (gnuplot would count one more)
    dat.print("\"{}\" x\n", curve);
    for (const Point& p : points)
      if (p.config.curve() == curve && p.finished)
        dat.print("{:.6g} {:.6g} {:g}\n", cost_of(p, s.duration), std::max(p.error.largest(), 1e-16), p.config.step);
  }
  const std::vector<const Point*> front = pareto_front(points);
  auto pareto = fmt::output_file((out / (s.name + "_pareto.dat")).string());
  for (const Point* p : front) pareto.print("{:.6g} {:.6g}\n", cost_of(*p, s.duration), std::max(p->error.largest(), 1e-16));
  pareto.close();
  dat.close();

  // The report: the front, then where each method failed.
  report += fmt::format("## {}\n\nReference: generic O(n), dormand_prince45 at rtol {:g}: {} steps, {:.3g} CPU s per simulated s; "
                        "its own error (against rtol {:g}) {:.2g}. Error: the largest deviation from it of the base position (m), "
                        "the base orientation (rad) and every joint (rad, m) over the {:g} s, sampled every {:g} s.\n\n",
                        s.title, reference_rtol, reference.statistics.accepted_steps, reference.cpu_seconds / s.duration, reference_rtol / 2,
                        self_error, s.duration, kSamplePeriod);
  report += "The Pareto front (no other run is both cheaper and more accurate):\n\n| backend | integrator | step or tolerance | CPU s per "
            "simulated s | error | energy error [J] |\n|---|---|---|---|---|---|\n";
  for (const Point* p : front)
    report += fmt::format("| {} | {} | {} | {:.3g} | {:.2g} | {:.2g} |\n", p->config.backend, sim::to_string(p->config.integrator),
                          parameter(p->config), cost_of(*p, s.duration), p->error.largest(), p->energy_error);
  report += "\nRuns that failed (the simulator's status, at the time it stopped):\n\n| backend | integrator | step or tolerance | "
            "status | at t [s] |\n|---|---|---|---|---|\n";
  int failed = 0;
  for (const Point& p : points)
    if (!p.finished) {
      ++failed;
      report += fmt::format("| {} | {} | {} | {} | {:.4f} |\n", p.config.backend, sim::to_string(p.config.integrator), parameter(p.config),
                            sim::to_string(p.run.status), p.run.end_time);
    }
  if (failed == 0) report += "| none | | | | |\n";
  report += "\n";

  if (plot) {
    const std::string png = (out / ("study_" + s.name + ".png")).string();
    run_gnuplot(fmt::format("dat='{}'; pareto='{}'; plot_title='{}: error against cost'; reference_error={:g}; per_backend={}",
                            (out / (s.name + ".dat")).string(), (out / (s.name + "_pareto.dat")).string(), s.title,
                            std::max(self_error, 1e-16), curves.size() / std::max<std::size_t>(1, backends_of(points))),
                "plot_study.gp", png);
    report += fmt::format("![{}](study_{}.png)\n\n", s.title, s.name);
  }

  // The invariants.
  for (const Point& p : points)
    if (p.finished && !(p.error.largest() > self_error))
      failures.push_back(fmt::format("{} ({}, {}): error {:.2g} not above the reference's own {:.2g}", s.name, p.config.curve(),
                                     parameter(p.config), p.error.largest(), self_error));
  // Error falls with the step at the integrator's order (within 0.5) in the smooth scenario, for
  // the backends that integrate the exact closed-system ODE in double; KKT with Baumgarte is
  // reported, not held to it (its stages leave the constraint manifold, where the stabilisation
  // changes the ODE), nor is float (its round-off floor flattens the curve within the range).
  if (s.smooth) {
    int checked = 0;
    report += "Measured orders (the slope of log error against log step, least squares over the points between 100x the "
              "reference's own error and 0.5):\n\n| backend | integrator | measured | expected |\n|---|---|---|---|\n";
    for (const auto& [curve, order] : measured_orders(points, self_error)) {
      const Point& any = *std::find_if(points.begin(), points.end(), [&](const Point& p) { return p.config.curve() == curve; });
      const int expected = sim::order_of(any.config.integrator);
      fmt::print("  {}: measured order {:.2f} (expected {})\n", curve, order, expected);
      report += fmt::format("| {} | {} | {:.2f} | {} |\n", any.config.backend, sim::to_string(any.config.integrator), order, expected);
      if (any.config.backend == "kkt" || any.config.backend == "float") continue;
      ++checked;
      if (!(order >= expected - 0.5))
        failures.push_back(fmt::format("{}: {}: measured order {:.2f}, expected {}", s.name, curve, order, expected));
    }
    if (checked == 0) failures.push_back(s.name + ": no curve in the asymptotic range to check the orders on");
    report += "\n";
  }
  fmt::print("  {} runs, {} failed; Pareto front of {}\n", points.size(), failed, front.size());
}

// The stability map: on the drop with the generated backend (the compiled-in robot), the largest
// stable step of each fixed-step integrator against the contact stiffness. The controller runs at
// 1 kHz and ends every step at its calls, so 1 ms is the ladder's top: "stable at 1e-3" means
// "at least".
void stability_map(Study& study) {
  const std::filesystem::path& out = study.out;
  const bool plot = study.plot, full = study.full;
  std::string& report = study.report;
  std::vector<std::string>& failures = study.failures;
  Scenario drop = make_scenario("drop_lola", simulate::Scenario::drop, MBGEN_STUDY_DESCRIPTION, full ? 0.25 : 0.15);
  const std::vector<double> stiffnesses = full ? std::vector<double>{1e5, 1e6, 1e7, 1e8, 1e9} : std::vector<double>{1e6, 1e8};
  const std::vector<Integrator> integrators =
      full ? std::vector<Integrator>{Integrator::explicit_euler, Integrator::symplectic_euler, Integrator::rk4, Integrator::linearly_implicit_euler}
           : std::vector<Integrator>{Integrator::explicit_euler, Integrator::linearly_implicit_euler};
  const std::vector<double> ladder = study::step_ladder(1e-5, 1e-3);
  fmt::print("stability map: {}, generated backend, steps 1e-5 to 1e-3 s\n", drop.title);
  auto map_dat = fmt::output_file((out / "stability_map.dat").string());
  report += fmt::format("## Stability map\n\nThe largest step (of 10^(k/4) s, 1e-5 to 1e-3) with which the drop of Lola runs its {:g} s "
                        "with status ok, against the contact stiffness (N/m^1.5; the scene's is {:g}), generated backend; the "
                        "controller's 1 ms period caps the steps.\n\n| integrator | stiffness | largest stable step [s] | smallest "
                        "failing step [s] | its status, at t [s] | runs |\n|---|---|---|---|---|---|\n",
                        drop.duration, drop.options.simulator.contact_parameters.stiffness);
  std::map<std::string, std::map<double, double>> stable;
  for (Integrator integrator : integrators) {
    if (integrator != integrators.front()) map_dat.print("\n\n");
    map_dat.print("\"{}\" x\n", sim::to_string(integrator));
    for (double k : stiffnesses) {
      Scenario s = drop;
      s.options.simulator.contact_parameters.stiffness = k;
      const study::StabilityResult r = study::largest_stable_step(ladder, [&](double h, sim::StepStatus& status, double& time) {
        const study::Trajectory t = run(s, {"generated", integrator, h, 0});
        status = t.status, time = t.end_time;
        return t.finished(s.duration);
      });
      stable[sim::to_string(integrator)][k] = r.stable;
      map_dat.print("{:g} {:g}\n", k, r.stable);
      report += fmt::format("| {} | {:g} | {} | {} | {} | {} |\n", sim::to_string(integrator), k,
                            r.stable > 0 ? fmt::format("{:.3g}", r.stable) : "none",
                            r.unstable > 0 ? fmt::format("{:.3g}", r.unstable) : "none up to 1e-3",
                            r.unstable > 0 ? fmt::format("{}, {:.4f}", sim::to_string(r.failure), r.failure_time) : "", r.runs);
      fmt::print("  {} at stiffness {:g}: largest stable step {:.3g} s ({} runs)\n", sim::to_string(integrator), k, r.stable, r.runs);
    }
  }
  map_dat.close();
  report += "\n";
  if (plot) {
    const std::string png = (out / "study_stability_map.png").string();
    run_gnuplot(fmt::format("dat='{}'; plot_title='{}: the largest stable step'; default_stiffness={:g}",
                            (out / "stability_map.dat").string(), drop.title, drop.options.simulator.contact_parameters.stiffness),
                "plot_stability_map.gp", png);
    report += fmt::format("![{}: the largest stable step](study_stability_map.png)\n\n", drop.title);
  }
  // The invariants: a stiffer contact never allows explicit Euler a larger step, and linearly
  // implicit Euler, built for stiff contact, is stable at every step explicit Euler is.
  const auto& ee = stable["explicit_euler"];
  for (auto it = ee.begin(); std::next(it) != ee.end(); ++it)
    if (std::next(it)->second > it->second)
      failures.push_back(fmt::format("stability map: explicit Euler's largest stable step grows with the stiffness ({:g} s at {:g}, {:g} s "
                                     "at {:g})", it->second, it->first, std::next(it)->second, std::next(it)->first));
  for (const auto& [k, h] : stable["linearly_implicit_euler"])
    if (h < ee.at(k))
      failures.push_back(fmt::format("stability map: linearly implicit Euler's largest stable step {:g} s is below explicit Euler's {:g} s "
                                     "at stiffness {:g}", h, ee.at(k), k));
}

// The closure drift: the four-bar swinging, RK4, the loops' violation max |Phi| (kept rows, by
// the generic runtime in double) over time: the O(n) backend with the projection after each
// step and without it, KKT without projection at Baumgarte gains from none to too high.
void closure_drift(Study& study) {
  const std::filesystem::path& out = study.out;
  const bool plot = study.plot, full = study.full;
  std::string& report = study.report;
  std::vector<std::string>& failures = study.failures;
  Scenario swing = make_scenario("drift_four_bar", simulate::Scenario::swing, MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.urdf",
                                 full ? 10.0 : 1.0);
  struct Variant {
    std::string name, backend;
    bool project;
    double baumgarte;
  };
  const std::vector<Variant> variants = {{"O(n), projected", "generic", true, 0},       {"O(n), not projected", "generic", false, 0},
                                         {"KKT, no Baumgarte", "kkt", false, 0},        {"KKT, Baumgarte 20/s", "kkt", false, 20},
                                         {"KKT, Baumgarte 200/s", "kkt", false, 200},   {"KKT, Baumgarte 2000/s", "kkt", false, 2000},
                                         {"KKT, Baumgarte 20000/s", "kkt", false, 20000}};
  constexpr double kDriftStep = 1e-3;
  fmt::print("closure drift: {}, RK4 at h = {:g} s\n", swing.title, kDriftStep);
  auto drift_dat = fmt::output_file((out / "closure_drift.dat").string());
  report += fmt::format("## Closure drift\n\nThe loops' violation max |Phi| (kept rows, m and rad, computed by the generic runtime in "
                        "double) while the four-bar swings for {:g} s, RK4 at h = {:g} s.\n\n| variant | status | largest |Phi| | at the "
                        "end |\n|---|---|---|---|\n",
                        swing.duration, kDriftStep);
  Data<double> check(swing.description.model);
  std::map<std::string, double> largest;
  for (const Variant& v : variants) {
    Scenario s = swing;
    s.options.simulator.project = v.project;
    s.options.baumgarte = v.baumgarte;
    const study::Trajectory t = run(s, {v.backend, Integrator::rk4, kDriftStep, 0});
    if (&v != &variants.front()) drift_dat.print("\n\n");
    drift_dat.print("\"{}{}\" x\n", v.name,
                    t.finished(s.duration) ? "" : fmt::format(" ({} at {:.3f} s)", sim::to_string(t.status), t.end_time));
    double worst = 0, last = 0;
    for (std::size_t k = 0; k < t.q.size(); ++k) {
      const double phi = simulate::loop_violation(s.description.model, check, t.q[k]);
      drift_dat.print("{:g} {:.6g}\n", static_cast<double>(k) * kSamplePeriod, std::max(phi, 1e-17));
      worst = std::max(worst, phi), last = phi;
    }
    largest[v.name] = t.finished(s.duration) ? worst : INFINITY;
    report += fmt::format("| {} | {}{} | {:.2g} | {:.2g} |\n", v.name, sim::to_string(t.status),
                          t.finished(s.duration) ? "" : fmt::format(" at {:.3f} s", t.end_time), worst, last);
    fmt::print("  {}: {} , largest |Phi| {:.2g}\n", v.name, sim::to_string(t.status), worst);
  }
  drift_dat.close();
  report += "\n";
  if (plot) {
    const std::string png = (out / "study_closure_drift.png").string();
    run_gnuplot(fmt::format("dat='{}'; plot_title='{}: the loop closure over time, RK4 at h = {:g} s'",
                            (out / "closure_drift.dat").string(), swing.title, kDriftStep),
                "plot_closure_drift.gp", png);
    report += "![the loop closure over time](study_closure_drift.png)\n\n";
  }
  // The invariants: projected, the loop stays closed to the simulator's claim (1e-10); without
  // projection or stabilisation it opens further than that.
  if (!(largest["O(n), projected"] <= 1e-10))
    failures.push_back(fmt::format("closure drift: projected, max |Phi| {:.2g} above 1e-10", largest["O(n), projected"]));
  if (!(largest["KKT, no Baumgarte"] > 1e-10))
    failures.push_back(fmt::format("closure drift: KKT without Baumgarte nor projection stays within 1e-10 ({:.2g})",
                                   largest["KKT, no Baumgarte"]));
}

// How soft the continuation's spans may be: the slider-driven swing through its four dead points
// with the continuation on, per time constant t_c and impedance d of the soft rows (sim/
// soft_loops.hpp), against the crank-driven exact motion. The chart: deviation against 1 - d.
void continuation_softness(Study& study, const Scenario& slider_driven, int crank, const study::Trajectory& exact,
                           double kkt_deviation) {
  const std::vector<double> time_constants = {0.002, 0.01, 0.05};
  const std::vector<double> softness = {1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9};  // 1 - d
  auto dat = fmt::output_file((study.out / "dead_point_softness.dat").string());
  study.report += "\nThrough the dead points with the continuation on (slider driving, O(n), RK4 at 1e-4 s), per time constant "
                  "t_c and impedance d of the soft rows: the largest deviation of the crank angle from the crank-driven motion "
                  "[rad], and the largest loop violation (m).\n\n| t_c [s] |";
  for (double s : softness) study.report += fmt::format(" 1 - d = {:g} |", s);
  study.report += "\n|---|";
  for (std::size_t i = 0; i < softness.size(); ++i) study.report += "---|";
  study.report += "\n";
  for (double tc : time_constants) {
    if (tc != time_constants.front()) dat.print("\n\n");
    dat.print("\"t_c = {:g} s\" x x\n", tc);
    study.report += fmt::format("| {:g} |", tc);
    for (double s : softness) {
      Scenario run_scenario = slider_driven;
      sim::ContinuationOptions& c = run_scenario.options.simulator.continuation;
      c.enabled = true, c.time_constant = tc, c.impedance = 1 - s;
      const study::Trajectory t = run(run_scenario, {"generic", Integrator::rk4, 1e-4, 0});
      double deviation = 0;
      for (std::size_t k = 0; k < std::min(t.q.size(), exact.q.size()); ++k)
        deviation = std::max(deviation, std::abs(t.q[k][crank] - exact.q[k][crank]));
      if (!t.finished(1.0)) deviation = std::numeric_limits<double>::quiet_NaN();
      dat.print("{:g} {:.6g} {:.6g}\n", s, deviation, t.statistics.max_loop_violation);
      study.report += fmt::format(" {:.2g}, {:.1g} |", deviation, t.statistics.max_loop_violation);
    }
    study.report += "\n";
  }
  dat.close();
  study.report += "\n";
  if (study.plot) {
    const std::string png = (study.out / "study_dead_point_softness.png").string();
    run_gnuplot(fmt::format("dat='{}'; plot_title='slider-crank through four dead points: the continuation against the exact motion'; "
                            "kkt={:g}",
                            (study.out / "dead_point_softness.dat").string(), kkt_deviation),
                "plot_dead_point_softness.gp", png);
  }
}

// The slider-crank's dead points (crank in line with the rod, q_crank = -pi/2 + k pi), per
// backend: the mechanism swinging freely through them for 1 s, RK4 at 1e-4 s, driven once by
// the crank (independent: crank_joint; the map from crank to slider is regular everywhere) and
// once by the slider (independent: slider_joint, as Lola's knee nut drives its crank; that map
// is singular at a dead point, where the slider stands still while the crank turns).
void dead_points(Study& study) {
  std::string& report = study.report;
  std::vector<std::string>& failures = study.failures;
  const std::string urdf = MBGEN_SOURCE_DIR "/robots/mechanisms/slider_crank.urdf";
  const std::string yaml = MBGEN_SOURCE_DIR "/robots/mechanisms/slider_crank.yaml";
  struct Variant {
    std::string name, backend;
    bool project, continuation = false;
  };
  const std::vector<Variant> variants = {{"O(n), projected", "generic", true},
                                         {"independent coordinates O(n^3), projected", "independent", true},
                                         {"KKT, Baumgarte 20/s, not projected", "kkt", false},
                                         {"O(n), projected, continued through dead points", "generic", true, true}};
  report += "## The slider-crank's dead points\n\nThe slider-crank (robots/mechanisms) swinging freely for 1 s, RK4 at h = 1e-4 s, "
            "driven by the crank (6 rad/s at the start) or by the slider (-0.3 m/s at the start: the same motion). Dead points "
            "passed: how often the crank crossed q = -pi/2 + k pi (crank in line with the rod). Deviation: the largest difference "
            "of the crank angle from the crank-driven O(n) run's (the same motion), over their common samples. Largest |Phi|: the "
            "loop's violation, computed by the generic runtime in double.\n\n| independent coordinate | backend | status | stopped "
            "at [s] | dead points passed | deviation [rad] | largest \\|Phi\\| |\n|---|---|---|---|---|---|---|\n";
  fmt::print("dead points: slider_crank, RK4 at h = 1e-4 s\n");
  study::Trajectory crank_driven;
  double kkt_deviation = 0;  // the exact full-coordinate backend's, the chart's floor
  for (const std::string driver : {"crank_joint", "slider_joint"}) {
    std::string extras = yaml;
    if (driver == "slider_joint") {
      std::ifstream in(yaml);
      std::stringstream text;
      text << in.rdbuf();
      std::string content = text.str();
      content.replace(content.find("independent: [crank_joint]"), 26, "independent: [slider_joint]");
      extras = (std::filesystem::temp_directory_path() / "mbgen_study_slider_driven.yaml").string();
      std::ofstream(extras) << content;
    }
    Scenario sc = make_scenario("dead_point_slider_crank", simulate::Scenario::swing, urdf, 1.0, extras);
    sc.options.swing_speed = driver == "crank_joint" ? 6.0 : -0.3;  // at the start dx/dtheta = -r
    const Model& m = sc.description.model;
    const int crank = m.joint(*m.find_joint("crank_joint")).idx_q;
    Data<double> check(m);
    for (const Variant& v : variants) {
      Scenario s = sc;
      s.options.simulator.project = v.project;
      s.options.simulator.continuation.enabled = v.continuation;
      const study::Trajectory t = run(s, {v.backend, Integrator::rk4, 1e-4, 0});
      int passed = 0;
      double violation = 0;
      for (std::size_t k = 0; k < t.q.size(); ++k) {
        violation = std::max(violation, simulate::loop_violation(m, check, t.q[k]));
        if (k > 0 && std::floor((t.q[k][crank] + M_PI / 2) / M_PI) != std::floor((t.q[k - 1][crank] + M_PI / 2) / M_PI)) ++passed;
      }
      if (crank_driven.q.empty()) crank_driven = t;  // the first run: crank-driven, O(n)
      double deviation = 0;
      for (std::size_t k = 0; k < std::min(t.q.size(), crank_driven.q.size()); ++k)
        deviation = std::max(deviation, std::abs(t.q[k][crank] - crank_driven.q[k][crank]));
      if (driver == "slider_joint" && v.backend == "kkt") kkt_deviation = deviation;
      const std::string spans =
          v.continuation ? fmt::format(" ({} spans, {} soft steps)", t.statistics.continuation_spans, t.statistics.soft_steps) : "";
      report += fmt::format("| {} | {} | {}{} | {:.3f} | {} | {:.2g} | {:.2g} |\n", driver, v.name, sim::to_string(t.status), spans,
                            t.end_time, passed, deviation, violation);
      fmt::print("  {} driving, {}: {}{} at {:.3f} s, {} dead points passed, deviation {:.2g} rad, max |Phi| {:.2g}\n", driver, v.name,
                 sim::to_string(t.status), spans, t.end_time, passed, deviation, violation);
      // Through a dead point a backend either stops with a status or follows the motion: never a
      // silent fold back onto the other branch. The continuation's soft spans follow it less
      // closely than the exact backends (1.4e-6 rad: their error goes as 1 - d): 1e-5 rad.
      const double follows = v.continuation && driver == "slider_joint" ? 1e-5 : 1e-6;
      if (t.finished(1.0) && !(deviation < follows))
        failures.push_back(fmt::format("dead points: {} driving, {}: finished {:.2g} rad away from the crank-driven motion", driver,
                                       v.name, deviation));
      if (driver == "crank_joint" && v.backend == "generic" && !(t.finished(1.0) && passed >= 2))
        failures.push_back(fmt::format("dead points: the crank-driven O(n) backend stopped with {} at {:.3f} s after {} dead points",
                                       sim::to_string(t.status), t.end_time, passed));
    }
    if (driver == "slider_joint") continuation_softness(study, sc, crank, crank_driven, kkt_deviation);
  }
  report += "\n";
}

// Model reductions: the drop of Lola with each of the scene's reductions (docs/extras.md), the
// generic backend and RK4 at 1e-4 s, against the whole model's reference: the error each
// reduction causes and the speed it gains. A welded joint is compared at its welded value.
void model_reductions(Study& study) {
  const std::filesystem::path& out = study.out;
  const bool plot = study.plot, full = study.full;
  std::string& report = study.report;
  std::vector<std::string>& failures = study.failures;
  const double duration = full ? 0.3 : 0.05;
  const std::string lola_yaml = std::filesystem::path(MBGEN_STUDY_DESCRIPTION).replace_extension(".yaml").string();
  const Scenario whole = make_scenario("drop_lola", simulate::Scenario::drop, MBGEN_STUDY_DESCRIPTION, duration, lola_yaml);
  const auto variant_extras = [&](const std::string& tag, const std::string& scene_line) {
    std::ifstream in(lola_yaml);
    std::stringstream text;
    text << in.rdbuf();
    std::string yaml = text.str();
    yaml.insert(yaml.find("\nscene:\n") + 8, scene_line + "\n");
    const std::string path = (std::filesystem::temp_directory_path() / ("mbgen_study_" + tag + ".yaml")).string();
    std::ofstream(path) << yaml;
    return path;
  };
  struct Reduction {
    std::string name, extras;
  };
  const std::vector<Reduction> reductions = {
      {"whole model", lola_yaml},
      {"lock: upper body (lola_legs.yaml)", std::filesystem::path(lola_yaml).replace_filename("lola_legs.yaml").string()},
      {"merge_below: 2 kg", variant_extras("merge_below", "  merge_below: 2")},
      {"rotors: none", variant_extras("rotors_none", "  rotors: none")},
      {"loops: transmission", variant_extras("transmission", "  loops: transmission")},
      {"lock + loops: transmission (lola_legs_transmission.yaml)",
       std::filesystem::path(lola_yaml).replace_filename("lola_legs_transmission.yaml").string()}};
  fmt::print("model reductions: {}, generic backend, RK4 at h = 1e-4 s\n", whole.title);
  const study::Trajectory reference = run(whole, {"generic", Integrator::dormand_prince45, 1e-4, kReferenceRtol});
  if (!reference.finished(duration))
    throw std::runtime_error(fmt::format("reductions: the reference run stopped with {}", sim::to_string(reference.status)));
  const Model& W = whole.description.model;
  auto red_dat = fmt::output_file((out / "reductions.dat").string());
  report += fmt::format("## Model reductions\n\nThe drop of Lola for {:g} s with each reduction of the scene (docs/extras.md, "
                        "\"Model reductions\"), generic backend, RK4 at h = 1e-4 s. Error: the largest deviation from the whole "
                        "model's reference (dormand_prince45, rtol {:g}) of the base and of every joint of the whole model, a welded "
                        "joint at its welded value; speed-up: the whole model's CPU time per simulated second over the reduced one's "
                        "(the same integrator and step).\n\n| reduction | nv | forward dynamics operations (generated) | status | CPU s per "
                        "simulated s | speed-up | error | worst joint |\n|---|---|---|---|---|---|---|---|\n",
                        duration, kReferenceRtol);
  double whole_cost = 0;
  for (const Reduction& r : reductions) {
    const Scenario v = make_scenario("drop_lola", simulate::Scenario::drop, MBGEN_STUDY_DESCRIPTION, duration, r.extras);
    const Model& R = v.description.model;
    study::Trajectory t = run(v, {"generic", Integrator::rk4, 1e-4, 0});
    // Into the whole model's coordinates: the reduced model's joints by name, the welded ones at
    // their lock value (0 for merge_below), a transmission's linkage where its map closes it.
    std::map<std::string, double> welded;
    if (v.description.scene)
      for (const auto& [name, value] : v.description.scene->lock) welded[name] = value;
    std::optional<TransmissionMap<double>> map;
    if (v.description.transmission_model) {
      std::vector<std::string> actuators;
      for (const gen::TransmissionSpec& ts : v.description.transmissions) actuators.insert(actuators.end(), ts.actuators.begin(), ts.actuators.end());
      map.emplace(*v.description.transmission_model, R, actuators, neutral_configuration<double>(*v.description.transmission_model));
    }
    for (std::size_t k = 0; k < t.q.size(); ++k) {
      VecX<double> q = VecX<double>::Zero(W.nq());
      if (W.floating_base()) q[6] = 1;
      VecX<double> a(map ? map->num_actuators() : 0);
      const bool mapped = map && map->evaluate(t.q[k].data(), a.data()) == ClosureStatus::Converged;
      for (int j = 1; j < W.num_joints(); ++j) {
        const Joint& wj = W.joint(JointIndex(j));
        if (const auto rj = R.find_joint(wj.name))
          for (int i = 0; i < wj.nq; ++i) q[wj.idx_q + i] = t.q[k][R.joint(*rj).idx_q + i];
        else if (welded.count(wj.name))
          q[wj.idx_q] = welded[wj.name];
        else if (mapped)
          q[wj.idx_q] = map->linkage_q()[map->linkage_model().joint(*map->linkage_model().find_joint(wj.name)).idx_q];
      }
      t.q[k] = q;
    }
    const double cost = t.cpu_seconds / std::max(t.end_time, 1e-12);
    if (r.name == "whole model") whole_cost = cost;
    const study::Deviation e = study::deviation(t, reference, W.floating_base());
    const long operations = codegen::count_operations(codegen::trace_generated_forward_dynamics(R)).total();
    const bool finished = t.finished(duration);
    if (!finished) failures.push_back(fmt::format("reductions: {} stopped with {} at {:.4f} s", r.name, sim::to_string(t.status), t.end_time));
    red_dat.print("{:.4g} {:.4g} \"{}\"\n", whole_cost / cost, finished ? std::max(e.largest(), 1e-16) : NAN, r.name);
    report += fmt::format("| {} | {} | {} | {}{} | {:.3g} | {:.2f} | {:.2g} | {} |\n", r.name, R.nv(), operations, sim::to_string(t.status),
                          finished ? "" : fmt::format(" at {:.4f} s", t.end_time), cost, whole_cost / cost, e.largest(),
                          joint_at_q(W, e.worst_joint_q));
    fmt::print("  {}: nv {}, {} operations, {:.3g} CPU s per simulated s (x{:.2f}), error {:.2g} at {}\n", r.name, R.nv(), operations,
               cost, whole_cost / cost, e.largest(), joint_at_q(W, e.worst_joint_q));
  }
  red_dat.close();
  report += "\n";
  if (plot) {
    const std::string png = (out / "study_reductions.png").string();
    run_gnuplot(fmt::format("dat='{}'; plot_title='{}: the error each reduction causes against the speed it gains'",
                            (out / "reductions.dat").string(), whole.title),
                "plot_reductions.gp", png);
    report += "![model reductions: error against speed-up](study_reductions.png)\n\n";
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string grid_name = "full", out_dir = "study", only_scenario, only_backends;
  bool plot = true, check = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--grid" && i + 1 < argc) grid_name = argv[++i];
    else if (a == "--out" && i + 1 < argc) out_dir = argv[++i];
    else if (a == "--scenario" && i + 1 < argc) only_scenario = argv[++i];
    else if (a == "--backends" && i + 1 < argc) only_backends = argv[++i];
    else if (a == "--no-plot") plot = false;
    else if (a == "--check") check = true;
    else if (a == "--help" || a == "-h") return fmt::print("{}", kUsage), 0;
    else return fmt::print(stderr, "mbgen_study: unknown option '{}'\n{}", a, kUsage), 2;
  }
  if (grid_name != "full" && grid_name != "small") return fmt::print(stderr, "mbgen_study: --grid full or small\n{}", kUsage), 2;
  const bool full = grid_name == "full";

  std::vector<Scenario> scenarios;
  std::vector<double> steps, rtols;
  std::vector<std::string> backends = {"generated", "generic", "float", "independent", "kkt"};
  try {
    if (full) {
      scenarios.push_back(make_scenario("swing_four_bar", simulate::Scenario::swing, MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.urdf", 1.0));
      scenarios.push_back(make_scenario("drop_lola", simulate::Scenario::drop, MBGEN_STUDY_DESCRIPTION, 0.3));
      scenarios.push_back(push_scenario());
      steps = {1e-5, 2e-5, 5e-5, 1e-4, 2e-4, 5e-4, 1e-3, 2e-3, 5e-3, 1e-2};  // the drop's controller (1 kHz) caps them at 1e-3
      rtols = {1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9};
    } else {
      scenarios.push_back(make_scenario("swing_four_bar", simulate::Scenario::swing, MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.urdf", 0.5));
      steps = {2.5e-4, 5e-4, 1e-3, 2e-3, 5e-3};
      rtols = {1e-4, 1e-6, 1e-8};
      backends = {"generic", "float", "independent", "kkt"};
    }
  } catch (const gen::LoadError& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
  if (!only_scenario.empty()) {
    scenarios.erase(std::remove_if(scenarios.begin(), scenarios.end(), [&](const Scenario& s) { return s.name != only_scenario; }),
                    scenarios.end());
    if (scenarios.empty() && only_scenario != "stability" && only_scenario != "drift" && only_scenario != "reductions" &&
        only_scenario != "dead_point") return fmt::print(stderr, "mbgen_study: no scenario '{}' in the {} grid\n", only_scenario, grid_name), 2;
  }
  if (!only_backends.empty()) {
    std::vector<std::string> chosen;
    for (std::size_t start = 0; start <= only_backends.size();) {
      const std::size_t comma = std::min(only_backends.find(',', start), only_backends.size());
      chosen.push_back(only_backends.substr(start, comma - start));
      start = comma + 1;
    }
    for (const std::string& b : chosen)
      if (b != "generated" && b != "generic" && b != "float" && b != "independent" && b != "kkt")
        return fmt::print(stderr, "mbgen_study: unknown backend '{}'\n{}", b, kUsage), 2;
    backends = chosen;
  }

  std::filesystem::create_directories(out_dir);
  Study study;
  study.out = out_dir, study.plot = plot, study.full = full;
  const std::filesystem::path& out = study.out;
  auto csv = fmt::output_file((out / "study.csv").string());
  csv.print("scenario,backend,integrator,step,rtol,status,end_time,cpu_per_simulated_s,error,error_base_position,"
            "error_base_orientation,error_joints,worst_joint,energy_error,accepted_steps,rejected_steps,evaluations\n");
  study.report = fmt::format("# mbgen_study ({} grid)\n\n", grid_name);

  try {
    for (const Scenario& s : scenarios) compare_methods(study, s, grid(s, steps, rtols, backends), csv);
    if (only_scenario.empty() || only_scenario == "stability") stability_map(study);  // needs the generated robot
    if (only_scenario.empty() || only_scenario == "drift") closure_drift(study);
    if (only_scenario.empty() || only_scenario == "dead_point") dead_points(study);
    if (only_scenario.empty() || only_scenario == "reductions") model_reductions(study);
  } catch (const std::runtime_error& e) {
    fmt::print(stderr, "mbgen_study: {}\n", e.what());
    return 1;
  }

  auto md = fmt::output_file((out / "study.md").string());
  md.print("{}", study.report);
  md.close();
  fmt::print("report: {}\n", (out / "study.md").string());
  for (const std::string& f : study.failures) fmt::print(stderr, "mbgen_study: invariant: {}\n", f);
  return check && !study.failures.empty() ? 1 : 0;
}
