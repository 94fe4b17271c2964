#include "load/urdf_numbers.hpp"

#include <fmt/format.h>
#include <tinyxml2.h>

#include <sstream>

#include "load/load_error.hpp"
#include "load/parse_numbers.hpp"

namespace mbgen::gen {

const std::vector<UrdfNumericAttribute>& urdf_numeric_attributes() {
  static const std::vector<UrdfNumericAttribute> table = {
      {"link", "inertial/origin", "xyz", 3, "0 0 0.1"},
      {"link", "inertial/origin", "rpy", 3, "0 0 1.5708"},
      {"link", "inertial/mass", "value", 1, "1.5"},
      {"link", "inertial/inertia", "ixx", 1, "0.01"},
      {"link", "inertial/inertia", "ixy", 1, "0"},
      {"link", "inertial/inertia", "ixz", 1, "0"},
      {"link", "inertial/inertia", "iyy", 1, "0.01"},
      {"link", "inertial/inertia", "iyz", 1, "0"},
      {"link", "inertial/inertia", "izz", 1, "0.01"},
      {"link", "collision/origin", "xyz", 3, "0 0 0.1"},
      {"link", "collision/origin", "rpy", 3, "0 0 1.5708"},
      {"link", "collision/geometry/sphere", "radius", 1, "0.05"},
      {"link", "collision/geometry/cylinder", "radius", 1, "0.05"},
      {"link", "collision/geometry/cylinder", "length", 1, "0.3"},
      {"link", "collision/geometry/box", "size", 3, "0.1 0.2 0.3"},
      {"link", "collision/geometry/mesh", "scale", 3, "1 1 1"},
      {"joint", "origin", "xyz", 3, "0 0 0.1"},
      {"joint", "origin", "rpy", 3, "0 0 1.5708"},
      {"joint", "axis", "xyz", 3, "0 0 1"},
      {"joint", "limit", "lower", 1, "-1.57"},
      {"joint", "limit", "upper", 1, "1.57"},
      {"joint", "limit", "effort", 1, "100"},
      {"joint", "limit", "velocity", 1, "3"},
      {"joint", "dynamics", "damping", 1, "0.1"},
      {"joint", "dynamics", "friction", 1, "0.05"},
      {"joint", "mimic", "multiplier", 1, "1"},
      {"joint", "mimic", "offset", 1, "0"},
  };
  return table;
}

namespace {

/// Calls f on every element reached from `from` along `path` (a/b/c; every match, since a link
/// may have several <collision> elements).
template <typename F> void for_each_at(const tinyxml2::XMLElement& from, const std::string& path, F&& f) {
  const std::size_t slash = path.find('/');
  const std::string head = path.substr(0, slash);
  for (const tinyxml2::XMLElement* e = from.FirstChildElement(head.c_str()); e; e = e->NextSiblingElement(head.c_str())) {
    if (slash == std::string::npos) f(*e);
    else for_each_at(*e, path.substr(slash + 1), f);
  }
}

void check_attribute(const std::string& path, const std::string& owner, const tinyxml2::XMLElement& e,
                     const UrdfNumericAttribute& spec) {
  const char* text = e.Attribute(spec.attribute);
  if (!text) return;  // absent: urdfdom's default
  const std::string tag = fmt::format("<{} {}=\"{}\">", e.Name(), spec.attribute, text);
  const std::string fix = fmt::format("write {} finite decimal number{} separated by spaces, e.g. {}=\"{}\"", spec.count,
                                      spec.count == 1 ? "" : "s", spec.attribute, spec.example);
  const ParsedNumbers parsed = parse_numbers(text);
  if (!parsed.problem.empty()) throw LoadError(path, e.GetLineNum(), owner, fmt::format("{}: {}", tag, parsed.problem), fix);
  if (static_cast<int>(parsed.values.size()) != spec.count)
    throw LoadError(path, e.GetLineNum(), owner,
                    fmt::format("{}: {} number{}, {} expected", tag, parsed.values.size(),
                                parsed.values.size() == 1 ? "" : "s", spec.count),
                    fix);
}

bool moves(const tinyxml2::XMLElement& joint) {
  const char* type = joint.Attribute("type");
  return !type || (std::string(type) != "fixed" && std::string(type) != "floating");
}

}  // namespace

void check_urdf_numbers(const std::string& path, const tinyxml2::XMLElement& robot) {
  for (const tinyxml2::XMLElement* e = robot.FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string kind = e->Name();
    if (kind != "link" && kind != "joint") continue;
    const char* name = e->Attribute("name");
    const std::string owner = fmt::format("{} '{}'", kind, name ? name : "");
    for (const UrdfNumericAttribute& spec : urdf_numeric_attributes())
      if (kind == spec.owner)
        for_each_at(*e, spec.path, [&](const tinyxml2::XMLElement& at) { check_attribute(path, owner, at, spec); });
    // A zero axis has no direction to normalise (a fixed or floating joint ignores its axis).
    if (kind == "joint" && moves(*e))
      for_each_at(*e, "axis", [&](const tinyxml2::XMLElement& axis) {
        const char* xyz = axis.Attribute("xyz");
        const ParsedNumbers parsed = parse_numbers(xyz ? xyz : "1 0 0");
        if (parsed.values[0] == 0 && parsed.values[1] == 0 && parsed.values[2] == 0)
          throw LoadError(path, axis.GetLineNum(), owner, fmt::format("<axis xyz=\"{}\">: the joint axis is zero", xyz),
                          "give a non-zero <axis xyz=\"...\"/>, e.g. xyz=\"0 0 1\"");
      });
  }
}

}  // namespace mbgen::gen
