/**
 * @file types.h
 * @brief Point and flow types shared by every stage of the core.
 */
#pragma once

#include <Eigen/Core>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <vector>

namespace action_flow
{
/** @brief The point type of every cloud in the pipeline: XYZ with packed RGB. */
using PointT = pcl::PointXYZRGB;
/** @brief A colored point cloud. */
using Cloud = pcl::PointCloud<PointT>;

/** @brief One 3D flow vector: where a point of the current frame is and how fast it moves (m/s). */
struct FlowPoint
{
  Eigen::Vector3f position;
  Eigen::Vector3f velocity;
};

/** @brief The flow of one person between two consecutive frames. */
using FlowVectors = std::vector<FlowPoint>;

}  // namespace action_flow
