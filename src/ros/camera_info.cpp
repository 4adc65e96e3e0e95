#include <action_flow/ros/camera_info.h>

namespace action_flow
{
sensor_msgs::CameraInfo pinholeCameraInfo(int width, int height, double fx, double fy, double cx, double cy)
{
  sensor_msgs::CameraInfo info;
  info.width = static_cast<std::uint32_t>(width);
  info.height = static_cast<std::uint32_t>(height);
  info.distortion_model = "plumb_bob";
  info.D.assign(5, 0.0);
  info.K = { fx, 0, cx, 0, fy, cy, 0, 0, 1 };
  info.R = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
  info.P = { fx, 0, cx, 0, 0, fy, cy, 0, 0, 0, 1, 0 };
  return info;
}
}  // namespace action_flow
