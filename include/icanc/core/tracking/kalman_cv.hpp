// Constant-velocity Kalman filter in 3D: state [x y z vx vy vz], position measurements.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace icanc {

class ConstantVelocityKalman {
 public:
  using Vector6 = Eigen::Matrix<double, 6, 1>;
  using Matrix6 = Eigen::Matrix<double, 6, 6>;

  // Starts at `position` with zero velocity; variances are per axis [m^2], [(m/s)^2].
  void init(const Eigen::Vector3d& position, double position_variance, double velocity_variance);

  // Propagates by dt >= 0 seconds with white-acceleration process noise of standard deviation
  // accel_std [m/s^2] (discrete Wiener process acceleration model).
  void predict(double dt, double accel_std);

  // Fuses a position measurement with isotropic variance [m^2].
  void update(const Eigen::Vector3d& measured_position, double measurement_variance) {
    update(measured_position, Eigen::Vector3d::Constant(measurement_variance));
  }
  // Same, with a variance per axis [m^2].
  void update(const Eigen::Vector3d& measured_position, const Eigen::Vector3d& measurement_variance);

  // Re-expresses the estimate in another frame: p' = motion * p, v' = R v, covariance rotated
  // alike (the vehicle moved between frames; the object did not, because of that).
  void changeFrame(const Eigen::Isometry3d& motion);

  // Replaces state and covariance (an IMM's mixing step).
  void set(const Vector6& state, const Matrix6& covariance) {
    x_ = state;
    P_ = covariance;
  }

  Eigen::Vector3d position() const { return x_.head<3>(); }
  Eigen::Vector3d velocity() const { return x_.tail<3>(); }
  const Vector6& state() const { return x_; }
  const Matrix6& covariance() const { return P_; }

 private:
  Vector6 x_ = Vector6::Zero();
  Matrix6 P_ = Matrix6::Identity();
};

}  // namespace icanc
