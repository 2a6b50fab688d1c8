#include "icanc/core/evaluation/monte_carlo.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace icanc {
namespace {

constexpr double kDegToRad = M_PI / 180.0;
constexpr int kBearingSectors = 180;  // one-degree sectors of the front half
constexpr int kOrientations = 360;
constexpr int kMaxUlps = 2;           // search radius for the exact distance / speed ...
constexpr int kMaxAngleSteps = 1000;  // ... around angles nudged by up to 1e-6 rad

// The box's footprint beyond its closest corner, and its vertical extent around the sensor.
constexpr double kBoxSizeM = 0.5;
constexpr double kBoxZMin = -1.0, kBoxZMax = 1.0;

double ulpStep(double x, int k) {
  const double toward = k > 0 ? std::numeric_limits<double>::infinity()
                              : -std::numeric_limits<double>::infinity();
  for (int i = 0; i < std::abs(k); ++i) x = std::nextafter(x, toward);
  return x;
}

// Finds a point (x, y) of norm `magnitude` near angle `angle` [rad] that `exact` accepts: tries
// (magnitude cos a, magnitude sin a) and its neighbours a few ulps away, for a = angle, then
// angles nudged by 1e-9 rad steps. (One coordinate alone cannot always fix the norm: near the
// axes the small one moves it by far less than an ulp.)
template <class Exact>
bool searchExact(double magnitude, double angle, Exact exact) {
  for (int step = 0; step <= kMaxAngleSteps; ++step) {
    const double a = angle + (step % 2 ? 1 : -1) * ((step + 1) / 2) * 1e-9;
    const double x0 = magnitude * std::cos(a), y0 = magnitude * std::sin(a);
    for (int i = -kMaxUlps; i <= kMaxUlps; ++i)
      for (int j = -kMaxUlps; j <= kMaxUlps; ++j)
        if (exact(ulpStep(x0, i), ulpStep(y0, j))) return true;
  }
  return false;
}

// A box whose closest point to the origin is the corner (cx, cy, 0), extending away from it.
ObjectKinematics boxFromCorner(double cx, double cy) {
  ObjectKinematics o;
  const double y_far = cy >= 0.0 ? cy + kBoxSizeM : cy - kBoxSizeM;
  o.aabb_min = Eigen::Vector3d(cx, std::min(cy, y_far), kBoxZMin);
  o.aabb_max = Eigen::Vector3d(cx + kBoxSizeM, std::max(cy, y_far), kBoxZMax);
  o.center = 0.5 * (o.aabb_min + o.aabb_max);
  return o;
}

ObjectKinematics exactBox(int distance_m, int bearing_sector) {
  ObjectKinematics found;
  const bool ok = searchExact(distance_m, (-90.5 + bearing_sector) * kDegToRad, [&](double x, double y) {
    found = boxFromCorner(x, y);
    return closestPointDistance(found.aabb_min, found.aabb_max) == double(distance_m);
  });
  if (!ok) {
    std::ostringstream why;
    why << "monte carlo: no box at exactly " << distance_m << " m, bearing sector " << bearing_sector;
    throw std::logic_error(why.str());
  }
  return found;
}

Eigen::Vector3d exactVelocity(int speed_mps, int orientation_deg) {
  Eigen::Vector3d found;
  const bool ok = searchExact(speed_mps, (orientation_deg - 0.5) * kDegToRad, [&](double x, double y) {
    found = Eigen::Vector3d(x, y, 0.0);
    return getSpeedOfObject(found) == double(speed_mps);
  });
  if (!ok) {
    std::ostringstream why;
    why << "monte carlo: no velocity of exactly " << speed_mps << " m/s, orientation "
        << orientation_deg;
    throw std::logic_error(why.str());
  }
  return found;
}

int sectionIndex(Section s) {
  switch (s) {
    case Section::kLeft: return 0;
    case Section::kFront: return 1;
    case Section::kRight: return 2;
  }
  return 1;
}

// Regularised lower incomplete gamma P(a, x) by its series (x < a + 1).
double gammaPSeries(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < 10000; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::fabs(term) < std::fabs(sum) * 1e-15) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

// Regularised upper incomplete gamma Q(a, x) by its continued fraction (x >= a + 1; Lentz).
double gammaQContinuedFraction(double a, double x) {
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1.0) < 1e-15) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

}  // namespace

std::string validate(const MonteCarloParams& p) {
  std::ostringstream why;
  if (p.max_boxes < 1)
    why << "monte carlo: max_boxes must be >= 1 (got " << p.max_boxes << ")";
  else if (p.range < 1 || p.range > 1000)
    why << "monte carlo: range must be in [1, 1000] (got " << p.range << ")";
  else if (p.trials < 1)
    why << "monte carlo: trials must be >= 1 (got " << p.trials << ")";
  else if (!(p.reaction_time_s > 0.0) || !std::isfinite(p.reaction_time_s))
    why << "monte carlo: reaction_time_s must be > 0 (got " << p.reaction_time_s << ")";
  else if (!(p.half_width_m > 0.0))
    why << "monte carlo: half_width_m must be > 0 (got " << p.half_width_m << ")";
  else if (p.model == DangerModel::kInvalid)
    why << "monte carlo: model must be paper or predictive";
  return why.str();
}

BoxGenerator::BoxGenerator(int range, std::uint64_t seed)
    : range_(range), rng_(seed), value_(1, range), orientation_(1, kOrientations),
      bearing_(1, kBearingSectors) {
  if (range < 1) throw std::invalid_argument("monte carlo: range must be >= 1");
  boxes_.reserve(std::size_t(kBearingSectors) * range);
  for (int b = 1; b <= kBearingSectors; ++b)
    for (int d = 1; d <= range; ++d) boxes_.push_back(exactBox(d, b));
  velocities_.reserve(std::size_t(kOrientations) * range);
  for (int o = 1; o <= kOrientations; ++o)
    for (int s = 1; s <= range; ++s) velocities_.push_back(exactVelocity(s, o));
}

GeneratedBox BoxGenerator::make(int d, int s, int psi, int b) const {
  if (d < 1 || d > range_ || s < 1 || s > range_ || psi < 1 || psi > kOrientations || b < 1 ||
      b > kBearingSectors)
    throw std::out_of_range("monte carlo: draw outside its distribution");
  GeneratedBox box;
  box.distance_m = d;
  box.speed_mps = s;
  box.orientation_deg = psi;
  box.bearing_sector = b;
  box.kinematics = boxes_[std::size_t(b - 1) * range_ + (d - 1)];
  box.kinematics.velocity = velocities_[std::size_t(psi - 1) * range_ + (s - 1)];
  return box;
}

GeneratedBox BoxGenerator::next() {
  const int d = value_(rng_);
  const int s = value_(rng_);
  const int psi = orientation_(rng_);
  const int b = bearing_(rng_);
  return make(d, s, psi, b);
}

double paperDangerProbability(int n) { return 150.0 / 360.0 * (0.5 + 0.5 / n); }

double analyticDanger(int range, double reaction_time_s) {
  // P(E1) = P(d <= alpha * s) = sum over s of #{d <= alpha * s} / range^2, with the product
  // computed as assessDanger computes its threshold.
  double count = 0.0;
  for (int s = 1; s <= range; ++s)
    count += std::min<double>(range, std::floor(double(s) * reaction_time_s));
  return 150.0 / 360.0 * count / (double(range) * range);
}

double chiSquareSurvival(double x, int dof) {
  if (dof < 1) throw std::invalid_argument("chiSquareSurvival: dof must be >= 1");
  if (!(x > 0.0)) return 1.0;
  const double a = 0.5 * dof, hx = 0.5 * x;
  return hx < a + 1.0 ? 1.0 - gammaPSeries(a, hx) : gammaQContinuedFraction(a, hx);
}

DependenceTest testDependenceOnBoxCount(const std::vector<BoxCountResult>& rows) {
  DependenceTest t;
  double n_sum = 0.0, d_sum = 0.0, xw = 0.0, yw = 0.0;
  for (const auto& r : rows) {
    const double n = double(r.boxes) * r.trials;
    n_sum += n;
    d_sum += double(r.dangerous);
    xw += n * r.boxes;
  }
  if (rows.size() < 2 || n_sum <= 0.0) return t;
  const double p = d_sum / n_sum;
  xw /= n_sum;
  yw = p;
  double sxx = 0.0, sxy = 0.0, chi = 0.0;
  for (const auto& r : rows) {
    const double n = double(r.boxes) * r.trials;
    const double y = double(r.dangerous) / n;
    sxx += n * (r.boxes - xw) * (r.boxes - xw);
    sxy += n * (r.boxes - xw) * (y - yw);
    if (p > 0.0 && p < 1.0) chi += (r.dangerous - n * p) * (r.dangerous - n * p) / (n * p * (1.0 - p));
  }
  t.slope_per_box = sxy / sxx;
  t.slope_se = std::sqrt(p * (1.0 - p) / sxx);
  t.slope_ci95_low = t.slope_per_box - 1.959964 * t.slope_se;
  t.slope_ci95_high = t.slope_per_box + 1.959964 * t.slope_se;
  t.chi_square = chi;
  t.dof = int(rows.size()) - 1;
  t.p_value = chiSquareSurvival(chi, t.dof);
  t.depends_on_box_count = t.slope_ci95_low > 0.0 || t.slope_ci95_high < 0.0 || t.p_value < 0.05;
  return t;
}

MonteCarloResult runMonteCarlo(const MonteCarloParams& params) {
  const std::string why = validate(params);
  if (!why.empty()) throw std::invalid_argument(why);

  MonteCarloResult result;
  result.params = params;
  result.analytic = analyticDanger(params.range, params.reaction_time_s);
  result.paper_analytic = paperDangerProbability(params.range);

  DangerParams danger;
  danger.half_width_m = params.half_width_m;
  danger.reaction_time_s = params.reaction_time_s;
  danger.model = params.model;
  DangerParams paper_rule = danger;
  paper_rule.model = DangerModel::kPaper;

  BoxGenerator generator(params.range, params.seed);
  std::int64_t all_dangerous = 0, paper_rule_dangerous = 0;
  for (int i = 1; i <= params.max_boxes; ++i) {
    BoxCountResult row;
    row.boxes = i;
    row.trials = params.trials;
    row.analytic = result.analytic;
    double sum = 0.0, sum_sq = 0.0;
    for (int j = 0; j < params.trials; ++j) {
      int dangerous = 0;
      for (int k = 0; k < i; ++k) {  // GenerateBoxes(i), PublishBoxes, GetPercentDanger(i)
        const GeneratedBox box = generator.next();
        const DangerAssessment a = assessDanger(box.kinematics, danger);
        const int section = sectionIndex(a.section);
        ++result.by_section[section];
        result.toward_by_section[section] += a.moving_toward;
        const bool by_paper_rule = params.model == DangerModel::kPaper
                                       ? a.dangerous
                                       : assessDanger(box.kinematics, paper_rule).dangerous;
        paper_rule_dangerous += by_paper_rule;
        if (a.dangerous) {
          ++dangerous;
          ++result.dangerous_by_section[section];
          result.dangerous_by_both += by_paper_rule;
        }
      }
      const double pct_danger = double(dangerous) / i;
      sum += pct_danger;
      sum_sq += pct_danger * pct_danger;
      row.dangerous += dangerous;
    }
    row.mean_fraction = sum / params.trials;
    row.std_fraction = params.trials > 1
        ? std::sqrt(std::max(0.0, (sum_sq - params.trials * row.mean_fraction * row.mean_fraction) /
                                      (params.trials - 1)))
        : 0.0;
    result.mean_of_averages += row.mean_fraction;
    result.boxes_assessed += std::int64_t(i) * params.trials;
    all_dangerous += row.dangerous;
    result.rows.push_back(row);
  }
  result.mean_of_averages /= params.max_boxes;
  result.pooled_fraction = double(all_dangerous) / double(result.boxes_assessed);
  result.paper_rule_pooled_fraction = double(paper_rule_dangerous) / double(result.boxes_assessed);
  result.dependence = testDependenceOnBoxCount(result.rows);
  return result;
}

}  // namespace icanc
