// Pins the constant-velocity Kalman filter: the process noise model, covariance growth and
// shrinkage, and velocity convergence on a noisy constant-velocity target.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/Eigenvalues>

#include "icanc/core/tracking/kalman_cv.hpp"

namespace icanc {
namespace {

TEST(KalmanCv, InitSetsStateAndDiagonalCovariance) {
  ConstantVelocityKalman k;
  k.init(Eigen::Vector3d(1, 2, 3), 0.04, 25.0);
  EXPECT_EQ(k.position(), Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(k.velocity(), Eigen::Vector3d::Zero());
  ConstantVelocityKalman::Vector6 diag;
  diag << 0.04, 0.04, 0.04, 25.0, 25.0, 25.0;
  EXPECT_TRUE(k.covariance().isApprox(ConstantVelocityKalman::Matrix6(diag.asDiagonal())));
}

TEST(KalmanCv, ProcessNoiseIsDiscreteWhiteAcceleration) {
  // From zero covariance, one predict leaves exactly Q: per axis a^2 [dt^4/4 dt^3/2; dt^3/2 dt^2].
  ConstantVelocityKalman k;
  k.init(Eigen::Vector3d::Zero(), 0.0, 0.0);
  const double dt = 0.2, a = 3.0, q = a * a;
  k.predict(dt, a);
  const auto& P = k.covariance();
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(P(axis, axis), q * std::pow(dt, 4) / 4.0, 1e-12);
    EXPECT_NEAR(P(axis, axis + 3), q * std::pow(dt, 3) / 2.0, 1e-12);
    EXPECT_NEAR(P(axis + 3, axis), q * std::pow(dt, 3) / 2.0, 1e-12);
    EXPECT_NEAR(P(axis + 3, axis + 3), q * dt * dt, 1e-12);
  }
  // No coupling between axes.
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) {
      if (r % 3 != c % 3) {
        EXPECT_EQ(P(r, c), 0.0) << r << "," << c;
      }
    }
  }
}

TEST(KalmanCv, PredictMovesWithVelocityAndGrowsCovariance) {
  ConstantVelocityKalman k;
  k.init(Eigen::Vector3d(0, 0, 0), 0.01, 1.0);
  // Teach it a velocity: measurement 1 m ahead in x after 1 s.
  k.predict(1.0, 0.0);
  k.update(Eigen::Vector3d(1, 0, 0), 1e-6);
  const Eigen::Vector3d v = k.velocity();
  const Eigen::Vector3d p = k.position();
  EXPECT_GT(v.x(), 0.5);

  const ConstantVelocityKalman::Matrix6 before = k.covariance();
  k.predict(0.5, 1.0);
  EXPECT_TRUE(k.position().isApprox(p + 0.5 * v, 1e-12));
  EXPECT_TRUE(k.velocity().isApprox(v, 1e-12));
  // Growth. The uncertainty volume: det(F P F^T + Q) >= det(P) since det F = 1 and Q >= 0, here
  // strictly. Position variance grows by 2 dt Ppv + dt^2 Pvv + dt^4/4 a^2, velocity variance by
  // dt^2 a^2 (exactly, per axis).
  const auto& P = k.covariance();
  EXPECT_GT(P.determinant(), 1.01 * before.determinant());
  EXPECT_GT(P.trace(), before.trace());
  EXPECT_NEAR(P(0, 0), before(0, 0) + 2 * 0.5 * before(0, 3) + 0.25 * before(3, 3) +
                           std::pow(0.5, 4) / 4,
              1e-12);
  EXPECT_GT(P(0, 0), before(0, 0));
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(P(axis + 3, axis + 3), before(axis + 3, axis + 3) + 0.25, 1e-12);
  }
}

TEST(KalmanCv, PredictWithZeroDtChangesNothing) {
  ConstantVelocityKalman k;
  k.init(Eigen::Vector3d(1, 2, 3), 0.1, 2.0);
  k.predict(0.1, 1.0);
  k.update(Eigen::Vector3d(1.2, 2, 3), 0.01);
  const auto x = k.state();
  const auto P = k.covariance();
  k.predict(0.0, 5.0);
  EXPECT_EQ(k.state(), x);
  EXPECT_EQ(k.covariance(), P);
}

TEST(KalmanCv, UpdateShrinksCovarianceAndPullsTowardsMeasurement) {
  ConstantVelocityKalman k;
  const double p0 = 0.5, r = 0.5;
  k.init(Eigen::Vector3d::Zero(), p0, 4.0);
  const ConstantVelocityKalman::Matrix6 before = k.covariance();
  k.update(Eigen::Vector3d(1, -2, 0.5), r);
  // Independent axes, no position/velocity correlation yet: scalar Kalman gain p/(p+r) = 0.5.
  EXPECT_TRUE(k.position().isApprox(Eigen::Vector3d(0.5, -1, 0.25), 1e-12));
  EXPECT_TRUE(k.velocity().isZero(1e-12));
  EXPECT_NEAR(k.covariance()(0, 0), p0 * r / (p0 + r), 1e-12);
  EXPECT_NEAR(k.covariance()(3, 3), 4.0, 1e-12);  // uncorrelated velocity: not informed
  const ConstantVelocityKalman::Matrix6 shrunk = before - k.covariance();
  Eigen::SelfAdjointEigenSolver<ConstantVelocityKalman::Matrix6> eig(shrunk);
  EXPECT_GE(eig.eigenvalues().minCoeff(), -1e-12);
  EXPECT_GT(shrunk.trace(), 0.0);

  // After a predict, position and velocity are correlated: the update shrinks velocity too.
  k.predict(0.1, 1.0);
  const double vel_var = k.covariance()(3, 3);
  k.update(Eigen::Vector3d(0.5, -1, 0.25), 0.01);
  EXPECT_LT(k.covariance()(3, 3), vel_var);
}

// A variance per axis: each axis takes its own scalar gain p / (p + r_axis).
TEST(KalmanCv, PerAxisVarianceGivesEachAxisItsOwnGain) {
  ConstantVelocityKalman k;
  k.init(Eigen::Vector3d::Zero(), 1.0, 4.0);
  k.update(Eigen::Vector3d(1, 1, 1), Eigen::Vector3d(1.0, 3.0, 1.0 / 3.0));
  EXPECT_NEAR(k.position().x(), 0.5, 1e-12);
  EXPECT_NEAR(k.position().y(), 0.25, 1e-12);
  EXPECT_NEAR(k.position().z(), 0.75, 1e-12);
  EXPECT_NEAR(k.covariance()(1, 1), 1.0 * 3.0 / 4.0, 1e-12);
}

// Constant-velocity target, 10 Hz, Gaussian position noise 0.1 m; several seeds so that the bound
// is not one lucky draw. The filter's velocity sigma after 30 frames is about 0.025 m/s here.
TEST(KalmanCv, VelocityConvergesOnConstantVelocityTarget) {
  const Eigen::Vector3d v_true(1.5, -0.8, 0.1);
  const Eigen::Vector3d p_start(5.0, 3.0, 0.5);
  const double dt = 0.1, noise = 0.1, accel_std = 0.05;
  for (unsigned seed : {1u, 2u, 3u, 4u, 5u}) {
    SCOPED_TRACE(seed);
    std::mt19937 rng(seed);
    std::normal_distribution<double> n(0.0, noise);
    ConstantVelocityKalman k;
    const auto measure = [&](int f) {
      return Eigen::Vector3d(p_start + f * dt * v_true + Eigen::Vector3d(n(rng), n(rng), n(rng)));
    };
    k.init(measure(0), noise * noise, 25.0);
    for (int f = 1; f < 30; ++f) {
      k.predict(dt, accel_std);
      k.update(measure(f), noise * noise);
    }
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(k.velocity()(axis), v_true(axis), 0.1) << "axis " << axis;
      // The reported uncertainty is honest (within 4 sigma) and small.
      const double sigma = std::sqrt(k.covariance()(axis + 3, axis + 3));
      EXPECT_LT(sigma, 0.05);
      EXPECT_LT(std::abs(k.velocity()(axis) - v_true(axis)), 4 * sigma);
    }
    EXPECT_NEAR((k.position() - (p_start + 29 * dt * v_true)).norm(), 0.0, 0.15);
    // Symmetric and positive definite after many steps.
    EXPECT_TRUE(k.covariance().isApprox(k.covariance().transpose(), 1e-12));
    Eigen::SelfAdjointEigenSolver<ConstantVelocityKalman::Matrix6> eig(k.covariance());
    EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0);
  }
}

}  // namespace
}  // namespace icanc
