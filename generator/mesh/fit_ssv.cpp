// The SSV fit's outer loop (fit_ssv.hpp): greedy splitting within the budget, rounding for the
// YAML, the enclosure check, and the report.
#include "mesh/fit_ssv.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "mbgen/collision/closest_triangle.hpp"
#include "mesh/convex_hull.hpp"
#include "mesh/fit_part.hpp"

namespace mbgen::mesh {

namespace {

using V = Vec3<double>;
constexpr double kGrid = 1e-6;  // output coordinates: micrometres (six decimals in metres)

std::vector<V> corners(const std::vector<Triangle>& soup) {
  std::vector<V> points;
  points.reserve(3 * soup.size());
  for (const Triangle& t : soup) points.insert(points.end(), t.begin(), t.end());
  return points;
}

/// The points an enclosing convex part must contain: the corners' convex hull vertices.
std::vector<V> hull_points(const std::vector<Triangle>& soup) {
  const std::vector<V> points = corners(soup);
  const ConvexHull hull = convex_hull(points);
  std::vector<V> kept;
  kept.reserve(hull.vertices.size());
  for (int i : hull.vertices) kept.push_back(points[i]);
  return kept;
}

/// The parts of `soup` on each side of the plane n.x = c (Sutherland-Hodgman per triangle, the
/// clipped polygons fanned into triangles): together they cover the soup, and both contain the
/// points where the plane cuts it.
std::pair<std::vector<Triangle>, std::vector<Triangle>> split_soup(const std::vector<Triangle>& soup, const V& n, double c) {
  std::pair<std::vector<Triangle>, std::vector<Triangle>> halves;
  for (const Triangle& t : soup) {
    for (int side = 0; side < 2; ++side) {
      const double sign = side == 0 ? 1.0 : -1.0;  // keep sign * (n.x - c) <= 0
      V polygon[4];
      int count = 0;
      for (int i = 0; i < 3; ++i) {
        const V& a = t[i];
        const V& b = t[(i + 1) % 3];
        const double da = sign * (n.dot(a) - c), db = sign * (n.dot(b) - c);
        if (da <= 0) polygon[count++] = a;
        if ((da < 0 && db > 0) || (da > 0 && db < 0)) polygon[count++] = a + (da / (da - db)) * (b - a);
      }
      auto& half = side == 0 ? halves.first : halves.second;
      for (int i = 1; i + 1 < count; ++i) half.push_back({polygon[0], polygon[i], polygon[i + 1]});
    }
  }
  return halves;
}

struct Piece {
  std::vector<Triangle> soup;
  PrincipalFrame frame;
  Part part;
};

Piece make_piece(std::vector<Triangle> soup, int max_primitives, double min_gain) {
  Piece piece;
  piece.soup = std::move(soup);
  piece.frame = principal_frame(piece.soup);
  piece.part = fit_part(hull_points(piece.soup), piece.frame, max_primitives, min_gain);
  return piece;
}

struct Split {
  Piece a, b;
  double volume = std::numeric_limits<double>::infinity();
};

/// The best cut of `piece`: planes normal to each principal axis at 1/3, 1/2 and 2/3 of its extent.
std::optional<Split> best_split(const Piece& piece, int max_primitives, double min_gain) {
  std::optional<Split> best;
  const std::vector<V> points = corners(piece.soup);
  for (int k = 0; k < 3; ++k) {
    const V n = piece.frame.axes.col(k);
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (const V& p : points) lo = std::min(lo, n.dot(p)), hi = std::max(hi, n.dot(p));
    if (!(hi - lo > 0)) continue;
    for (double f : {1.0 / 3, 0.5, 2.0 / 3}) {
      auto [left, right] = split_soup(piece.soup, n, lo + f * (hi - lo));
      if (left.empty() || right.empty()) continue;
      Split s;
      s.a = make_piece(std::move(left), max_primitives, min_gain);
      s.b = make_piece(std::move(right), max_primitives, min_gain);
      s.volume = s.a.part.volume + s.b.part.volume;
      if (!best || s.volume < best->volume) best = std::move(s);
    }
  }
  return best;
}

int count(const Piece& p) { return static_cast<int>(p.part.primitives.size()); }

/// Rounds the part's corners to the grid and its radius up to the grid, with half a grid step
/// to spare, so that the six-decimal text still encloses the piece.
void round_part(Part& part, const std::vector<V>& points) {
  for (FittedPrimitive& p : part.primitives)
    for (V& x : p.points)
      for (int i = 0; i < 3; ++i) x[i] = std::round(x[i] / kGrid) * kGrid;
  const double needed = std::max(part.primitives[0].radius, needed_radius(points, part.primitives));
  const double r = std::ceil(needed / kGrid + 0.5) * kGrid;
  for (FittedPrimitive& p : part.primitives) p.radius = r;
  part.volume = part_volume(part.primitives);
}

/// Directions spread evenly over the sphere (a Fibonacci lattice).
std::vector<V> sphere_directions(int n) {
  std::vector<V> d;
  const double golden = 3.14159265358979323846 * (3 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1 - (2 * i + 1.0) / n, r = std::sqrt(1 - z * z);
    d.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  return d;
}

/// Points spread over a core: the point, 9 along a segment, 15 barycentric on a triangle.
std::vector<V> core_samples(const FittedPrimitive& p) {
  const auto& c = p.points;
  std::vector<V> s;
  if (c.size() == 1) return {c[0]};
  if (c.size() == 2) {
    for (int i = 0; i <= 8; ++i) s.push_back(c[0] + (i / 8.0) * (c[1] - c[0]));
    return s;
  }
  for (int i = 0; i <= 4; ++i)
    for (int j = 0; i + j <= 4; ++j) s.push_back(c[0] + (i / 4.0) * (c[1] - c[0]) + (j / 4.0) * (c[2] - c[0]));
  return s;
}

double distance_to_mesh(const V& p, const std::vector<Triangle>& soup, double enough) {
  double best = std::numeric_limits<double>::infinity();
  for (const Triangle& t : soup) {
    best = std::min(best, std::sqrt(collision::closest_point_triangle<double>(p, t[0], t[1], t[2]).dist2));
    if (best <= enough) break;  // this point cannot raise the maximum any more
  }
  return best;
}

/// Largest distance from the compound's surface to the mesh, over sampled surface points.
double largest_gap(const std::vector<FittedPrimitive>& compound, const std::vector<Triangle>& soup) {
  const std::vector<V> directions = sphere_directions(64);
  double gap = 0;
  for (const FittedPrimitive& primitive : compound)
    for (const V& c : core_samples(primitive))
      for (const V& d : directions) {
        const V s = c + primitive.radius * d;
        bool on_surface = true;
        for (const FittedPrimitive& other : compound)
          if (core_distance(s, other) < other.radius * (1 - 1e-9)) on_surface = false;
        if (on_surface) gap = std::max(gap, distance_to_mesh(s, soup, gap));
      }
  return gap;
}

double total_volume(const std::vector<Piece>& pieces) {
  double v = 0;
  for (const Piece& p : pieces) v += p.part.volume;
  return v;
}

/// Greedy: the best part for the whole, then the cut that saves most, while one saves min_gain.
std::vector<Piece> greedy_pieces(const std::vector<Triangle>& soup, const FitOptions& options) {
  std::vector<Piece> pieces;
  pieces.push_back(make_piece(soup, options.budget, options.min_gain));
  std::vector<std::optional<Split>> splits(1);
  std::vector<bool> tried(1, false);
  for (;;) {
    int used = 0;
    for (const Piece& p : pieces) used += count(p);
    int chosen = -1;
    double best_gain = 0;
    for (std::size_t i = 0; i < pieces.size(); ++i) {
      if (!tried[i]) splits[i] = best_split(pieces[i], options.budget, options.min_gain), tried[i] = true;
      if (!splits[i]) continue;
      const int extra = count(splits[i]->a) + count(splits[i]->b) - count(pieces[i]);
      const double gain = pieces[i].part.volume - splits[i]->volume;
      if (used + extra <= options.budget && gain >= options.min_gain * pieces[i].part.volume && gain > best_gain)
        best_gain = gain, chosen = static_cast<int>(i);
    }
    if (chosen < 0) break;
    Split s = std::move(*splits[chosen]);
    pieces[chosen] = std::move(s.a);
    splits[chosen].reset(), tried[chosen] = false;
    pieces.push_back(std::move(s.b));
    splits.emplace_back(), tried.push_back(false);
  }

  return pieces;
}

/// Cut first: single-primitive parts, the largest cut at its best plane (if that makes it
/// smaller) until the budget is spent or nothing can be cut.
std::vector<Piece> cut_first_pieces(const std::vector<Triangle>& soup, const FitOptions& options) {
  std::vector<Piece> pieces;
  pieces.push_back(make_piece(soup, 1, options.min_gain));
  while (static_cast<int>(pieces.size()) < options.budget) {
    std::vector<std::size_t> order(pieces.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return pieces[a].part.volume > pieces[b].part.volume; });
    bool cut = false;
    for (std::size_t i : order) {
      std::optional<Split> split = best_split(pieces[i], 1, options.min_gain);
      if (!split || !(split->volume < pieces[i].part.volume)) continue;
      pieces[i] = std::move(split->a);
      pieces.push_back(std::move(split->b));
      cut = true;
      break;
    }
    if (!cut) break;
  }
  return pieces;
}

}  // namespace

FittedCompound fit_ssv_compound(const TriangleMesh& mesh, const FitOptions& options) {
  if (options.budget < 1)
    throw std::invalid_argument(fmt::format("the SSV budget is {}: give at least 1 primitive per link", options.budget));
  if (mesh.triangles.empty()) throw std::invalid_argument("the mesh has no triangles");
  const std::vector<Triangle> soup = triangle_soup(mesh);
  std::vector<Piece> pieces = greedy_pieces(soup, options);
  // The greedy step stops where no single cut saves min_gain; a tapered or bent part may need
  // two cuts before either pays. Cutting first (the largest part at its best cut into single
  // primitives, until the budget is spent) is the other way round; it is kept when it saves
  // min_gain of the greedy result's volume.
  if (options.budget >= 2) {
    std::vector<Piece> cut = cut_first_pieces(soup, options);
    if (total_volume(cut) < (1 - options.min_gain) * total_volume(pieces)) pieces = std::move(cut);
  }

  FittedCompound result;
  FitReport& report = result.report;
  for (Piece& piece : pieces) {
    round_part(piece.part, hull_points(piece.soup));
    report.volume += piece.part.volume;
    result.primitives.insert(result.primitives.end(), piece.part.primitives.begin(), piece.part.primitives.end());
  }
  report.vertices = static_cast<int>(mesh.vertices.size());
  report.triangles = static_cast<int>(mesh.triangles.size());
  const std::vector<V> points = corners(soup);  // a vertex no triangle uses is no surface
  report.hull_volume = convex_hull(points).volume;
  report.largest_outside = -std::numeric_limits<double>::infinity();
  for (const V& v : points) report.largest_outside = std::max(report.largest_outside, distance_to_compound(v, result.primitives));
  if (report.largest_outside > 0)
    throw std::logic_error(fmt::format("SSV fit: a vertex lies {:.3g} m outside the fitted compound (a bug: please report it)",
                                       report.largest_outside));
  report.largest_gap = largest_gap(result.primitives, soup);
  return result;
}

}  // namespace mbgen::mesh
