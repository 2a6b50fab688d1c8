// Pins the IMM of two constant-velocity models (ImmConstantVelocity): the single filter when both
// process noises are equal, the steady model's small uncertainty while the object moves steadily,
// the manoeuvring model's speed when it starts, and a one-frame jump not taken for a manoeuvre.
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "icanc/core/tracking/imm_cv.hpp"

namespace icanc {
namespace {

constexpr double kDt = 0.1;
constexpr double kR = 0.15 * 0.15;  // the profiles' measurement_std_m 0.15

// Positions of a walker along x: standing until `start_frame`, then at `speed`, with Gaussian
// measurement noise of `noise_std` (seeded).
std::vector<Eigen::Vector3d> walker(int frames, int start_frame, double speed, double noise_std,
                                    unsigned seed = 3) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_std);
  std::vector<Eigen::Vector3d> z;
  for (int k = 0; k < frames; ++k) {
    const double x = 5.0 + speed * kDt * std::max(0, k - start_frame);
    z.emplace_back(x + noise(rng), 2.0 + noise(rng), 0.8 + noise(rng));
  }
  return z;
}

// Runs the IMM over the measurements; returns it after the last.
ImmConstantVelocity run(const std::vector<Eigen::Vector3d>& z, const ImmModels& models,
                        double robust_sigma = 0.0, std::vector<double>* vx = nullptr,
                        std::vector<double>* manoeuvre = nullptr) {
  ImmConstantVelocity f;
  f.init(z[0], kR, 25.0);
  for (std::size_t k = 1; k < z.size(); ++k) {
    f.predict(kDt, models);
    f.update(z[k], kR, robust_sigma);
    if (vx) vx->push_back(f.velocity().x());
    if (manoeuvre) manoeuvre->push_back(f.modeProbability(ImmConstantVelocity::kManoeuvre));
  }
  return f;
}

TEST(ImmCv, EqualProcessNoisesAreTheSingleFilter) {
  const std::vector<Eigen::Vector3d> z = walker(40, 10, 1.5, 0.1);
  for (double robust_sigma : {0.0, 3.0}) {
    ImmConstantVelocity imm;
    ConstantVelocityKalman single;
    imm.init(z[0], kR, 25.0);
    single.init(z[0], kR, 25.0);
    for (std::size_t k = 1; k < z.size(); ++k) {
      imm.predict(kDt, ImmModels{3.0, 3.0, 0.5});
      single.predict(kDt, 3.0);
      imm.update(z[k], kR, robust_sigma);
      single.update(z[k], robustMeasurementVariance(single, z[k], kR, robust_sigma));
      ASSERT_LT((imm.state() - single.state()).norm(), 1e-9) << "frame " << k;
      ASSERT_LT((imm.covariance() - single.covariance()).norm(), 1e-9) << "frame " << k;
    }
  }
}

// A walker at a steady 1.5 m/s, measured to 0.03 m: a single filter tuned for manoeuvres keeps
// reporting its process noise as the velocity's uncertainty; the IMM reports what the estimate is
// known to, and its estimate is as good or better.
TEST(ImmCv, SteadyMotionReportsWhatTheVelocityIsKnownTo) {
  const std::vector<Eigen::Vector3d> z = walker(60, 0, 1.5, 0.03);
  std::vector<double> vx_imm, vx_single;
  const ImmConstantVelocity imm = run(z, ImmModels{0.05, 3.0, 0.02}, 0.0, &vx_imm);
  const ImmConstantVelocity single = run(z, ImmModels{3.0, 3.0, 0.02}, 0.0, &vx_single);
  const double sigma_imm = std::sqrt(imm.covariance()(3, 3));
  const double sigma_single = std::sqrt(single.covariance()(3, 3));
  EXPECT_GT(sigma_single, 0.45);
  EXPECT_LT(sigma_imm, 0.1);
  EXPECT_GT(imm.modeProbability(ImmConstantVelocity::kSteady), 0.9);
  double err_imm = 0.0, err_single = 0.0;
  for (std::size_t k = vx_imm.size() - 30; k < vx_imm.size(); ++k) {
    err_imm += (vx_imm[k] - 1.5) * (vx_imm[k] - 1.5);
    err_single += (vx_single[k] - 1.5) * (vx_single[k] - 1.5);
  }
  EXPECT_LT(err_imm, err_single);
  EXPECT_LT(std::sqrt(err_imm / 30), 0.1);
}

// A walker standing for 2 s, then walking at 1.5 m/s: the manoeuvring model takes over and the
// IMM's velocity follows nearly as fast as the manoeuvring filter alone, much faster than the
// steady one alone; once walking steadily, the steady model takes over again.
TEST(ImmCv, AStartIsFollowedAsTheManoeuvringModelDoes) {
  const std::vector<Eigen::Vector3d> z = walker(60, 20, 1.5, 0.03);
  std::vector<double> vx_imm, vx_steady, vx_manoeuvre, p_manoeuvre;
  run(z, ImmModels{0.05, 3.0, 0.02}, 0.0, &vx_imm, &p_manoeuvre);
  run(z, ImmModels{0.05, 0.05, 0.02}, 0.0, &vx_steady);
  run(z, ImmModels{3.0, 3.0, 0.02}, 0.0, &vx_manoeuvre);
  // vx[k] is after measurement k + 1; the walker moves from measurement 21 on.
  const auto framesTo = [](const std::vector<double>& vx, double v) {
    for (std::size_t k = 20; k < vx.size(); ++k)
      if (vx[k] >= v) return static_cast<int>(k) - 19;
    return 1000;
  };
  const int imm = framesTo(vx_imm, 1.2), steady = framesTo(vx_steady, 1.2),
            manoeuvre = framesTo(vx_manoeuvre, 1.2);
  EXPECT_LE(imm, manoeuvre + 2);
  EXPECT_GE(steady, imm + 5);
  double peak = 0.0;
  for (std::size_t k = 20; k < 30; ++k) peak = std::max(peak, p_manoeuvre[k]);
  EXPECT_GT(peak, 0.9);
  EXPECT_LT(p_manoeuvre.back(), 0.1);
  EXPECT_NEAR(vx_imm.back(), 1.5, 0.1);
}

// One frame 1 m off (a stray return merged into the cluster): with the Huber update the IMM's
// velocity moves less than the manoeuvring filter's, and it is back to steady soon after.
TEST(ImmCv, AOneFrameJumpIsNotAManoeuvre) {
  std::vector<Eigen::Vector3d> z = walker(50, 0, 1.5, 0.03);
  z[30].y() += 1.0;
  std::vector<double> p_manoeuvre;
  ImmConstantVelocity imm;
  ConstantVelocityKalman single;
  imm.init(z[0], kR, 25.0);
  single.init(z[0], kR, 25.0);
  double worst_imm = 0.0, worst_single = 0.0;
  for (std::size_t k = 1; k < z.size(); ++k) {
    imm.predict(kDt, ImmModels{0.05, 3.0, 0.02});
    single.predict(kDt, 3.0);
    imm.update(z[k], kR, 3.0);
    single.update(z[k], robustMeasurementVariance(single, z[k], kR, 3.0));
    p_manoeuvre.push_back(imm.modeProbability(ImmConstantVelocity::kManoeuvre));
    if (k >= 30) {
      worst_imm = std::max(worst_imm, std::abs(imm.velocity().y()));
      worst_single = std::max(worst_single, std::abs(single.velocity().y()));
    }
  }
  EXPECT_LT(worst_imm, worst_single);
  EXPECT_LT(worst_imm, 0.5);
  EXPECT_LT(p_manoeuvre.back(), 0.1);
  EXPECT_NEAR(imm.velocity().y(), 0.0, 0.1);
}

TEST(ImmCv, ModeProbabilitiesStayAProbability) {
  const std::vector<Eigen::Vector3d> z = walker(30, 10, 1.5, 0.05);
  ImmConstantVelocity f;
  f.init(z[0], kR, 25.0);
  EXPECT_DOUBLE_EQ(f.modeProbability(ImmConstantVelocity::kSteady), 0.5);
  for (std::size_t k = 1; k < z.size(); ++k) {
    const double dt = k % 7 == 0 ? 0.0 : (k % 11 == 0 ? 0.9 : kDt);  // equal stamps, a long gap
    f.predict(dt, ImmModels{0.05, 3.0, 0.5});
    f.update(z[k], kR, 3.0);
    const double a = f.modeProbability(ImmConstantVelocity::kSteady);
    const double b = f.modeProbability(ImmConstantVelocity::kManoeuvre);
    ASSERT_TRUE(std::isfinite(a) && std::isfinite(b));
    ASSERT_GE(a, 0.0);
    ASSERT_GE(b, 0.0);
    ASSERT_NEAR(a + b, 1.0, 1e-12);
    ASSERT_TRUE(f.state().allFinite());
  }
  // A measurement no model predicts at all (underflowing likelihoods) keeps the probabilities.
  f.predict(kDt, ImmModels{0.05, 3.0, 0.5});
  f.update(Eigen::Vector3d(1e6, -1e6, 0.0), kR, 0.0);
  EXPECT_NEAR(f.modeProbability(ImmConstantVelocity::kSteady) +
                  f.modeProbability(ImmConstantVelocity::kManoeuvre), 1.0, 1e-12);
  EXPECT_TRUE(f.state().allFinite());
}

}  // namespace
}  // namespace icanc
