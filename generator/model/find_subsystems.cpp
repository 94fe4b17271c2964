// Loop detection and sub-systems at the assembled pose: fundamental cycles, grouping by shared
// moving joints, rank and kept rows, independent and dependent coordinates.
#include <Eigen/QR>
#include <Eigen/SVD>
#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <numeric>
#include <string>
#include <set>

#include "mbgen/algorithm/closure.hpp"
#include "mbgen/algorithm/givens_qr.hpp"
#include "load/load_error.hpp"
#include "model/topology.hpp"

namespace mbgen::gen {

namespace {

using Eigen::MatrixXd;

/// Non-root bodies of a closure's fundamental cycle: body_a and body_b up to (without) their
/// common ancestor.
std::set<int> cycle_bodies(const Model& model, const LoopClosure& c) {
  const BodyIndex top = common_ancestor(model, c.body_a, c.body_b);
  std::set<int> bodies;
  for (BodyIndex start : {c.body_a, c.body_b})
    for (BodyIndex b = start; b != top; b = model.body(b).parent) bodies.insert(b.value());
  return bodies;
}

const Joint& joint_of_coordinate(const Model& model, int v_index) {
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    if (v_index >= joint.idx_v && v_index < joint.idx_v + joint.nv) return joint;
  }
  throw std::out_of_range("no joint has velocity index " + std::to_string(v_index));
}

/// SubSystem::nominal_pivot_ratio: the runtime's factorisation of Phi_z (givens_qr.hpp, rows
/// ascending, columns in `dependent`'s order) at the assembled pose, rounded to two significant
/// digits through its decimal text, so that the generated constant is this very double.
double nominal_pivot_ratio(const MatrixXd& Phi_q, const SubSystem& s) {
  const int r = s.rank();
  if (r == 0) return 1.0;
  MatX<double> R(r, r);
  VecX<double> c(r * (r - 1) / 2), sn(r * (r - 1) / 2);
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < r; ++j) R(i, j) = Phi_q(s.rows[i], s.dependent[j]);
  givens_qr_factor<double>(R, r, c, sn);
  const Eigen::VectorXd pivots = R.diagonal().cwiseAbs();
  return std::stod(fmt::format("{:.1e}", pivots.minCoeff() / pivots.maxCoeff()));
}

/// Entries a Givens QR (givens_qr.hpp) updates on Phi_z when `nonzero` (rows x columns, in the
/// factor's order) is its structure: each column's rotations run up its rows, a structural zero
/// below is skipped, and a rotation leaves both rows with the union of their non-zeros.
long givens_updates(std::vector<std::vector<bool>> nonzero) {
  const std::size_t n = nonzero.size();
  long updates = 0;
  for (std::size_t j = 0; j < n; ++j)
    for (std::size_t i = n - 1; i > j; --i) {
      if (!nonzero[i][j]) continue;
      for (std::size_t col = j + 1; col < n; ++col) {
        const bool any = nonzero[i - 1][col] || nonzero[i][col];
        nonzero[i - 1][col] = nonzero[i][col] = any;
        updates += any ? 1 : 0;
      }
      nonzero[i - 1][j] = true;
      nonzero[i][j] = false;
    }
  return updates;
}

/// The order of a sub-system's dependent coordinates, which is the order of Phi_z's columns in
/// its factorisation. A closure's rows depend only on the joints of its own cycle, so the Phi_z of
/// loops sharing a few joints (digit_like's toe rods: two loops through the foot's two joints) is
/// block-structured; ascending order puts the shared joints, nearer the root, first, and their
/// rotations mix every row of every loop (a dense factorisation). Taking first the coordinates on
/// fewest cycles (each loop's own, loop by loop) keeps each loop's rotations within its rows up to
/// the shared columns. Kept only where it updates fewer entries than the ascending order (for one
/// loop, or loops whose shared joints come last already, the order stays ascending).
std::vector<int> factorisation_order(const SubSystem& s, const std::vector<std::set<int>>& cycles,
                                     const std::vector<LoopClosure>& closures, const std::map<int, int>& body_of) {
  const std::size_t r = s.rows.size();
  auto cycles_through = [&](int v) {
    std::vector<int> on;
    for (std::size_t k = 0; k < s.closures.size(); ++k)
      if (cycles[static_cast<std::size_t>(s.closures[k])].count(body_of.at(v)) > 0) on.push_back(static_cast<int>(k));
    return on;
  };
  auto structure = [&](const std::vector<int>& order) {
    std::vector<std::vector<bool>> nonzero(r, std::vector<bool>(r, false));
    for (std::size_t i = 0; i < r; ++i)
      for (std::size_t c = 0; c < r; ++c)
        for (int k : cycles_through(order[c])) {
          const LoopClosure& closure = closures[static_cast<std::size_t>(s.closures[static_cast<std::size_t>(k)])];
          if (s.rows[i] >= closure.row_offset && s.rows[i] < closure.row_offset + closure.rows()) nonzero[i][c] = true;
        }
    return nonzero;
  };
  std::vector<int> order = s.dependent;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    const std::vector<int> on_a = cycles_through(a), on_b = cycles_through(b);
    return on_a.size() != on_b.size() ? on_a.size() < on_b.size() : on_a < on_b;
  });
  return givens_updates(structure(order)) < givens_updates(structure(s.dependent)) ? order : s.dependent;
}

int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

/// Column-pivoted Gram-Schmidt over the columns of A: picks `count` columns, first from
/// `preferred` while one of them keeps at least `preferred_floor` of norm after projecting out
/// the columns already picked, then from all columns down to `floor`. Returns the picks (column
/// numbers of A), fewer than `count` if the rest fall below `floor`.
std::vector<int> pick_columns(MatrixXd A, int count, const std::vector<bool>& preferred, double preferred_floor,
                              double floor) {
  std::vector<int> picked;
  std::vector<bool> used(A.cols(), false);
  while (static_cast<int>(picked.size()) < count) {
    int best = -1;
    for (int pass = 0; pass < 2 && best < 0; ++pass) {
      double best_norm = pass == 0 ? preferred_floor : floor;
      for (int j = 0; j < A.cols(); ++j) {
        if (used[j] || (pass == 0 && !preferred[j])) continue;
        if (A.col(j).norm() > best_norm) best_norm = A.col(j).norm(), best = j;
      }
    }
    if (best < 0) break;
    used[best] = true;
    picked.push_back(best);
    const Eigen::VectorXd e = A.col(best).normalized();
    for (int j = 0; j < A.cols(); ++j)
      if (!used[j]) A.col(j) -= e * e.dot(A.col(j));
  }
  return picked;
}

}  // namespace

SubSystemChoice choose_subsystems(const Description& d, const VecX<double>& q, const AssemblyOptions& options) {
  const Model& model = d.model;
  SubSystemChoice out;
  const int n = static_cast<int>(model.closures.size());
  if (n == 0) return out;
  // Group the closures: union-find over shared cycle bodies (= shared moving joints).
  std::vector<std::set<int>> cycles;
  for (const LoopClosure& c : model.closures) cycles.push_back(cycle_bodies(model, c));
  std::vector<int> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const bool share = std::any_of(cycles[i].begin(), cycles[i].end(), [&](int b) { return cycles[j].count(b) > 0; });
      if (share) parent[find_root(parent, j)] = find_root(parent, i);
    }

  Data<double> data(model);
  const MatrixXd Phi_q = closure_jacobian<double>(model, data, q);
  std::set<std::string> hinted(d.actuated_joints.begin(), d.actuated_joints.end());
  out.worst_conditioning = 1.0;
  for (int i = 0; i < n; ++i) {
    if (find_root(parent, i) != i) continue;
    SubSystem s;
    std::set<int> bodies;
    BodyIndex root = model.closures[i].body_a;
    for (int k = 0; k < n; ++k) {
      if (find_root(parent, k) != i) continue;
      s.closures.push_back(k);
      bodies.insert(cycles[k].begin(), cycles[k].end());
      const LoopClosure& c = model.closures[k];
      root = common_ancestor(model, root, common_ancestor(model, c.body_a, c.body_b));
      for (int r = 0; r < c.rows(); ++r) s.rows.push_back(c.row_offset + r);
    }
    s.root = root;
    std::map<int, int> body_of;  // coordinate -> the body its joint moves
    for (int b : bodies) {
      s.bodies.push_back(BodyIndex(b));
      const Joint& joint = model.joint(model.body(BodyIndex(b)).joint);
      for (int k = 0; k < joint.nv; ++k) s.coordinates.push_back(joint.idx_v + k), body_of[joint.idx_v + k] = b;
    }
    std::sort(s.coordinates.begin(), s.coordinates.end());
    const int k = static_cast<int>(s.coordinates.size()), m = static_cast<int>(s.rows.size());
    MatrixXd block(m, k);
    for (int r = 0; r < m; ++r)
      for (int c = 0; c < k; ++c) block(r, c) = Phi_q(s.rows[r], s.coordinates[c]);
    // Rank (LOOPS.md's tolerance), then the kept rows: the first `rank` pivots of a column-
    // pivoted QR of block^T, i.e. the rows that are the most independent.
    const Eigen::VectorXd sv = Eigen::JacobiSVD<MatrixXd>(block).singularValues();
    const double sigma_max = sv.size() ? sv[0] : 0.0;
    int rank = 0;
    for (int r = 0; r < sv.size(); ++r)
      if (sv[r] >= options.rank_tolerance * std::max(1.0, sigma_max)) rank = r + 1;
    Eigen::ColPivHouseholderQR<MatrixXd> qr(block.transpose());
    std::vector<int> kept;
    for (int r = 0; r < rank; ++r) kept.push_back(s.rows[qr.colsPermutation().indices()[r]]);
    std::sort(kept.begin(), kept.end());
    s.rows = kept;
    MatrixXd kept_block(rank, k);
    for (int r = 0; r < rank; ++r)
      for (int c = 0; c < k; ++c) kept_block(r, c) = Phi_q(kept[r], s.coordinates[c]);
    // Dependent coordinates: a square block of full rank, taken from the joints that are not
    // actuated while they still add rank (pivoting picks the best-conditioned of them), then from
    // the actuated ones; what is left is independent: the actuators first, the idle spins too.
    std::vector<bool> free_joint(k);
    for (int c = 0; c < k; ++c) free_joint[c] = hinted.count(joint_of_coordinate(model, s.coordinates[c]).name) == 0;
    const double scale = std::max(1.0, sigma_max);
    std::vector<int> z = pick_columns(kept_block, rank, free_joint, options.rank_tolerance * scale,
                                      options.rank_tolerance * scale);
    if (static_cast<int>(z.size()) != rank)
      throw LoadError(d.extras_file, 0, fmt::format("loops of closure '{}'", model.closures[i].name),
                      "no set of dependent coordinates makes the constraint rows solvable",
                      "report this model: the rank of the rows and their coordinates disagree");
    if (rank > 0) {
      MatrixXd Phi_z(rank, rank);
      for (int c = 0; c < rank; ++c) Phi_z.col(c) = kept_block.col(z[c]);
      const Eigen::VectorXd sz = Eigen::JacobiSVD<MatrixXd>(Phi_z).singularValues();
      out.worst_conditioning = std::min(out.worst_conditioning, sz[rank - 1] / sz[0]);
    }
    std::vector<bool> is_dependent(k, false);
    for (int c : z) is_dependent[c] = true;
    for (int c = 0; c < k; ++c) (is_dependent[c] ? s.dependent : s.independent).push_back(s.coordinates[c]);
    s.dependent = factorisation_order(s, cycles, model.closures, body_of);
    s.nominal_pivot_ratio = nominal_pivot_ratio(Phi_q, s);
    for (int c : z)
      if (!free_joint[c] && ++out.dependent_actuated)
        out.warnings.push_back(fmt::format(
            "actuated joint '{}' is a dependent coordinate of the loops of closure '{}': the other joints of its "
            "loops determine it, so it cannot be an independent coordinate there",
            joint_of_coordinate(model, s.coordinates[c]).name, model.closures[i].name));
    out.total_rank += rank;
    out.subsystems.push_back(std::move(s));
  }
  return out;
}

void find_subsystems(Description& d, const AssemblyOptions& options) {
  SubSystemChoice choice = choose_subsystems(d, d.assembly.q, options);
  d.model.subsystems = std::move(choice.subsystems);
  d.warnings.insert(d.warnings.end(), choice.warnings.begin(), choice.warnings.end());
  d.closed_dof = d.model.nv() - choice.total_rank;
}

}  // namespace mbgen::gen
