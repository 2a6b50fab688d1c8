// Detection quality on labelled KITTI frames, one rule for every tool: a labelled Car, Van,
// Cyclist or Pedestrian within 40 m (x/y) with at least 20 LiDAR points inside its box must be
// found by a detection whose centre lies inside the box grown by 0.5 m (recall); a detection in
// the labelled field of view (ahead, within 45 deg of +x, within 40 m) is correct when its centre
// lies inside any label box grown by 0.5 m (precision; unlabelled poles and walls count against
// it, so compare methods, not absolute values).
#pragma once

#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "icanc/core/perception/box.hpp"
#include "icanc/core/evaluation/kitti.hpp"

namespace icanc {
namespace kitti {

struct DetectionScore {
  std::map<std::string, int> labelled;  // per type: labels that count
  std::map<std::string, int> found;     // per type: of those, found
  std::map<std::string, int> outside_roi;  // per type: of the labelled, centre outside the ROI
  int detections = 0;                   // detections in the labelled field of view
  int correct = 0;                      // of those, inside a label box

  int labelledTotal() const;
  int foundTotal() const;
  int outsideRoiTotal() const;
  double recall() const;     // found / labelled (1 when nothing is labelled)
  double precision() const;  // correct / detections (1 when there is no detection)
  void add(const DetectionScore& other);
};

// Scores one frame: `labels` of that frame (velodyne frame), the frame's raw `cloud` (to count
// points inside each label) and the detector's boxes (velodyne frame). With `roi` (the detector's
// region of interest seen from above, x/y bounds), a counted label whose centre lies outside it is
// also counted in outside_roi: the detector crops it away,
// so it is missed whatever the method does.
DetectionScore scoreFrame(const std::vector<VeloBox>& labels, const Cloud& cloud,
                          const std::vector<Box3D>& detections, const Eigen::AlignedBox2d* roi = nullptr);

}  // namespace kitti
}  // namespace icanc
