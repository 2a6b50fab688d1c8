// Interacting multiple model (IMM) filter of two constant-velocity Kalman filters that differ only
// in their process noise: a steady model (small white acceleration: an object walking or driving
// on) and a manoeuvring one (large: starting, stopping, turning). Each frame the models are mixed
// by their mode probabilities, predicted, updated with the same measurement and re-weighted by how
// well each predicted it (Bar-Shalom, Li, Kirubarajan, "Estimation with Applications to Tracking
// and Navigation", 2001, section 11.6.6). The combined estimate follows a manoeuvre as fast as the
// manoeuvring model, and its covariance is the steady model's while the object moves steadily: a
// single filter tuned for manoeuvres reports its process noise as the velocity's uncertainty
// forever (0.49 m/s at 3 m/s^2, 10 Hz, 0.15 m), the IMM reports what the estimate is actually known
// to (0.04 m/s with the steady model at 0.05 m/s^2; test_imm_cv). With equal process noises the two
// models stay identical and the IMM is the single filter.
#pragma once

#include <array>

#include <Eigen/Core>

#include "icanc/core/tracking/kalman_cv.hpp"

namespace icanc {

struct ImmModels {
  double steady_accel_std = 0.05;  // white acceleration of the steady model [m/s^2]
  double manoeuvre_accel_std = 3.0;  // ... of the manoeuvring model [m/s^2]
  // Rate at which the object changes between moving steadily and manoeuvring [1/s]: over dt the
  // mode changes with probability 1 - exp(-rate * dt) (0.002 per frame at 0.02 /s and 10 Hz).
  double switch_rate_per_s = 0.02;
};

class ImmConstantVelocity {
 public:
  using Vector6 = ConstantVelocityKalman::Vector6;
  using Matrix6 = ConstantVelocityKalman::Matrix6;
  enum Mode { kSteady = 0, kManoeuvre = 1, kModes = 2 };

  // Both models at `position` with zero velocity, equally likely.
  void init(const Eigen::Vector3d& position, double position_variance, double velocity_variance);

  // Mixes the models and propagates each by dt >= 0 with its own process noise.
  void predict(double dt, const ImmModels& models);

  // Updates each model with the position measurement (variance per axis) and re-weights the modes
  // by the planar (x, y) likelihood of each model's innovation. robust_sigma > 0: per model and
  // planar axis, an innovation beyond that many standard deviations of its predicted spread
  // counts as one of exactly that many (Huber; the variance is raised), in the update and the
  // likelihood alike, so one jumping face moves neither the velocity nor the modes as a
  // manoeuvre would.
  void update(const Eigen::Vector3d& measured_position, double measurement_variance,
              double robust_sigma);

  // Re-expresses every model's estimate in another frame (ConstantVelocityKalman::changeFrame).
  void changeFrame(const Eigen::Isometry3d& motion);

  // The combined estimate: probability-weighted mean, covariance including the spread of the
  // models' means.
  Eigen::Vector3d position() const { return x_.head<3>(); }
  Eigen::Vector3d velocity() const { return x_.tail<3>(); }
  const Vector6& state() const { return x_; }
  const Matrix6& covariance() const { return P_; }
  double modeProbability(Mode mode) const { return mu_[mode]; }

 private:
  // The models as one Gaussian, weighted: mean, and covariance with the spread of the means.
  // The mixing step (per model, by where it came from) and the combined estimate (by mu_).
  void mixture(const std::array<double, kModes>& weights, Vector6& x, Matrix6& P) const;
  // x_, P_: the mixture by the mode probabilities.
  void combine();

  std::array<ConstantVelocityKalman, kModes> filters_;
  std::array<double, kModes> mu_{{0.5, 0.5}};
  Vector6 x_ = Vector6::Zero();
  Matrix6 P_ = Matrix6::Identity();
};

// Huber weighting of one position update, per planar axis: the measurement variance (per axis)
// with which an innovation more than `sigmas` standard deviations of its predicted spread
// sqrt(P + R) away counts as exactly that many (z keeps `variance`). 0 = plain `variance`.
Eigen::Vector3d robustMeasurementVariance(const ConstantVelocityKalman& filter,
                                          const Eigen::Vector3d& z, double variance, double sigmas);

}  // namespace icanc
