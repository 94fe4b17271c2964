// MJCF orientation attributes -> rotation matrix, as MuJoCo's compiler reads them:
//   quat="w x y z"          scalar FIRST (unlike mbgen's q, which stores x y z w), normalised;
//   axisangle="x y z a"     a in the compiler's angle unit, axis normalised;
//   euler="a b c"           three rotations about the axes named by <compiler eulerseq>: a lower-case
//                           letter rotates about the moving (already rotated) axis, so it multiplies
//                           on the right; an upper-case letter about the fixed axis, on the left;
//   xyaxes="x1 x2 x3 y1 y2 y3"  x normalised, y made orthogonal to x, z = x cross y;
//   zaxis="x y z"           the shortest rotation taking (0, 0, 1) to the given axis.
#include <Eigen/Geometry>
#include <fmt/format.h>

#include <cctype>
#include <cmath>

#include "load/mjcf_support.hpp"

namespace mbgen::gen::mjcf {

namespace {

constexpr double kPi = 3.14159265358979323846;

double angle(double value, const Compiler& compiler) { return compiler.degrees ? value * kPi / 180.0 : value; }

Mat3<double> from_quat(const Element& e, const std::vector<double>& q) {
  Eigen::Quaterniond quat(q[0], q[1], q[2], q[3]);
  if (quat.norm() < 1e-12) e.fail("quat is zero", "give a unit quaternion in MuJoCo's order w x y z, e.g. quat=\"1 0 0 0\"");
  return quat.normalized().toRotationMatrix();
}

Mat3<double> from_axisangle(const Element& e, const std::vector<double>& v, const Compiler& compiler) {
  const Vec3<double> axis(v[0], v[1], v[2]);
  if (axis.norm() < 1e-12) e.fail("axisangle has a zero axis", "give a non-zero axis, e.g. axisangle=\"0 0 1 90\"");
  return Eigen::AngleAxisd(angle(v[3], compiler), axis.normalized()).toRotationMatrix();
}

Mat3<double> from_euler(const Element& e, const std::vector<double>& v, const Compiler& compiler) {
  Mat3<double> R = Mat3<double>::Identity();
  for (int i = 0; i < 3; ++i) {
    const char c = compiler.eulerseq[i];
    Vec3<double> axis = Vec3<double>::Zero();
    axis[std::tolower(static_cast<unsigned char>(c)) - 'x'] = 1.0;
    const Mat3<double> step = Eigen::AngleAxisd(angle(v[i], compiler), axis).toRotationMatrix();
    R = std::islower(static_cast<unsigned char>(c)) ? Mat3<double>(R * step) : Mat3<double>(step * R);
  }
  (void)e;
  return R;
}

Mat3<double> from_xyaxes(const Element& e, const std::vector<double>& v) {
  Vec3<double> x(v[0], v[1], v[2]), y(v[3], v[4], v[5]);
  if (x.norm() < 1e-12) e.fail("xyaxes has a zero x axis", "give two non-parallel axes, e.g. xyaxes=\"1 0 0 0 1 0\"");
  x.normalize();
  y -= x * x.dot(y);
  if (y.norm() < 1e-12) e.fail("xyaxes gives parallel x and y axes", "give two non-parallel axes, e.g. xyaxes=\"1 0 0 0 1 0\"");
  y.normalize();
  Mat3<double> R;
  R.col(0) = x;
  R.col(1) = y;
  R.col(2) = x.cross(y);
  return R;
}

Mat3<double> from_zaxis(const Element& e, const std::vector<double>& v) {
  Vec3<double> z(v[0], v[1], v[2]);
  if (z.norm() < 1e-12) e.fail("zaxis is zero", "give a non-zero axis, e.g. zaxis=\"0 0 1\"");
  z.normalize();
  const Vec3<double> axis = Vec3<double>::UnitZ().cross(z);
  const double s = axis.norm();
  if (s < 1e-12)  // parallel: identity, or a half turn about x when z points down (MuJoCo's choice)
    return z.z() > 0 ? Mat3<double>::Identity() : Mat3<double>(Eigen::AngleAxisd(kPi, Vec3<double>::UnitX()));
  return Eigen::AngleAxisd(std::atan2(s, z.z()), axis / s).toRotationMatrix();
}

}  // namespace

/// Rotation entries within 1e-14 of 0 or +-1 are made exact, as load_urdf.cpp does: euler="0 0 90"
/// leaves 6e-17 where a 0 is meant, and exact zeros let generated code drop structural terms.
static double snap_unit(double x) {
  for (double target : {0.0, 1.0, -1.0})
    if (std::abs(x - target) < 1e-14) return target;
  return x;
}

static Mat3<double> orientation_as_given(const Element& e, const Compiler& compiler);

Mat3<double> orientation(const Element& e, const Compiler& compiler) {
  return orientation_as_given(e, compiler).unaryExpr(&snap_unit);
}

static Mat3<double> orientation_as_given(const Element& e, const Compiler& compiler) {
  struct Given {
    const char* name;
    int count;
  };
  static const Given kinds[] = {{"quat", 4}, {"axisangle", 4}, {"euler", 3}, {"xyaxes", 6}, {"zaxis", 3}};
  const Given* found = nullptr;
  std::vector<double> values;
  // The element's own orientation wins as a whole; only when it gives none does its class's
  // default (a geom class may carry one) apply.
  for (bool own : {true, false}) {
    for (const Given& g : kinds) {
      if (own ? !e.xml()->Attribute(g.name) : !e.attribute(g.name)) continue;
      if (found)
        e.fail(fmt::format("gives both {} and {}", found->name, g.name), "give the orientation once");
      found = &g;
      values = *e.numbers(g.name, g.count);
    }
    if (found) break;
  }
  if (!found) return Mat3<double>::Identity();
  const std::string name = found->name;
  if (name == "quat") return from_quat(e, values);
  if (name == "axisangle") return from_axisangle(e, values, compiler);
  if (name == "euler") return from_euler(e, values, compiler);
  if (name == "xyaxes") return from_xyaxes(e, values);
  return from_zaxis(e, values);
}

SE3<double> pose(const Element& e, const Compiler& compiler) {
  SE3<double> X;
  X.rotation = orientation(e, compiler);
  X.translation = e.vec3("pos", Vec3<double>::Zero());
  return X;
}

}  // namespace mbgen::gen::mjcf
