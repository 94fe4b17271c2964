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
  const BodyIndex top = closure_top(model, c);
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

/// Structural non-zeros of a sub-system's Phi_z (rows x columns), columns as in `dependent`.
using Structure = std::vector<std::vector<bool>>;

/// Entries a Givens QR (givens_qr.hpp) updates when it zeroes column `column` below row j of
/// `nonzero` (rows x columns), the columns in `left` still to come: the column's rotations run up
/// its rows, a structural zero below is skipped, and a rotation leaves both rows with the union
/// of their non-zeros.
long eliminate(Structure& nonzero, std::size_t j, std::size_t column, const std::vector<std::size_t>& left) {
  long updates = 0;
  for (std::size_t i = nonzero.size() - 1; i > j; --i) {
    if (!nonzero[i][column]) continue;
    for (std::size_t col : left) {
      const bool any = nonzero[i - 1][col] || nonzero[i][col];
      nonzero[i - 1][col] = nonzero[i][col] = any;
      updates += any ? 1 : 0;
    }
    nonzero[i - 1][column] = true;
    nonzero[i][column] = false;
  }
  return updates;
}

/// Entries the factorisation updates with the columns in `order` (positions into the structure's).
long givens_updates(Structure nonzero, const std::vector<std::size_t>& order) {
  long updates = 0;
  for (std::size_t j = 0; j < order.size(); ++j)
    updates += eliminate(nonzero, j, order[j], std::vector<std::size_t>(order.begin() + static_cast<long>(j) + 1, order.end()));
  return updates;
}

/// Column by column, the one whose rotations update the fewest entries of the columns left (the
/// first of `candidates` on a tie).
std::vector<std::size_t> greedy_order(Structure nonzero, std::vector<std::size_t> candidates) {
  std::vector<std::size_t> order;
  while (!candidates.empty()) {
    std::size_t best = 0;
    long best_updates = -1;
    for (std::size_t c = 0; c < candidates.size(); ++c) {
      std::vector<std::size_t> left = candidates;
      left.erase(left.begin() + static_cast<long>(c));
      Structure trial = nonzero;
      const long updates = eliminate(trial, order.size(), candidates[c], left);
      if (best_updates < 0 || updates < best_updates) best_updates = updates, best = c;
    }
    std::vector<std::size_t> left = candidates;
    left.erase(left.begin() + static_cast<long>(best));
    eliminate(nonzero, order.size(), candidates[best], left);
    order.push_back(candidates[best]);
    candidates = left;
  }
  return order;
}

/// The order of a sub-system's dependent coordinates, which is the order of Phi_z's columns in
/// its factorisation. A closure's rows depend only on the joints of its own cycle, so the Phi_z of
/// loops sharing a few joints (digit_like's toe rods: two loops through the foot's two joints) is
/// block-structured; ascending order puts the shared joints, nearer the root, first, and their
/// rotations mix every row of every loop (a dense factorisation). Two other orders are tried: the
/// coordinates on fewest cycles first (each loop's own, loop by loop, then the shared ones), and
/// column by column the one whose rotations update fewest entries; the one that updates fewest
/// in all is kept, ascending on a tie (a single loop, or loops whose shared joints come last
/// already, such as Lola's ankle, keep it).
std::vector<int> factorisation_order(const SubSystem& s, const std::vector<std::set<int>>& cycles,
                                     const std::vector<LoopClosure>& closures, const std::map<int, int>& body_of) {
  const std::size_t r = s.rows.size();
  // on[c]: the sub-system's closures (positions in s.closures) whose cycle column c's joint is on.
  std::vector<std::vector<std::size_t>> on(r);
  for (std::size_t c = 0; c < r; ++c)
    for (std::size_t k = 0; k < s.closures.size(); ++k)
      if (cycles[static_cast<std::size_t>(s.closures[k])].count(body_of.at(s.dependent[c])) > 0) on[c].push_back(k);
  Structure nonzero(r, std::vector<bool>(r, false));
  for (std::size_t i = 0; i < r; ++i)
    for (std::size_t c = 0; c < r; ++c)
      for (std::size_t k : on[c]) {
        const LoopClosure& closure = closures[static_cast<std::size_t>(s.closures[k])];
        if (s.rows[i] >= closure.row_offset && s.rows[i] < closure.row_offset + closure.rows()) nonzero[i][c] = true;
      }
  std::vector<std::size_t> ascending(r);
  std::iota(ascending.begin(), ascending.end(), std::size_t{0});
  std::vector<std::size_t> by_cycles = ascending;
  std::stable_sort(by_cycles.begin(), by_cycles.end(), [&](std::size_t a, std::size_t b) {
    return on[a].size() != on[b].size() ? on[a].size() < on[b].size() : on[a] < on[b];
  });
  std::vector<std::size_t> best = ascending;
  long best_updates = givens_updates(nonzero, ascending);
  for (const std::vector<std::size_t>& order : {by_cycles, greedy_order(nonzero, by_cycles)}) {
    const long updates = givens_updates(nonzero, order);
    if (updates < best_updates) best_updates = updates, best = order;
  }
  std::vector<int> dependent;
  for (std::size_t c : best) dependent.push_back(s.dependent[c]);
  return dependent;
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
  // A coupling's follower is the dependent coordinate (a mimic joint has none of its own), its
  // leader the independent one, whatever the actuators say.
  for (const LoopClosure& c : model.closures)
    if (c.type == ClosureType::Coupling) {
      hinted.insert(model.joint(model.body(c.body_a).joint).name);
      hinted.erase(model.joint(model.body(c.body_b).joint).name);
    }
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
      root = common_ancestor(model, root, closure_top(model, c));
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


}  // namespace mbgen::gen
