/**
 * @file camera_info.h
 * @brief The camera_info of an ideal pinhole camera, as the driver (a device without calibration)
 *        and the virtual Kinect's bags publish it.
 */
#pragma once

#include <sensor_msgs/CameraInfo.h>

namespace action_flow
{
/**
 * @brief width x height pixels, focal lengths @p fx, @p fy and principal point (@p cx, @p cy) in
 *        pixels; plumb_bob without distortion, identity rectification. Header left empty.
 */
sensor_msgs::CameraInfo pinholeCameraInfo(int width, int height, double fx, double fy, double cx, double cy);
}  // namespace action_flow
