/**
 * @file params.h
 * @brief Reading the core's parameter structs from a ROS parameter namespace (the nodelets'
 *        private namespaces, loaded from the yaml files in config/). Defaults are the core's.
 */
#pragma once

#include <action_flow/action_model.h>
#include <action_flow/people_tracker.h>
#include <action_flow/recognition_policy.h>

#include <ros/node_handle.h>

namespace action_flow
{
/**
 * @brief Reads voxel_size, flow/{k,reciprocal,reject_outliers,min_speed,isolation_speed,
 *        neighbour_radius}, grid/{parts_x,parts_y,parts_z,width,height,depth,reference_height},
 *        descriptor (sumflow|meanflow), frames, use_pca, pca_variance, neighbours.
 * @throws std::invalid_argument on an unknown descriptor name
 */
RecognitionParams readRecognitionParams(const ros::NodeHandle& nh);

/**
 * @brief Reads the classifier's policy: mode (segmented|online) and the members of PolicyParams
 *        under the same names (idle_labels as a list of strings).
 * @throws std::invalid_argument on an unknown mode or a value out of range, naming it
 */
PolicyParams readPolicyParams(const ros::NodeHandle& nh);

/** @brief Reads the tracker's parameters (same names as TrackerParams' members; ground as a 4-list). */
TrackerParams readTrackerParams(const ros::NodeHandle& nh);

}  // namespace action_flow
