#include "loop_chain.hpp"

#include <fmt/format.h>

#include <fstream>
#include <stdexcept>

namespace mbgen::bench {

namespace {
constexpr double kCrank = 0.2, kGround = 0.3;

/// A 1 kg slender rod of length `length` along `axis` (x or z) from the link origin.
std::string rod_link(const std::string& name, double length, char axis) {
  const double i_perp = length * length / 12.0 + 1e-4, i_axial = 1e-4;
  const std::string com = axis == 'x' ? fmt::format("{} 0 0", length / 2) : fmt::format("0 0 {}", length / 2);
  const double ixx = axis == 'x' ? i_axial : i_perp, izz = axis == 'z' ? i_axial : i_perp;
  return fmt::format(
      "  <link name=\"{}\">\n    <inertial><origin xyz=\"{}\"/><mass value=\"1\"/>"
      "<inertia ixx=\"{}\" ixy=\"0\" ixz=\"0\" iyy=\"{}\" iyz=\"0\" izz=\"{}\"/></inertial>\n  </link>\n",
      name, com, ixx, i_perp, izz);
}

std::string revolute(const std::string& name, const std::string& parent, const std::string& child, const std::string& xyz) {
  return fmt::format(
      "  <joint name=\"{}\" type=\"continuous\">\n    <parent link=\"{}\"/><child link=\"{}\"/>\n"
      "    <origin xyz=\"{}\"/><axis xyz=\"0 1 0\"/>\n  </joint>\n",
      name, parent, child, xyz);
}
}  // namespace

std::string write_loop_chain(const std::string& directory, int k) {
  if (k < 1) throw std::invalid_argument("write_loop_chain: k must be at least 1");
  const std::string name = fmt::format("loop_chain_{}", k);
  std::string urdf = fmt::format("<?xml version=\"1.0\"?>\n<!-- bench/loop_chain.hpp: {} parallelogram four-bars in a chain -->\n"
                                 "<robot name=\"{}\">\n  <link name=\"world\"/>\n",
                                 k, name);
  std::string yaml = fmt::format("# bench/loop_chain.hpp: closures of {}.urdf\nrobot: {}\nbase: fixed\nclosures:\n", name, name);
  std::string independent;
  for (int i = 1; i <= k; ++i) {
    const std::string ground = i == 1 ? "world" : fmt::format("rocker_{}", i - 1);
    const double lift = i == 1 ? 0.0 : kCrank;  // module i's pivots sit at the top of rocker i - 1
    urdf += rod_link(fmt::format("crank_{}", i), kCrank, 'z') + rod_link(fmt::format("coupler_{}", i), kGround, 'x') +
            rod_link(fmt::format("rocker_{}", i), kCrank, 'z');
    urdf += revolute(fmt::format("crank_joint_{}", i), ground, fmt::format("crank_{}", i), fmt::format("0 0 {}", lift));
    urdf += revolute(fmt::format("coupler_joint_{}", i), fmt::format("crank_{}", i), fmt::format("coupler_{}", i),
                     fmt::format("0 0 {}", kCrank));
    urdf += revolute(fmt::format("rocker_joint_{}", i), ground, fmt::format("rocker_{}", i), fmt::format("{} 0 {}", kGround, lift));
    yaml += fmt::format(
        "  - {{name: close_{0}, type: revolute, parent: coupler_{0}, child: rocker_{0}, parent_origin: {{xyz: [{1}, 0, 0]}}, "
        "child_origin: {{xyz: [0, 0, {2}]}}, axis: [0, 1, 0]}}\n",
        i, kGround, kCrank);
    independent += fmt::format("{}crank_joint_{}", i == 1 ? "" : ", ", i);
  }
  urdf += "</robot>\n";
  yaml += fmt::format("independent: [{}]\n", independent);
  const std::string urdf_path = directory + "/" + name + ".urdf";
  std::ofstream(urdf_path) << urdf;
  std::ofstream(directory + "/" + name + ".yaml") << yaml;
  return urdf_path;
}

}  // namespace mbgen::bench
