// dangerMarkers / lampMarkers (src/ros/markers.cpp): what rviz is given.
#include <cmath>

#include <gtest/gtest.h>

#include "icanc/ros/markers.hpp"

namespace icanc {
namespace {

using visualization_msgs::Marker;
using visualization_msgs::MarkerArray;

Obstacle obstacle(std::uint32_t id, double x, double y, double vx, double vy, bool dangerous) {
  Obstacle o;
  o.id = id;
  o.pose.position.x = x;
  o.pose.position.y = y;
  o.pose.position.z = 0.85;
  o.pose.orientation.w = 1.0;
  o.dimensions.x = 0.5;
  o.dimensions.y = 0.6;
  o.dimensions.z = 1.7;
  o.velocity.x = vx;
  o.velocity.y = vy;
  o.speed = static_cast<float>(std::hypot(vx, vy));
  o.dangerous = dangerous;
  return o;
}

const Marker* find(const MarkerArray& a, const std::string& ns, int id) {
  for (const Marker& m : a.markers)
    if (m.ns == ns && m.id == id) return &m;
  return nullptr;
}

ObstacleArray twoObstacles() {
  ObstacleArray a;
  a.header.frame_id = "base_link";
  a.header.stamp = ros::Time(42.5);
  a.obstacles.push_back(obstacle(7, 5.0, 0.2, -1.5, 0.0, true));
  a.obstacles.push_back(obstacle(12, 8.0, 4.0, 0.0, 0.0, false));
  return a;
}

TEST(DangerMarkers, BoxLabelAndArrowPerObstacleWithTrackIds) {
  DangerParams params;
  const MarkerArray m = dangerMarkers(twoObstacles(), params);
  ASSERT_EQ(m.markers.size(), 2u * 3u + 5u);  // 3 per obstacle, 2 boundaries, 3 section names
  for (const Marker& k : m.markers) {
    EXPECT_EQ(k.header.frame_id, "base_link");
    EXPECT_EQ(k.header.stamp, ros::Time(42.5));
    EXPECT_EQ(k.action, Marker::ADD);
    EXPECT_GT(k.lifetime.toSec(), 0.0) << "without a lifetime a vanished track's marker stays";
  }
  const Marker* box = find(m, kBoxesNs, 7);
  ASSERT_NE(box, nullptr);
  EXPECT_EQ(box->type, Marker::CUBE);
  EXPECT_DOUBLE_EQ(box->pose.position.x, 5.0);
  EXPECT_DOUBLE_EQ(box->pose.position.y, 0.2);
  EXPECT_DOUBLE_EQ(box->scale.x, 0.5);
  EXPECT_DOUBLE_EQ(box->scale.z, 1.7);

  const Marker* label = find(m, kLabelsNs, 12);
  ASSERT_NE(label, nullptr);
  EXPECT_EQ(label->type, Marker::TEXT_VIEW_FACING);
  EXPECT_EQ(label->text, "#12  0.0 m/s");
  EXPECT_EQ(find(m, kLabelsNs, 7)->text, "#7  1.5 m/s");
  EXPECT_GT(label->pose.position.z, 1.7) << "above the box";

  const Marker* arrow = find(m, kVelocityNs, 7);
  ASSERT_NE(arrow, nullptr);
  EXPECT_EQ(arrow->type, Marker::ARROW);
  ASSERT_EQ(arrow->points.size(), 2u);
  EXPECT_DOUBLE_EQ(arrow->points[0].x, 5.0);
  EXPECT_DOUBLE_EQ(arrow->points[1].x, 5.0 - 1.5);  // one second of motion
  EXPECT_DOUBLE_EQ(arrow->points[1].y, 0.2);
}

TEST(DangerMarkers, RedWhenDangerousGreenOtherwise) {
  const MarkerArray m = dangerMarkers(twoObstacles(), DangerParams());
  const Marker* danger = find(m, kBoxesNs, 7);
  const Marker* safe = find(m, kBoxesNs, 12);
  EXPECT_FLOAT_EQ(danger->color.r, 1.0f);
  EXPECT_FLOAT_EQ(danger->color.g, 0.0f);
  EXPECT_FLOAT_EQ(safe->color.r, 0.0f);
  EXPECT_GT(safe->color.g, 0.5f);
  EXPECT_GT(danger->color.a, 0.0f);
  EXPECT_GT(safe->color.a, 0.0f);
}

TEST(DangerMarkers, SectionBoundariesAtPlusMinusHalfWidth) {
  DangerParams params;
  params.half_width_m = 1.2;
  MarkerStyle style;
  style.section_length_m = 25.0;
  const MarkerArray m = dangerMarkers(ObstacleArray(), params, style);
  ASSERT_EQ(m.markers.size(), 5u) << "sections are drawn without obstacles too";
  for (int side = 0; side < 2; ++side) {
    const Marker* line = find(m, kSectionsNs, side);
    ASSERT_NE(line, nullptr);
    EXPECT_EQ(line->type, Marker::LINE_STRIP);
    ASSERT_EQ(line->points.size(), 2u);
    const double y = side == 0 ? 1.2 : -1.2;
    EXPECT_DOUBLE_EQ(line->points[0].x, 0.0);
    EXPECT_DOUBLE_EQ(line->points[1].x, 25.0);
    EXPECT_DOUBLE_EQ(line->points[0].y, y);
    EXPECT_DOUBLE_EQ(line->points[1].y, y);
  }
  // The names sit inside their sections (icanc::getSection).
  EXPECT_EQ(getSection(find(m, kSectionsNs, 2)->pose.position.y, 1.2), Section::kLeft);
  EXPECT_EQ(getSection(find(m, kSectionsNs, 3)->pose.position.y, 1.2), Section::kFront);
  EXPECT_EQ(getSection(find(m, kSectionsNs, 4)->pose.position.y, 1.2), Section::kRight);
}

TEST(LampMarkers, YellowWhenOnGreyWhenOffWithTheReason) {
  LightState on;
  on.header.stamp = ros::Time(3.0);
  on.on = true;
  on.reason = LightState::REASON_DANGER;
  on.reason_text = "danger";
  on.time_left = 2.4f;
  const MarkerArray a = lampMarkers(on, "base_link");
  ASSERT_EQ(a.markers.size(), 2u);
  const Marker* sphere = find(a, kLampNs, 0);
  ASSERT_NE(sphere, nullptr);
  EXPECT_EQ(sphere->type, Marker::SPHERE);
  EXPECT_EQ(sphere->header.frame_id, "base_link");
  EXPECT_EQ(sphere->header.stamp, ros::Time(3.0));
  EXPECT_GT(sphere->color.r, 0.9f);
  EXPECT_GT(sphere->color.g, 0.8f);
  EXPECT_EQ(find(a, kLampNs, 1)->text, "lamp ON: danger, 2.4 s left");

  LightState off;
  const MarkerArray b = lampMarkers(off, "base_link");
  EXPECT_LT(find(b, kLampNs, 0)->color.r, 0.5f);
  EXPECT_EQ(find(b, kLampNs, 1)->text, "lamp off");

  LightState stale = on;
  stale.reason = LightState::REASON_SENSOR_STALE;
  stale.reason_text = "sensor stale";
  EXPECT_EQ(find(lampMarkers(stale, "base_link"), kLampNs, 1)->text, "lamp ON: sensor stale");
}

}  // namespace
}  // namespace icanc
