// The one list of parameter keys (as in config/*.yaml) for each core parameter struct. A reader
// is any callable `reader(key, value&)`: the ROS ParamReader (rosparam) and the YAML reader
// (icanc/core/common/yaml_params.hpp) both walk these lists, so a key is spelled in one place only.
#pragma once

#include <string>

#include "icanc/core/danger/danger.hpp"
#include "icanc/core/evaluation/ground_truth.hpp"
#include "icanc/core/camera/illumination.hpp"
#include "icanc/core/light/lamp_segments.hpp"
#include "icanc/core/light/light_controller.hpp"
#include "icanc/core/perception/obstacle_detector.hpp"

namespace icanc {

template <class Reader>
void visitParams(Reader& r, ObstacleDetectorParams& p) {
  std::string method = toString(p.method);  // "classic" | "fast"; validate() rejects others
  r("method", method);
  p.method = parseDetectorMethod(method);
  r("footprint_cell_m", p.footprint_cell_m);
  r("prep/roi_min", p.prep.roi_min);
  r("prep/roi_max", p.prep.roi_max);
  r("prep/remove_ego", p.prep.remove_ego);
  r("prep/ego_min", p.prep.ego_min);
  r("prep/ego_max", p.prep.ego_max);
  r("prep/voxel_leaf_m", p.prep.voxel_leaf_m);
  r("ground/enabled", p.ground.enabled);
  r("ground/max_iterations", p.ground.max_iterations);
  r("ground/distance_threshold_m", p.ground.distance_threshold_m);
  r("ground/max_slope_deg", p.ground.max_slope_deg);
  r("ground/expected_height_m", p.ground.expected_height_m);
  r("ground/max_height_error_m", p.ground.max_height_error_m);
  r("cluster/tolerance_m", p.cluster.tolerance_m);
  r("cluster/min_points", p.cluster.min_points);
  r("cluster/min_points_range_m", p.cluster.min_points_range_m);
  r("cluster/min_points_far", p.cluster.min_points_far);
  r("cluster/max_points", p.cluster.max_points);
  r("cluster/grazing_reach_m", p.cluster.grazing.reach_m);
  r("cluster/grazing_angle_deg", p.cluster.grazing.angle_deg);
  r("cluster/grazing_max_step_m", p.cluster.grazing.max_step_m);
  r("tracker/gate_distance_m", p.tracker.gate_distance_m);
  r("tracker/iou_weight", p.tracker.iou_weight);
  r("tracker/min_hits_to_confirm", p.tracker.min_hits_to_confirm);
  r("tracker/min_birth_points", p.tracker.min_birth_points);
  r("tracker/max_missed_frames", p.tracker.max_missed_frames);
  r("tracker/accel_std", p.tracker.accel_std);
  r("tracker/steady_accel_std", p.tracker.steady_accel_std);
  r("tracker/mode_switch_rate_per_s", p.tracker.mode_switch_rate_per_s);
  r("tracker/measurement_std_m", p.tracker.measurement_std_m);
  r("tracker/initial_velocity_std", p.tracker.initial_velocity_std);
  r("tracker/max_dt_s", p.tracker.max_dt_s);
  r("tracker/robust_sigma", p.tracker.robust_sigma);
  std::string anchor = toString(p.tracker.anchor);  // "centre" | "nearest_face"
  r("tracker/anchor", anchor);
  p.tracker.anchor = parseTrackAnchor(anchor);
  r("tracker/face_min_extent_m", p.tracker.face_min_extent_m);
  r("tracker/face_jump_m", p.tracker.face_jump_m);
  r("tracker/occlusion_gap_deg", p.tracker.occlusion_gap_deg);
  r("tracker/merge_hold_m", p.tracker.merge_hold_m);
  r("tracker/merge_hold_frames", p.tracker.merge_hold_frames);
  r("tracker/hidden_hold_frames", p.tracker.hidden_hold_frames);
  r("fast/cell_m", p.fast.cell_m);
  r("fast/link_m", p.fast.link_m);
  r("fast/link_max_step_m", p.fast.link_max_step_m);
  r("fast/step_check_min_extent_m", p.fast.step_check_min_extent_m);
  r("fast/step_piece_max_m", p.fast.step_piece_max_m);
  r("fast/link_step_beams", p.fast.link_step_beams);
  r("fast/sectors", p.fast.sectors);
  r("fast/range_bin_m", p.fast.range_bin_m);
  r("fast/max_slope_deg", p.fast.max_slope_deg);
  r("fast/ground_step_m", p.fast.ground_step_m);
  r("fast/obstacle_height_m", p.fast.obstacle_height_m);
  r("fast/max_height_m", p.fast.max_height_m);
  r("fast/overhang_gap_m", p.fast.overhang_gap_m);
  r("fast/overhang_min_height_m", p.fast.overhang_min_height_m);
  r("fast/grazing_reach_m", p.fast.grazing_reach_m);
  r("fast/grazing_angle_deg", p.fast.grazing_angle_deg);
  r("fast/link_gap_m", p.fast.link_gap_m);
  r("fast/link_gap_max_extent_m", p.fast.link_gap_max_extent_m);
  r("fast/min_points", p.fast.min_points);
  r("fast/max_points", p.fast.max_points);
  r("fast/range_split_angle_deg", p.fast.range_split_angle_deg);
  r("fast/range_split_vertical_angle_deg", p.fast.range_split_vertical_angle_deg);
  r("fast/range_split_min_extent_m", p.fast.range_split_min_extent_m);
  r("fast/range_piece_max_m", p.fast.range_piece_max_m);
  r("fast/range_piece_max_width_m", p.fast.range_piece_max_width_m);
  r("fast/range_piece_min_height_m", p.fast.range_piece_min_height_m);
  r("fast/range_piece_foreground", p.fast.range_piece_foreground);
  r("free_space/azimuth_step_deg", p.free_space.azimuth_step_deg);
  r("free_space/elevation_step_deg", p.free_space.elevation_step_deg);
  r("free_space/tolerance_m", p.free_space.tolerance_m);
}

template <class Reader>
void visitParams(Reader& r, DangerParams& p) {
  r("half_width_m", p.half_width_m);
  r("reaction_time_s", p.reaction_time_s);
  r("heading_window_deg", p.heading_window_deg);
  std::string model = toString(p.model);  // "paper" | "predictive"; validate() rejects others
  r("model", model);
  p.model = parseDangerModel(model);
  r("predictive/margin_m", p.margin_m);
  r("predictive/vehicle_front_m", p.vehicle_front_m);
  r("predictive/stopping_margin_m", p.stopping_margin_m);
  r("predictive/velocity_std_k", p.velocity_std_k);
  r("predictive/uncertainty_cap_m", p.uncertainty_cap_m);
  r("predictive/footprint_margin_m", p.footprint_margin_m);
  r("predictive/static_clearance_m", p.static_clearance_m);
  r("predictive/static_prior_k", p.static_prior_k);
  r("predictive/time_step_s", p.time_step_s);
  r("predictive/on_frames", p.on_frames);
  r("predictive/off_frames", p.off_frames);
  r("predictive/immediate_ttc_s", p.immediate_ttc_s);
  r("predictive/forget_after_s", p.forget_after_s);
}

template <class Reader>
void visitParams(Reader& r, LightControllerParams& p) {
  r("tau_s", p.tau_s);
  r("recheck_below_s", p.recheck_below_s);
  r("stale_timeout_s", p.stale_timeout_s);
  r("watchdog_enabled", p.watchdog_enabled);
  r("illumination/enabled", p.illumination_enabled);
  r("illumination/stale_timeout_s", p.illumination_stale_timeout_s);
}

// The segmented lamp, in the same light_controller section.
template <class Reader>
void visitParams(Reader& r, SegmentLampParams& p) {
  r("segments", p.segments);
  r("lamp_position_m", p.lamp_position_m);
  r("segment_margin_deg", p.segment_margin_deg);
  r("low_beam_below_m", p.low_beam_below_m);
  r("full_power_range_m", p.full_power_range_m);
  r("min_level", p.min_level);
}

// The IlluminationMonitor nodelet's section (illumination_monitor in config/*.yaml).
template <class Reader>
void visitParams(Reader& r, IlluminationParams& p) {
  r("grid_step_px", p.grid_step_px);
  r("percentile", p.percentile);
  r("dark_at", p.dark_at);
  r("bright_at", p.bright_at);
  r("min_dwell_s", p.min_dwell_s);
  r("stale_timeout_s", p.stale_timeout_s);
}

// Evaluation only: the corridor of the ground truth. loadProfile starts it from the danger_detector
// section's corridor (half_width_m, reaction_time_s, predictive margin_m, vehicle_front_m,
// stopping_margin_m); this section overrides it.
template <class Reader>
void visitParams(Reader& r, CorridorParams& p) {
  r("margin_m", p.margin_m);
  r("vehicle_front_m", p.vehicle_front_m);
  r("stopping_margin_m", p.stopping_margin_m);
}

}  // namespace icanc
