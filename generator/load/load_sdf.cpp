// SDFormat -> Description, through libsdformat (Debian's libsdformat-dev, SDFormat 12): it parses,
// converts any version to its own, resolves poses (relative_to, use_parent_model_frame), checks
// units and reports errors with their file and line. This file only maps its model to mbgen's.
//
// Frames. Every pose is resolved in the model frame at the file's pose, which SDFormat defines as
// the joints' zero. A moving joint's child body has its frame at the joint frame J (as a URDF
// child link), so mbgen's q is SDFormat's joint position; the link frame L is kept as a Frame at
// X_JL. A fixed joint merges its child into its parent, inertia lumped. A ball joint in the tree
// becomes three hinges about J's x, y, z ("<joint>_x", ...); a universal or revolute2 joint two
// hinges about its axis and axis2 ("<joint>_1", "_2").
//
// Loops. A link may be the child of two joints. The spanning tree is chosen by
// choose_spanning_tree (sdf_spanning_tree.hpp: breadth-first from the root, non-ball joints
// first; the extras' `closure_joints:` overrides); every joint left out becomes a closure between
// its parent and child links, at its joint frame: ball -> point (3 rows), revolute or continuous
// -> revolute (5), prismatic -> prismatic (5), fixed -> weld (6). The file's pose closes each one
// by construction (the joint frame resolved in both links).
//
// Base. A joint from "world" is the robot's attachment (a fixed one gives a fixed base, replaced
// by a free joint when a floating base is asked for); otherwise the root link (the one that is no
// joint's child) floats unless the model is <static> or --fixed / `base: fixed` is given.
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tinyxml2.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

#include "load/check_values.hpp"
#include "load/load_error.hpp"
#include "load/sdf_spanning_tree.hpp"
#include "load/sdf_support.hpp"
#include "load/xml_error.hpp"

namespace mbgen::gen {

namespace sdformat {

SE3<double> resolve(const std::string& path, const sdf::SemanticPose& pose, const std::string& in, const std::string& element,
                    int line) {
  ignition::math::Pose3d p;
  const sdf::Errors errors = pose.Resolve(p, in);
  if (!errors.empty())
    throw LoadError(path, line, element, fmt::format("its pose cannot be resolved in '{}': {}", in, errors.front().Message()),
                    "correct its <pose relative_to=...>");
  return to_se3(p);
}

namespace {

constexpr double kSdfUnbounded = 1e16;  // SDFormat's default limits (+-1e16) mean "none"

/// libsdformat's first error as a LoadError with the file and line it names.
[[noreturn]] void throw_sdf_error(const std::string& path, const sdf::Errors& errors) {
  const sdf::Error& e = errors.front();
  std::string more = errors.size() > 1 ? fmt::format(" ({} more error(s) after it)", errors.size() - 1) : "";
  throw LoadError(e.FilePath().value_or(path), e.LineNumber().value_or(0), "", fmt::format("SDFormat: {}{}", e.Message(), more),
                  "correct the file where libsdformat says; mbgen reads what libsdformat 12 accepts (SDFormat 1.0-1.9)");
}

/// The one model the file describes: its <model>, or the only <model> of its <world>.
const sdf::Model& pick_model(const std::string& path, const sdf::Root& root, Description& d) {
  if (const sdf::Model* m = root.Model()) return *m;
  std::vector<const sdf::Model*> models;
  std::vector<std::string> names;
  for (uint64_t w = 0; w < root.WorldCount(); ++w)
    for (uint64_t i = 0; i < root.WorldByIndex(w)->ModelCount(); ++i) {
      models.push_back(root.WorldByIndex(w)->ModelByIndex(i));
      names.push_back(models.back()->Name());
    }
  if (models.size() == 1) {
    d.notes.push_back(fmt::format("{}: the <world>'s one model '{}' is read (its pose in the world is not: the model frame is "
                                  "mbgen's world)", path, names.front()));
    return *models.front();
  }
  throw LoadError(path, line_of(root.Element()), "<sdf>",
                  models.empty() ? "describes no <model>" : fmt::format("has {} models ({}): mbgen reads one robot", models.size(),
                                                                        fmt::join(names, ", ")),
                  models.empty() ? "give a file with one <model>" : "give a file with the robot's <model> alone");
}

struct Builder {
  const std::string& path;
  const sdf::Model& sdf_model;
  Description& d;
  bool repair_inertia = false;
  std::map<std::string, BodyIndex> body_of;   // link -> mbgen body
  std::map<std::string, SE3<double>> X_ML;    // link -> its pose in the model frame
  std::map<BodyIndex, SE3<double>> X_MB;      // mbgen body -> its frame's pose in the model frame (q = 0)

  int link_line(const std::string& link) const { return d.urdf_lines.line_of_link(link); }

  /// The link's inertia in mbgen body `body` (whose frame is at X_MB[body]). Read from the
  /// <inertial> element as written, so that mbgen's checks (and --repair-inertia) see the values
  /// libsdformat would have replaced; an element left out has SDFormat's default.
  Inertia<double> inertia_of(const sdf::Link& link, BodyIndex body) {
    const int line = link_line(link.Name());
    if (!link.Element()->HasElement("inertial"))
      d.warnings.push_back(fmt::format("{}:{}: link '{}' has no <inertial>, so it has SDFormat's default, 1 kg and 1 kg m^2 about "
                                       "each axis: give its <inertial>", path, line, link.Name()));
    const sdf::ElementPtr in = link.Element()->GetElement("inertial");
    const sdf::ElementPtr moments = in->GetElement("inertia");
    const SE3<double> X_LI = to_se3(in->Get<ignition::math::Pose3d>("pose"));
    auto moment = [&](const char* name) { return moments->Get<double>(name); };
    Mat3<double> I;
    I << moment("ixx"), moment("ixy"), moment("ixz"), moment("ixy"), moment("iyy"), moment("iyz"), moment("ixz"), moment("iyz"),
        moment("izz");
    Inertia<double> inertia;
    inertia.mass = in->Get<double>("mass");
    ValueReport report{d.warnings, d.notes, repair_inertia};
    I = check_link_inertia(path, line_of(in) ? line_of(in) : line, link.Name(), inertia.mass, I, report);
    inertia.com = X_LI.translation;
    inertia.inertia_com = X_LI.rotation * I * X_LI.rotation.transpose();
    const SE3<double> X_BL = X_MB.at(body).inverse() * X_ML.at(link.Name());
    return inertia.transformed(X_BL);
  }

  /// Adds link `name` to body `body` (a new one, or merged into its parent's) with its frame.
  void place_link(const std::string& name, BodyIndex body, bool moving) {
    const sdf::Link& link = *sdf_model.LinkByName(name);
    body_of[name] = body;
    if (body != kWorldBody) {
      const Inertia<double> inertia = inertia_of(link, body);
      Body& b = d.model.mutable_body(body);
      b.inertia = b.inertia + inertia;
    }
    const SE3<double> X_BL = X_MB.at(body).inverse() * X_ML.at(name);
    add_frame(Frame{name, moving ? FrameKind::Body : FrameKind::Link, body, X_BL});
  }

  /// SDFormat 1.6 keeps links, joints and frames in separate name spaces, mbgen in one: the first
  /// element of a name keeps it (links come first), and a later one is said to have none.
  void add_frame(const Frame& frame) {
    if (d.model.find_frame(frame.name)) {
      d.warnings.push_back(fmt::format("{}: joint or frame '{}' has the name of an earlier link or frame: no frame is kept for it",
                                       path, frame.name));
      return;
    }
    d.model.add_frame(frame);
  }

  /// The 1-DoF mbgen joints an SDFormat joint becomes (name, type, axis in J, limits).
  std::vector<Joint> elementary_joints(const sdf::Joint& j, int line) {
    const std::string element = fmt::format("joint '{}'", j.Name());
    auto axis = [&](unsigned k) {
      const sdf::JointAxis* a = j.Axis(k);
      if (!a) throw LoadError(path, line, element, fmt::format("has no <axis{}>", k ? "2" : ""), "give its axis");
      ignition::math::Vector3d xyz;
      const sdf::Errors errors = a->ResolveXyz(xyz);  // in the joint frame
      if (!errors.empty()) throw LoadError(path, line, element, fmt::format("its axis: {}", errors.front().Message()), "correct <axis>");
      if (xyz.Length() < 1e-12) throw LoadError(path, line, element, "has a zero axis", "give a non-zero <xyz>");
      return Vec3<double>(to_vec3(xyz).normalized());
    };
    auto with_dynamics = [&](Joint out, unsigned k) {
      const sdf::JointAxis& a = *j.Axis(k);
      out.damping = a.Damping();
      out.friction = a.Friction();
      if (a.MaxVelocity() > 0) out.velocity_limit = a.MaxVelocity();
      if (a.Effort() > 0) out.effort_limit = a.Effort();
      if (out.type != JointType::Revolute || j.Type() != sdf::JointType::CONTINUOUS) {
        const bool lower = a.Lower() > -kSdfUnbounded, upper = a.Upper() < kSdfUnbounded;
        if (lower != upper)
          throw LoadError(path, line, element, "has only one of <lower> and <upper>", "give both limits, or neither");
        if (lower) {
          out.bounded = true;
          out.lower = a.Lower();
          out.upper = a.Upper();
          check_joint_limits(path, line, j.Name(), out.lower, out.upper);
        }
      }
      if (a.SpringStiffness() != 0)
        d.warnings.push_back(fmt::format("{}:{}: joint '{}' has a spring of stiffness {}: a passive force mbgen does not model; add "
                                         "it to the joint torque", path, line, out.name, a.SpringStiffness()));
      return out;
    };
    std::vector<Joint> out;
    Joint base;
    switch (j.Type()) {
      case sdf::JointType::REVOLUTE:
      case sdf::JointType::CONTINUOUS:
      case sdf::JointType::PRISMATIC:
        base.name = j.Name();
        base.type = j.Type() == sdf::JointType::PRISMATIC ? JointType::Prismatic : JointType::Revolute;
        base.axis = axis(0);
        out.push_back(with_dynamics(base, 0));
        break;
      case sdf::JointType::UNIVERSAL:
      case sdf::JointType::REVOLUTE2:
        for (unsigned k = 0; k < 2; ++k) {
          Joint h;
          h.name = fmt::format("{}_{}", j.Name(), k + 1);
          h.axis = axis(k);
          out.push_back(with_dynamics(h, k));
        }
        break;
      case sdf::JointType::BALL:
        for (int k = 0; k < 3; ++k) {
          Joint h;
          h.name = fmt::format("{}_{}", j.Name(), "xyz"[k]);
          h.axis = Vec3<double>::Unit(k);
          if (const sdf::JointAxis* a = j.Axis(0)) h.damping = a->Damping();
          out.push_back(h);
        }
        break;
      case sdf::JointType::FIXED: break;
      default:
        throw LoadError(path, line, element,
                        fmt::format("has type '{}', which mbgen cannot model",
                                    j.Element() ? j.Element()->Get<std::string>("type") : std::string("invalid")),
                        j.Type() == sdf::JointType::GEARBOX
                            ? "replace the gearbox by a `coupling` closure of its two joints in the extras (docs/extras.md)"
                            : "use revolute, continuous, prismatic, ball, universal, revolute2 or fixed");
    }
    return out;
  }

  /// Tree joint j: link `child` attached below link `parent`'s body. `reversed`: the joint is
  /// followed from its SDFormat child to its parent, so it moves the parent relative to the child
  /// by the inverse motion: R(a, q)^-1 = R(-a, q), the hinges of a chain in reverse order, so
  /// that q keeps the file's meaning (a ball's three angles are its own in either direction).
  void attach(const sdf::Joint& j, const std::string& parent, const std::string& child, bool reversed) {
    const int line = d.urdf_lines.line_of_joint(j.Name());
    const SE3<double> X_MJ = resolve(path, j.SemanticPose(), "__model__", fmt::format("joint '{}'", j.Name()), line);
    const BodyIndex parent_body = body_of.at(parent);
    std::vector<Joint> chain = elementary_joints(j, line);
    if (reversed) {
      std::reverse(chain.begin(), chain.end());
      for (Joint& joint : chain) joint.axis = -joint.axis;
    }
    if (chain.empty()) {  // fixed: the child moves with its parent
      place_link(child, parent_body, false);
      add_frame(Frame{j.Name(), FrameKind::Joint, parent_body, X_MB.at(parent_body).inverse() * X_MJ});
      return;
    }
    BodyIndex body = parent_body;
    SE3<double> X = X_MB.at(parent_body).inverse() * X_MJ;  // J in the current body, q = 0
    std::vector<BodyIndex> bodies;
    for (std::size_t k = 0; k < chain.size(); ++k) {
      Joint joint = chain[k];
      joint.X_PJ = X;
      const bool last = k + 1 == chain.size();
      body = d.model.add_body(body, joint, last ? child : fmt::format("{}/{}", child, joint.name), Inertia<double>{});
      bodies.push_back(body);
      X_MB[body] = X_MJ;
      d.urdf_lines.joint[joint.name] = line;
      X = SE3<double>::Identity();
    }
    place_link(child, body, true);
    // Each joint's frame is fixed in the body it moves, at its anchor (as a URDF joint's in its child link).
    for (std::size_t k = 0; k < chain.size(); ++k) add_frame(Frame{chain[k].name, FrameKind::Joint, bodies[k], SE3<double>::Identity()});
    if (chain.size() > 1) add_frame(Frame{j.Name(), FrameKind::Joint, body, SE3<double>::Identity()});
  }

  /// Cut joint j: a closure between its parent and child links at its joint frame.
  void add_closure(const sdf::Joint& j, const std::string& parent, const std::string& child) {
    const int line = d.urdf_lines.line_of_joint(j.Name());
    const std::string element = fmt::format("joint '{}'", j.Name());
    ClosureSpec c;
    c.name = j.Name();
    switch (j.Type()) {
      case sdf::JointType::BALL: c.type = "spherical"; break;
      case sdf::JointType::REVOLUTE:
      case sdf::JointType::CONTINUOUS: c.type = "revolute"; break;
      case sdf::JointType::PRISMATIC: c.type = "prismatic"; break;
      case sdf::JointType::FIXED: c.type = "weld"; break;
      default:
        throw LoadError(path, line, element,
                        "closes a loop (it is left out of the spanning tree), and a joint of its type cannot be a closure",
                        "make it a tree joint: name another joint of its loop in the extras' `closure_joints:`");
    }
    if (c.type == "revolute" || c.type == "prismatic") c.axis = elementary_joints(j, line).front().axis;
    if (j.Type() == sdf::JointType::REVOLUTE && j.Axis(0) &&
        (j.Axis(0)->Lower() > -kSdfUnbounded || j.Axis(0)->Upper() < kSdfUnbounded))
      d.warnings.push_back(fmt::format("{}:{}: joint '{}' closes a loop: its limits are not modelled", path, line, j.Name()));
    const SE3<double> X_MJ = resolve(path, j.SemanticPose(), "__model__", element, line);
    c.frame_a = parent;
    c.frame_b = child;
    c.X_AC = X_ML.at(parent).inverse() * X_MJ;
    c.X_BC = X_ML.at(child).inverse() * X_MJ;
    c.resolved_a = d.model.find_frame(parent).value();
    c.resolved_b = d.model.find_frame(child).value();
    c.source = fmt::format("{}:{}: <joint> '{}'", path, line, j.Name());
    c.source_line = line;
    d.closures.push_back(c);
    const BodyIndex body = body_of.at(child);
    add_frame(Frame{j.Name(), FrameKind::Joint, body, X_MB.at(body).inverse() * X_MJ});
  }
};

/// The link every chain starts from: "world" when a joint hangs the robot from it, else the one
/// link that is no joint's child.
std::string find_root(const std::string& path, const sdf::Model& m, const std::vector<GraphJoint>& joints) {
  std::set<std::string> children;
  bool world = false;
  for (const GraphJoint& j : joints) {
    children.insert(j.child);
    world = world || j.parent == "world";
  }
  if (world) return "world";
  std::vector<std::string> roots;
  for (uint64_t i = 0; i < m.LinkCount(); ++i)
    if (!children.count(m.LinkByIndex(i)->Name())) roots.push_back(m.LinkByIndex(i)->Name());
  if (roots.size() == 1) return roots.front();
  throw LoadError(path, line_of(m.Element()), fmt::format("model '{}'", m.Name()),
                  roots.empty() ? "has no root link: every link is some joint's child"
                                : fmt::format("has {} root links ({}), each no joint's child: mbgen reads one connected robot",
                                              roots.size(), fmt::join(roots, ", ")),
                  roots.empty() ? "attach the base link to no joint as a child (or to 'world')" : "join them by joints");
}

void check_model_elements(const std::string& path, const sdf::Model& m, Description& d) {
  if (m.ModelCount() > 0)
    throw LoadError(path, line_of(m.ModelByIndex(0)->Element()), fmt::format("model '{}'", m.ModelByIndex(0)->Name()),
                    "is nested in model '" + m.Name() + "': mbgen reads one flat model",
                    "merge its links and joints into the outer model");
  for (sdf::ElementPtr e = m.Element()->GetFirstElement(); e; e = e->GetNextElement()) {
    const std::string kind = e->GetName();
    if (kind == "plugin" || kind == "gripper")
      d.warnings.push_back(fmt::format("{}:{}: <{}> '{}' is not read: it configures a simulator, not the robot's mechanics", path,
                                       line_of(e), kind, e->GetAttribute("name") ? e->GetAttribute("name")->GetAsString() : ""));
  }
}

}  // namespace
}  // namespace sdformat

void load_sdf(const std::string& path, std::optional<BaseType> base, const std::vector<std::string>& closure_joints,
              Description& d, bool repair_inertia) {
  using namespace sdformat;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    throw LoadError(path, 0, "", "cannot open the file", "check the path and the file's permissions");
  sdf::Console::Instance()->SetQuiet(true);  // its errors come back as sdf::Errors and are reported below
  sdf::Root root;
  sdf::Errors errors = root.Load(path);
  // Inertias are checked by mbgen's own rules below, with their line and --repair-inertia.
  errors.erase(std::remove_if(errors.begin(), errors.end(),
                              [](const sdf::Error& e) { return e.Code() == sdf::ErrorCode::LINK_INERTIA_INVALID; }),
               errors.end());
  if (!errors.empty()) {
    // An XML syntax error comes back without a line: tinyxml2 gives one.
    tinyxml2::XMLDocument doc;
    if (doc.LoadFile(path.c_str()) != tinyxml2::XML_SUCCESS) throw xml_parse_error(path, doc);
    throw_sdf_error(path, errors);
  }
  const sdf::Model& m = pick_model(path, root, d);
  check_model_elements(path, m, d);

  d.model = Model{};
  d.model.name = m.Name();
  d.robot_name = m.Name();
  d.base = BaseType::Fixed;
  std::vector<std::string> links;
  for (uint64_t i = 0; i < m.LinkCount(); ++i) {
    links.push_back(m.LinkByIndex(i)->Name());
    d.urdf_lines.link[links.back()] = line_of(m.LinkByIndex(i)->Element());
  }
  std::vector<GraphJoint> graph;
  for (uint64_t i = 0; i < m.JointCount(); ++i) {
    const sdf::Joint& j = *m.JointByIndex(i);
    d.urdf_lines.joint[j.Name()] = line_of(j.Element());
    std::string parent = j.ParentLinkName(), child = j.ChildLinkName();
    if (parent != "world" && j.ResolveParentLink(parent).size()) parent = j.ParentLinkName();
    if (j.ResolveChildLink(child).size()) child = j.ChildLinkName();
    for (const auto& [side, link] : {std::pair{"parent", parent}, std::pair{"child", child}})
      if (!(link == "world" && std::string(side) == "parent") && !m.LinkByName(link))
        throw LoadError(path, line_of(j.Element()), fmt::format("joint '{}'", j.Name()),
                        fmt::format("its {} '{}' is no link of model '{}'", side, link, m.Name()), "name a <link> of the model");
    graph.push_back({j.Name(), parent, child, j.Type() == sdf::JointType::BALL});
  }
  for (const std::string& name : closure_joints)
    if (!m.JointByName(name))
      throw LoadError(d.extras_file, 0, "closure_joints", fmt::format("names '{}', which is no joint of {}", name, path),
                      "name joints of the SDFormat file");
  const std::string root_link = find_root(path, m, graph);
  SpanningTree tree;
  try {
    tree = choose_spanning_tree(root_link, links, graph, {closure_joints.begin(), closure_joints.end()});
  } catch (const std::runtime_error& e) {
    throw LoadError(path, line_of(m.Element()), fmt::format("model '{}'", m.Name()), e.what(),
                    "check each joint's <parent> and <child> (the tree follows joints from parent to child), and the "
                    "extras' closure_joints");
  }

  Builder b{path, m, d, repair_inertia, {}, {}, {}};
  for (const std::string& name : links)
    b.X_ML[name] = resolve(path, m.LinkByName(name)->SemanticPose(), "__model__", fmt::format("link '{}'", name),
                           b.link_line(name));
  b.X_ML["world"] = SE3<double>::Identity();
  b.X_MB[kWorldBody] = SE3<double>::Identity();
  d.model.add_frame(Frame{"world", FrameKind::Body, kWorldBody, SE3<double>::Identity()});
  b.body_of["world"] = kWorldBody;
  if (root_link == "world") {
    if (base == BaseType::Floating) {
      // A floating base replaces the fixed joints from the world; moving ones would leave nothing free.
      for (int j : tree.tree) {
        if (graph[j].parent != "world") continue;
        if (m.JointByName(graph[j].name)->Type() != sdf::JointType::FIXED)
          throw LoadError(path, d.urdf_lines.line_of_joint(graph[j].name), fmt::format("joint '{}'", graph[j].name),
                          "hangs the robot from 'world' by a moving joint, and a floating base was asked for",
                          "load it with a fixed base (--fixed / `base: fixed`)");
      }
    }
    for (std::size_t k = 0; k < tree.tree.size(); ++k) {
      const GraphJoint& g = graph[static_cast<std::size_t>(tree.tree[k])];
      if (g.parent == "world" && base == BaseType::Floating) {
        Joint free;
        free.name = g.name;
        free.type = JointType::Floating;
        const BodyIndex body = d.model.add_body(kWorldBody, free, g.child, Inertia<double>{});
        b.X_MB[body] = b.X_ML.at(g.child);
        b.place_link(g.child, body, true);
        d.base = BaseType::Floating;
        d.warnings.push_back(fmt::format("floating base: fixed joint '{}' from 'world' replaced by a floating joint", g.name));
      } else if (tree.reversed[k]) {
        b.attach(*m.JointByName(g.name), g.child, g.parent, true);
      } else {
        b.attach(*m.JointByName(g.name), g.parent, g.child, false);
      }
    }
  } else {
    const bool floating = base ? *base == BaseType::Floating : !m.Static();
    if (floating) {
      Joint free;
      free.name = "root_joint";
      free.type = JointType::Floating;
      const BodyIndex body = d.model.add_body(kWorldBody, free, root_link, Inertia<double>{});
      b.X_MB[body] = b.X_ML.at(root_link);
      b.place_link(root_link, body, true);
      d.base = BaseType::Floating;
    } else {
      b.place_link(root_link, kWorldBody, false);
    }
    for (std::size_t k = 0; k < tree.tree.size(); ++k) {
      const GraphJoint& g = graph[static_cast<std::size_t>(tree.tree[k])];
      if (tree.reversed[k])
        b.attach(*m.JointByName(g.name), g.child, g.parent, true);
      else
        b.attach(*m.JointByName(g.name), g.parent, g.child, false);
    }
  }
  for (int j : tree.cut) {
    b.add_closure(*m.JointByName(graph[j].name), graph[j].parent, graph[j].child);
    d.notes.push_back(fmt::format("spanning tree: joint '{}' ({}) closes a loop between '{}' and '{}': a {} closure", graph[j].name,
                                  m.JointByName(graph[j].name)->Element()->Get<std::string>("type"), graph[j].parent,
                                  graph[j].child, d.closures.back().type));
  }
  // The model's <frame> elements, fixed in the link they are attached to.
  for (uint64_t i = 0; i < m.FrameCount(); ++i) {
    const sdf::Frame& f = *m.FrameByIndex(i);
    std::string link;
    if (!f.ResolveAttachedToBody(link).empty() || !b.body_of.count(link)) continue;
    const SE3<double> X_LF = resolve(path, f.SemanticPose(), link, fmt::format("frame '{}'", f.Name()), line_of(f.Element()));
    const BodyIndex body = b.body_of.at(link);
    b.add_frame(Frame{f.Name(), FrameKind::User, body, b.X_MB.at(body).inverse() * b.X_ML.at(link) * X_LF});
  }
  add_sdf_collisions(path, m, d);
}

}  // namespace mbgen::gen
