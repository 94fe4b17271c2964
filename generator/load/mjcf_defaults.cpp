// MJCF `<default>` classes and attribute resolution. The top `<default>` is class "main"; a nested
// `<default class="c">` starts from everything its parent sets and overrides per attribute. An
// element takes its values from, in order: its own attribute, the class named by its `class`
// attribute, else the nearest `childclass` of its body or an enclosing body, else "main"
// (load_mjcf.cpp decides the class; this file only looks values up).
#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

#include "load/load_error.hpp"
#include "load/mjcf_support.hpp"
#include "load/parse_numbers.hpp"

namespace mbgen::gen::mjcf {

namespace {

using AttributeMap = std::map<std::string, std::map<std::string, std::string>>;

void read_class(const std::string& path, const tinyxml2::XMLElement* e, const std::string& name, AttributeMap values,
                std::map<std::string, AttributeMap>& classes) {
  for (const tinyxml2::XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    if (std::string(c->Name()) == "default") continue;
    for (const tinyxml2::XMLAttribute* a = c->FirstAttribute(); a; a = a->Next()) values[c->Name()][a->Name()] = a->Value();
  }
  if (!classes.emplace(name, values).second)
    throw LoadError(path, e->GetLineNum(), fmt::format("default class '{}'", name), "is defined twice",
                    "give each <default class=...> a unique name");
  for (const tinyxml2::XMLElement* c = e->FirstChildElement("default"); c; c = c->NextSiblingElement("default")) {
    const char* child = c->Attribute("class");
    if (!child)
      throw LoadError(path, c->GetLineNum(), "<default>", "a nested <default> has no class name",
                      "name it: <default class=\"...\">");
    read_class(path, c, child, values, classes);
  }
}

}  // namespace

Defaults::Defaults(const std::string& path, const tinyxml2::XMLElement* root) {
  classes_["main"];
  for (const tinyxml2::XMLElement* d = root->FirstChildElement("default"); d; d = d->NextSiblingElement("default")) {
    const char* name = d->Attribute("class");
    const std::string cls = name ? name : "main";
    if (cls == "main") {
      classes_.erase("main");  // the top class may be written once, possibly with class="main"
    }
    read_class(path, d, cls, {}, classes_);
  }
}

std::optional<std::string> Defaults::lookup(const std::string& cls, const std::string& kind,
                                            const std::string& attribute) const {
  auto c = classes_.find(cls);
  if (c == classes_.end()) return std::nullopt;
  auto k = c->second.find(kind);
  if (k == c->second.end()) return std::nullopt;
  auto a = k->second.find(attribute);
  if (a == k->second.end()) return std::nullopt;
  return a->second;
}

std::string Element::describe() const {
  const char* name = e_->Attribute("name");
  if (name) return fmt::format("{} '{}'", e_->Name(), name);
  // Say "unnamed" only where a name is usual; <option> or <compiler> never have one.
  static const std::set<std::string> named = {"body", "joint", "freejoint", "geom", "site", "connect", "weld",
                                              "motor", "position", "velocity", "general"};
  return named.count(e_->Name()) ? fmt::format("<{}> (unnamed)", e_->Name()) : fmt::format("<{}>", e_->Name());
}

std::optional<std::string> Element::attribute(const std::string& name) const {
  if (const char* own = e_->Attribute(name.c_str())) return std::string(own);
  return defaults_.lookup(cls_, e_->Name(), name);
}

std::string Element::string(const std::string& name, const std::string& fallback) const {
  return attribute(name).value_or(fallback);
}

std::optional<std::vector<double>> Element::numbers(const std::string& name, int n) const {
  const std::optional<std::string> text = attribute(name);
  if (!text) return std::nullopt;
  const ParsedNumbers parsed = parse_numbers(*text);
  if (!parsed.problem.empty())
    fail(fmt::format("{}=\"{}\" is not a list of numbers: {}", name, *text, parsed.problem),
         "write plain decimal numbers separated by spaces");
  const std::vector<double>& values = parsed.values;
  if (n > 0 && static_cast<int>(values.size()) != n)
    fail(fmt::format("{}=\"{}\" has {} number(s), {} expected", name, *text, values.size(), n),
         fmt::format("give exactly {} numbers", n));
  return values;
}

double Element::number(const std::string& name, double fallback) const {
  auto v = numbers(name, 1);
  return v ? (*v)[0] : fallback;
}

Vec3<double> Element::vec3(const std::string& name, const Vec3<double>& fallback) const {
  auto v = numbers(name, 3);
  return v ? Vec3<double>((*v)[0], (*v)[1], (*v)[2]) : fallback;
}

void Element::fail(const std::string& problem, const std::string& fix) const {
  throw LoadError(path_, line(), describe(), problem, fix);
}

}  // namespace mbgen::gen::mjcf
