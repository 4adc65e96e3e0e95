// Driver stage: an OpenNI2 device (sensor, .oni recording or the Dummy test device) as an
// organized XYZRGB cloud and camera_info; streams run only while someone subscribes.
#include "../driver/openni2_device.h"

#include <action_flow/ros/input_checks.h>
#include <action_flow/types.h>

#include <nodelet/nodelet.h>
#include <pcl_conversions/pcl_conversions.h>
#include <pcl_ros/point_cloud.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>

#include <atomic>
#include <limits>
#include <thread>

namespace action_flow
{
/**
 * Publishes `cloud` (pcl::PointCloud<pcl::PointXYZRGB>, organized, depth registered to colour)
 * and `camera_info`. Parameters (private): device_uri ("" first device, a .oni path, "Dummy"),
 * frame_id (default camera_rgb_optical_frame), retry_period (s between attempts to open an
 * absent device).
 */
class DriverNodelet : public nodelet::Nodelet
{
public:
  ~DriverNodelet() override
  {
    running_ = false;
    if (thread_.joinable())
      thread_.join();
  }

private:
  void onInit() override
  {
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    pnh.param("device_uri", uri_, uri_);
    pnh.param("frame_id", frame_id_, frame_id_);
    pnh.param("retry_period", retry_period_, retry_period_);
    while (!frame_id_.empty() && frame_id_[0] == '/')
      frame_id_.erase(0, 1);
    // The polling thread reads the subscriber counts; the connect callbacks only need to exist.
    auto cb = [](const ros::SingleSubscriberPublisher&) {};
    cloud_pub_ = getNodeHandle().advertise<InputCloud>("cloud", 2, cb, cb);
    info_pub_ = getNodeHandle().advertise<sensor_msgs::CameraInfo>("camera_info", 2, cb, cb);
    running_ = true;
    thread_ = std::thread(&DriverNodelet::run, this);
  }

  bool wanted() const { return cloud_pub_.getNumSubscribers() > 0 || info_pub_.getNumSubscribers() > 0; }

  // Sleeps in small steps so that unloading never waits for a whole retry period.
  void pause(double seconds)
  {
    const auto until = ros::WallTime::now() + ros::WallDuration(seconds);
    while (running_ && ros::WallTime::now() < until)
      ros::WallDuration(0.05).sleep();
  }

  void run()
  {
    std::unique_ptr<OpenNI2Device> device;
    RgbdFrame frame;
    const std::string name = uri_.empty() ? std::string("first OpenNI2 device") : "'" + uri_ + "'";
    while (running_ && ros::ok())
    {
      try
      {
        if (!device)
        {
          device = std::make_unique<OpenNI2Device>(uri_);
          NODELET_INFO("opened %s", device->description().c_str());
        }
        const bool want = wanted();
        if (want && !device->streaming())
        {
          device->start();
          NODELET_INFO("a subscriber appeared: streaming from %s", device->description().c_str());
        }
        else if (!want && device->streaming())
        {
          device->stop();
          NODELET_INFO("no subscribers left: streams stopped");
        }
        if (!device->streaming())
        {
          pause(0.05);
          continue;
        }
        if (device->read(frame, 200))
          publish(frame);
      }
      catch (const DeviceError& e)
      {
        NODELET_ERROR("%s; retrying %s in %.1f s", e.what(), name.c_str(), retry_period_);
        device.reset();
        pause(retry_period_);
      }
    }
    device.reset();  // streams stopped and destroyed before the device closes, on this thread
  }

  void publish(const RgbdFrame& f)
  {
    if (f.default_intrinsics)
      NODELET_WARN_ONCE("the device reports no field of view: using Kinect v1 intrinsics (f = %.1f px at %dx%d)",
                        f.fx, f.width, f.height);
    std_msgs::Header header;
    header.stamp = ros::Time::now();
    header.frame_id = frame_id_;

    auto cloud = boost::make_shared<Cloud>();
    cloud->width = f.width;
    cloud->height = f.height;
    cloud->is_dense = false;
    cloud->points.resize(static_cast<std::size_t>(f.width) * f.height);
    cloud->header = pcl_conversions::toPCL(header);
    const float nan = std::numeric_limits<float>::quiet_NaN();
    for (int v = 0; v < f.height; ++v)
      for (int u = 0; u < f.width; ++u)
      {
        const std::size_t i = static_cast<std::size_t>(v) * f.width + u;
        PointT& p = cloud->points[i];
        const float z = f.depth_mm[i] * 0.001f;
        if (f.depth_mm[i] == 0)
          p.x = p.y = p.z = nan;
        else
        {
          p.x = (u - f.cx) * z / f.fx;
          p.y = (v - f.cy) * z / f.fy;
          p.z = z;
        }
        p.r = f.rgb[3 * i];
        p.g = f.rgb[3 * i + 1];
        p.b = f.rgb[3 * i + 2];
      }
    cloud_pub_.publish(InputCloud::of(cloud));

    auto info = boost::make_shared<sensor_msgs::CameraInfo>();
    info->header = header;
    info->width = f.width;
    info->height = f.height;
    info->distortion_model = "plumb_bob";
    info->D.assign(5, 0.0);
    info->K = { f.fx, 0, f.cx, 0, f.fy, f.cy, 0, 0, 1 };
    info->R = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
    info->P = { f.fx, 0, f.cx, 0, 0, f.fy, f.cy, 0, 0, 0, 1, 0 };
    info_pub_.publish(info);
  }

  std::string uri_;
  std::string frame_id_ = "camera_rgb_optical_frame";
  double retry_period_ = 3.0;
  ros::Publisher cloud_pub_, info_pub_;
  std::atomic<bool> running_{ false };
  std::thread thread_;
};

}  // namespace action_flow

PLUGINLIB_EXPORT_CLASS(action_flow::DriverNodelet, nodelet::Nodelet)
