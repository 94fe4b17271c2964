// URDF -> Model. The graph is built from the joint list, never from urdfdom's tree pointers
// (urdfdom keeps one parent per link and silently drops a second one). Fixed joints are merged:
// the child link's inertia is lumped into the moving body it is welded to, and its frame kept.
#include <Eigen/Geometry>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <console_bridge/console.h>
#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "load/description.hpp"
#include "load/load_error.hpp"
#include "load/name_match.hpp"
#include "load/check_values.hpp"
#include "load/parse_urdf.hpp"
#include "load/urdf_numbers.hpp"
#include "load/xml_error.hpp"

namespace mbgen::gen {

namespace {

/// Captures what urdfdom says through console_bridge instead of letting it print raw.
class CapturedLog : public console_bridge::OutputHandler {
 public:
  CapturedLog() { console_bridge::useOutputHandler(this); }
  ~CapturedLog() override { console_bridge::restorePreviousOutputHandler(); }
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_WARN) messages.push_back(text);
  }
  std::vector<std::string> messages;
};

/// Rotation entries within 1e-14 of 0 or +-1 are made exact: a quarter turn written in decimal
/// (rpy="1.570796326794897 0 0") leaves 6e-17 where a 0 is meant. The change is below double
/// round-off of any dynamics quantity, and it lets generated code drop the structural zeros.
double snap_unit(double x) {
  for (double target : {0.0, 1.0, -1.0})
    if (std::abs(x - target) < 1e-14) return target;
  return x;
}

/// R, or the rotation by quarter turns about the axes (a signed permutation matrix, determinant
/// 1) that every entry of R is within `tolerance` of (the extras' `snap_quarter_turns`): a URDF that
/// writes pi/2 as 1.57079632679 leaves 4.9e-12 where a 0 is meant, above snap_unit's 1e-14, and
/// generated code carries every product with it (hyq: a quarter of its mass matrix's operations).
/// The whole matrix or nothing, so that the result is a rotation exactly: a rotation within
/// tolerance <= 1e-6 (extras_quarter_turns' bound) of its entries rounded has one +-1 per row and
/// column (two entries of a unit row cannot both round to +-1 within 0.3) and keeps its determinant.
Mat3<double> snap_quarter_turn(const Mat3<double>& R, double tolerance) {
  if (!(tolerance > 0)) return R;
  const Mat3<double> P = R.unaryExpr([](double x) { return std::round(x); });
  return (R - P).cwiseAbs().maxCoeff() <= tolerance ? P : R;
}

SE3<double> to_se3(const urdf::Pose& pose, double quarter_turn_tolerance) {
  SE3<double> X;
  double x, y, z, w;
  pose.rotation.getQuaternion(x, y, z, w);
  X.rotation = snap_quarter_turn(Eigen::Quaterniond(w, x, y, z).normalized().toRotationMatrix().unaryExpr(&snap_unit),
                                 quarter_turn_tolerance);
  X.translation = Vec3<double>(pose.position.x, pose.position.y, pose.position.z);
  return X;
}

Inertia<double> to_inertia(const urdf::Link& link, double quarter_turn_tolerance) {
  Inertia<double> I;
  if (!link.inertial) return I;
  const urdf::Inertial& in = *link.inertial;
  SE3<double> X_LC = to_se3(in.origin, quarter_turn_tolerance);
  Mat3<double> I_C;
  I_C << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  I.mass = in.mass;
  I.com = X_LC.translation;
  I.inertia_com = X_LC.rotation * I_C * X_LC.rotation.transpose();
  return I;
}

/// Document order of the <joint> elements and the line of each link and joint element.
struct XmlIndex {
  std::vector<std::string> joint_order, link_order;
  std::map<std::string, int> link_line, joint_line;
  std::vector<std::string> joints_without_limit;  ///< revolute/prismatic joints with no <limit>
  /// revolute/prismatic joints whose <limit> gives neither lower nor upper: URDF's defaults
  /// [0, 0] would lock them, which is never what such files mean (parallel_legs has 150 of them).
  std::vector<std::string> joints_without_range;
  std::string urdf_text;  ///< the text handed to urdfdom (with the <limit> elements it insists on)
};

/// The tree's references, checked before urdfdom builds it (its messages carry no line, and on
/// these errors it leaks the half-built model): names are unique, every joint's <parent> and
/// <child> name a link, and exactly one link is no joint's child (the root).
void check_references(const std::string& path, const tinyxml2::XMLElement& robot, const XmlIndex& index) {
  std::map<std::string, int> seen;
  std::map<std::string, std::string> parent_joint;  // child link -> a joint that has it as child
  for (const tinyxml2::XMLElement* e = robot.FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string kind = e->Name();
    if (kind != "link" && kind != "joint") continue;
    const char* name = e->Attribute("name");
    if (!name || !*name)
      throw LoadError(path, e->GetLineNum(), fmt::format("<{}>", kind), "has no name", "give it a name=\"...\"");
    const auto [previous, fresh] = seen.emplace(kind + " " + name, e->GetLineNum());
    if (!fresh)
      throw LoadError(path, e->GetLineNum(), fmt::format("{} '{}'", kind, name),
                      fmt::format("is defined twice (first on line {})", previous->second),
                      fmt::format("rename one of the two {}s", kind));
    if (kind != "joint") continue;
    for (const char* end : {"parent", "child"}) {
      const tinyxml2::XMLElement* ref = e->FirstChildElement(end);
      const char* link = ref ? ref->Attribute("link") : nullptr;
      if (!link)
        throw LoadError(path, e->GetLineNum(), fmt::format("joint '{}'", name), fmt::format("has no <{} link=\"...\"/>", end),
                        fmt::format("name the joint's {} link", end));
      if (!index.link_line.count(link)) {
        const std::string suggestion = did_you_mean(link, index.link_order);
        throw LoadError(path, ref->GetLineNum(), fmt::format("joint '{}'", name),
                        fmt::format("its {} link '{}' is not a link of the robot", end, link),
                        suggestion.empty() ? fmt::format("add <link name=\"{}\"/> or correct the name", link)
                                           : fmt::format("{} (or add <link name=\"{}\"/>)", suggestion, link));
      }
      if (std::string(end) == "child") parent_joint.emplace(link, name);
    }
  }
  std::vector<std::string> roots;
  for (const std::string& link : index.link_order)
    if (!parent_joint.count(link)) roots.push_back(link);
  if (roots.empty() && !index.link_order.empty())
    throw LoadError(path, robot.GetLineNum(), fmt::format("robot '{}'", robot.Attribute("name") ? robot.Attribute("name") : ""),
                    "has no root link: every link is some joint's child, so the joints form a loop",
                    "URDF describes a tree: remove one joint of the loop and declare it as a closure in the YAML extras");
  if (roots.size() > 1)
    throw LoadError(path, index.link_line.at(roots[1]), fmt::format("link '{}'", roots[1]),
                    fmt::format("is a second root: no joint has it as child, nor '{}' (line {})", roots[0],
                                index.link_line.at(roots[0])),
                    "connect it to the robot with a joint (a fixed one if it does not move), or remove it");
}

/// Indexes the XML and, because urdfdom rejects a revolute or prismatic joint without <limit>
/// (Drake and MuJoCo accept it as unbounded), gives such joints a zero limit, marked unbounded later.
XmlIndex index_xml(const std::string& path, const std::string& text) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(text.c_str(), text.size()) != tinyxml2::XML_SUCCESS) {
    throw xml_parse_error(path, doc);
  }
  XmlIndex index;
  tinyxml2::XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) {
    const tinyxml2::XMLElement* root = doc.RootElement();
    std::string what = root ? fmt::format("the root element is <{}>, not <robot>", root->Name()) : "no <robot> root element";
    throw LoadError(path, root ? root->GetLineNum() : 1, "", fmt::format("not a URDF: {}", what),
                    "give a URDF file (one <robot name=...> element), or an MJCF file with the .xml extension; SDF is not read yet");
  }
  check_urdf_numbers(path, *robot);
  for (tinyxml2::XMLElement* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const char* name = e->Attribute("name");
    if (!name) continue;
    if (std::string(e->Name()) == "link") {
      index.link_order.push_back(name);
      index.link_line.emplace(name, e->GetLineNum());
    }
    if (std::string(e->Name()) == "joint") {
      index.joint_order.push_back(name);
      index.joint_line.emplace(name, e->GetLineNum());
      const char* type = e->Attribute("type");
      const bool needs_limit = type && (std::string(type) == "revolute" || std::string(type) == "prismatic");
      const tinyxml2::XMLElement* given = e->FirstChildElement("limit");
      if (needs_limit && given && !given->Attribute("lower") && !given->Attribute("upper"))
        index.joints_without_range.push_back(name);
      if (needs_limit && !given) {
        index.joints_without_limit.push_back(name);
        tinyxml2::XMLElement* limit = doc.NewElement("limit");
        limit->SetAttribute("effort", 0);
        limit->SetAttribute("velocity", 0);
        e->InsertEndChild(limit);
      }
    }
  }
  check_references(path, *robot, index);
  if (index.joints_without_limit.empty()) {
    index.urdf_text = text;
  } else {
    tinyxml2::XMLPrinter printer;
    doc.Print(&printer);
    index.urdf_text = printer.CStr();
  }
  return index;
}

struct Builder {
  const std::string& path;
  const urdf::ModelInterface& urdf;
  const XmlIndex& xml;
  BaseType base;
  std::vector<std::string>& warnings;
  double quarter_turn_tolerance;
  Model model;
  std::map<std::string, std::vector<urdf::JointConstSharedPtr>> children_of;  // in document order

  int line_of_joint(const std::string& name) const {
    auto it = xml.joint_line.find(name);
    return it == xml.joint_line.end() ? 0 : it->second;
  }
  int line_of_link(const std::string& name) const {
    auto it = xml.link_line.find(name);
    return it == xml.link_line.end() ? 0 : it->second;
  }

  /// Attaches link `link_name`, whose frame sits at X_BL in body `body`, and everything below it.
  void attach(const std::string& link_name, BodyIndex body, const SE3<double>& X_BL, bool is_body_frame) {
    const urdf::Link& link = *urdf.getLink(link_name);
    if (!is_body_frame) {
      if (body != kWorldBody) {
        Body& b = model.mutable_body(body);
        b.inertia = b.inertia + to_inertia(link, quarter_turn_tolerance).transformed(X_BL);
      }
    }
    model.add_frame(Frame{link_name, is_body_frame ? FrameKind::Body : FrameKind::Link, body, X_BL});
    attach_children(link_name, body, X_BL);
  }

  /// Attaches the joints below link `link_name`, whose frame sits at X_BL in body `body`.
  void attach_children(const std::string& link_name, BodyIndex body, const SE3<double>& X_BL) {
    for (const urdf::JointConstSharedPtr& joint : children_of[link_name]) {
      const SE3<double> X_BJ = X_BL * to_se3(joint->parent_to_joint_origin_transform, quarter_turn_tolerance);
      const urdf::Link& child = *urdf.getLink(joint->child_link_name);
      if (joint->type == urdf::Joint::FIXED) {
        model.add_frame(Frame{joint->name, FrameKind::Joint, body, X_BJ});
        attach(child.name, body, X_BJ, false);
        continue;
      }
      Joint j;
      j.name = joint->name;
      j.X_PJ = X_BJ;
      const Vec3<double> axis(joint->axis.x, joint->axis.y, joint->axis.z);
      switch (joint->type) {
        case urdf::Joint::REVOLUTE:
        case urdf::Joint::CONTINUOUS: j.type = JointType::Revolute; break;
        case urdf::Joint::PRISMATIC: j.type = JointType::Prismatic; break;
        case urdf::Joint::FLOATING: j.type = JointType::Floating; break;
        default:
          throw LoadError(path, line_of_joint(joint->name), fmt::format("joint '{}'", joint->name),
                          "joint type 'planar' is not supported",
                          "model it as two prismatic joints and one revolute joint through intermediate links");
      }
      if (j.type == JointType::Floating) {
        j.X_PJ = X_BL;  // q of a floating joint is the child's pose in the parent link's frame
      } else {
        j.axis = axis.normalized();  // not zero: check_urdf_numbers refused that
      }
      const bool limit_added = std::find(xml.joints_without_limit.begin(), xml.joints_without_limit.end(),
                                         joint->name) != xml.joints_without_limit.end();
      if (limit_added)
        warnings.push_back(fmt::format("joint '{}' has no <limit>: loaded as unbounded", joint->name));
      const bool no_range = std::find(xml.joints_without_range.begin(), xml.joints_without_range.end(),
                                      joint->name) != xml.joints_without_range.end();
      if (joint->limits && !limit_added && !no_range && joint->type != urdf::Joint::CONTINUOUS &&
          j.type != JointType::Floating) {
        j.bounded = true;
        j.lower = joint->limits->lower;
        j.upper = joint->limits->upper;
      }
      if (joint->limits) {
        j.velocity_limit = joint->limits->velocity;
        j.effort_limit = joint->limits->effort;
      }
      if (joint->dynamics) {
        j.damping = joint->dynamics->damping;
        j.friction = joint->dynamics->friction;
      }
      BodyIndex child_body = model.add_body(body, j, child.name, to_inertia(child, quarter_turn_tolerance));
      attach(child.name, child_body, SE3<double>::Identity(), true);
    }
  }
};

/// Checks what urdfdom accepts but dynamics cannot use, on the raw per-link and per-joint
/// values, so that each message names the URDF element and its line.
void check_urdf_values(const std::string& path, urdf::ModelInterface& urdf, const XmlIndex& xml, ValueReport& report) {
  for (const std::string& link_name : xml.link_order) {
    const auto found = urdf.links_.find(link_name);
    if (found == urdf.links_.end() || !found->second->inertial) continue;
    urdf::Inertial& in = *found->second->inertial;
    Mat3<double> I_C;
    I_C << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
    // The inertia to use (round-off zeroed, or repaired on request) replaces urdfdom's values.
    const Mat3<double> used = check_link_inertia(path, xml.link_line.at(link_name), link_name, in.mass, I_C, report);
    if (used != I_C) {
      in.ixx = used(0, 0), in.iyy = used(1, 1), in.izz = used(2, 2);
      in.ixy = used(0, 1), in.ixz = used(0, 2), in.iyz = used(1, 2);
    }
  }
  for (const std::string& joint_name : xml.joint_order) {
    urdf::JointConstSharedPtr joint = urdf.getJoint(joint_name);
    if (!joint || !joint->limits) continue;
    if (joint->type != urdf::Joint::REVOLUTE && joint->type != urdf::Joint::PRISMATIC) continue;
    if (std::find(xml.joints_without_limit.begin(), xml.joints_without_limit.end(), joint_name) !=
        xml.joints_without_limit.end())
      continue;
    check_joint_limits(path, xml.joint_line.at(joint_name), joint_name, joint->limits->lower, joint->limits->upper);
  }
}

}  // namespace

Model load_urdf_model(const std::string& path, BaseType base, std::vector<std::string>& warnings) {
  std::vector<std::string> notes;
  ValueReport report{warnings, notes};
  return load_urdf_model(path, base, report, nullptr);
}

namespace {
XmlIndex read_and_index(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw LoadError(path, 0, "", "cannot open the file", "check the path and the file's permissions");
  std::stringstream buffer;
  buffer << in.rdbuf();
  return index_xml(path, buffer.str());
}

urdf::ModelInterfaceSharedPtr parse_indexed(const std::string& path, const XmlIndex& xml) {
  CapturedLog log;
  urdf::ModelInterfaceSharedPtr urdf = urdf::parseURDF(xml.urdf_text);
  if (!urdf) {
    std::string why = log.messages.empty() ? "urdfdom rejected the description" : log.messages.back();
    throw LoadError(path, 0, "", fmt::format("invalid URDF: {}", why),
                    "correct the element named above (see the URDF specification)");
  }
  return urdf;
}
}  // namespace

urdf::ModelInterfaceSharedPtr parse_urdf_file(const std::string& path) { return parse_indexed(path, read_and_index(path)); }

Model load_urdf_model(const std::string& path, BaseType base, ValueReport& report, SourceLines* lines, double quarter_turn_tolerance) {
  std::vector<std::string>& warnings = report.warnings;
  const XmlIndex xml = read_and_index(path);
  urdf::ModelInterfaceSharedPtr urdf = parse_indexed(path, xml);

  if (lines) {
    lines->link = xml.link_line;
    lines->joint = xml.joint_line;
  }
  check_urdf_values(path, *urdf, xml, report);
  if (!xml.joints_without_range.empty())
    warnings.push_back(fmt::format(
        "{} joint(s) have a <limit> without lower and upper: loaded as unbounded rather than locked at URDF's "
        "default [0, 0] ({})",
        xml.joints_without_range.size(), fmt::join(xml.joints_without_range, ", ")));

  Builder builder{path, *urdf, xml, base, warnings, quarter_turn_tolerance, Model{}, {}};
  builder.model.name = urdf->getName();
  // The joint list, in document order, is the graph. A link with two parent joints is a loop
  // that URDF cannot express: say so instead of dropping one as urdfdom does.
  std::map<std::string, std::string> parent_joint_of;
  for (const std::string& joint_name : xml.joint_order) {
    urdf::JointConstSharedPtr joint = urdf->getJoint(joint_name);
    if (!joint) continue;
    auto [it, inserted] = parent_joint_of.emplace(joint->child_link_name, joint->name);
    if (!inserted)
      throw LoadError(path, builder.line_of_joint(joint->name), fmt::format("link '{}'", joint->child_link_name),
                      fmt::format("has two parent joints, '{}' and '{}'", it->second, joint->name),
                      "URDF describes a tree: keep one joint and declare the other as a closure in the YAML extras");
    builder.children_of[joint->parent_link_name].push_back(joint);
  }
  const std::string root = urdf->getRoot()->name;
  // A massless root link named "world" is the world itself (a common URDF idiom).
  const bool world_root = root == "world" && !urdf->getRoot()->inertial;
  if (world_root) {
    if (base == BaseType::Floating) {
      // A floating base replaces the fixed joint(s) that weld the robot to "world". A moving
      // joint from "world" stays what it is: say so, since the robot is then not free-floating
      // there, and refuse if nothing floats at all (a silent fixed base would be nonsense).
      int replaced = 0;
      std::vector<std::string> moving;
      for (urdf::JointConstSharedPtr& joint : builder.children_of[root]) {
        if (joint->type != urdf::Joint::FIXED) {
          moving.push_back(joint->name);
          continue;
        }
        ++replaced;
        auto floating = std::make_shared<urdf::Joint>(*joint);
        floating->type = urdf::Joint::FLOATING;
        warnings.push_back(
            fmt::format("floating base: fixed joint '{}' from 'world' replaced by a floating joint", joint->name));
        joint = floating;
      }
      if (replaced == 0)
        throw LoadError(path, builder.line_of_link(root), "link 'world'",
                        fmt::format("a floating base was asked for, but the robot hangs from 'world' only through "
                                    "moving joint(s) ({}), so nothing would float",
                                    fmt::join(moving, ", ")),
                        "load it with a fixed base (--fixed / `base: fixed`), or attach the base link to 'world' "
                        "with a fixed joint that mbgen can replace");
      if (!moving.empty())
        warnings.push_back(fmt::format("floating base: joint(s) {} from 'world' are moving joints and stay attached to "
                                       "the world",
                                       fmt::join(moving, ", ")));
    }
    builder.model.add_frame(Frame{root, FrameKind::Body, kWorldBody, SE3<double>::Identity()});
    builder.attach_children(root, kWorldBody, SE3<double>::Identity());
  } else if (base == BaseType::Floating) {
    Joint free;
    free.name = "root_joint";
    free.type = JointType::Floating;
    BodyIndex b = builder.model.add_body(kWorldBody, free, root, to_inertia(*urdf->getRoot(), quarter_turn_tolerance));
    builder.attach(root, b, SE3<double>::Identity(), true);
  } else {
    builder.attach(root, kWorldBody, SE3<double>::Identity(), false);
  }
  return std::move(builder.model);
}

}  // namespace mbgen::gen
