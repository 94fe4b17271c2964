#pragma once
// Description: everything the loader read about a robot: the tree Model, plus what URDF cannot
// say (closures, actuated joints, drives) from the YAML extras, and the warnings raised.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "load/check_values.hpp"
#include "mbgen/model.hpp"
#include "mbgen/contact_model.hpp"
#include "mbgen/joint_limits.hpp"

namespace mbgen::gen {

enum class BaseType { Fixed, Floating };

/// A loop closure as given by the user (loop detection and sub-systems come later).
struct ClosureSpec {
  std::string name;
  std::string type;     ///< revolute, spherical, universal, weld, prismatic (extras) or 6d / 3d (robot.yaml)
  std::string frame_a;  ///< frame (link, joint or user frame) on one side
  std::string frame_b;  ///< frame on the other side
  SE3<double> X_AC;     ///< closure frame in frame_a (identity unless the extras give an origin)
  SE3<double> X_BC;     ///< closure frame in frame_b
  Vec3<double> axis = Vec3<double>::UnitZ();  ///< closure joint axis in the closure frame, where it has one
  /// type "coupling": frame_a names the leader joint, frame_b the follower, and
  /// q_follower = ratio q_leader + offset (URDF <mimic>, MJCF joint equalities and fixed tendons).
  double ratio = 1.0, offset = 0.0;
  std::string source;   ///< file and line it came from
  int source_line = 0;  ///< the line alone (1-based; 0 when unknown), for error messages
  /// The model frames the two names resolve to (a moving joint's name resolves to its child
  /// body's frame). Filled by the loader; invalid only while loading.
  FrameIndex resolved_a, resolved_b;
};

/// A harmonic-drive (or other geared) actuator on a joint.
struct DriveSpec {
  std::string joint;
  double gear_ratio = 1.0;
  double rotor_inertia = 0.0;  ///< rotor inertia about its spin axis, kg m^2
  std::string model = "armature";  ///< armature (reflected inertia) or body (rotor body with gyroscopic terms)
};

/// One swept-sphere-volume primitive fixed in a link: a point (sphere), a line (capsule) or a
/// triangle, swept by a sphere of `radius`. Points are in the link's frame.
struct SsvPrimitive {
  enum class Kind { Point, Line, Triangle };
  Kind kind = Kind::Point;
  std::vector<Vec3<double>> points;  ///< 1, 2 or 3 points
  double radius = 0.0;
  std::string source;  ///< where it was given: the extras' file:line, or the URDF <collision> it models
};

/// A mesh or box that a URDF link's <collision> elements give (its <visual> ones when it has no
/// <collision> at all): what `fit-ssv` and `scene: collision: fit` enclose in SSVs.
struct MeshGeometry {
  std::string reference;  ///< the <mesh filename> as written (package://, file:// or a path); empty for a box
  bool box = false;
  Vec3<double> scale = Vec3<double>::Ones();  ///< the mesh's scale; for a box, its size
  SE3<double> X_LG;       ///< the geometry's frame in the link's (its <origin>)
  std::string source;     ///< file:line and element, for warnings
};

/// One contact of `scene: rigid_contacts`: a frame held rigidly (kind `frame`: 6 rows, a flat foot)
/// or its origin held (kind `point`: 3 rows), for rigid_contact_fd_derivatives
/// (mbgen/algorithm/rigid_contact_dynamics.hpp).
struct RigidContactSpec {
  std::string frame;
  std::string kind = "frame";  ///< frame or point
  int line = 0;                ///< the extras file's line, for errors
  /// The rows the contact holds (RigidContact::rows of the runtime).
  int rows() const { return kind == "point" ? 3 : 6; }
};

/// The ground contact a simulation of the scene uses (`scene: contact`, docs/extras.md): which
/// links touch the ground (the vertex spheres of their SSVs, sim/contact.hpp), the compliant
/// law's parameters and the ground plane.
struct ContactSpec {
  std::vector<std::string> links;
  ContactParameters parameters;
  GroundPlane ground;
};

/// What the generated code must provide (`scene:` of the extras). Kept as given; later issues
/// (planning, collision) interpret it.
struct SceneSpec {
  /// forward_dynamics, mass_matrix, ..., in the order given. Checked against the generator's
  /// catalogue (codegen/function_catalog.hpp) when a generation or `inspect` selects functions:
  /// the loader knows no list of its own.
  std::vector<std::string> outputs;
  std::vector<int> output_lines;            ///< the extras file's line of each output (0: unknown)
  std::vector<std::string> jacobian_frames; ///< from `jacobians: [frame, ...]`
  /// `derivatives_wrt: [q, v, tau]`: the inputs the derivative outputs are taken with respect to
  /// (the others' blocks are left out); empty: not given (all three).
  std::vector<std::string> derivatives_wrt;
  /// `rigid_contacts: [{frame: l_sole, kind: frame}, ...]`: the contacts rigid_contact_fd_derivatives
  /// holds, in the order given (their rows in that order).
  std::vector<RigidContactSpec> rigid_contacts;
  double collision_margin = 0.0;
  std::vector<std::pair<std::string, std::string>> collision_exclude, collision_include;
  int prune_samples = 0;                    ///< 0: not given
  bool collision_fit = false;               ///< `fit: true`: SSVs fitted to the links' meshes when loading
  int collision_fit_budget = 0;             ///< `fit_budget:` primitives per link; 0: not given (mesh::FitOptions' default)
  std::string scalar;                       ///< double or float; empty: not given (then both are emitted)
  std::string rotors;                       ///< armature or body: overrides every drive's model; none: no rotor modelled; empty: each drive's own
  std::optional<ContactSpec> contact;       ///< `contact:`; absent: the robot touches nothing
  /// `joint_limits:` the end stops of a simulation of the scene (false: none); absent: the defaults
  JointStopParameters joint_limits;
  /// Model reductions (docs/extras.md, "Model reductions"; model/reduce_model.hpp):
  /// `lock:` welds these joints at these values (rad or m), in the order given;
  std::vector<std::pair<std::string, double>> lock;
  int lock_line = 0;                        ///< the `lock:` line of the extras, for errors
  /// `merge_below:` lumps every limb lighter than this (kg) into its parent; 0: none.
  double merge_below = 0;
  /// `loops:` exact (default, empty) or transmission: each sub-system replaced by the kinematic
  /// map from its actuators to its output joints, the linkage's bodies lumped into their parents.
  std::string loops;
  int loops_line = 0;                       ///< the `loops:` line of the extras, for errors
};

/// Where each URDF element starts (1-based lines), so that later checks can point at it. For an
/// MJCF file, `link` holds the <body> lines and `joint` the <joint> lines (a ball's three hinges
/// share their ball's line).
struct SourceLines {
  std::map<std::string, int> link, joint;
  int line_of_link(const std::string& name) const {
    auto it = link.find(name);
    return it == link.end() ? 0 : it->second;
  }
  int line_of_joint(const std::string& name) const {
    auto it = joint.find(name);
    return it == joint.end() ? 0 : it->second;
  }
};

/// What assembly found (topology.hpp): the closed pose nearest the starting pose (the zero pose,
/// or the description's assembly_seed) that is well conditioned, within the joint ranges where
/// one of the poses tried is, and how far it is from the starting pose.
struct AssemblyReport {
  VecX<double> q;                  ///< assembled configuration (nq); empty without closures
  double max_joint_change = 0;     ///< max |q - q0| over the 1-DoF joints (rad or m), q0 the starting pose
  std::string max_change_joint;    ///< the joint that moved most
  double residual = 0;             ///< max |Phi| at q
  double sigma_min = 0;            ///< smallest kept singular value of Phi_q at q
  double sigma_max = 0;            ///< largest singular value of Phi_q at q
  double dependent_conditioning = 0;  ///< worst 1 / condition number of the sub-systems' Phi_z at q
  int seeds = 0;                   ///< starting points tried (1: the zero pose, or the seed, sufficed)
  int outside_ranges = 0;          ///< joints outside their ranges in the pose kept
  int iterations = 0;              ///< Levenberg-Marquardt iterations, all seeds
};

/// A linkage that `scene: loops: transmission` replaced (model/reduce_model.hpp): its actuators
/// drive its output joints through the kinematic map of its loops.
struct TransmissionSpec {
  std::vector<std::string> closures;   ///< the loops it replaced
  std::vector<std::string> actuators;  ///< the sub-system's independent joints, gone from the reduced model
  std::vector<std::string> outputs;    ///< the joints they drive, kept in the reduced tree (as many)
  std::vector<std::string> linkage;    ///< bodies on the actuators' side of the loops, lumped into their parents
};

struct Description {
  Model model;
  std::string description_file;       ///< as given on the command line
  std::string extras_file;            ///< empty when there is none
  BaseType base = BaseType::Fixed;
  std::vector<ClosureSpec> closures;
  std::vector<std::string> actuated_joints;  ///< name_mot of robot.yaml, or `independent` hints
  std::vector<DriveSpec> drives;
  std::vector<std::string> warnings;
  /// Values the loader changed that were not wrong enough to refuse: inertia round-off treated as
  /// zero, inertias repaired on request (LoadOptions::repair_inertia). `inspect` prints them.
  std::vector<std::string> notes;
  /// What the scene's model reductions removed (reduce_model.hpp), one line each; `inspect` prints them.
  std::vector<std::string> reductions;
  /// `loops: transmission`: the linkages replaced, and the whole robot with its loops whose
  /// sub-systems have the outputs as independent coordinates, so that closure_positions maps
  /// outputs to actuators and velocity_map's actuator rows are the map's Jacobian (the force
  /// transmission: tau_outputs = J^T f_actuators). Empty without transmissions.
  std::vector<TransmissionSpec> transmissions;
  std::optional<Model> transmission_model;

  // Added with the YAML extras (issue 2, items 2 and 4).
  std::string robot_name;  ///< `robot:` of the extras (namespace of generated code); else the URDF's name
  /// joint_name / joint_type of a parallel_legs robot.yaml: URDF revolute joints that stand for
  /// another joint (SPHERICAL, UJOINT_XY). The loader replaces each by a chain of revolute
  /// joints `<joint>_x`, `<joint>_y`(, `<joint>_z`) (topology.hpp).
  std::map<std::string, std::string> joint_type_overrides;
  /// Loops (topology.hpp): model.closures and model.subsystems are filled from `closures`
  /// after an assembly; these say how the pose was found.
  AssemblyReport assembly;
  /// Where the assembly starts (joint name -> value, rad or m): an MJCF file's first <key qpos>
  /// (mjcf_keyframe.cpp); joints not named start at 0. assembly_seed_source says where it came from.
  std::map<std::string, double> assembly_seed;
  std::string assembly_seed_source;
  int closed_dof = 0;  ///< DoF of the closed system: nv - total rank of the closure rows
  std::map<std::string, std::vector<SsvPrimitive>> ssv;  ///< link name -> compound (extras, else URDF spheres/cylinders)
  std::map<std::string, int> collision_geometry_not_modelled;  ///< URDF <collision> kinds with no SSV (box, mesh) -> count
  /// Each link's meshes and boxes (URDF), for SSV fitting (load/fit_link_ssvs.hpp); link name ->
  /// geometry in document order.
  std::map<std::string, std::vector<MeshGeometry>> link_meshes;
  std::set<std::string> ssv_from_extras;  ///< links whose compound the extras' `ssv:` gives (never refitted)
  std::optional<SceneSpec> scene;
  SourceLines urdf_lines;  ///< lines of the URDF's <link> and <joint> elements
};

struct LoadOptions {
  std::optional<std::string> extras_file;  ///< YAML extras; if absent, a robot.yaml beside the URDF is used
  std::optional<BaseType> base;            ///< overrides the extras' `base`
  bool pick_up_robot_yaml = true;
  /// Replace inertias that no rigid body has by the nearest valid ones, with a note each
  /// (ValueReport::repair_inertia; `--repair-inertia`), instead of refusing them.
  bool repair_inertia = false;
  /// Apply the scene's model reductions (`lock`, `merge_below`; model/reduce_model.hpp). Off: the
  /// whole robot, as `inspect` loads it to compare.
  bool reduce = true;
  /// `package://NAME` -> DIR for mesh references (`--package-path NAME=DIR`); ROS_PACKAGE_PATH after these.
  std::map<std::string, std::string> package_paths;
  /// Fit SSVs to the meshes when the scene says `collision: fit: true`. `fit-ssv` turns it off
  /// and fits with its own budget.
  bool apply_scene_fit = true;
  /// URDF <mimic>: true couples the joints (coupling closures, urdf_mimic.cpp), false loads the
  /// mimicking joint as an independent one (a warning each), as Pinocchio's buildModel and
  /// MuJoCo's URDF import do by default; unset: the extras' `mimic:` (couple | independent),
  /// else independent. `--mimic` on the command line.
  std::optional<bool> couple_mimics;
};

/// Reads a URDF or, for a .xml file, an MJCF, for a .sdf file an SDFormat model (and extras) as written: parsed, each value checked
/// (check_values.hpp), the extras applied, parallel_legs joint types turned into chains. Throws
/// LoadError with file, line, element and fix on bad input. Not yet validated as a whole nor
/// assembled: model/load_description.hpp does both.
Description read_description(const std::string& path, const LoadOptions& options = {});

/// Reads an MJCF (MuJoCo XML) file into `d` (load_mjcf.cpp, docs/mjcf.md): the tree model, base,
/// closures from <equality>, actuated joints from <actuator>, SSVs from collision geoms, and the
/// lines of <body> (as urdf_lines.link) and <joint> elements. The file's free joint decides the
/// base unless `base` overrides it (fixed: the free body is welded where the file puts it;
/// floating: a body welded to the world gets a free joint 'root_joint').
void load_mjcf(const std::string& path, std::optional<BaseType> base, Description& d, bool repair_inertia = false);

/// The formats read_description reads, told apart by the file's extension (any case): .xml is
/// MJCF, .sdf and .world are SDFormat, anything else is read as URDF.
enum class DescriptionFormat { Urdf, Mjcf, Sdf };
DescriptionFormat description_format(const std::string& path);

/// Reads an SDFormat file (.sdf, .world) into `d` through libsdformat (load_sdf.cpp,
/// docs/sdf.md): links, joints, limits, damping, collision geometry, the model's <frame>s, and,
/// when the joints form a graph rather than a tree, a spanning tree whose left-out joints become
/// closures (`closure_joints` names joints to leave out; sdf_spanning_tree.hpp gives the rule).
/// The root link floats unless the model is <static>, hangs from "world" by a fixed joint, or
/// `base` says fixed.
void load_sdf(const std::string& path, std::optional<BaseType> base, const std::vector<std::string>& closure_joints,
              Description& d, bool repair_inertia = false);

/// Adds SSV compounds for the URDF's sphere and cylinder collision geometry (collision_ssv.cpp).
void add_collision_ssvs(const std::string& path, Description& d);
/// The frame of the body that the moving joint `joint` moves (a coupling's side); invalid when
/// there is no such joint.
FrameIndex moved_body_frame(const Model& model, const std::string& joint);
/// The URDF's <mimic> elements as coupling closures (urdf_mimic.cpp), in document order; with
/// `couple` false, a warning each that the joint is loaded as an independent one.
void add_urdf_mimics(const std::string& path, Description& d, bool couple);

/// Builds the tree Model from a URDF file alone (fixed joints merged). Warnings are appended.
Model load_urdf_model(const std::string& path, BaseType base, std::vector<std::string>& warnings);
/// The same, also reporting where each <link> and <joint> element starts. Fixed rotations (joint
/// and inertial origins) within `quarter_turn_tolerance` of a rotation by quarter turns become it
/// exactly (the extras' `snap_quarter_turns`; 0: only entries within 1e-14 of 0 or +-1 are snapped).
Model load_urdf_model(const std::string& path, BaseType base, ValueReport& report, SourceLines* lines,
                      double quarter_turn_tolerance = 0);

}  // namespace mbgen::gen
