#include "icanc/core/evaluation/evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <sstream>

#include "icanc/core/common/percentile.hpp"
#include "icanc/core/tracking/hungarian.hpp"
#include "icanc/core/light/light_controller.hpp"

namespace icanc {
namespace {

double ratio(double a, double b) { return b > 0.0 ? a / b : 0.0; }

bool inScope(const Eigen::Vector2d& c, const EvalParams& p) {
  if (c.norm() > p.max_range_m) return false;
  const double bearing = std::abs(std::atan2(c.y(), c.x())) * 180.0 / M_PI;
  return bearing <= p.fov_half_angle_deg;
}

// Optimal one-to-one matching of true objects to detections by distance to the true footprint,
// gated; ties inside a footprint are broken by centre distance.
std::vector<int> match(const std::vector<TruthObject>& truth,
                       const std::vector<DetectedObject>& dets, double gate) {
  if (truth.empty() || dets.empty()) return std::vector<int>(truth.size(), -1);
  Eigen::MatrixXd cost(truth.size(), dets.size());
  for (std::size_t i = 0; i < truth.size(); ++i)
    for (std::size_t j = 0; j < dets.size(); ++j) {
      const double d = distanceToFootprint(truth[i], dets[j].center);
      cost(i, j) = d <= gate ? d + 1e-3 * (truth[i].center - dets[j].center).norm() : kForbiddenCost;
    }
  return solveAssignment(cost);
}

const TruthObject* unscoredObjectAt(const std::vector<TruthObject>& all_truth,
                                    const DetectedObject& det, const EvalParams& params) {
  for (const TruthObject& o : all_truth)
    if (distanceToFootprint(o, det.center) <= params.match_distance_m) return &o;
  return nullptr;
}

// An unmatched true object merged into a matched detection: the first matched detection whose box
// holds its centre (EvalReport::detection_merged), else -1.
int mergedInto(const TruthObject& o, const std::vector<DetectedObject>& dets,
               const std::vector<bool>& matched) {
  for (std::size_t j = 0; j < dets.size(); ++j) {
    const DetectedObject& d = dets[j];
    if (matched[j] && d.has_aabb && Eigen::AlignedBox2d(d.aabb_min, d.aabb_max).contains(o.center))
      return static_cast<int>(j);
  }
  return -1;
}

// Half extents along x and y of the true oriented footprint's axis-aligned bounds.
Eigen::Vector2d axisAlignedReach(const TruthObject& o) {
  const Eigen::Vector2d half = 0.5 * o.size.cwiseAbs();
  const double c = std::abs(std::cos(o.yaw)), s = std::abs(std::sin(o.yaw));
  return Eigen::Vector2d(c * half.x() + s * half.y(), s * half.x() + c * half.y());
}

// The true oriented footprint as axis-aligned parts (the form of icanc/Obstacle's footprint): a
// grid of cells at most kPerfectCellM on a side along the box's own axes, each part the bounds of
// one cell, so a yawed car is not judged by the bounds of the whole box.
constexpr double kPerfectCellM = 0.15;
std::vector<Eigen::AlignedBox2d> orientedFootprint(const TruthObject& o) {
  const Eigen::Vector2d size = o.size.cwiseAbs();
  const int nx = std::max(1, static_cast<int>(std::ceil(size.x() / kPerfectCellM)));
  const int ny = std::max(1, static_cast<int>(std::ceil(size.y() / kPerfectCellM)));
  const Eigen::Rotation2Dd rotation(o.yaw);
  const Eigen::Vector2d cell(size.x() / nx, size.y() / ny);
  std::vector<Eigen::AlignedBox2d> parts;
  parts.reserve(static_cast<std::size_t>(nx) * ny);
  for (int i = 0; i < nx; ++i) {
    for (int j = 0; j < ny; ++j) {
      const Eigen::Vector2d lo = -0.5 * size + Eigen::Vector2d(i * cell.x(), j * cell.y());
      Eigen::AlignedBox2d part;
      for (int corner = 0; corner < 4; ++corner) {
        const Eigen::Vector2d p = lo + Eigen::Vector2d(corner & 1 ? cell.x() : 0.0,
                                                       corner & 2 ? cell.y() : 0.0);
        part.extend(o.center + rotation * p);
      }
      parts.push_back(part);
    }
  }
  return parts;
}

// A true object's velocity over ground: its labelled relative velocity plus the frame's ego twist
// at its centre.
Eigen::Vector2d overGround(const TruthObject& o, const EvalFrame& frame) {
  return o.velocity + frame.ego_velocity + frame.ego_yaw_rate * Eigen::Vector2d(-o.center.y(), o.center.x());
}

Outcome outcomeOf(bool truly_dangerous, bool predicted) {
  return truly_dangerous ? (predicted ? Outcome::kTruePositive : Outcome::kFalseNegative)
                         : (predicted ? Outcome::kFalsePositive : Outcome::kTrueNegative);
}

void count(Confusion& c, Outcome outcome) {
  switch (outcome) {
    case Outcome::kTruePositive: ++c.tp; break;
    case Outcome::kFalsePositive: ++c.fp; break;
    case Outcome::kFalseNegative: ++c.fn; break;
    case Outcome::kTrueNegative: ++c.tn; break;
    case Outcome::kDontCare: break;
    case Outcome::kStandingApart: break;
  }
}

}  // namespace

ObjectKinematics perfectTrack(const TruthObject& o, const EvalFrame& frame, double static_speed_mps) {
  ObjectKinematics k;
  k.ego_velocity = frame.ego_velocity;
  k.ego_yaw_rate = frame.ego_yaw_rate;
  k.ego_path = frame.ego_path;
  const Eigen::Vector2d reach = axisAlignedReach(o);
  k.center << o.center, 0.0;
  k.aabb_min << o.center - reach, 0.0;
  k.aabb_max << o.center + reach, 0.0;
  k.footprint = orientedFootprint(o);
  if (o.has_velocity) {
    k.velocity << o.velocity, 0.0;
    if (frame.ego_motion)
      k.motion = overGround(o, frame).norm() < static_speed_mps ? MotionState::kStatic : MotionState::kMoving;
  }
  return k;
}

bool standsApart(const TruthObject& o, const EvalFrame& frame, const EvalParams& params) {
  if (!o.dangerous || o.horizon_cut || params.danger.model != DangerModel::kPredictive) return false;
  const ObjectKinematics k = perfectTrack(o, frame, params.static_speed_mps);
  return k.motion == MotionState::kStatic && sweptPathTimeToReach(k, params.danger) < 0.0;
}

Eigen::AlignedBox2d footprintBounds(const TruthObject& truth) {
  const Eigen::Vector2d reach = axisAlignedReach(truth);
  return Eigen::AlignedBox2d(truth.center - reach, truth.center + reach);
}

const char* toString(Outcome outcome) {
  switch (outcome) {
    case Outcome::kTruePositive: return "TP";
    case Outcome::kFalsePositive: return "FP";
    case Outcome::kFalseNegative: return "FN";
    case Outcome::kTrueNegative: return "TN";
    case Outcome::kDontCare: return "DC";
    case Outcome::kStandingApart: return "SA";
  }
  return "?";
}

double distanceToFootprint(const TruthObject& truth, const Eigen::Vector2d& point) {
  const Eigen::Vector2d d = point - truth.center;
  const double c = std::cos(truth.yaw), s = std::sin(truth.yaw);
  const Eigen::Vector2d local(c * d.x() + s * d.y(), -s * d.x() + c * d.y());
  const Eigen::Vector2d outside = (local.cwiseAbs() - 0.5 * truth.size.cwiseAbs()).cwiseMax(0.0);
  return outside.norm();
}

double Confusion::precision() const { return ratio(tp, tp + fp); }
double Confusion::recall() const { return ratio(tp, tp + fn); }
double Confusion::accuracy() const { return ratio(tp + tn, tp + tn + fp + fn); }
double Confusion::f1() const { return ratio(2.0 * tp, 2.0 * tp + fp + fn); }

double EvalReport::velocityAgreesShare() const {
  return ratio(static_cast<double>(detection_velocity_agrees),
               static_cast<double>(detection.tp + detection.fn));
}

EvalReport evaluate(const std::vector<EvalFrame>& frames, const EvalParams& params,
                    std::vector<ScoredRow>* rows) {
  EvalReport r;
  r.velocity_agree_mps = params.velocity_agree_mps;
  r.frames = frames.size();
  std::vector<double> latencies;
  std::size_t on_frames = 0;
  double velocity_sq = 0.0, velocity_sq_settled = 0.0, offset_step_sq = 0.0;
  // Per true id, its last match: the detection id (id switches) and, while it was matched in the
  // previous scored frame, the detected centre's offset from the true centre (offset steps).
  struct LastMatch {
    std::uint32_t det_id = 0;
    Eigen::Vector2d offset = Eigen::Vector2d::Zero();
    bool consecutive = false;
  };
  std::map<std::uint32_t, LastMatch> last_match;
  std::vector<double> near_bias, side_bias, static_speeds;
  LightControllerParams lamp;
  lamp.tau_s = params.lamp_tau_s;
  lamp.recheck_below_s = params.lamp_recheck_below_s;
  lamp.watchdog_enabled = false;  // frames are given, not awaited
  LightController truth_lamp(lamp), perfect_lamp(lamp);
  LampCauseLog causes(lamp);
  std::size_t truth_on_frames = 0, perfect_on_frames = 0;
  // On perfect tracks the true box is the whole object: footprint_margin_m, which makes up for
  // what the LiDAR does not see of it, is not added.
  DangerParams perfect_danger = params.danger;
  perfect_danger.footprint_margin_m = 0.0;
  DangerHysteresis perfect_hysteresis(perfect_danger);
  const bool hysteresis = params.danger.model == DangerModel::kPredictive;

  struct Episode {
    bool open = false;
    double entry_t = 0.0;  // corridor entry time predicted at the episode's start
    double first_on = -1.0;
  };
  std::map<std::uint32_t, Episode> episodes;
  const auto close_episode = [&](Episode& e) {
    if (!e.open) return;
    ++r.episodes;
    if (e.first_on >= 0.0) {
      ++r.caught;
      r.lead_times_s.push_back(e.entry_t - e.first_on);
    }
    e = Episode();
  };

  for (const EvalFrame& f : frames) {
    if (!f.processed) continue;
    ++r.processed;
    r.ego_motion_faults += f.ego_motion_fault;
    const bool has_ego = f.ego_motion;
    on_frames += f.lamp_on;
    bool any_truly_dangerous = false;
    for (const TruthObject& o : f.truth) any_truly_dangerous |= o.dangerous;
    truth_lamp.onInput(f.t, any_truly_dangerous);
    truth_on_frames += truth_lamp.on();
    latencies.push_back(f.latency_ms);
    causes.beginFrame(f.t);

    std::vector<TruthObject> truth;
    for (const TruthObject& o : f.truth)
      if (o.num_points >= params.min_points && inScope(o.center, params)) truth.push_back(o);
    std::vector<DetectedObject> dets;
    for (const DetectedObject& d : f.detections) {
      if (inScope(d.center, params)) dets.push_back(d);
      else if (d.dangerous) causes.flag(LampCause::kUnscored);
    }
    const std::vector<int> m = match(truth, dets, params.match_distance_m);
    std::set<std::uint32_t> flagged_ids;  // true objects flagged (match or fragment) this frame
    bool any_perfect_flag = false;
    std::set<std::uint32_t> perfect_flagged;
    std::set<std::uint32_t> apart;  // dangerous by the corridor, beside the swept path
    for (const TruthObject& o : f.truth)
      if (standsApart(o, f, params)) apart.insert(o.id);
    for (const TruthObject& o : truth) {
      const DangerAssessment a = assessDanger(perfectTrack(o, f, params.static_speed_mps), perfect_danger);
      const bool flagged = hysteresis ? perfect_hysteresis.update(o.id, a, f.t) : a.dangerous;
      if (!o.horizon_cut && !apart.count(o.id)) count(r.perfect_tracks, outcomeOf(o.dangerous, flagged));
      any_perfect_flag |= flagged;
      if (flagged) perfect_flagged.insert(o.id);
    }
    perfect_lamp.onInput(f.t, any_perfect_flag);
    perfect_on_frames += perfect_lamp.on();

    // Detections left over by the one-to-one matching that lie within the match distance of a
    // true object's footprint are fragments of it (a car's roof scan line, a split wall): they
    // count for its danger, not as false alarms of their own.
    std::vector<bool> det_used(dets.size(), false);
    std::vector<int> flagged_by(truth.size(), -1);  // a dangerous fragment of each true object
    for (std::size_t i = 0; i < truth.size(); ++i)
      if (m[i] >= 0) det_used[m[i]] = true;
    std::vector<int> fragment_of(dets.size(), -1);
    for (std::size_t j = 0; j < dets.size(); ++j) {
      if (det_used[j]) continue;
      double nearest = params.match_distance_m;
      for (std::size_t i = 0; i < truth.size(); ++i) {
        const double d = distanceToFootprint(truth[i], dets[j].center);
        if (d <= nearest) {
          nearest = d;
          fragment_of[j] = static_cast<int>(i);
        }
      }
      if (fragment_of[j] >= 0 && dets[j].dangerous && flagged_by[fragment_of[j]] < 0)
        flagged_by[fragment_of[j]] = static_cast<int>(j);
    }

    for (std::size_t i = 0; i < truth.size(); ++i) {
      const TruthObject& o = truth[i];
      const bool found = m[i] >= 0;
      // Detection and tracking.
      if (params.roi.contains(o.center)) ++(found ? r.detection_roi.tp : r.detection_roi.fn);
      if (found) {
        ++r.detection.tp;
        const DetectedObject& d = dets[m[i]];
        const Eigen::Vector2d offset = d.center - o.center;
        auto it = last_match.find(o.id);
        if (it != last_match.end()) {
          if (it->second.det_id != d.id) {
            ++r.id_switches;
          } else if (it->second.consecutive) {
            offset_step_sq += (offset - it->second.offset).squaredNorm();
            ++r.offset_steps;
          }
        }
        last_match[o.id] = LastMatch{d.id, offset, true};
        if (d.has_aabb) {
          const Eigen::Vector2d reach = axisAlignedReach(o);
          const Eigen::Vector2d tmin = o.center - reach, tmax = o.center + reach;
          near_bias.push_back(o.center.x() >= 0.0 ? d.aabb_min.x() - tmin.x()
                                                  : tmax.x() - d.aabb_max.x());
          side_bias.push_back(d.aabb_min.y() - tmin.y());
          side_bias.push_back(tmax.y() - d.aabb_max.y());
        }
        if (o.has_velocity && has_ego && d.age >= 2) {
          const double over_ground = overGround(o, f).norm();
          if (over_ground < params.static_speed_mps) r.motion_standing.add(d.motion);
          else if (over_ground > params.moving_speed_mps) r.motion_moving.add(d.motion);
        }
        if (o.has_velocity && d.age >= params.settled_age && has_ego) {
          if (overGround(o, f).norm() < params.static_speed_mps)
            static_speeds.push_back(d.velocity_over_ground.norm());
        }
        if (o.has_velocity) {
          const double e2 = (d.velocity - o.velocity).squaredNorm();
          velocity_sq += e2;
          ++r.velocity_samples;
          if (e2 <= params.velocity_agree_mps * params.velocity_agree_mps)
            ++r.detection_velocity_agrees;
          if (d.age >= params.settled_age) {
            velocity_sq_settled += e2;
            ++r.velocity_samples_settled;
          }
        }
      } else {
        ++r.detection.fn;
        auto it = last_match.find(o.id);
        if (it != last_match.end()) it->second.consecutive = false;  // steps need consecutive matches
      }
      // Danger per object-frame: its detection or one of its fragments flagged.
      const bool by_match = found && dets[m[i]].dangerous;
      const bool predicted = by_match || flagged_by[i] >= 0;
      const int merged = found ? -1 : mergedInto(o, dets, det_used);
      if (merged >= 0) ++r.detection_merged;
      if (predicted) {
        flagged_ids.insert(o.id);
        causes.flag(o.horizon_cut ? LampCause::kUnscored
                    : o.dangerous ? LampCause::kTrueDanger
                    : perfect_flagged.count(o.id) ? LampCause::kModel
                                                  : LampCause::kLabelledPerception);
      }
      // Danger unknown (the labels end within the horizon): not scored, as KITTI's DontCare.
      const Outcome outcome = o.horizon_cut      ? Outcome::kDontCare
                              : apart.count(o.id) ? Outcome::kStandingApart
                                                  : outcomeOf(o.dangerous, predicted);
      count(r.danger, outcome);
      if (outcome == Outcome::kStandingApart) {
        ++r.danger_standing_apart;
        r.danger_standing_apart_flagged += predicted;
      }
      if (outcome == Outcome::kFalseNegative && merged >= 0 && dets[merged].dangerous)
        ++r.danger_fn_in_flagged_merge;
      if (rows) {
        ScoredRow row{f.t, outcome, true, o, false, false, DetectedObject()};
        row.perfect_flagged = perfect_flagged.count(o.id) > 0;
        const int j = by_match || !predicted ? m[i] : flagged_by[i];
        if (j >= 0) {
          row.has_detection = true;
          row.fragment = j != m[i];
          row.detection = dets[j];
        }
        if (merged >= 0) row.merged_into = dets[merged].id;
        rows->push_back(row);
      }
    }
    for (std::size_t j = 0; j < dets.size(); ++j) {
      if (det_used[j]) continue;
      // On a true object that is not scored (too few returns, just out of range or view): not
      // scored either, as KITTI's DontCare.
      const TruthObject* unscored =
          fragment_of[j] < 0 ? unscoredObjectAt(f.truth, dets[j], params) : nullptr;
      if (unscored) {
        if (dets[j].dangerous) causes.flag(LampCause::kUnscored);
        if (rows && dets[j].dangerous)
          rows->push_back(ScoredRow{f.t, Outcome::kDontCare, true, *unscored, true, false, dets[j], false});
        continue;
      }
      ++r.detection.fp;
      if (params.roi.contains(dets[j].center)) ++r.detection_roi.fp;
      if (has_ego && fragment_of[j] < 0 && dets[j].age >= 2) r.motion_unlabelled.add(dets[j].motion);
      if (dets[j].dangerous && fragment_of[j] < 0) {
        ++r.danger.fp;
        ++r.false_alarms_unmatched;
        causes.flag(dets[j].velocity_over_ground.norm() < params.static_speed_mps
                        ? LampCause::kUnlabelledStanding
                        : LampCause::kUnlabelledMoving);
        if (rows) {
          rows->push_back(
              ScoredRow{f.t, Outcome::kFalsePositive, false, TruthObject(), true, false, dets[j], false});
        }
      }
    }

    // Episodes over all true objects with a label (seen or not: a danger nobody saw is missed).
    for (const TruthObject& o : f.truth) {
      Episode& e = episodes[o.id];
      const bool dangerous = o.dangerous && !apart.count(o.id);
      if (dangerous && !e.open) {
        e.open = true;
        e.entry_t = f.t + std::max(0.0, o.time_to_corridor);
      }
      if (!dangerous) close_episode(e);
      // Caught: the lamp on because of this object (its detection or a fragment flagged), not the
      // lamp on for any reason (another object, the watchdog) while it happened to be dangerous.
      if (e.open && f.lamp_on && flagged_ids.count(o.id) && e.first_on < 0.0) e.first_on = f.t;
    }
    for (auto& kv : episodes) {  // ids absent from this frame end their episode
      bool present = false;
      for (const TruthObject& o : f.truth) present |= o.id == kv.first;
      if (!present) close_episode(kv.second);
    }
  }
  for (auto& kv : episodes) close_episode(kv.second);

  r.velocity_rmse = r.velocity_samples ? std::sqrt(velocity_sq / r.velocity_samples) : 0.0;
  r.velocity_rmse_settled =
      r.velocity_samples_settled ? std::sqrt(velocity_sq_settled / r.velocity_samples_settled) : 0.0;
  r.offset_step_rms_m = r.offset_steps ? std::sqrt(offset_step_sq / r.offset_steps) : 0.0;
  r.box_bias_near_m = percentile(near_bias, 0.5);
  r.box_bias_side_m = percentile(side_bias, 0.5);
  r.box_bias_samples = near_bias.size();
  r.static_speed_p50_mps = percentile(static_speeds, 0.5);
  r.static_speed_p90_mps = percentile(static_speeds, 0.9);
  r.static_speed_samples = static_speeds.size();
  std::sort(latencies.begin(), latencies.end());
  r.latency_p50_ms = percentileOfSorted(latencies, 0.50);
  r.latency_p90_ms = percentileOfSorted(latencies, 0.90);
  r.latency_p99_ms = percentileOfSorted(latencies, 0.99);
  r.latency_max_ms = percentileOfSorted(latencies, 1.0);
  r.duty_cycle = ratio(on_frames, r.processed);
  r.truth_duty_cycle = ratio(truth_on_frames, r.processed);
  r.perfect_tracks_duty_cycle = ratio(perfect_on_frames, r.processed);
  r.lamp_causes = causes.result();
  return r;
}

void MotionCounts::add(MotionState state) {
  switch (state) {
    case MotionState::kUnknown: ++unknown; break;
    case MotionState::kStatic: ++still; break;
    case MotionState::kMoving: ++moving; break;
  }
}

double MotionCounts::share(MotionState state) const {
  const std::uint64_t k = state == MotionState::kStatic   ? still
                          : state == MotionState::kMoving ? moving
                                                          : unknown;
  return n() ? static_cast<double>(k) / static_cast<double>(n()) : 0.0;
}

namespace {

std::string motionLine(const char* what, const MotionCounts& c) {
  char buf[200];
  std::snprintf(buf, sizeof(buf), "  %s: static %.1f %%  moving %.1f %%  unknown %.1f %% (n %llu)\n", what,
                100 * c.share(MotionState::kStatic), 100 * c.share(MotionState::kMoving),
                100 * c.share(MotionState::kUnknown), static_cast<unsigned long long>(c.n()));
  return buf;
}

std::string motionJson(const MotionCounts& c) {
  std::ostringstream j;
  j << "{\"static\": " << c.still << ", \"moving\": " << c.moving << ", \"unknown\": " << c.unknown << "}";
  return j.str();
}

}  // namespace

std::string toTable(const EvalReport& r, const std::string& title) {
  char buf[4096];
  const double lead_min = r.lead_times_s.empty() ? 0.0 : *std::min_element(r.lead_times_s.begin(), r.lead_times_s.end());
  const double lead_p50 = percentile(r.lead_times_s, 0.5);
  std::snprintf(buf, sizeof(buf),
      "== %s ==\n"
      "frames %zu (processed %zu, ego motion extrapolated, jumped or lost in %zu)\n"
      "danger per object-frame: TP %llu FP %llu FN %llu TN %llu (false alarms without a true object: %llu)\n"
      "  precision %.2f %%  recall %.2f %%  accuracy %.2f %%  F1 %.2f %%\n"
      "  standing beside the swept path, dangerous by the corridor only (not scored): %llu object-frames, flagged %llu\n"
      "danger episodes: %zu caught of %zu; warning lead time p50 %.2f s, min %.2f s\n"
      "detection: recall %.2f %%  precision %.2f %% (BEV centre to true footprint); id switches %zu; velocity RMSE %.2f m/s (n %zu)\n"
      "  found with the track's velocity within %.1f m/s of the truth's: %llu (%.2f %% of true objects)\n"
      "  in the detector's region of interest: recall %.2f %%  precision %.2f %% (true objects %llu)\n"
      "  missed inside the box of a detection matched to another (merged): %llu of %llu missed; dangerous ones whose merged box was flagged: %llu\n"
      "  settled tracks' velocity RMSE %.2f m/s (n %zu); centre offset step RMS %.3f m (n %zu)\n"
      "  true box beyond the detected one (median): near face %.3f m, sides %.3f m (n %zu)\n"
      "  speed over ground of static objects' settled tracks: p50 %.2f  p90 %.2f m/s (n %zu)\n"
      "latency cloud -> lamp: p50 %.2f  p90 %.2f  p99 %.2f  max %.2f ms\n"
      "lamp duty cycle %.1f %% (a perfect danger detector: %.1f %%)\n"
      "danger model on perfect tracks: TP %llu FP %llu FN %llu TN %llu, precision %.2f %%  recall %.2f %%, lamp duty %.1f %%\n",
      title.c_str(), r.frames, r.processed, r.ego_motion_faults,
      static_cast<unsigned long long>(r.danger.tp), static_cast<unsigned long long>(r.danger.fp),
      static_cast<unsigned long long>(r.danger.fn), static_cast<unsigned long long>(r.danger.tn),
      static_cast<unsigned long long>(r.false_alarms_unmatched),
      100 * r.danger.precision(), 100 * r.danger.recall(), 100 * r.danger.accuracy(), 100 * r.danger.f1(),
      static_cast<unsigned long long>(r.danger_standing_apart),
      static_cast<unsigned long long>(r.danger_standing_apart_flagged),
      r.caught, r.episodes, lead_p50, lead_min,
      100 * r.detection.recall(), 100 * r.detection.precision(), r.id_switches, r.velocity_rmse,
      r.velocity_samples, r.velocity_agree_mps,
      static_cast<unsigned long long>(r.detection_velocity_agrees),
      100 * r.velocityAgreesShare(),
      100 * r.detection_roi.recall(), 100 * r.detection_roi.precision(),
      static_cast<unsigned long long>(r.detection_roi.tp + r.detection_roi.fn),
      static_cast<unsigned long long>(r.detection_merged),
      static_cast<unsigned long long>(r.detection.fn),
      static_cast<unsigned long long>(r.danger_fn_in_flagged_merge),
      r.velocity_rmse_settled, r.velocity_samples_settled, r.offset_step_rms_m,
      r.offset_steps, r.box_bias_near_m, r.box_bias_side_m, r.box_bias_samples,
      r.static_speed_p50_mps, r.static_speed_p90_mps, r.static_speed_samples, r.latency_p50_ms,
      r.latency_p90_ms, r.latency_p99_ms, r.latency_max_ms,
      100 * r.duty_cycle, 100 * r.truth_duty_cycle,
      static_cast<unsigned long long>(r.perfect_tracks.tp),
      static_cast<unsigned long long>(r.perfect_tracks.fp),
      static_cast<unsigned long long>(r.perfect_tracks.fn),
      static_cast<unsigned long long>(r.perfect_tracks.tn), 100 * r.perfect_tracks.precision(),
      100 * r.perfect_tracks.recall(), 100 * r.perfect_tracks_duty_cycle);
  return buf + std::string("motion states (from a track's second frame):\n") +
         motionLine("tracks of true objects standing still", r.motion_standing) +
         motionLine("tracks of true objects moving", r.motion_moving) +
         motionLine("detections of no true object", r.motion_unlabelled) + toText(r.lamp_causes);
}

std::string toJson(const EvalReport& r, const std::string& name) {
  std::ostringstream j;
  const auto conf = [&](const char* key, const Confusion& c) {
    j << "\"" << key << "\": {\"tp\": " << c.tp << ", \"fp\": " << c.fp << ", \"fn\": " << c.fn
      << ", \"tn\": " << c.tn << ", \"precision\": " << c.precision() << ", \"recall\": "
      << c.recall() << ", \"accuracy\": " << c.accuracy() << ", \"f1\": " << c.f1() << "}";
  };
  j << "{\"name\": \"" << name << "\", \"frames\": " << r.frames << ", \"processed\": " << r.processed
    << ", \"ego_motion_faults\": " << r.ego_motion_faults << ", ";
  conf("danger", r.danger);
  j << ", \"false_alarms_unmatched\": " << r.false_alarms_unmatched;
  j << ", \"danger_standing_apart\": {\"n\": " << r.danger_standing_apart
    << ", \"flagged\": " << r.danger_standing_apart_flagged << "}";
  j << ", \"episodes\": " << r.episodes << ", \"caught\": " << r.caught << ", \"lead_times_s\": [";
  for (std::size_t i = 0; i < r.lead_times_s.size(); ++i) j << (i ? ", " : "") << r.lead_times_s[i];
  j << "], ";
  conf("detection", r.detection);
  j << ", ";
  conf("detection_roi", r.detection_roi);
  j << ", \"detection_merged\": " << r.detection_merged
    << ", \"danger_fn_in_flagged_merge\": " << r.danger_fn_in_flagged_merge
    << ", \"detection_velocity_agrees\": {\"n\": " << r.detection_velocity_agrees
    << ", \"within_mps\": " << r.velocity_agree_mps << "}";
  j << ", \"id_switches\": " << r.id_switches << ", \"velocity_rmse\": " << r.velocity_rmse
    << ", \"velocity_rmse_settled\": " << r.velocity_rmse_settled
    << ", \"offset_step_rms_m\": " << r.offset_step_rms_m
    << ", \"box_bias_near_m\": " << r.box_bias_near_m
    << ", \"box_bias_side_m\": " << r.box_bias_side_m
    << ", \"static_speed_mps\": {\"p50\": " << r.static_speed_p50_mps << ", \"p90\": "
    << r.static_speed_p90_mps << ", \"n\": " << r.static_speed_samples << "}"
    << ", \"latency_ms\": {\"p50\": " << r.latency_p50_ms << ", \"p90\": " << r.latency_p90_ms
    << ", \"p99\": " << r.latency_p99_ms << ", \"max\": " << r.latency_max_ms << "}"
    << ", \"motion_states\": {\"standing\": " << motionJson(r.motion_standing)
    << ", \"moving\": " << motionJson(r.motion_moving)
    << ", \"unlabelled\": " << motionJson(r.motion_unlabelled) << "}"
    << ", \"duty_cycle\": " << r.duty_cycle
    << ", \"truth_duty_cycle\": " << r.truth_duty_cycle << ", ";
  conf("perfect_tracks", r.perfect_tracks);
  j << ", \"perfect_tracks_duty_cycle\": " << r.perfect_tracks_duty_cycle
    << ", \"lamp_causes\": " << toJson(r.lamp_causes) << "}";
  return j.str();
}

std::string toCsv(const std::vector<ScoredRow>& rows) {
  std::ostringstream c;
  c << "t,outcome,truth_id,truth_type,truth_x,truth_y,truth_length,truth_width,truth_yaw,"
       "truth_vx,truth_vy,truth_ttc_s,"
       "det_id,det_fragment,det_dangerous,det_x,det_y,det_vx,det_vy,det_vx_std,det_vy_std,"
       "det_vgx,det_vgy,det_x_min,det_x_max,det_y_min,det_y_max,det_age,perfect_dangerous,merged_into\n";
  char buf[512];
  for (const ScoredRow& row : rows) {
    std::snprintf(buf, sizeof(buf), "%.3f,%s,", row.t, toString(row.outcome));
    c << buf;
    if (row.has_truth) {
      const TruthObject& o = row.truth;
      std::snprintf(buf, sizeof(buf), "%u,%s,%.3f,%.3f,%.3f,%.3f,%.4f,%.3f,%.3f,%.2f,", o.id,
                    o.type.c_str(), o.center.x(), o.center.y(), o.size.x(), o.size.y(), o.yaw,
                    o.velocity.x(), o.velocity.y(), o.time_to_corridor);
      c << buf;
    } else {
      c << ",,,,,,,,,,";
    }
    if (row.has_detection) {
      const DetectedObject& d = row.detection;
      std::snprintf(buf, sizeof(buf),
                    "%u,%d,%d,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%u,",
                    d.id, row.fragment ? 1 : 0, d.dangerous ? 1 : 0, d.center.x(), d.center.y(),
                    d.velocity.x(), d.velocity.y(), d.velocity_std.x(), d.velocity_std.y(),
                    d.velocity_over_ground.x(), d.velocity_over_ground.y(), d.aabb_min.x(), d.aabb_max.x(), d.aabb_min.y(), d.aabb_max.y(), d.age);
      c << buf;
    } else {
      c << ",,,,,,,,,,,,,,,,";
    }
    // The model on the true object's perfect track (empty for a false alarm of no true object).
    c << (row.has_truth ? (row.perfect_flagged ? "1" : "0") : "") << ",";
    if (row.merged_into) c << row.merged_into;
    c << "\n";
  }
  return c.str();
}

}  // namespace icanc
