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
 * @brief The recognition parameters (RecognitionParams::visit) set in @p nh's namespace, over
 *        defaultRecognitionParams(): recognizer, flow/..., grid/..., descriptor, ...
 *        (docs/parameters.md lists them all).
 * @throws std::invalid_argument "<name>: <what was wrong>" on a value that does not parse
 */
RecognitionParams readRecognitionParams(const ros::NodeHandle& nh);

/**
 * @brief The classifier's policy (PolicyParams::visit): mode (segmented|online) and the rest.
 * @throws std::invalid_argument on a value that does not parse or is out of range, naming it
 */
PolicyParams readPolicyParams(const ros::NodeHandle& nh);

/** @brief The tracker's parameters (TrackerParams::visit; ground as a 4-list, [] = estimated). */
TrackerParams readTrackerParams(const ros::NodeHandle& nh);

}  // namespace action_flow
