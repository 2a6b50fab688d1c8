// The dynamic_reconfigure mapping (icanc/ros/live_params.hpp): every name of cfg/*.cfg is a key of
// the core's parameter list (visitParams), and values survive params -> config -> params.
#include <gtest/gtest.h>

#include "icanc/DangerDetectorConfig.h"
#include "icanc/LightControllerConfig.h"
#include "icanc/ObstacleDetectorConfig.h"
#include "icanc/ros/live_params.hpp"

namespace icanc {
namespace {

// Every .cfg parameter is written from the struct, i.e. none is left at the .cfg's default.
template <class ConfigT, class Params>
void expectEveryCfgNameIsAKey(Params params) {
  dynamic_reconfigure::Config msg;
  ConfigT::__getDefault__().__toMessage__(msg);
  ConfigMessageWriter writer(msg);
  visitParams(writer, params);
  for (const auto& p : ConfigT::__getParamDescriptions__())
    EXPECT_TRUE(writer.written().count(p->name)) << p->name << " is not a visitParams key";
}

TEST(LiveParams, ReconfigureNamesAreTheKeysWithUnderscores) {
  EXPECT_EQ(reconfigureName("prep/voxel_leaf_m"), "prep_voxel_leaf_m");
  EXPECT_EQ(reconfigureName("reaction_time_s"), "reaction_time_s");
  expectEveryCfgNameIsAKey<ObstacleDetectorConfig>(ObstacleDetectorParams());
  expectEveryCfgNameIsAKey<DangerDetectorConfig>(DangerParams());
  expectEveryCfgNameIsAKey<LightControllerConfig>(LightControllerParams());
}

TEST(LiveParams, ObstacleDetectorRoundTripKeepsTheRoi) {
  ObstacleDetectorParams p;
  p.prep.voxel_leaf_m = 0.35f;
  p.prep.remove_ego = false;
  p.prep.roi_max = Eigen::Vector3f(12.0f, 3.0f, 2.0f);  // not in the .cfg: stays as loaded
  p.ground.max_iterations = 77;
  p.cluster.tolerance_m = 0.45f;
  p.cluster.max_points = 1234;
  p.tracker.gate_distance_m = 3.5f;
  p.tracker.initial_velocity_std = 2.5;
  p.tracker.anchor = TrackAnchor::kCentre;
  const ObstacleDetectorConfig c = toConfig<ObstacleDetectorConfig>(p);
  EXPECT_EQ(c.tracker_anchor, "centre");
  EXPECT_DOUBLE_EQ(c.prep_voxel_leaf_m, 0.35f);
  EXPECT_EQ(c.ground_max_iterations, 77);
  const ObstacleDetectorParams q = fromConfig(c, ObstacleDetectorParams());
  EXPECT_FLOAT_EQ(q.prep.voxel_leaf_m, 0.35f);
  EXPECT_FALSE(q.prep.remove_ego);
  EXPECT_EQ(q.ground.max_iterations, 77);
  EXPECT_FLOAT_EQ(q.cluster.tolerance_m, 0.45f);
  EXPECT_EQ(q.cluster.max_points, 1234);
  EXPECT_FLOAT_EQ(q.tracker.gate_distance_m, 3.5f);
  EXPECT_DOUBLE_EQ(q.tracker.initial_velocity_std, 2.5);
  EXPECT_EQ(q.tracker.anchor, TrackAnchor::kCentre);
  EXPECT_TRUE(fromConfig(c, p).prep.roi_max.isApprox(Eigen::Vector3f(12.0f, 3.0f, 2.0f)));
  EXPECT_TRUE(q.prep.roi_max.isApprox(ObstacleDetectorParams().prep.roi_max));
}

TEST(LiveParams, DangerRoundTripIncludingTheModel) {
  DangerParams p;
  p.half_width_m = 1.2;
  p.reaction_time_s = 7.5;
  p.model = DangerModel::kPredictive;
  p.margin_m = 0.45;
  p.off_frames = 6;
  const DangerDetectorConfig c = toConfig<DangerDetectorConfig>(p);
  EXPECT_EQ(c.model, "predictive");
  EXPECT_DOUBLE_EQ(c.reaction_time_s, 7.5);
  EXPECT_DOUBLE_EQ(c.predictive_margin_m, 0.45);
  const DangerParams q = fromConfig(c, DangerParams());
  EXPECT_DOUBLE_EQ(q.half_width_m, 1.2);
  EXPECT_DOUBLE_EQ(q.reaction_time_s, 7.5);
  EXPECT_EQ(q.model, DangerModel::kPredictive);
  EXPECT_DOUBLE_EQ(q.margin_m, 0.45);
  EXPECT_EQ(q.off_frames, 6);
}

TEST(LiveParams, LightControllerRoundTrip) {
  LightControllerParams p;
  p.tau_s = 5.0;
  p.recheck_below_s = 0.5;
  p.stale_timeout_s = 1.5;
  const LightControllerParams q = fromConfig(toConfig<LightControllerConfig>(p), LightControllerParams());
  EXPECT_DOUBLE_EQ(q.tau_s, 5.0);
  EXPECT_DOUBLE_EQ(q.recheck_below_s, 0.5);
  EXPECT_DOUBLE_EQ(q.stale_timeout_s, 1.5);
}

}  // namespace
}  // namespace icanc
