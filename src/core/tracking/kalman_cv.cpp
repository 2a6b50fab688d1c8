#include "icanc/core/tracking/kalman_cv.hpp"

#include <Eigen/LU>  // 3x3 inverse

namespace icanc {

void ConstantVelocityKalman::init(const Eigen::Vector3d& position, double position_variance,
                                  double velocity_variance) {
  x_.head<3>() = position;
  x_.tail<3>().setZero();
  P_.setZero();
  P_.diagonal() << Eigen::Vector3d::Constant(position_variance),
      Eigen::Vector3d::Constant(velocity_variance);
}

void ConstantVelocityKalman::predict(double dt, double accel_std) {
  // x' = F x with F = [I dt*I; 0 I]; P' = F P F^T + Q, written with 3x3 blocks.
  x_.head<3>() += dt * x_.tail<3>();

  const Eigen::Matrix3d Ppp = P_.topLeftCorner<3, 3>();
  const Eigen::Matrix3d Ppv = P_.topRightCorner<3, 3>();
  const Eigen::Matrix3d Pvv = P_.bottomRightCorner<3, 3>();
  const Eigen::Matrix3d Ppv_new = Ppv + dt * Pvv;
  P_.topLeftCorner<3, 3>() = Ppp + dt * (Ppv + Ppv.transpose()) + dt * dt * Pvv;
  P_.topRightCorner<3, 3>() = Ppv_new;
  P_.bottomLeftCorner<3, 3>() = Ppv_new.transpose();

  // Discrete white-noise acceleration, per axis q^2 * [dt^4/4 dt^3/2; dt^3/2 dt^2].
  const double q = accel_std * accel_std;
  const double dt2 = dt * dt;
  P_.topLeftCorner<3, 3>().diagonal().array() += q * dt2 * dt2 / 4.0;
  P_.topRightCorner<3, 3>().diagonal().array() += q * dt2 * dt / 2.0;
  P_.bottomLeftCorner<3, 3>().diagonal().array() += q * dt2 * dt / 2.0;
  P_.bottomRightCorner<3, 3>().diagonal().array() += q * dt2;
}

void ConstantVelocityKalman::update(const Eigen::Vector3d& measured_position,
                                    const Eigen::Vector3d& measurement_variance) {
  // H = [I 0]: S = P_pp + R, K = P H^T S^-1 = P.leftCols<3>() S^-1. S is 3x3 symmetric positive
  // definite: Eigen's closed-form inverse (a decomposition's solve() would go through the blocked
  // triangular solver, which queries the CPU cache sizes on every call).
  const Eigen::Matrix3d R = measurement_variance.asDiagonal();
  const Eigen::Matrix3d S = P_.topLeftCorner<3, 3>() + R;
  const Eigen::Matrix<double, 6, 3> K = P_.leftCols<3>() * S.inverse();

  x_ += K * (measured_position - x_.head<3>());

  // Joseph form (I - K H) P (I - K H)^T + K R K^T, then symmetrised against round-off.
  Matrix6 IKH = Matrix6::Identity();
  IKH.leftCols<3>() -= K;
  const Matrix6 P = IKH * P_ * IKH.transpose() + K * R * K.transpose();
  P_ = 0.5 * (P + P.transpose());
}

void ConstantVelocityKalman::changeFrame(const Eigen::Isometry3d& motion) {
  Matrix6 T = Matrix6::Zero();
  T.topLeftCorner<3, 3>() = motion.linear();
  T.bottomRightCorner<3, 3>() = motion.linear();
  x_ = T * x_;
  x_.head<3>() += motion.translation();
  P_ = T * P_ * T.transpose();
}

}  // namespace icanc
