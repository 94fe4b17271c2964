// Assembly: the zero pose of a closed-loop description is usually not closed (LOOPS.md: errors
// up to 0.55 m and pi rad in parallel_legs). Levenberg-Marquardt over all tree joints finds a
// closed pose near it; the damping keeps the steps small, so the pose found is a near one.
//
// The solve minimises an assembly residual of its own rather than Phi: Phi's rotation rows
// vee(R - R^T)/2 vanish at a half turn as well as at the identity, and a weld that starts a
// half turn off would look closed. Here a rotation is compared column by column (R_b e_k -
// R_a e_k), which is zero only at the identity; Phi is checked at the end.
#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <fmt/format.h>

#include <cmath>
#include <random>

#include "mbgen/algorithm/closure.hpp"
#include "mbgen/algorithm/configuration.hpp"
#include "mbgen/algorithm/jacobian.hpp"
#include "load/load_error.hpp"
#include "model/topology.hpp"

namespace mbgen::gen {

namespace {

using Eigen::MatrixXd;
using Eigen::VectorXd;

int assembly_rows(ClosureType type) {
  switch (type) {
    case ClosureType::Weld: return 12;
    case ClosureType::Point: return 3;
    case ClosureType::Revolute: return 6;
    case ClosureType::Prismatic: return 12;
    case ClosureType::Universal: return 4;
    case ClosureType::Coupling: return 1;
  }
  return 0;
}

/// The assembly residual r(q) and its Jacobian dr/dv (world axes).
class AssemblyResidual {
 public:
  explicit AssemblyResidual(const Model& model) : model_(model), data_(model), Ja_(6, model.nv()), Jb_(6, model.nv()) {
    for (const LoopClosure& c : model.closures) rows_ += assembly_rows(c.type);
  }
  int rows() const { return rows_; }

  void evaluate(const VectorXd& q, VectorXd& r, MatrixXd& J) {
    r.resize(rows_);
    J.resize(rows_, model_.nv());
    compute_joint_jacobians<double>(model_, data_, q);
    int row = 0;
    for (const LoopClosure& c : model_.closures) {
      if (c.type == ClosureType::Coupling) {  // linear in q: its own row is the assembly's
        r[row] = detail::coupling_residual<double>(model_, c, q.data());
        J.row(row).setZero();
        detail::coupling_jacobian_row<double>(model_, c, J.middleRows(row, 1));
        row += 1;
        continue;
      }
      const SE3<double> Xa = data_.X_WB[c.body_a] * c.X_ACa, Xb = data_.X_WB[c.body_b] * c.X_BCb;
      detail::point_frame_jacobian<double>(model_, data_, c.body_a, Xa.translation, Xa.rotation,
                                           ReferenceFrame::LocalWorldAligned, Ja_);
      detail::point_frame_jacobian<double>(model_, data_, c.body_b, Xb.translation, Xb.rotation,
                                           ReferenceFrame::LocalWorldAligned, Jb_);
      const auto Ja_lin = Ja_.topRows<3>(), Ja_ang = Ja_.bottomRows<3>();
      const auto Jb_lin = Jb_.topRows<3>(), Jb_ang = Jb_.bottomRows<3>();
      const Vec3<double> P = Xb.translation - Xa.translation;
      const Vec3<double> a_W = Xa.rotation * c.axis;
      if (c.type == ClosureType::Prismatic) {
        // Only the offset across the axis must vanish.
        const Mat3<double> across = Mat3<double>::Identity() - a_W * a_W.transpose();
        r.segment<3>(row) = across * P;
        J.middleRows<3>(row) = across * (Jb_lin - Ja_lin) +
                               (P.dot(a_W) * Mat3<double>::Identity() + a_W * P.transpose()) * skew<double>(a_W) * Ja_ang;
      } else {
        r.segment<3>(row) = P;
        J.middleRows<3>(row) = Jb_lin - Ja_lin;
      }
      row += 3;
      auto match = [&](const Vec3<double>& A, const Vec3<double>& B) {  // B - A, both turning with their bodies
        r.segment<3>(row) = B - A;
        J.middleRows<3>(row) = -skew<double>(B) * Jb_ang + skew<double>(A) * Ja_ang;
        row += 3;
      };
      switch (c.type) {
        case ClosureType::Weld:
        case ClosureType::Prismatic:
          for (int k = 0; k < 3; ++k) match(Xa.rotation.col(k), Xb.rotation.col(k));
          break;
        case ClosureType::Revolute: match(a_W, Xb.rotation * c.axis); break;
        case ClosureType::Universal: {
          const Vec3<double> B = Xb.rotation * c.axis_b;
          r[row] = a_W.dot(B);
          J.row(row) = a_W.cross(B).transpose() * (Ja_ang - Jb_ang);
          row += 1;
          break;
        }
        case ClosureType::Point:
        case ClosureType::Coupling: break;
      }
    }
  }

 private:
  const Model& model_;
  Data<double> data_;
  Mat6X<double> Ja_, Jb_;
  int rows_ = 0;
};

struct Attempt {
  VectorXd q;
  double phi = INFINITY;  ///< max |Phi|
  double displacement = 0;
  std::string moved_most;
  double sigma_min = 0, sigma_max = 0;
  double dependent_conditioning = 0;  ///< worst sigma_min / sigma_max of the sub-systems' Phi_z
  int dependent_actuated = 0;         ///< actuated joints that are dependent coordinates there
  int rank = 0;
  int iterations = 0;
  int outside_ranges = 0;  ///< bounded 1-DoF joints outside their ranges
};

double max_abs_phi(const Model& model, Data<double>& data, const VectorXd& q) {
  return closure_residual<double>(model, data, q).cwiseAbs().maxCoeff();
}

/// Levenberg-Marquardt from q (in place); returns the iterations used.
int levenberg_marquardt(const Model& model, AssemblyResidual& res, Data<double>& data, VectorXd& q,
                        const AssemblyOptions& options) {
  VectorXd r, r_new, q_new(model.nq());
  MatrixXd J, J_new;
  res.evaluate(q, r, J);
  double cost = r.squaredNorm();
  double lambda = 1e-3;
  int it = 0;
  for (; it < options.max_iterations; ++it) {
    if (max_abs_phi(model, data, q) < options.tolerance) break;
    const MatrixXd JtJ = J.transpose() * J;
    const VectorXd g = J.transpose() * r;
    const double scale = std::max(1.0, JtJ.diagonal().maxCoeff());
    // Damping on the identity: of all steps that reduce the residual alike, the shortest.
    const VectorXd step = (JtJ + lambda * scale * MatrixXd::Identity(model.nv(), model.nv())).ldlt().solve(-g);
    integrate<double>(model, q, step, q_new);
    res.evaluate(q_new, r_new, J_new);
    const double cost_new = r_new.squaredNorm();
    if (std::isfinite(cost_new) && cost_new < cost) {
      q = q_new;
      r.swap(r_new);
      J.swap(J_new);
      cost = cost_new;
      lambda = std::max(lambda / 3, 1e-16);
    } else {
      lambda *= 4;
      if (lambda > 1e12) break;  // stalled: no step reduces the residual
    }
  }
  return it;
}

/// Wraps revolute coordinates to (-pi, pi] (or into their limits, a turn away) and measures the
/// change from q0.
void finish(const Model& model, const VectorXd& q0, Attempt& a) {
  a.displacement = 0;
  a.outside_ranges = 0;
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    if (joint.nq != 1) continue;
    double& x = a.q[joint.idx_q];
    if (joint.type == JointType::Revolute) {
      // The same pose with the angle in (-pi, pi], or a turn away where that enters the limits.
      x = std::remainder(x, 2 * M_PI);
      for (double turn : {2 * M_PI, -2 * M_PI})
        if (joint.bounded && (x < joint.lower || x > joint.upper) && x + turn >= joint.lower && x + turn <= joint.upper)
          x += turn;
    }
    if (joint.bounded && (x < joint.lower || x > joint.upper)) ++a.outside_ranges;
    const double change = std::abs(x - q0[joint.idx_q]);
    if (change > a.displacement) {
      a.displacement = change;
      a.moved_most = joint.name;
    }
  }
}

void measure_conditioning(const Description& d, const Model& model, Data<double>& data, const AssemblyOptions& options,
                          Attempt& a) {
  try {
    const SubSystemChoice choice = choose_subsystems(d, a.q, options);
    a.dependent_conditioning = choice.worst_conditioning;
    a.dependent_actuated = choice.dependent_actuated;
  } catch (const LoadError&) {  // a pose so near a singularity that no dependent block is found
    a.dependent_conditioning = 0;
    a.dependent_actuated = model.nv();
  }
  const MatrixXd Phi_q = closure_jacobian<double>(model, data, a.q);
  const VectorXd sv = Eigen::JacobiSVD<MatrixXd>(Phi_q).singularValues();
  a.sigma_max = sv.size() ? sv[0] : 0;
  a.rank = 0;
  for (int i = 0; i < sv.size(); ++i)
    if (sv[i] >= options.rank_tolerance * std::max(1.0, a.sigma_max)) a.rank = i + 1;
  a.sigma_min = a.rank ? sv[a.rank - 1] : 0;
}

/// Better: higher rank (a lower one is a singular pose), then fewer actuators forced dependent
/// (a pose singular for the actuators), then well conditioned, then fewer joints outside their
/// ranges, then nearer the starting pose.
bool better(const Attempt& x, const Attempt& y, double conditioning) {
  if (x.rank != y.rank) return x.rank > y.rank;
  if (x.dependent_actuated != y.dependent_actuated) return x.dependent_actuated < y.dependent_actuated;
  const bool wx = x.dependent_conditioning >= conditioning, wy = y.dependent_conditioning >= conditioning;
  if (wx != wy) return wx;
  if (x.outside_ranges != y.outside_ranges) return x.outside_ranges < y.outside_ranges;
  if (!wx) return x.dependent_conditioning > y.dependent_conditioning;
  return x.displacement < y.displacement;
}

[[noreturn]] void report_open(const Description& d, const Model& model, Data<double>& data, const Attempt& best,
                              int seeds) {
  closure_residual<double>(model, data, best.q);
  std::vector<std::string> open, names;
  int line = 0;
  std::string file = d.extras_file;  // where the closure is written: the extras, or an MJCF / SDFormat file
  // The closures open by more than 1e-9; when all are closer (the assembly asks for 1e-12), the
  // worst one, so that the message always names one.
  double worst = 0;
  for (const LoopClosure& c : model.closures) worst = std::max(worst, data.Phi.segment(c.row_offset, c.rows()).cwiseAbs().maxCoeff());
  const double shown = std::min(1e-9, worst);
  for (const LoopClosure& c : model.closures) {
    const auto rows = data.Phi.segment(c.row_offset, c.rows());
    if (rows.cwiseAbs().maxCoeff() < shown) continue;
    names.push_back(fmt::format("'{}'", c.name));
    for (const ClosureSpec& spec : d.closures)
      if (spec.name == c.name && line == 0) {
        line = spec.source_line;
        if (spec.source.rfind(d.description_file, 0) == 0) file = d.description_file;
      }
    if (c.type == ClosureType::Coupling) {
      open.push_back(fmt::format("'{}' by {:.3g}", c.name, rows[0]));
      continue;
    }
    const int lin = c.type == ClosureType::Prismatic ? 2 : 3;
    const double position = rows.head(lin).norm(), rotation = rows.tail(c.rows() - lin).norm();
    open.push_back(c.type == ClosureType::Point
                       ? fmt::format("'{}' by {:.3g} m", c.name, position)
                       : fmt::format("'{}' by {:.3g} m and {:.3g} rad", c.name, position, rotation));
  }
  throw LoadError(file, line, fmt::format("closure{} {}", names.size() > 1 ? "s" : "", fmt::join(names, ", ")),
                  fmt::format("cannot be assembled: no pose of the tree closes {0}; the best of {1} starting poses leaves {0} "
                              "open: {2}",
                              names.size() > 1 ? "them" : "it", seeds, fmt::join(open, ", ")),
                  "check the closure's frames, origins (parent_origin / child_origin), axis and type against the URDF: "
                  "the two closure frames must be able to meet");
}

}  // namespace

Assembled assemble_closures(const Description& d, const AssemblyOptions& options) {
  const Model& model = d.model;
  Data<double> data(model);
  AssemblyResidual residual(model);
  // The starting pose: the neutral one, with the description's seed (an MJCF keyframe) where it names joints.
  VectorXd q0 = neutral_configuration<double>(model);
  for (const auto& [name, value] : d.assembly_seed)
    if (const auto j = model.find_joint(name); j && model.joint(*j).nq == 1) q0[model.joint(*j).idx_q] = value;
  std::optional<Attempt> best;
  Attempt closest_open;
  int iterations = 0, seeds = 0;
  for (int seed = 0; seed < options.max_seeds; ++seed) {
    Attempt a;
    a.q = q0;
    if (seed > 0) {
      // Perturbed seeds, growing with the seed number, reproducible.
      std::mt19937_64 rng(seed);
      std::normal_distribution<double> noise(0.0, std::min(0.25 * seed, 2.0));
      for (int j = 1; j < model.num_joints(); ++j) {
        const Joint& joint = model.joint(JointIndex(j));
        if (joint.nq == 1) a.q[joint.idx_q] += joint.type == JointType::Revolute ? noise(rng) : 0.1 * noise(rng);
      }
    }
    a.iterations = levenberg_marquardt(model, residual, data, a.q, options);
    iterations += a.iterations;
    ++seeds;
    a.phi = max_abs_phi(model, data, a.q);
    if (!(a.phi < options.tolerance)) {
      if (a.phi < closest_open.phi) closest_open = a;
      continue;
    }
    finish(model, q0, a);
    measure_conditioning(d, model, data, options, a);
    if (!best || better(a, *best, options.conditioning)) best = a;
    if (best->dependent_conditioning >= options.conditioning && seeds >= options.min_seeds) break;
  }
  if (!best) report_open(d, model, data, closest_open, seeds);
  Assembled out;
  AssemblyReport& report = out.report;
  report.q = best->q;
  report.max_joint_change = best->displacement;
  report.max_change_joint = best->moved_most;
  report.residual = best->phi;
  report.sigma_min = best->sigma_min;
  report.sigma_max = best->sigma_max;
  report.seeds = seeds;
  report.iterations = iterations;
  report.outside_ranges = best->outside_ranges;
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    const double x = joint.nq == 1 ? best->q[joint.idx_q] : 0.0;
    if (joint.bounded && (x < joint.lower || x > joint.upper))
      out.warnings.push_back(fmt::format("assembly: joint '{}' is at {:.6g}, outside its limits [{:.6g}, {:.6g}], in the "
                                       "closed pose: none of the {} starting poses tried led to a closed pose with every joint within its range; "
                                       "seed the assembly nearer one (`assembly:` in the extras, or an MJCF keyframe)",
                                       joint.name, x, joint.lower, joint.upper, seeds));
  }
  report.dependent_conditioning = best->dependent_conditioning;
  if (best->dependent_conditioning < options.conditioning / 10)
    out.warnings.push_back(fmt::format("assembly: the best closed pose found is poorly conditioned: a dependent block Phi_z "
                                     "has condition {:.3g} (smallest kept singular value of Phi_q {:.3g}, largest {:.3g})",
                                     1 / best->dependent_conditioning, best->sigma_min, best->sigma_max));
  return out;
}

}  // namespace mbgen::gen
