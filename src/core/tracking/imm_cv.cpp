#include "icanc/core/tracking/imm_cv.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>  // 2x2 inverse and determinant

namespace icanc {

Eigen::Vector3d robustMeasurementVariance(const ConstantVelocityKalman& filter,
                                          const Eigen::Vector3d& z, double variance,
                                          double sigmas) {
  Eigen::Vector3d R = Eigen::Vector3d::Constant(variance);
  if (!(sigmas > 0.0)) return R;
  const ConstantVelocityKalman::Matrix6& P = filter.covariance();
  for (int axis = 0; axis < 2; ++axis) {
    const double spread2 = P(axis, axis) + variance;
    const double innovation = z[axis] - filter.position()[axis];
    const double r2 = innovation * innovation / spread2;
    if (r2 > sigmas * sigmas) R[axis] = spread2 * r2 / (sigmas * sigmas) - P(axis, axis);
  }
  return R;
}

void ImmConstantVelocity::init(const Eigen::Vector3d& position, double position_variance,
                               double velocity_variance) {
  for (ConstantVelocityKalman& f : filters_) f.init(position, position_variance, velocity_variance);
  mu_ = {{0.5, 0.5}};
  combine();
}

void ImmConstantVelocity::predict(double dt, const ImmModels& models) {
  // Mixing: mix[j][i] = P(mode i before | mode j now), c[j] = P(mode j now) before the update.
  const double p_switch = 1.0 - std::exp(-std::max(0.0, models.switch_rate_per_s) * dt);
  std::array<std::array<double, kModes>, kModes> mix;
  std::array<double, kModes> c{};
  for (int j = 0; j < kModes; ++j) {
    for (int i = 0; i < kModes; ++i) c[j] += (i == j ? 1.0 - p_switch : p_switch) * mu_[i];
    for (int i = 0; i < kModes; ++i)
      mix[j][i] = c[j] > 0.0 ? (i == j ? 1.0 - p_switch : p_switch) * mu_[i] / c[j] : (i == j);
  }
  std::array<Vector6, kModes> x0;
  std::array<Matrix6, kModes> P0;
  for (int j = 0; j < kModes; ++j) mixture(mix[j], x0[j], P0[j]);
  const double accel_std[kModes] = {models.steady_accel_std, models.manoeuvre_accel_std};
  for (int j = 0; j < kModes; ++j) {
    filters_[j].set(x0[j], P0[j]);
    filters_[j].predict(dt, accel_std[j]);
  }
  mu_ = c;
  combine();
}

void ImmConstantVelocity::update(const Eigen::Vector3d& measured_position,
                                 double measurement_variance, double robust_sigma) {
  std::array<double, kModes> log_likelihood{};
  for (int j = 0; j < kModes; ++j) {
    ConstantVelocityKalman& f = filters_[j];
    const Eigen::Vector3d R =
        robustMeasurementVariance(f, measured_position, measurement_variance, robust_sigma);
    Eigen::Matrix2d S = f.covariance().topLeftCorner<2, 2>();
    S.diagonal() += R.head<2>();
    const Eigen::Vector2d nu = (measured_position - f.position()).head<2>();
    log_likelihood[j] = -0.5 * nu.dot(S.inverse() * nu) - 0.5 * std::log(S.determinant());
    f.update(measured_position, R);
  }
  // mu_j * exp(l_j), scaled by the largest likelihood against underflow.
  const double top = *std::max_element(log_likelihood.begin(), log_likelihood.end());
  std::array<double, kModes> w{};
  double sum = 0.0;
  for (int j = 0; j < kModes; ++j) sum += w[j] = mu_[j] * std::exp(log_likelihood[j] - top);
  if (sum > 0.0 && std::isfinite(sum))
    for (int j = 0; j < kModes; ++j) mu_[j] = w[j] / sum;
  combine();
}

void ImmConstantVelocity::mixture(const std::array<double, kModes>& weights, Vector6& x,
                                  Matrix6& P) const {
  x.setZero();
  for (int i = 0; i < kModes; ++i) x += weights[i] * filters_[i].state();
  P.setZero();
  for (int i = 0; i < kModes; ++i) {
    const Vector6 d = filters_[i].state() - x;
    P += weights[i] * (filters_[i].covariance() + d * d.transpose());
  }
}

void ImmConstantVelocity::combine() { mixture(mu_, x_, P_); }

void ImmConstantVelocity::changeFrame(const Eigen::Isometry3d& motion) {
  for (ConstantVelocityKalman& filter : filters_) filter.changeFrame(motion);
  combine();
}

}  // namespace icanc
