// contact_force_jacobians (runtime/include/mbgen/algorithm/contact_law.hpp), the law's Jacobians
// written by hand for the generator, against forward-mode automatic differentiation (Eigen's
// AutoDiffScalar over the six inputs w and v_w) through contact_force_at_witness: every regime
// of the law (apart, pressing, clamped while leaving fast, sliding above the stiction speed,
// sticking below it, at zero slip) and every exponent path (1, 1.5, 2 and pow), 1e-13 relative to
// the largest entry; apart, exact zeros.
#include <gtest/gtest.h>

#include <unsupported/Eigen/AutoDiff>

#include "mbgen/algorithm/contact_law.hpp"

namespace mbgen::test {
namespace {

using AD = Eigen::AutoDiffScalar<Eigen::Matrix<double, 6, 1>>;

struct Reference {
  Vec3<double> f;
  Mat3<double> df_dw, df_dv;
};

Reference autodiff_jacobians(const Vec3<double>& w, const Vec3<double>& v_w, const double* ground, const double* law,
                             double exponent) {
  Vec3<AD> w_ad, v_ad;
  for (int i = 0; i < 3; ++i) {
    w_ad[i] = AD(w[i], 6, i);
    v_ad[i] = AD(v_w[i], 6, 3 + i);
  }
  const AD g[kGroundInputs] = {AD(ground[0]), AD(ground[1]), AD(ground[2]), AD(ground[3])};
  const AD l[kLawInputs] = {AD(law[0]), AD(law[1]), AD(law[2]), AD(law[3])};
  const ContactForce<AD> out = contact_force_at_witness<AD>(w_ad, v_ad, g, l, exponent);
  Reference r;
  for (int i = 0; i < 3; ++i) {
    r.f[i] = out.force[i].value();
    // A force that is exactly zero (apart) carries no derivative vector.
    const bool seeded = out.force[i].derivatives().size() == 6;
    for (int k = 0; k < 3; ++k) {
      r.df_dw(i, k) = seeded ? out.force[i].derivatives()[k] : 0.0;
      r.df_dv(i, k) = seeded ? out.force[i].derivatives()[3 + k] : 0.0;
    }
  }
  return r;
}

struct Case {
  const char* name;
  double height;           ///< n . w - offset: below 0 in contact
  Vec3<double> velocity;   ///< v_w in the ground's axes (z along n)
  double exponent;
};

// Ground tilted so that no axis is special; law: k 1e5, d 0.8 s/m, mu 0.6, v_s 0.05 m/s.
constexpr double kLaw[kLawInputs] = {1e5, 0.8, 0.6, 0.05};

class ContactLawJacobians : public ::testing::TestWithParam<Case> {};

TEST_P(ContactLawJacobians, MatchAutomaticDifferentiation) {
  const Case& c = GetParam();
  const Vec3<double> n = Vec3<double>(0.1, -0.2, 1.0).normalized();
  // An orthonormal frame (t1, t2, n) for the case's velocity.
  const Vec3<double> t1 = n.cross(Vec3<double>(1, 0, 0)).normalized(), t2 = n.cross(t1);
  const double offset = 0.3;
  const double ground[kGroundInputs] = {n.x(), n.y(), n.z(), offset};
  const Vec3<double> w = Vec3<double>(0.4, -0.7, 0.0) + (offset + c.height - n.dot(Vec3<double>(0.4, -0.7, 0.0))) * n;
  const Vec3<double> v_w = c.velocity.x() * t1 + c.velocity.y() * t2 + c.velocity.z() * n;
  Vec3<double> f;
  Mat3<double> df_dw, df_dv;
  contact_force_jacobians<double>(w, v_w, ground, kLaw, c.exponent, f, df_dw, df_dv);
  // Apart, the force is 0 in a neighbourhood, so are its Jacobians; automatic differentiation
  // gives NaN there (the root of delta^1.5 at 0 times 0), hence the reference is 0 outright.
  const Reference r = c.height > 0 ? Reference{Vec3<double>::Zero(), Mat3<double>::Zero(), Mat3<double>::Zero()}
                                   : autodiff_jacobians(w, v_w, ground, kLaw, c.exponent);
  const double scale = std::max({r.f.cwiseAbs().maxCoeff(), r.df_dw.cwiseAbs().maxCoeff(), r.df_dv.cwiseAbs().maxCoeff()});
  EXPECT_LE((f - r.f).cwiseAbs().maxCoeff(), 1e-13 * scale) << f.transpose() << " against " << r.f.transpose();
  EXPECT_LE((df_dw - r.df_dw).cwiseAbs().maxCoeff(), 1e-13 * scale) << df_dw << "\nagainst\n" << r.df_dw;
  EXPECT_LE((df_dv - r.df_dv).cwiseAbs().maxCoeff(), 1e-13 * scale) << df_dv << "\nagainst\n" << r.df_dv;
  // The regime is the case's: the force and its Jacobians vanish apart and while clamped, and only there.
  const bool pushing = c.height < 0 && 1 - kLaw[1] * c.velocity.z() > 0;
  EXPECT_EQ(f.norm() > 0, pushing);
  EXPECT_EQ(df_dw.norm() > 0 || df_dv.norm() > 0, pushing);
}

INSTANTIATE_TEST_SUITE_P(
    Regimes, ContactLawJacobians,
    ::testing::Values(Case{"apart", 0.01, {0.3, -0.2, -0.5}, 1.5},
                      Case{"pressing_sliding_hertz", -0.002, {0.3, -0.2, -0.5}, 1.5},
                      Case{"pressing_sliding_linear", -0.002, {0.3, -0.2, 0.4}, 1.0},
                      Case{"pressing_sliding_square", -0.002, {-0.1, 0.25, -0.3}, 2.0},
                      Case{"pressing_sliding_pow", -0.002, {0.2, 0.1, 0.2}, 1.3},
                      Case{"sticking_below_stiction", -0.001, {0.02, -0.01, 0.1}, 1.5},
                      Case{"sticking_linear", -0.001, {-0.03, 0.02, -0.2}, 1.0},
                      Case{"at_zero_slip", -0.001, {0.0, 0.0, 0.3}, 1.5},
                      Case{"clamped_leaving_fast", -0.002, {0.3, 0.1, 2.0}, 1.5},
                      Case{"clamped_linear", -0.002, {0.0, 0.1, 1.5}, 1.0}),
    [](const ::testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

TEST(ContactLaw, UnitStepIsTheSlopeOfMax) {
  EXPECT_EQ(unit_step(2.5), 1.0);
  EXPECT_EQ(unit_step(-1e-300), 0.0);
  EXPECT_EQ(unit_step(0.0), 0.0);  // a select's max(0, 0) takes the constant side
  EXPECT_EQ(unit_step(-0.0f), 0.0f);
  EXPECT_EQ(unit_step(1e-30f), 1.0f);
}

}  // namespace
}  // namespace mbgen::test
