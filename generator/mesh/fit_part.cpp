// The single-part candidates of the SSV fit: sphere, capsule, plate (fit_ssv.hpp says why these).
#include "mesh/fit_part.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <limits>

#include "mbgen/collision/closest_triangle.hpp"

namespace mbgen::mesh {

namespace {

using V = Vec3<double>;
constexpr double kPi = 3.14159265358979323846;

double sphere_volume(double r) { return 4.0 / 3.0 * kPi * r * r * r; }

/// Badoiu-Clarkson: step towards the farthest point by 1/(k+1); within a few per cent of the
/// smallest enclosing ball after a few hundred steps. The radius is then measured exactly.
V ball_centre(const std::vector<V>& points, const V& start, const V& drop_axis) {
  V c = start;
  for (int k = 1; k <= 400; ++k) {
    double far = -1;
    V target = c;
    for (const V& p : points) {
      V d = p - c;
      d -= d.dot(drop_axis) * drop_axis;  // a zero axis keeps all three directions
      if (d.squaredNorm() > far) far = d.squaredNorm(), target = c + d;
    }
    c += (target - c) / (k + 1.0);
  }
  return c;
}

V bounding_box_centre(const std::vector<V>& points) {
  V lo = points.front(), hi = points.front();
  for (const V& p : points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return (lo + hi) / 2;
}

Part sphere(const std::vector<V>& points) {
  const V c = ball_centre(points, bounding_box_centre(points), V::Zero());
  Part part;
  part.primitives = {{{c}, 0.0}};
  part.primitives[0].radius = needed_radius(points, part.primitives);
  part.volume = part_volume(part.primitives);
  return part;
}

/// The capsule along `axis` with the least volume over a grid of radii.
Part capsule(const std::vector<V>& points, const V& axis) {
  const V centre = ball_centre(points, bounding_box_centre(points), axis);  // centre of the projections' circle
  std::vector<double> t(points.size()), rho(points.size());
  double rho_max = 0, t_lo = std::numeric_limits<double>::infinity(), t_hi = -t_lo;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const V d = points[i] - centre;
    t[i] = d.dot(axis);
    rho[i] = (d - t[i] * axis).norm();
    rho_max = std::max(rho_max, rho[i]);
    t_lo = std::min(t_lo, t[i]), t_hi = std::max(t_hi, t[i]);
  }
  const double r_top = std::sqrt(rho_max * rho_max + 0.25 * (t_hi - t_lo) * (t_hi - t_lo));  // a sphere's
  Part best;
  best.volume = std::numeric_limits<double>::infinity();
  const int steps = 48;
  for (int j = 0; j <= steps; ++j) {
    const double s = static_cast<double>(j) / steps;
    const double r = rho_max + (r_top - rho_max) * s * s;  // finer near the thinnest capsule
    // The segment [lo, hi] must reach every point's interval [t - w, t + w], w = sqrt(r^2 - rho^2).
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double w = std::sqrt(std::max(0.0, r * r - rho[i] * rho[i]));
      lo = std::min(lo, t[i] + w), hi = std::max(hi, t[i] - w);
    }
    if (lo > hi) lo = hi = (lo + hi) / 2;  // every interval shares a point: a sphere
    const double volume = kPi * r * r * (hi - lo) + sphere_volume(r);
    if (volume < best.volume) {
      best.volume = volume;
      best.primitives = {{{centre + lo * axis, centre + hi * axis}, r}};
    }
  }
  best.primitives[0].radius = std::max(best.primitives[0].radius, needed_radius(points, best.primitives));
  best.volume = part_volume(best.primitives);
  return best;
}

/// The plate normal to `normal` (in-plane axes u, v) with the least volume over a grid of radii.
Part plate(const std::vector<V>& points, const V& centre, const V& u, const V& v, const V& normal) {
  std::vector<double> pu(points.size()), pv(points.size()), pw(points.size());
  double w_lo = std::numeric_limits<double>::infinity(), w_hi = -w_lo;
  double u_lo = w_lo, u_hi = w_hi, v_lo = w_lo, v_hi = w_hi;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const V d = points[i] - centre;
    pu[i] = d.dot(u), pv[i] = d.dot(v), pw[i] = d.dot(normal);
    w_lo = std::min(w_lo, pw[i]), w_hi = std::max(w_hi, pw[i]);
    u_lo = std::min(u_lo, pu[i]), u_hi = std::max(u_hi, pu[i]);
    v_lo = std::min(v_lo, pv[i]), v_hi = std::max(v_hi, pv[i]);
  }
  const double w_mid = (w_lo + w_hi) / 2, r0 = (w_hi - w_lo) / 2;
  const double r_top = r0 + 0.5 * std::min(u_hi - u_lo, v_hi - v_lo);
  Part best;
  best.volume = std::numeric_limits<double>::infinity();
  const int steps = 48;
  for (int j = 0; j <= steps; ++j) {
    const double s = static_cast<double>(j) / steps;
    const double r = r0 + (r_top - r0) * s * s;
    // Each point may lie e = sqrt(r^2 - w^2) from the rectangle in its plane; e / sqrt(2) per
    // in-plane axis keeps it within reach at a corner too.
    double a0 = std::numeric_limits<double>::infinity(), a1 = -a0, b0 = a0, b1 = -a0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const double w = pw[i] - w_mid;
      const double e = std::sqrt(std::max(0.0, r * r - w * w)) / std::sqrt(2.0);
      a0 = std::min(a0, pu[i] + e), a1 = std::max(a1, pu[i] - e);
      b0 = std::min(b0, pv[i] + e), b1 = std::max(b1, pv[i] - e);
    }
    if (a0 > a1) a0 = a1 = (a0 + a1) / 2;
    if (b0 > b1) b0 = b1 = (b0 + b1) / 2;
    const double width = a1 - a0, height = b1 - b0;
    const double volume = 2 * r * width * height + kPi * (width + height) * r * r + sphere_volume(r);
    if (volume < best.volume) {
      best.volume = volume;
      const V o = centre + w_mid * normal;
      const V c00 = o + a0 * u + b0 * v, c10 = o + a1 * u + b0 * v, c11 = o + a1 * u + b1 * v, c01 = o + a0 * u + b1 * v;
      best.primitives = {{{c00, c10, c11}, r}, {{c00, c11, c01}, r}};
    }
  }
  const double r = std::max(best.primitives[0].radius, needed_radius(points, best.primitives));
  for (FittedPrimitive& p : best.primitives) p.radius = r;
  best.volume = part_volume(best.primitives);
  return best;
}

}  // namespace

double core_distance(const V& p, const FittedPrimitive& primitive) {
  using collision::SsvVec3;
  const auto& c = primitive.points;
  if (c.size() == 1) return (p - c[0]).norm();
  if (c.size() == 2) return std::sqrt(collision::closest_point_segment<double>(p, c[0], c[1]).dist2);
  return std::sqrt(collision::closest_point_triangle<double>(p, c[0], c[1], c[2]).dist2);
}

double distance_to_compound(const V& p, const std::vector<FittedPrimitive>& compound) {
  double best = std::numeric_limits<double>::infinity();
  for (const FittedPrimitive& primitive : compound) best = std::min(best, core_distance(p, primitive) - primitive.radius);
  return best;
}

double primitive_volume(const FittedPrimitive& primitive) {
  const auto& c = primitive.points;
  const double r = primitive.radius;
  if (c.size() == 1) return sphere_volume(r);
  if (c.size() == 2) return kPi * r * r * (c[1] - c[0]).norm() + sphere_volume(r);
  // Steiner: a flat convex set of area A and perimeter P swept by a ball: 2 r A + (pi/2) P r^2 + sphere.
  const double area = 0.5 * (c[1] - c[0]).cross(c[2] - c[0]).norm();
  const double perimeter = (c[1] - c[0]).norm() + (c[2] - c[1]).norm() + (c[0] - c[2]).norm();
  return 2 * r * area + kPi / 2 * perimeter * r * r + sphere_volume(r);
}

double part_volume(const std::vector<FittedPrimitive>& part) {
  if (part.size() == 1) return primitive_volume(part[0]);
  // A plate: triangles (c00, c10, c11) and (c00, c11, c01), the rectangle c00 c10 c11 c01.
  const auto& t = part[0].points;
  const auto& s = part[1].points;
  const double r = part[0].radius;
  const double width = (t[1] - t[0]).norm(), height = (s[2] - s[0]).norm();
  return 2 * r * width * height + kPi * (width + height) * r * r + sphere_volume(r);
}

double needed_radius(const std::vector<V>& points, const std::vector<FittedPrimitive>& part) {
  double r = 0;
  for (const V& p : points) {
    double d = std::numeric_limits<double>::infinity();
    for (const FittedPrimitive& primitive : part) d = std::min(d, core_distance(p, primitive));
    r = std::max(r, d);
  }
  return r;
}

PrincipalFrame principal_frame(const std::vector<Triangle>& soup) {
  // Second moments of the surface: a triangle of area A and corners v_i contributes
  // A/12 (sum v_i v_i^T + s s^T), s = sum v_i, and A s / 3 to the first moment.
  double area = 0;
  V first = V::Zero();
  Mat3<double> second = Mat3<double>::Zero();
  for (const Triangle& t : soup) {
    const double a = 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).norm();
    const V s = t[0] + t[1] + t[2];
    area += a;
    first += a * s / 3;
    second += a / 12 * (t[0] * t[0].transpose() + t[1] * t[1].transpose() + t[2] * t[2].transpose() + s * s.transpose());
  }
  PrincipalFrame frame;
  Mat3<double> covariance;
  if (area > 0) {
    frame.centre = first / area;
    covariance = second / area - frame.centre * frame.centre.transpose();
  } else {
    frame.centre = V::Zero();
    for (const Triangle& t : soup) frame.centre += (t[0] + t[1] + t[2]) / (3.0 * soup.size());
    covariance.setZero();
    for (const Triangle& t : soup)
      for (const V& p : t) covariance += (p - frame.centre) * (p - frame.centre).transpose();
  }
  Eigen::SelfAdjointEigenSolver<Mat3<double>> eigen(covariance);
  for (int k = 0; k < 3; ++k) {  // eigenvalues increase: largest spread first
    V axis = eigen.eigenvectors().col(2 - k);
    int largest = 0;
    for (int i = 1; i < 3; ++i)
      if (std::abs(axis[i]) > std::abs(axis[largest]) + 1e-12) largest = i;
    frame.axes.col(k) = axis[largest] < 0 ? V(-axis) : axis;
  }
  return frame;
}

Part fit_part(const std::vector<V>& points, const PrincipalFrame& frame, int max_primitives, double min_gain) {
  Part best = sphere(points);
  for (int k = 0; k < 3; ++k) {
    Part c = capsule(points, frame.axes.col(k));
    if (c.volume < best.volume) best = std::move(c);
  }
  if (max_primitives >= 2) {
    const double single = best.volume;
    for (int k = 0; k < 3; ++k) {
      Part p = plate(points, frame.centre, frame.axes.col((k + 1) % 3), frame.axes.col((k + 2) % 3), frame.axes.col(k));
      if (p.volume < (1 - min_gain) * single && p.volume < best.volume) best = std::move(p);
    }
  }
  return best;
}

}  // namespace mbgen::mesh
