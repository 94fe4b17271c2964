// mbgen_sim: the simulation scenarios from the command line (docs/simulation.md).
//
//   mbgen_sim drop  [options]   the default robot (Lola) dropped from 5 cm, PD + gravity
//   mbgen_sim push  [options]   standing, then pushed at the base
//   mbgen_sim swing [options]   a mechanism swinging freely (default: the four-bar)
//
// Writes <out>/<scenario>_<robot>.csv (one row per ms) and, with gnuplot, the PNG plot of it
// (scripts/plot_simulation.gp), and prints a summary: the status, the CPU time per simulated
// second, the largest penetration and loop-closure drift, the energy balance.
#include <fmt/format.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include MBGEN_SIM_HEADER
#include "collision/contact_spheres.hpp"
#include "examples/sim/run_scenario.hpp"
#include "load/load_error.hpp"
#include "model/load_description.hpp"

namespace robot = MBGEN_SIM_NS;
using namespace mbgen;
using namespace mbgen::simulate;

namespace {

constexpr const char* kUsage = R"(usage: mbgen_sim drop|push|swing [options]
  --robot URDF         description (default: robots/lola/lola.urdf; swing: robots/mechanisms/four_bar.urdf)
  --extras YAML        its extras (default: the .yaml beside the URDF)
  --floating|--fixed   base (default: the extras' base)
  --backend B          generated (the robot compiled into mbgen_sim: )" MBGEN_SIM_NAME R"(), generic, kkt, independent
                       (default: generated for )" MBGEN_SIM_NAME R"(, else generic)
  --integrator I       explicit_euler, symplectic_euler, rk4, dormand_prince45, linearly_implicit_euler (default rk4)
  --step S             s (default 1e-4); the first step of dormand_prince45
  --rtol R --atol A    dormand_prince45 tolerances (default 1e-6, 1e-8)
  --duration T         simulated s (default 2; push: after settling)
  --height H           drop height of the lowest contact sphere, m (default 0.05)
  --impulse P          push, N s along +x at the base (default 4), over --push-time s (default 0.05)
  --bandwidth F        PD + gravity per actuated joint: natural frequency, Hz (default 40), at
  --damping-ratio Z    this damping ratio (default 1), scaled by each joint's inertia
  --baumgarte G        kkt backend: alpha = beta, 1/s (default 20)
  --no-projection      do not re-close the loops after each step (to measure the drift)
  --whole-body-contact every link with an SSV touches the ground (not only the scene's contact links),
                       and a fall runs to its end instead of stopping when the CoM is half down
                       (the generated backend has the scene's contacts only: generic by default)
  --no-joint-limits    no end stops at the joints' ranges (as `scene: joint_limits: false`)
  --continue-through-dead-points
                       where a linkage reaches a dead point (its loop cannot be closed), go on with
                       the loops soft until they close again, and report each span (default: stop
                       there with closure_lost; docs/simulation.md, "Through a dead point")
  --out DIR            where the CSV and PNG go (default .)
  --no-plot            CSV only
)";

[[noreturn]] void usage_error(const std::string& what) {
  fmt::print(stderr, "mbgen_sim: {}\n{}", what, kUsage);
  std::exit(2);
}

std::string stem(const std::string& path) { return std::filesystem::path(path).stem().string(); }

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h") {
    fmt::print("{}", kUsage);
    return argc < 2 ? 2 : 0;
  }
  ScenarioOptions o;
  const std::string scenario = argv[1];
  if (scenario == "drop") o.scenario = Scenario::drop;
  else if (scenario == "push") o.scenario = Scenario::push;
  else if (scenario == "swing") o.scenario = Scenario::swing;
  else usage_error("unknown scenario '" + scenario + "'");
  std::string urdf = o.scenario == Scenario::swing ? MBGEN_SOURCE_DIR "/robots/mechanisms/four_bar.urdf" : MBGEN_SIM_DESCRIPTION;
  std::string extras, out_dir = ".", backend;
  gen::LoadOptions load;
  bool plot = true, whole_body = false, joint_limits = true;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage_error(a + " needs a value");
      return argv[++i];
    };
    auto number = [&]() {
      const std::string v = value();
      char* end = nullptr;
      const double x = std::strtod(v.c_str(), &end);
      if (end == v.c_str() || *end || !std::isfinite(x)) usage_error(a + ": '" + v + "' is not a number");
      return x;
    };
    if (a == "--robot") urdf = value();
    else if (a == "--extras") extras = value();
    else if (a == "--floating") load.base = gen::BaseType::Floating;
    else if (a == "--fixed") load.base = gen::BaseType::Fixed;
    else if (a == "--backend") backend = value();
    else if (a == "--integrator") {
      const std::string v = value();
      if (!sim::parse_integrator(v.c_str(), o.simulator.integrator)) usage_error("unknown integrator '" + v + "'");
    } else if (a == "--step") o.simulator.step = number();
    else if (a == "--rtol") o.simulator.rtol = number();
    else if (a == "--atol") o.simulator.atol = number();
    else if (a == "--duration") o.duration = number();
    else if (a == "--height") o.height = number();
    else if (a == "--impulse") o.impulse = number();
    else if (a == "--push-time") o.push_time = number();
    else if (a == "--bandwidth") o.bandwidth = number();
    else if (a == "--damping-ratio") o.damping_ratio = number();
    else if (a == "--baumgarte") o.baumgarte = number();
    else if (a == "--no-projection") o.simulator.project = false;
    else if (a == "--whole-body-contact") whole_body = true;
    else if (a == "--no-joint-limits") joint_limits = false;
    else if (a == "--continue-through-dead-points") o.simulator.continuation.enabled = true;
    else if (a == "--out") out_dir = value();
    else if (a == "--no-plot") plot = false;
    else usage_error("unknown option '" + a + "'");
  }
  if (!(o.simulator.step > 0)) usage_error("--step must be > 0");
  if (extras.empty()) {
    const std::string beside = std::filesystem::path(urdf).replace_extension(".yaml").string();
    if (std::filesystem::exists(beside)) extras = beside;
  }
  if (!extras.empty()) load.extras_file = extras;

  gen::Description d;
  try {
    d = gen::load_description(urdf, load);
  } catch (const gen::LoadError& e) {
    fmt::print(stderr, "{}\n", e.what());
    return 1;
  }
  if (whole_body && d.scene && d.scene->contact) {
    // Every link with SSVs, in the model's frame order (deterministic), touches the ground.
    std::vector<std::string> links;
    for (int f = 0; f < d.model.num_frames(); ++f) {
      const std::string& name = d.model.frame(FrameIndex(f)).name;
      if (d.ssv.count(name) && !d.ssv.at(name).empty()) links.push_back(name);
    }
    d.scene->contact->links = links;
    o.stop_when_fallen = false;
  } else if (whole_body) {
    fmt::print(stderr, "mbgen_sim: --whole-body-contact needs `scene: contact:` in the extras (the ground's law)\n");
    return 1;
  }
  const std::vector<ContactSphere> spheres = gen::contact_spheres(d);
  if (o.scenario != Scenario::swing) {
    if (spheres.empty()) {
      fmt::print(stderr, "mbgen_sim: {} has no contact spheres: add `scene: contact: links: [...]` to its extras (docs/extras.md)\n", urdf);
      return 1;
    }
    if (!d.model.floating_base()) {
      fmt::print(stderr, "mbgen_sim: {} has a fixed base: a {} needs --floating\n", urdf, scenario);
      return 1;
    }
    if (d.scene && d.scene->contact) {
      o.simulator.contact_parameters = d.scene->contact->parameters;
      o.simulator.ground = d.scene->contact->ground;
    }
  }
  if (d.scene) o.simulator.joint_stops = d.scene->joint_limits;  // the end stops: the scene's law, or off
  if (!joint_limits) o.simulator.joint_stops.enabled = false;
  // The compiled-in robot is the generated backend's only robot: the same description only.
  const bool is_compiled_robot = std::filesystem::weakly_canonical(urdf) == std::filesystem::weakly_canonical(MBGEN_SIM_DESCRIPTION) &&
                                 d.model.nq() == robot::nq && d.model.nv() == robot::nv && !whole_body;
  if (backend.empty()) backend = is_compiled_robot ? "generated" : "generic";
  if (backend == "generated" && !is_compiled_robot) {
    fmt::print(stderr, "mbgen_sim: the generated backend compiled in is {}'s; for {} use --backend generic (or build your own "
                       "Simulator<your_robot::Backend> with mbgen_add_robot)\n", MBGEN_SIM_NAME, urdf);
    return 1;
  }
  std::filesystem::create_directories(out_dir);
  const std::string name = fmt::format("{}_{}", scenario, stem(urdf));
  o.csv = (std::filesystem::path(out_dir) / (name + ".csv")).string();
  o.poses_csv = (std::filesystem::path(out_dir) / (name + "_poses.csv")).string();
  o.backend = backend;

  ScenarioResult r;
  if (backend == "generated") {
    r = run_scenario(robot::Backend{}, robot::Backend{}, d, o);
  } else if (backend == "generic") {
    r = run_scenario(sim::GenericBackend<double>(d.model, spheres), sim::GenericBackend<double>(d.model), d, o);
  } else if (backend == "kkt") {
    const BaumgarteGains gains{o.baumgarte, o.baumgarte};
    r = run_scenario(sim::KktBackend<double>(d.model, gains, spheres), sim::KktBackend<double>(d.model, gains), d, o);
  } else if (backend == "independent") {
    r = run_scenario(sim::IndependentBackend<double>(d.model, spheres), sim::IndependentBackend<double>(d.model), d, o);
  } else {
    usage_error("unknown backend '" + backend + "'");
  }

  fmt::print("{} {} ({} backend, {}, step {:g} s): {} at t = {:.4f} s\n", scenario, d.model.name, backend,
             sim::to_string(o.simulator.integrator), o.simulator.step, sim::to_string(r.status), r.end_time);
  if (r.fell) fmt::print("  the robot fell: its centre of mass sank below half its start height; stopped there\n");
  if (!o.stop_when_fallen && d.model.floating_base())
    fmt::print("  centre of mass from {:.3f} m to {:.3f} m; kinetic energy at the end {:.3g} J\n", r.start_com_height, r.final_com_height,
               r.final_kinetic_energy);
  if (r.stops > 0)
    fmt::print("  end stops: {} ({} touched), deepest {:.2g} rad (or m), {}\n", r.stops, r.stops_touched, r.statistics.max_stop_penetration,
               r.deepest_stop.empty() ? "none touched" : "at " + r.deepest_stop);
  if (r.statistics.continuation_spans > 0) {
    fmt::print("  continued through {} dead-point span(s) with the loops soft: {} soft steps, largest loop violation {:.2g} m\n",
               r.statistics.continuation_spans, r.statistics.soft_steps, r.statistics.max_loop_violation);
    for (const sim::ContinuationSpan& span : r.spans)
      fmt::print("    {:.4f} .. {} s in {}: {} steps, largest violation {:.2g} m\n", span.begin,
                 span.end >= 0 ? fmt::format("{:.4f}", span.end) : std::string("(open)"), span_subsystem(span, r), span.steps,
                 span.max_violation);
  }
  if (r.status == sim::StepStatus::closure_lost)
    fmt::print("  the loops could not be closed: {}, in the sub-system of {}\n",
               r.closure_status == 2 ? "a linkage at (or too near) a dead point" : "Newton did not converge", r.closure_subsystem);
  fmt::print("  {} steps ({} rejected), {} evaluations; CPU {:.3f} s per simulated s\n", r.statistics.accepted_steps,
             r.statistics.rejected_steps, r.statistics.evaluations, r.end_time > 0 ? r.cpu_seconds / r.end_time : 0.0);
  fmt::print("  largest penetration {:.3f} mm, largest loop-closure violation {:.2g} m, energy balance at the end {:.4g} J\n",
             1e3 * r.max_penetration, r.max_closure_drift, r.final_energy_balance);
  if (d.model.floating_base())
    fmt::print("  base height at the end {:.4f} m, normal force {:.1f} N (m g = {:.1f} N)\n", r.final_base_height,
               r.final_normal_force, d.model.total_mass() * d.model.gravity.norm());
  fmt::print("  trajectory: {}; poses and contact forces: {} (mbgen view --trajectory)\n", o.csv, o.poses_csv);
  if (plot) {
    const std::string png = (std::filesystem::path(out_dir) / (name + ".png")).string();
    const std::string title = fmt::format("{} {}{}{}: {} backend, {}, h = {:g} s", scenario, d.model.name,
                                          o.scenario == Scenario::push ? fmt::format(" {:g} N s", o.impulse) : "",
                                          whole_body ? ", every link touching the ground" : "", backend,
                                          sim::to_string(o.simulator.integrator), o.simulator.step);
    const std::string command = fmt::format("gnuplot -e \"csv='{}'; png='{}'; plot_title='{}'; contact={}\" {} 2>&1", o.csv, png, title,
                                            o.scenario == Scenario::swing ? 0 : 1, MBGEN_SOURCE_DIR "/scripts/plot_simulation.gp");
    if (std::system(command.c_str()) == 0) fmt::print("  plot: {}\n", png);
    else fmt::print(stderr, "mbgen_sim: gnuplot failed (apt-get install gnuplot-nox); the CSV is written\n");
  }
  return sim::advanced(r.status) ? (r.fell ? 4 : 0) : 3;
}
