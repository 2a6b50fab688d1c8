// The paper's Monte Carlo simulation (Section IV-C, Algorithm 1): random boxes are put through the
// very danger rules the DangerDetector nodelet runs (icanc::assessDanger), and the fraction deemed
// dangerous is compared with the paper's analytic P(D) = 150/360 * (1/2 + 1/(2n)).
//
// Algorithm 1, for i = 1..n boxes and num_trials trials each: generate i boxes, pass them through
// the danger rules, record the fraction dangerous; the average over the trials is Averages[i].
// Every box draws, independently (std::mt19937_64 seeded by the caller, and
// std::uniform_int_distribution):
//   distance  d ~ unif{1..range} m     the box's closest-point distance is exactly d
//   speed     s ~ unif{1..range} m/s   the velocity's planar norm is exactly s
//   orientation psi ~ unif{1..360} deg the direction of motion (see below)
//   bearing   b ~ unif{1..180}         where the box stands (see below); not part of the paper
// with reaction time alpha (1 s in the paper), so E1 = {d <= alpha * s}. The paper uses range = n
// = 60.
//
// Orientation. psi names the one-degree sector ((psi - 1), psi] of directions and the box moves
// along its bisector, heading psi - 0.5 deg. This is the discrete uniform draw the paper writes
// with the continuous-angle probability it computes: each 150-degree window of isMovingTowardMe
// (integer edges) holds exactly 150 of the 360 bisectors, so P(E2) = 150/360 in every section.
// Reading psi literally as the heading instead would be ill-defined here: the windows include
// their edges, so an exact integer heading would make P(E2) = 151/360, but headingDeg() cannot
// return an exact edge value (e.g. 195.0) for about half of the (edge, speed) pairs whatever
// double velocity is chosen, so the edge cases would be counted by rounding luck.
//
// Position. The box stands in the front half of the vehicle frame: its closest point lies at
// distance d on the bisector of bearing sector b, i.e. at bearing -90.5 + b deg in (-90, 90),
// and the box (0.5 m x 0.5 m x 2 m, z from -1 to 1 so the sensor height adds nothing) extends
// away from the vehicle from that corner. The bearing decides the section (left / front / right
// with the half-width w) but not the probability of danger, because P(E2) = 150/360 for every
// section and the orientation is drawn independently of the position.
//
// Exactness. d and s are integers and E1 compares them, so a rounding error of one ulp in
// closestPointDistance or getSpeedOfObject would flip every d == s box (about a quarter of
// d cos(b), d sin(b) pairs miss d by an ulp). The generator moves each corner and velocity by a
// few ulps, and its angle by at most 1e-6 rad, until closestPointDistance() returns exactly d
// and getSpeedOfObject() exactly s; it throws std::logic_error if it cannot.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "icanc/core/danger/danger.hpp"

namespace icanc {

struct MonteCarloParams {
  int max_boxes = 60;            // n: Algorithm 1's box counts 1..n
  int range = 60;                // d, s ~ unif{1..range}; the paper uses range = n = 60
  int trials = 1000;             // num_trials per box count
  double reaction_time_s = 1.0;  // alpha
  double half_width_m = 0.7;     // sections' half-width w (moves boxes between sections only)
  std::uint64_t seed = 1;
  // The danger rule assessDanger applies (DangerParams::model). kPredictive keeps DangerParams'
  // corridor defaults (margin 0.3 m, bumper 0.5 m, stopping margin 1 m) with half_width_m and
  // reaction_time_s from here; the generated boxes have exact velocities (velocity_std 0) and no
  // footprint parts. The paper's rule is also run on the very same boxes, for comparison.
  DangerModel model = DangerModel::kPaper;
};

// Empty when valid, else why not.
std::string validate(const MonteCarloParams& params);

// One generated box: what was drawn, and the kinematics handed to assessDanger.
struct GeneratedBox {
  int distance_m = 0;
  int speed_mps = 0;
  int orientation_deg = 0;  // psi in 1..360; the heading is psi - 0.5
  int bearing_sector = 0;   // 1..180; the closest point lies at bearing -90.5 + sector deg
  ObjectKinematics kinematics;
};

// GenerateBoxes of Algorithm 1. Builds its position and velocity tables once (range x 180 and
// range x 360 entries), so drawing a box costs four integer draws and two table look-ups.
class BoxGenerator {
 public:
  BoxGenerator(int range, std::uint64_t seed);

  GeneratedBox next();
  // The box for given draws (no randomness): what next() returns for them.
  GeneratedBox make(int distance_m, int speed_mps, int orientation_deg, int bearing_sector) const;

  int range() const { return range_; }

 private:
  int range_;
  std::mt19937_64 rng_;
  std::uniform_int_distribution<int> value_, orientation_, bearing_;
  std::vector<ObjectKinematics> boxes_;      // [(bearing_sector - 1) * range + d - 1], velocity 0
  std::vector<Eigen::Vector3d> velocities_;  // [(orientation - 1) * range + s - 1]
};

// One row of Algorithm 1's output.
struct BoxCountResult {
  int boxes = 0;                // i
  int trials = 0;
  std::int64_t dangerous = 0;   // dangerous boxes over all trials
  double mean_fraction = 0.0;   // Averages[i]: mean over trials of (dangerous / i)
  double std_fraction = 0.0;    // spread of the per-trial fraction (sample standard deviation)
  double analytic = 0.0;        // exact P(D) for the drawn distributions (see analyticDanger)
};

// Does the danger fraction depend on the number of boxes? (The paper's hypothesis: it does not.)
// Counts D_i dangerous of N_i = i * trials boxes per box count i.
struct DependenceTest {
  // Weighted least squares of the fraction on the box count, weights N_i (binomial variances).
  double slope_per_box = 0.0;
  double slope_se = 0.0;
  double slope_ci95_low = 0.0, slope_ci95_high = 0.0;
  // Chi-square test of homogeneity of the n proportions (one pooled fraction for all counts).
  double chi_square = 0.0;
  int dof = 0;
  double p_value = 1.0;
  // true when the slope's 95 % interval excludes 0 or p < 0.05.
  bool depends_on_box_count = false;
};

struct MonteCarloResult {
  MonteCarloParams params;
  std::vector<BoxCountResult> rows;  // box counts 1..max_boxes
  double mean_of_averages = 0.0;     // mean of Averages[1..n]: the paper's "approximately 21 %"
  double pooled_fraction = 0.0;      // all dangerous boxes / all boxes
  double analytic = 0.0;             // analyticDanger(range, alpha)
  double paper_analytic = 0.0;       // paperDangerProbability(range)
  std::int64_t boxes_assessed = 0;
  // Per section (left, front, right): boxes, moving toward (E2) and dangerous. P(E2) is 150/360
  // in each; P(D) is not quite, because near boxes fall in the front section more often.
  std::int64_t by_section[3] = {0, 0, 0};
  std::int64_t toward_by_section[3] = {0, 0, 0};
  std::int64_t dangerous_by_section[3] = {0, 0, 0};
  // The paper's rule on the same boxes (equal to pooled_fraction when params.model is kPaper), and
  // how many boxes both rules flag.
  double paper_rule_pooled_fraction = 0.0;
  std::int64_t dangerous_by_both = 0;
  DependenceTest dependence;
};

// Algorithm 1 with assessDanger as GetPercentDanger. Throws std::invalid_argument on bad params.
MonteCarloResult runMonteCarlo(const MonteCarloParams& params);

// The paper's P(D) = 150/360 * (1/2 + 1/(2n)) (alpha = 1).
double paperDangerProbability(int n);
// Exact P(D) = 150/360 * P(d <= alpha * s) for d, s ~ unif{1..range}, any alpha > 0. Equals
// paperDangerProbability(range) for alpha = 1.
double analyticDanger(int range, double reaction_time_s);

// The dependence test over Algorithm 1's rows.
DependenceTest testDependenceOnBoxCount(const std::vector<BoxCountResult>& rows);

// P(X > x) for X ~ chi-square with dof degrees of freedom (regularised upper incomplete gamma).
double chiSquareSurvival(double x, int dof);

}  // namespace icanc
