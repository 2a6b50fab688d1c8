// Basic types shared by the core library (no ROS includes anywhere under icanc/core).
#pragma once

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

namespace icanc {

using Point = pcl::PointXYZ;
using Cloud = pcl::PointCloud<Point>;

}  // namespace icanc
