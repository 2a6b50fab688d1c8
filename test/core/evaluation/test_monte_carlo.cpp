// Pins the paper's Monte Carlo simulation (Section IV-C, Algorithm 1): boxes drawn as the paper
// states, judged by the DangerDetector's own assessDanger, land on P(D) = 150/360 (1/2 + 1/(2n)).
// A change to the danger rule (the <= of E1, the windows, the sections) moves these numbers.
#include <cmath>
#include <stdexcept>
#include <utility>

#include <gtest/gtest.h>

#include "icanc/core/danger/danger.hpp"
#include "icanc/core/evaluation/monte_carlo.hpp"

namespace icanc {
namespace {

constexpr std::uint64_t kSeed = 20250611;

// One run of the paper's configuration, shared by the tests that read it (~0.2 s).
const MonteCarloResult& paperRun() {
  static const MonteCarloResult result = [] {
    MonteCarloParams p;  // n = 60, range 60, 1000 trials, alpha = 1
    p.seed = kSeed;
    return runMonteCarlo(p);
  }();
  return result;
}

double binomialSigma(double p, double n) { return std::sqrt(p * (1.0 - p) / n); }

TEST(MonteCarloAnalytic, PapersFormulaAndItsValueAtSixty) {
  EXPECT_NEAR(paperDangerProbability(60), 0.2118, 5e-5);  // the paper's ".2118"
  EXPECT_NEAR(150.0 / 360.0 * 0.5, 5.0 / 24.0, 1e-15);    // its limit, ".2083"
  EXPECT_DOUBLE_EQ(paperDangerProbability(1), 150.0 / 360.0);
  // The exact sum over the discrete distributions is the paper's closed form for alpha = 1 ...
  for (int n = 1; n <= 200; ++n) EXPECT_NEAR(analyticDanger(n, 1.0), paperDangerProbability(n), 1e-15) << n;
  // ... and for alpha = 2: sum_s min(60, 2s) = 930 + 30 * 60 = 2730 of 3600 pairs.
  EXPECT_NEAR(analyticDanger(60, 2.0), 150.0 / 360.0 * 2730.0 / 3600.0, 1e-15);
  EXPECT_NEAR(analyticDanger(60, 0.5), 150.0 / 360.0 * 900.0 / 3600.0, 1e-15);  // sum floor(s/2)
}

TEST(BoxGenerator, DistanceAndSpeedAreExactlyTheDrawnIntegers) {
  const BoxGenerator gen(60, 1);
  int sections[3] = {0, 0, 0};
  for (int b = 1; b <= 180; ++b) {
    for (int d = 1; d <= 60; ++d) {
      const GeneratedBox box = gen.make(d, 1, 1, b);
      const ObjectKinematics& k = box.kinematics;
      ASSERT_EQ(closestPointDistance(k.aabb_min, k.aabb_max), double(d)) << "d " << d << " b " << b;
      const Eigen::Vector3d closest = Eigen::Vector3d::Zero().cwiseMax(k.aabb_min).cwiseMin(k.aabb_max);
      EXPECT_NEAR(std::atan2(closest.y(), closest.x()) * 180.0 / M_PI, -90.5 + b, 1e-4);  // angles nudged by <= 1e-6 rad
      EXPECT_EQ(closest.z(), 0.0);
      ++sections[static_cast<int>(getSection(closest.y(), 0.7)) - 1];  // as assessDanger
    }
  }
  EXPECT_GT(sections[0], 0);  // boxes land in all three sections
  EXPECT_GT(sections[1], 0);
  EXPECT_GT(sections[2], 0);
  for (int psi = 1; psi <= 360; ++psi) {
    for (int s = 1; s <= 60; ++s) {
      const Eigen::Vector3d& v = gen.make(1, s, psi, 90).kinematics.velocity;
      ASSERT_EQ(getSpeedOfObject(v), double(s)) << "s " << s << " psi " << psi;
      EXPECT_NEAR(headingDeg(v), psi - 0.5, 1e-4) << "s " << s << " psi " << psi;
    }
  }
}

TEST(BoxGenerator, EdgesOfE1AndOfTheFrontWindowThroughAssessDanger) {
  const BoxGenerator gen(60, 1);
  DangerParams alpha1;
  alpha1.reaction_time_s = 1.0;
  // Bearing sector 90: closest point at -0.5 deg, straight ahead -> front section.
  const auto judge = [&](int d, int s, int psi) {
    const GeneratedBox box = gen.make(d, s, psi, 90);
    const DangerAssessment a = assessDanger(box.kinematics, alpha1);
    EXPECT_EQ(a.section, Section::kFront);
    return a.dangerous;
  };
  EXPECT_TRUE(judge(7, 7, 180));   // d == alpha * s is dangerous (E1 is d <= theta)
  EXPECT_FALSE(judge(8, 7, 180));
  EXPECT_TRUE(judge(50, 50, 180));  // (at 60 m the -0.5 deg bearing is already the right section)
  EXPECT_TRUE(judge(1, 60, 180));
  EXPECT_FALSE(judge(3, 5, 105));  // heading 104.5: outside the front window [105, 255]
  EXPECT_TRUE(judge(3, 5, 106));   // heading 105.5
  EXPECT_TRUE(judge(3, 5, 255));   // heading 254.5
  EXPECT_FALSE(judge(3, 5, 256));  // heading 255.5
  // Exactly 150 of the 360 orientations count as moving toward, in each section.
  for (int sector : {1, 90, 180}) {  // right (-89.5 deg), front, left (+89.5 deg)
    int toward = 0;
    for (int psi = 1; psi <= 360; ++psi)
      toward += assessDanger(gen.make(1, 1, psi, sector).kinematics, alpha1).dangerous;
    EXPECT_EQ(toward, 150) << "bearing sector " << sector;
  }
}

TEST(MonteCarlo, PapersRunLandsOnItsAnalyticValue) {
  const MonteCarloResult& r = paperRun();
  ASSERT_EQ(r.rows.size(), 60u);
  EXPECT_EQ(r.boxes_assessed, 1000 * 60 * 61 / 2);
  EXPECT_NEAR(r.analytic, 0.21180555555555555, 1e-15);
  // The acceptance bound ...
  EXPECT_NEAR(r.mean_of_averages, 0.2118, 0.005);
  // ... and what the sampling error allows: sd of the mean of averages is
  // sqrt(p(1-p)/1000 * sum 1/i) / 60 = 0.00047; four of them.
  EXPECT_NEAR(r.mean_of_averages, r.analytic, 0.0019);
  EXPECT_NEAR(r.pooled_fraction, r.analytic, 4 * binomialSigma(r.analytic, double(r.boxes_assessed)));
}

TEST(MonteCarlo, FractionPerBoxCountMatchesTheAnalyticValue) {
  const MonteCarloResult& r = paperRun();
  for (int n : {1, 2, 5, 10, 30, 59, 60}) {
    const BoxCountResult& row = r.rows[n - 1];
    EXPECT_EQ(row.boxes, n);
    EXPECT_EQ(row.trials, 1000);
    EXPECT_NEAR(row.mean_fraction, row.dangerous / (1000.0 * n), 1e-12);
    EXPECT_NEAR(row.mean_fraction, r.analytic, 4 * binomialSigma(r.analytic, 1000.0 * n)) << n;
    // The per-frame fraction narrows with more boxes: sd sqrt(p(1-p)/n).
    EXPECT_NEAR(row.std_fraction, binomialSigma(r.analytic, n), 0.1 * binomialSigma(r.analytic, n)) << n;
  }
}

TEST(MonteCarlo, EverySectionHasTheSameTowardFraction) {
  // P(E2) = 150/360 whichever section the box stands in (the paper's independence of E1 and E2).
  const MonteCarloResult& r = paperRun();
  const double p_e2 = 150.0 / 360.0;
  for (int s = 0; s < 3; ++s) {
    ASSERT_GT(r.by_section[s], 30000) << s;
    const double f = double(r.toward_by_section[s]) / r.by_section[s];
    EXPECT_NEAR(f, p_e2, 4 * binomialSigma(p_e2, r.by_section[s])) << "section " << s;
  }
  EXPECT_EQ(r.by_section[0] + r.by_section[1] + r.by_section[2], r.boxes_assessed);
}

TEST(MonteCarlo, NoDependenceOnTheNumberOfBoxes) {
  const DependenceTest& t = paperRun().dependence;
  EXPECT_EQ(t.dof, 59);
  EXPECT_FALSE(t.depends_on_box_count) << "slope " << t.slope_per_box << " p " << t.p_value;
  EXPECT_LE(t.slope_ci95_low, 0.0);
  EXPECT_GE(t.slope_ci95_high, 0.0);
  EXPECT_LT(std::fabs(t.slope_per_box), 5e-5);
}

TEST(MonteCarlo, DependenceTestDetectsATrend) {
  std::vector<BoxCountResult> rows;
  for (int i = 1; i <= 60; ++i) {
    BoxCountResult r;
    r.boxes = i;
    r.trials = 1000;
    r.dangerous = std::llround(1000.0 * i * (0.15 + 0.002 * i));
    rows.push_back(r);
  }
  const DependenceTest t = testDependenceOnBoxCount(rows);
  EXPECT_TRUE(t.depends_on_box_count);
  EXPECT_GT(t.slope_ci95_low, 0.0);
  EXPECT_NEAR(t.slope_per_box, 0.002, 1e-4);
  EXPECT_LT(t.p_value, 1e-12);
}

TEST(MonteCarlo, ReactionTimeEntersThroughTheDangerRule) {
  MonteCarloParams p;
  p.max_boxes = 20;
  p.trials = 500;
  p.reaction_time_s = 2.0;
  p.seed = kSeed;
  const MonteCarloResult r = runMonteCarlo(p);
  EXPECT_NEAR(r.analytic, analyticDanger(60, 2.0), 1e-15);
  EXPECT_NEAR(r.pooled_fraction, r.analytic, 4 * binomialSigma(r.analytic, double(r.boxes_assessed)));
  EXPECT_GT(r.pooled_fraction, 0.3);  // far from alpha = 1's 0.21
}

// The predictive model on Algorithm 1's boxes (corridor |y| <= 0.7 + 0.3 m, 0 <= x <= 1.5 m),
// cases worked by hand where it and the paper's rule disagree.
TEST(BoxGenerator, PredictiveModelOnTheSameBoxes) {
  const BoxGenerator gen(60, 1);
  DangerParams paper, predictive;
  paper.reaction_time_s = predictive.reaction_time_s = 1.0;
  predictive.model = DangerModel::kPredictive;
  const auto both = [&](int d, int s, int psi, int sector) {
    const ObjectKinematics k = gen.make(d, s, psi, sector).kinematics;
    return std::make_pair(assessDanger(k, paper), assessDanger(k, predictive));
  };
  // 4 m ahead closing at 3 m/s: 4 > 3 * 1 for the paper, but its near face reaches the corridor's
  // end (1.5 m) after 2.5 / 3 s.
  auto r = both(4, 3, 181, 90);
  EXPECT_FALSE(r.first.dangerous);
  EXPECT_TRUE(r.second.dangerous);
  EXPECT_NEAR(r.second.time_to_corridor_s, 2.5 / 3.0, predictive.time_step_s);
  // 3 m away at -45.5 deg (x >= 2.1 m), crossing to the left at 5 m/s: the paper's rule flags it
  // (right section, heading 90.5), but it crosses 0.6 m beyond the corridor's end.
  r = both(3, 5, 91, 45);
  EXPECT_TRUE(r.first.dangerous);
  EXPECT_FALSE(r.second.dangerous);
  // Standing in the corridor 1 m ahead, moving away: the paper's windows say safe, it is in the path.
  r = both(1, 1, 1, 90);
  EXPECT_FALSE(r.first.dangerous);
  EXPECT_TRUE(r.second.dangerous);
  EXPECT_EQ(r.second.time_to_corridor_s, 0.0);
  // 20 m ahead closing at 10 m/s: neither.
  r = both(20, 10, 181, 90);
  EXPECT_FALSE(r.first.dangerous);
  EXPECT_FALSE(r.second.dangerous);
}

TEST(MonteCarlo, PredictiveRunScoresThePaperRuleOnTheSameBoxes) {
  MonteCarloParams p;
  p.max_boxes = 10;
  p.trials = 300;
  p.seed = kSeed;
  const MonteCarloResult paper = runMonteCarlo(p);
  EXPECT_EQ(paper.paper_rule_pooled_fraction, paper.pooled_fraction);
  EXPECT_EQ(double(paper.dangerous_by_both), paper.pooled_fraction * paper.boxes_assessed);
  p.model = DangerModel::kPredictive;
  const MonteCarloResult predictive = runMonteCarlo(p);
  ASSERT_EQ(predictive.boxes_assessed, paper.boxes_assessed);
  EXPECT_EQ(predictive.paper_rule_pooled_fraction, paper.pooled_fraction);  // same boxes
  // The corridor is a 1.5 m x 2 m patch of a 60 m half disc: far fewer boxes reach it within 1 s.
  EXPECT_LT(predictive.pooled_fraction, 0.5 * paper.pooled_fraction);
  EXPECT_GT(predictive.pooled_fraction, 0.0);
  const double n = double(predictive.boxes_assessed);
  EXPECT_LE(double(predictive.dangerous_by_both), predictive.pooled_fraction * n);
  EXPECT_GT(predictive.dangerous_by_both, 0);
  p.model = DangerModel::kInvalid;
  EXPECT_THROW(runMonteCarlo(p), std::invalid_argument);
}

TEST(MonteCarlo, SeededRunsRepeat) {
  MonteCarloParams p;
  p.max_boxes = 8;
  p.trials = 200;
  p.seed = 5;
  const MonteCarloResult a = runMonteCarlo(p), b = runMonteCarlo(p);
  p.seed = 6;
  const MonteCarloResult c = runMonteCarlo(p);
  bool differs = false;
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    EXPECT_EQ(a.rows[i].dangerous, b.rows[i].dangerous);
    EXPECT_EQ(a.rows[i].mean_fraction, b.rows[i].mean_fraction);
    differs |= a.rows[i].dangerous != c.rows[i].dangerous;
  }
  EXPECT_TRUE(differs);
}

TEST(MonteCarlo, RejectsBadParameters) {
  MonteCarloParams p;
  p.max_boxes = 0;
  EXPECT_THROW(runMonteCarlo(p), std::invalid_argument);
  p = MonteCarloParams();
  p.trials = 0;
  EXPECT_THROW(runMonteCarlo(p), std::invalid_argument);
  p = MonteCarloParams();
  p.reaction_time_s = 0.0;
  EXPECT_THROW(runMonteCarlo(p), std::invalid_argument);
  p = MonteCarloParams();
  p.range = 0;
  EXPECT_THROW(runMonteCarlo(p), std::invalid_argument);
  EXPECT_THROW(BoxGenerator(60, 1).make(61, 1, 1, 1), std::out_of_range);
  EXPECT_THROW(BoxGenerator(60, 1).make(1, 1, 0, 1), std::out_of_range);
}

TEST(ChiSquareSurvival, KnownCriticalValues) {
  EXPECT_NEAR(chiSquareSurvival(3.841459, 1), 0.05, 1e-6);
  EXPECT_NEAR(chiSquareSurvival(18.307038, 10), 0.05, 1e-6);
  EXPECT_NEAR(chiSquareSurvival(77.930524, 59), 0.05, 1e-5);
  EXPECT_NEAR(chiSquareSurvival(2.0, 2), std::exp(-1.0), 1e-12);  // dof 2: exp(-x/2)
  EXPECT_NEAR(chiSquareSurvival(40.0, 2), std::exp(-20.0), 1e-15);
  EXPECT_DOUBLE_EQ(chiSquareSurvival(0.0, 5), 1.0);
}

}  // namespace
}  // namespace icanc
