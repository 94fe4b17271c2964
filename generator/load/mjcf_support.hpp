#pragma once
// Shared by the MJCF reader's files (load_mjcf.cpp, mjcf_defaults.cpp, mjcf_orientation.cpp,
// mjcf_settings.cpp, mjcf_geoms.cpp, mjcf_equality.cpp): the compiler settings, attribute parsing
// with errors that name the file and line, and the class-resolved view of an element's attributes.
#include <tinyxml2.h>

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "load/description.hpp"

namespace mbgen::gen::mjcf {

/// `<compiler>` settings that change how numbers are read.
struct Compiler {
  bool degrees = true;          ///< MJCF's default angle unit is the degree
  std::string eulerseq = "xyz"; ///< lower case: rotating (intrinsic) axes; upper case: fixed (extrinsic)
  bool autolimits = true;       ///< a joint with a range but no `limited` is limited
  std::string meshdir;          ///< `meshdir`, else `assetdir`: where <mesh file> paths start (relative: from the file's folder)
};

/// `<default>` classes: per class, per element kind (joint, geom, site, ...), the attributes it sets,
/// already merged with those of its parent classes (mjcf_defaults.cpp).
class Defaults {
 public:
  /// Reads every `<default>` under `root` (the `<mujoco>` element). The top one is class "main".
  Defaults(const std::string& path, const tinyxml2::XMLElement* root);
  bool has_class(const std::string& name) const { return classes_.count(name) != 0; }
  /// The value class `cls` gives `attribute` of element kind `kind`, if any.
  std::optional<std::string> lookup(const std::string& cls, const std::string& kind, const std::string& attribute) const;

 private:
  std::map<std::string, std::map<std::string, std::map<std::string, std::string>>> classes_;
};

/// One element with its class resolved: attribute() returns the element's own value, else its
/// class's default. Every numeric reader throws a LoadError naming the element on bad text.
class Element {
 public:
  Element(const std::string& path, const tinyxml2::XMLElement* e, const Defaults& defaults, const std::string& cls)
      : path_(path), e_(e), defaults_(defaults), cls_(cls) {}
  const tinyxml2::XMLElement* xml() const { return e_; }
  int line() const { return e_->GetLineNum(); }
  std::string kind() const { return e_->Name(); }
  /// "joint 'knee'" or "<geom> (unnamed)": how messages name it.
  std::string describe() const;
  std::optional<std::string> attribute(const std::string& name) const;
  std::string string(const std::string& name, const std::string& fallback) const;
  /// Exactly `n` numbers (n > 0), or any count when n == 0.
  std::optional<std::vector<double>> numbers(const std::string& name, int n) const;
  double number(const std::string& name, double fallback) const;
  Vec3<double> vec3(const std::string& name, const Vec3<double>& fallback) const;
  [[noreturn]] void fail(const std::string& problem, const std::string& fix) const;

 private:
  const std::string& path_;
  const tinyxml2::XMLElement* e_;
  const Defaults& defaults_;
  std::string cls_;
};

// ---- mjcf_settings.cpp ----
/// <compiler> settings (errors for those that would change the inertias).
Compiler read_compiler(const std::string& path, const tinyxml2::XMLElement* root, const Defaults& defaults);
/// <option gravity> and <flag gravity="disable">; (0, 0, -9.81) by default.
Vec3<double> read_gravity(const std::string& path, const tinyxml2::XMLElement* root, const Defaults& defaults);
/// Fails on a top-level element that is neither read nor safely ignored (<tendon>, <include>, ...).
void check_top_level(const std::string& path, const tinyxml2::XMLElement* root);
/// LoadError "<element>: not supported: what" with a fix.
[[noreturn]] void not_supported(const std::string& path, const tinyxml2::XMLElement* e, const std::string& what,
                                const std::string& fix);
/// Fails on an attribute outside `known`: whatever mbgen does not read might change the dynamics.
void check_attributes(const Element& e, const std::set<std::string>& known);

/// Rotation given by whichever of quat, axisangle, euler, xyaxes, zaxis the element has (identity
/// if none; two of them is an error, as in MuJoCo). See mjcf_orientation.cpp.
Mat3<double> orientation(const Element& e, const Compiler& compiler);

/// Pose from `pos` and the orientation attributes.
SE3<double> pose(const Element& e, const Compiler& compiler);

/// Compiles every <frame> away, as MuJoCo does (mjcf_frames.cpp): its children move into the
/// enclosing body or <worldbody> with the frame's pose composed onto theirs and its childclass as
/// their class; a joint or inertial inside a frame is an error.
void dissolve_frames(const std::string& path, tinyxml2::XMLElement* root, const Defaults& defaults, const Compiler& compiler);

}  // namespace mbgen::gen::mjcf
