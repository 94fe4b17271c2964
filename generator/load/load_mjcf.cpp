// MJCF (MuJoCo XML) -> Description: the body tree becomes mbgen's spanning tree, with the same
// conventions as load_urdf.cpp (bodies welded to their parent are merged with their inertia
// lumped, and a Frame is kept for every MJCF body, joint and site).
//
// MuJoCo moves a body by its joints in order, each about its anchor `pos` in the body frame:
//   X_WB = X_WP X_PB  prod_k [T(p_k) R(a_k, q_k - ref_k) T(-p_k)]      (hinge; slide: T(a_k (q_k - ref_k)))
// mbgen's body frame is put at the (last) anchor, with the MJCF body's orientation, so the chain
// is exact: joint k has X_PJ = T(p_k - p_{k-1}) R(a_k, -ref_k) (the first one after X_PB), and the
// MJCF body frame sits at X_FB = T(-p_last) in it. mbgen's q therefore equals MuJoCo's qpos for
// hinges and slides (ref included), and the file's pose is MuJoCo's reference pose qpos0.
// Several joints in a body become a chain through massless bodies named "<body>/<joint>"; a ball
// becomes three hinges about the body's x, y, z axes ("<ball>_x", "_y", "_z").
#include <fmt/format.h>

#include <cctype>
#include <fstream>
#include <set>
#include <sstream>

#include "load/load_error.hpp"
#include "load/check_values.hpp"
#include "load/mjcf_tree.hpp"
#include "load/xml_error.hpp"

namespace mbgen::gen {

namespace mjcf {

Element Tree::element(const tinyxml2::XMLElement* e, int b) const {
  std::string cls = b >= 0 ? bodies[b].childclass : "main";
  if (const char* given = e->Attribute("class")) {
    cls = given;
    if (!defaults->has_class(cls))
      throw LoadError(path, e->GetLineNum(), Element(path, e, *defaults, "main").describe(),
                      fmt::format("uses class '{}', which no <default> defines", cls),
                      "define it with <default class=\"...\"> or correct the name");
  }
  return Element(path, e, *defaults, cls);
}

namespace {

constexpr double kPi = 3.14159265358979323846;

/// One mbgen joint of an MJCF joint (a ball gives three).
struct Elementary {
  std::string name;
  JointType type = JointType::Revolute;
  Vec3<double> axis = Vec3<double>::UnitZ();
  Vec3<double> anchor = Vec3<double>::Zero();  ///< in the MJCF body frame
  double ref = 0;
  bool bounded = false;
  double lower = 0, upper = 0, armature = 0, damping = 0, friction = 0;
  int line = 0;
};

struct Builder {
  Tree& tree;
  Description& d;
  std::optional<BaseType> base_override;
  int unnamed = 0;
  bool repair_inertia = false;

  const std::string& path() const { return tree.path; }

  Inertia<double> read_inertial(int b) {
    const tinyxml2::XMLElement* body = tree.bodies[b].xml;
    const tinyxml2::XMLElement* in = body->FirstChildElement("inertial");
    if (!in) {
      // MuJoCo would infer mass and inertia from the geoms (inertiafromgeom="auto"); mbgen does not.
      if (body->FirstChildElement("geom"))
        throw LoadError(path(), body->GetLineNum(), fmt::format("body '{}'", tree.bodies[b].name),
                        "has no <inertial>: MuJoCo would infer its mass and inertia from its geoms, mbgen does not",
                        "add an <inertial pos=\"...\" mass=\"...\" diaginertia=\"...\"/> to the body");
      return Inertia<double>{};  // no geom either: massless, as in MuJoCo
    }
    const Element x = tree.element(in, b);
    check_attributes(x, {"pos", "quat", "axisangle", "euler", "xyaxes", "zaxis", "mass", "diaginertia", "fullinertia"});
    const SE3<double> X_BI = pose(x, tree.compiler);
    if (!x.attribute("mass")) x.fail("has no mass", "give mass=\"...\" in kg");
    const auto diag = x.numbers("diaginertia", 3);
    const auto full = x.numbers("fullinertia", 6);
    if (diag.has_value() == full.has_value())
      x.fail("needs exactly one of diaginertia and fullinertia", "give diaginertia=\"ixx iyy izz\" or fullinertia=\"ixx iyy izz ixy ixz iyz\"");
    Mat3<double> I;
    if (diag) {
      I = Vec3<double>((*diag)[0], (*diag)[1], (*diag)[2]).asDiagonal();
    } else {
      if (X_BI.rotation != Mat3<double>::Identity())
        x.fail("gives fullinertia together with an orientation", "give fullinertia in the body frame, without quat/euler");
      const auto& f = *full;  // MJCF order: ixx iyy izz ixy ixz iyz
      I << f[0], f[3], f[4], f[3], f[1], f[5], f[4], f[5], f[2];
    }
    Inertia<double> inertia;
    inertia.mass = x.number("mass", 0);
    ValueReport report{d.warnings, d.notes, repair_inertia};
    I = check_link_inertia(path(), in->GetLineNum(), tree.bodies[b].name, inertia.mass, I, report);
    inertia.com = X_BI.translation;
    inertia.inertia_com = X_BI.rotation * I * X_BI.rotation.transpose();
    return inertia;
  }

  /// The joint's name (unnamed ones, which MuJoCo allows, get "<body>_joint<n>"); unique.
  std::string joint_name(const Element& x, int b, const char* fallback_kind) {
    std::string name;
    if (const char* given = x.xml()->Attribute("name")) {
      name = given;
    } else {
      ++unnamed;
      name = fmt::format("{}_{}{}", tree.bodies[b].name, fallback_kind, unnamed);
    }
    if (tree.joints.count(name)) x.fail("the joint name is used twice", "give every joint a unique name");
    return name;
  }

  /// The joints of body b in document order, expanded to mbgen's 1-DoF joints; `free` is set
  /// instead when the body has a free joint.
  std::vector<Elementary> read_joints(int b, std::optional<std::string>& free, int& free_line) {
    std::vector<Elementary> out;
    const tinyxml2::XMLElement* body = tree.bodies[b].xml;
    for (const tinyxml2::XMLElement* e = body->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string kind = e->Name();
      if (kind != "joint" && kind != "freejoint") continue;
      const Element x = tree.element(e, b);
      const std::string type = kind == "freejoint" ? "free" : x.string("type", "hinge");
      if (type == "free") {
        if (kind == "freejoint") check_attributes(x, {"name", "group", "align"});
        const std::string name = e->Attribute("name") ? joint_name(x, b, "free") : "root_joint";
        if (tree.bodies[b].parent != 0)
          x.fail(fmt::format("a free joint in body '{}', which is not a child of <worldbody>", tree.bodies[b].name),
                 "give free joints only to bodies directly under <worldbody> (a floating base)");
        free = name;
        free_line = e->GetLineNum();
        tree.qpos_layout.push_back({name, "free"});
        tree.joints[name] = {};
        d.urdf_lines.joint[name] = e->GetLineNum();
        continue;
      }
      check_attributes(x, {"name", "class", "type", "group", "pos", "axis", "springdamper", "limited", "solreflimit",
                           "solimplimit", "solreffriction", "solimpfriction", "stiffness", "range", "margin", "ref",
                           "springref", "armature", "damping", "frictionloss", "user", "actuatorfrclimited",
                           "actuatorfrcrange"});
      const std::string name = joint_name(x, b, "joint");
      Elementary j;
      j.line = e->GetLineNum();
      j.anchor = x.vec3("pos", Vec3<double>::Zero());
      j.armature = x.number("armature", 0);
      j.damping = x.number("damping", 0);
      j.friction = x.number("frictionloss", 0);
      if (x.number("stiffness", 0) != 0)
        d.warnings.push_back(fmt::format("joint '{}' has stiffness {}: the spring is a passive force mbgen does not "
                                         "model; add it to the joint torque",
                                         name, x.number("stiffness", 0)));
      const double unit = tree.compiler.degrees && type != "slide" ? kPi / 180.0 : 1.0;
      const auto range = x.numbers("range", 2);
      const std::string limited = x.string("limited", "auto");
      if (limited != "true" && limited != "false" && limited != "auto")
        x.fail(fmt::format("limited=\"{}\"", limited), "use limited=\"true\", \"false\" or \"auto\"");
      const bool is_limited = limited == "true" || (limited == "auto" && tree.compiler.autolimits && range);
      if (limited == "true" && !range) x.fail("is limited but has no range", "give range=\"lower upper\"");
      if (type == "ball") {
        if (is_limited)
          d.warnings.push_back(fmt::format("ball joint '{}': its cone limit is not modelled", name));
        std::vector<std::string> parts;
        for (int k = 0; k < 3; ++k) {
          Elementary axis_joint = j;
          axis_joint.name = fmt::format("{}_{}", name, "xyz"[k]);
          axis_joint.axis = Vec3<double>::Unit(k);
          axis_joint.armature = j.armature;
          out.push_back(axis_joint);
          parts.push_back(axis_joint.name);
          d.urdf_lines.joint[axis_joint.name] = j.line;
        }
        tree.joints[name] = parts;
        tree.qpos_layout.push_back({name, "ball"});
        continue;
      }
      if (type != "hinge" && type != "slide")
        x.fail(fmt::format("joint type '{}' is unknown", type), "use type=\"hinge\", \"slide\", \"ball\" or \"free\"");
      j.name = name;
      j.type = type == "hinge" ? JointType::Revolute : JointType::Prismatic;
      const Vec3<double> axis = x.vec3("axis", Vec3<double>::UnitZ());
      if (axis.norm() < 1e-12) x.fail("axis is zero", "give a non-zero axis, e.g. axis=\"0 0 1\"");
      j.axis = axis.normalized();
      j.ref = x.number("ref", 0) * unit;
      if (is_limited) {
        j.bounded = true;
        j.lower = (*range)[0] * unit;
        j.upper = (*range)[1] * unit;
        check_joint_limits(path(), j.line, name, j.lower, j.upper);
      }
      out.push_back(j);
      tree.joints[name] = {name};
      tree.qpos_layout.push_back({name, type, j.ref});
      d.urdf_lines.joint[name] = j.line;
    }
    return out;
  }

  void add_frame(const std::string& name, FrameKind kind, BodyIndex body, const SE3<double>& X) {
    if (d.model.find_frame(name)) return;  // MJCF names bodies, joints and sites apart; the first one keeps the name
    d.model.add_frame(Frame{name, kind, body, X});
  }

  /// Body b and its subtree; its parent MJCF frame sits at X_FP in mbgen body `parent`.
  void attach(int b, BodyIndex parent, const SE3<double>& X_FP) {
    TreeBody& tb = tree.bodies[b];
    const tinyxml2::XMLElement* body = tb.xml;
    const Element x = tree.element(body, b);
    check_attributes(x, {"name", "childclass", "pos", "quat", "axisangle", "euler", "xyaxes", "zaxis", "user", "gravcomp", "mocap"});
    if (x.string("mocap", "false") == "true") x.fail("not supported: a mocap body", "make it a body welded to the world");
    if (x.number("gravcomp", 0) != 0) x.fail("not supported: gravcomp", "remove gravcomp (it changes the gravity forces)");
    const SE3<double> X_PB = pose(x, tree.compiler);
    tb.X_WB0 = tree.bodies[tb.parent].X_WB0 * X_PB;
    d.urdf_lines.link[tb.name] = body->GetLineNum();
    for (const tinyxml2::XMLElement* e = body->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string kind = e->Name();
      static const std::set<std::string> known = {"inertial", "joint", "freejoint", "geom", "site", "camera", "light", "body"};
      if (!known.count(kind))
        not_supported(path(), e, fmt::format("<{}> inside a body", kind), "remove it or expand it by hand");
    }
    const Inertia<double> I_B = read_inertial(b);
    std::optional<std::string> free;
    int free_line = 0;
    std::vector<Elementary> joints = read_joints(b, free, free_line);
    if (free && !joints.empty())
      x.fail("has a free joint and other joints", "a floating body has its free joint only");
    if (free && base_override == BaseType::Fixed) {
      d.warnings.push_back(fmt::format("fixed base: free joint '{}' of body '{}' removed (the body is welded to the world)", *free, tb.name));
      tree.joints.erase(*free);
      free.reset();
    }
    if (!free && joints.empty() && parent == kWorldBody && tb.parent == 0 && base_override == BaseType::Floating) {
      if (d.model.find_joint("root_joint"))
        x.fail("a floating base was asked for, and a second body welded to the world would float too",
               "give the free joint in the file, or load it with a fixed base");
      free = "root_joint";
      d.warnings.push_back(fmt::format("floating base: body '{}', welded to the world, gets a free joint 'root_joint'", tb.name));
    }
    BodyIndex me = parent;
    SE3<double> X_FB = X_FP * X_PB;
    std::vector<BodyIndex> joint_bodies;  // the mbgen body each joint moves; its frame is at the anchor
    if (free) {
      Joint j;
      j.name = *free;
      j.type = JointType::Floating;
      me = d.model.add_body(kWorldBody, j, tb.name, I_B);  // q = the body's world pose; file pose = qpos0
      X_FB = SE3<double>::Identity();
      d.base = BaseType::Floating;
    } else if (!joints.empty()) {
      SE3<double> X = X_FP * X_PB;  // pose of the current MJCF-oriented frame in `me`
      Vec3<double> previous = Vec3<double>::Zero();
      for (std::size_t k = 0; k < joints.size(); ++k) {
        const Elementary& e = joints[k];
        Joint j;
        j.name = e.name;
        j.type = e.type;
        j.axis = e.axis;
        SE3<double> T;
        T.translation = e.anchor - previous;
        SE3<double> R;  // the reference pose is q = ref: q = 0 lies -ref away
        if (e.type == JointType::Revolute)
          R.rotation = Eigen::AngleAxisd(-e.ref, e.axis).toRotationMatrix();
        else
          R.translation = -e.ref * e.axis;
        j.X_PJ = X * T * R;
        j.bounded = e.bounded;
        j.lower = e.lower;
        j.upper = e.upper;
        j.armature = e.armature;
        j.damping = e.damping;
        j.friction = e.friction;
        const bool last = k + 1 == joints.size();
        me = d.model.add_body(me, j, last ? tb.name : fmt::format("{}/{}", tb.name, e.name), Inertia<double>{});
        joint_bodies.push_back(me);
        X = SE3<double>::Identity();
        previous = e.anchor;
      }
      X_FB = SE3<double>::Identity();
      X_FB.translation = -previous;
      d.model.mutable_body(me).inertia = I_B.transformed(X_FB);
    } else if (me != kWorldBody) {
      Body& merged = d.model.mutable_body(me);
      merged.inertia = merged.inertia + I_B.transformed(X_FB);
    }
    tb.body = me;
    tb.X_FB = X_FB;
    const bool moving = free || !joints.empty();
    tb.frame = d.model.add_frame(Frame{tb.name, moving ? FrameKind::Body : FrameKind::Link, me, X_FB});
    // A joint's frame is fixed in the body it moves (at its anchor, so the identity there), as a
    // URDF joint frame is fixed in its child link.
    for (std::size_t k = 0; k < joints.size(); ++k) add_frame(joints[k].name, FrameKind::Joint, joint_bodies[k], SE3<double>::Identity());
    add_sites(b);
    for (const tinyxml2::XMLElement* c = body->FirstChildElement("body"); c; c = c->NextSiblingElement("body"))
      attach(add_tree_body(c, b), me, X_FB);
  }

  void add_sites(int b) {
    const TreeBody& tb = tree.bodies[b];
    for (const tinyxml2::XMLElement* e = tb.xml->FirstChildElement("site"); e; e = e->NextSiblingElement("site")) {
      const char* name = e->Attribute("name");
      if (!name) continue;
      const Element x = tree.element(e, b);
      Site s{b, pose(x, tree.compiler), FrameIndex()};
      if (d.model.find_frame(name))
        d.warnings.push_back(fmt::format("site '{}' has the name of another frame: no frame is kept for it", name));
      else
        s.frame = d.model.add_frame(Frame{name, FrameKind::User, tb.body, tb.X_FB * s.X_BS});
      tree.sites[name] = s;
    }
  }

  int add_tree_body(const tinyxml2::XMLElement* e, int parent) {
    TreeBody tb;
    tb.xml = e;
    tb.parent = parent;
    const char* name = e->Attribute("name");
    tb.name = name ? name : fmt::format("body{}", tree.bodies.size());
    if (tree.body_index.count(tb.name))
      throw LoadError(path(), e->GetLineNum(), fmt::format("body '{}'", tb.name), "the name is used twice",
                      "give every body a unique name");
    const char* childclass = e->Attribute("childclass");
    tb.childclass = childclass ? childclass : tree.bodies[parent].childclass;
    if (!tree.defaults->has_class(tb.childclass))
      throw LoadError(path(), e->GetLineNum(), fmt::format("body '{}'", tb.name),
                      fmt::format("uses childclass '{}', which no <default> defines", tb.childclass),
                      "define it with <default class=\"...\"> or correct the name");
    tree.body_index[tb.name] = tree.bodies.size();
    tree.bodies.push_back(tb);
    return tree.bodies.size() - 1;
  }
};

}  // namespace
}  // namespace mjcf

void load_mjcf(const std::string& path, std::optional<BaseType> base, Description& d, bool repair_inertia) {
  std::ifstream in(path);
  if (!in) throw LoadError(path, 0, "", "cannot open the file", "check the path and the file's permissions");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  tinyxml2::XMLDocument doc;
  if (doc.Parse(text.c_str(), text.size()) != tinyxml2::XML_SUCCESS)
    throw xml_parse_error(path, doc);
  tinyxml2::XMLElement* root = doc.FirstChildElement("mujoco");
  if (!root) {
    const tinyxml2::XMLElement* r = doc.RootElement();
    throw LoadError(path, r ? r->GetLineNum() : 1, "",
                    fmt::format("not an MJCF file: the root element is <{}>, not <mujoco>", r ? r->Name() : ""),
                    "give a MuJoCo XML file (one <mujoco model=...> element), or a URDF with the .urdf extension");
  }
  mjcf::check_top_level(path, root);
  const mjcf::Defaults defaults(path, root);
  mjcf::Tree tree;
  tree.path = path;
  tree.root = root;
  tree.defaults = &defaults;
  tree.compiler = mjcf::read_compiler(path, root, defaults);
  mjcf::dissolve_frames(path, root, defaults, tree.compiler);

  d.model = Model{};
  d.model.name = root->Attribute("model") ? root->Attribute("model") : "mujoco_model";
  d.model.gravity = mjcf::read_gravity(path, root, defaults);
  d.base = BaseType::Fixed;

  mjcf::TreeBody world;
  world.name = "world";
  world.xml = root->FirstChildElement("worldbody");
  world.childclass = "main";
  world.body = kWorldBody;
  tree.bodies.push_back(world);
  tree.body_index["world"] = 0;
  tree.bodies[0].frame = d.model.add_frame(Frame{"world", FrameKind::Body, kWorldBody, SE3<double>::Identity()});
  mjcf::Builder builder{tree, d, base, 0, repair_inertia};
  if (world.xml) {
    for (const tinyxml2::XMLElement* e = world.xml->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const std::string kind = e->Name();
      if (kind == "joint" || kind == "freejoint" || kind == "inertial")
        mjcf::not_supported(path, e, fmt::format("<{}> directly in <worldbody>", kind), "put it inside a <body>");
      if (kind != "body" && kind != "geom" && kind != "site" && kind != "camera" && kind != "light")
        mjcf::not_supported(path, e, fmt::format("<{}> inside <worldbody>", kind), "remove it or expand it by hand");
    }
    builder.add_sites(0);
    for (const tinyxml2::XMLElement* c = world.xml->FirstChildElement("body"); c; c = c->NextSiblingElement("body"))
      builder.attach(builder.add_tree_body(c, 0), kWorldBody, SE3<double>::Identity());
  }
  d.robot_name = d.model.name;
  mjcf::add_mjcf_geoms(tree, d);
  mjcf::add_mjcf_equalities(tree, d);
  mjcf::add_mjcf_actuators(tree, d);
  mjcf::read_mjcf_keyframe(tree, d);
}

}  // namespace mbgen::gen
