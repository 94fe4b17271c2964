// Mass moments (InertiaMoments, runtime/include/mbgen/spatial/inertia.hpp), the 10-number form of
// CRBA's composite inertias and of ABA's rigid sub-system bodies, against the 6x6 spatial inertia
// of the same bodies moved by the 6x6 congruence (transform_spatial_inertia): an independent route.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "mbgen/spatial/inertia.hpp"

namespace mbgen {
namespace {

Inertia<double> random_body(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  Inertia<double> I;
  I.mass = 0.5 + 2.0 * (u(rng) + 1);
  I.com = Vec3<double>(u(rng), u(rng), u(rng)) * 0.3;
  Mat3<double> B;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) B(i, j) = u(rng) * 0.2;
  I.inertia_com = B * B.transpose() + 0.01 * Mat3<double>::Identity();
  return I;
}

SE3<double> random_pose(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1, 1);
  const Eigen::Quaterniond r(Eigen::Vector4d(u(rng), u(rng), u(rng), u(rng)).normalized());
  return SE3<double>{r.toRotationMatrix(), Vec3<double>(u(rng), u(rng), u(rng))};
}

// matrix() of a body's moments is the body's 6x6 spatial inertia; moved by a pose, and summed
// over two bodies, it stays the 6x6 congruence of the same; operator* is matrix() times the
// motion. 1e-13 relative to the matrix.
TEST(InertiaMoments, MatrixIsTheSpatialInertiaMovedAndSummedAlike) {
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const Inertia<double> a = random_body(rng), b = random_body(rng);
    const SE3<double> X = random_pose(rng);
    const Mat6<double> own = a.matrix();
    ASSERT_LT((InertiaMoments<double>::of_body(a).matrix() - own).norm(), 1e-13 * own.norm());

    InertiaMoments<double> sum = InertiaMoments<double>::of_body(a).transformed(X);
    sum += InertiaMoments<double>::of_body(b);
    const Mat6<double> expected = transform_spatial_inertia<double>(X, own) + b.matrix();
    ASSERT_LT((sum.matrix() - expected).norm(), 1e-13 * expected.norm()) << "trial " << trial;

    Vec6<double> m;
    for (int k = 0; k < 6; ++k) m[k] = u(rng);
    const Vec6<double> momentum = (sum * Motion<double>::from_vector(m)).vector();
    ASSERT_LT((momentum - sum.matrix() * m).norm(), 1e-13 * expected.norm() * m.norm());
  }
}

}  // namespace
}  // namespace mbgen
