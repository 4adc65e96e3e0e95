// Driver stage: a depth+colour sensor as openni2_camera with openni2_launch's registered cloud
// presents it (colour and registered depth images with camera_info, the organized XYZRGB cloud,
// the camera's TF frames); each output is made only while someone subscribes to it, and the
// streams run only while someone subscribes to any. Backends: OpenNI2 (Xtion, .oni recordings, the
// Dummy test device) and libfreenect (Kinect v1, fakenect dumps).
#include "../driver/device_clock.h"
#include "../driver/freenect_device.h"
#include "../driver/openni2_device.h"

#include <action_flow/depth_cloud.h>
#include <action_flow/ros/camera_info.h>
#include <action_flow/ros/input_checks.h>
#include <action_flow/ros/stage_diagnostics.h>
#include <action_flow/types.h>

#include <camera_info_manager/camera_info_manager.h>
#include <geometry_msgs/TransformStamped.h>
#include <nodelet/nodelet.h>
#include <pcl_conversions/pcl_conversions.h>
#include <pcl_ros/point_cloud.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/image_encodings.h>
#include <tf2_ros/static_transform_broadcaster.h>

#include <atomic>
#include <cstring>
#include <thread>

namespace action_flow
{
/**
 * Publishes, in its namespace (kinect.launch: `camera`): `depth_registered/points`
 * (pcl::PointCloud<pcl::PointXYZRGB>, organized, depth registered to colour), `rgb/image_raw`
 * (rgb8) and `depth_registered/image_raw` (16UC1, millimetres, 0 = none), each with its
 * camera_info. Parameters (private): backend (openni2 | freenect), device_uri (openni2: "" first
 * device, a .oni path, "Dummy"; freenect: "" first Kinect, an index, a fakenect dump folder),
 * fakenect_library ("" = the one found at build time), camera (the TF frames' prefix, default
 * "camera"), frame_id ("" = <camera>_rgb_optical_frame), publish_tf (the camera's frames from
 * <camera>_link, default true), rgb_camera_info_url (a calibration file for camera_info_manager;
 * "" = the device's intrinsics), retry_period (s between attempts to open an absent device).
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
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    pnh.param("backend", backend_, backend_);
    pnh.param("device_uri", uri_, uri_);
    pnh.param("fakenect_library", fakenect_library_, fakenect_library_);
    pnh.param("camera", camera_, camera_);
    pnh.param("frame_id", frame_id_, frame_id_);
    pnh.param("publish_tf", publish_tf_, publish_tf_);
    pnh.param("retry_period", retry_period_, retry_period_);
    std::string url;
    pnh.param("rgb_camera_info_url", url, url);
    while (!frame_id_.empty() && frame_id_[0] == '/')
      frame_id_.erase(0, 1);
    if (frame_id_.empty())
      frame_id_ = camera_ + "_rgb_optical_frame";
    info_manager_ = std::make_unique<camera_info_manager::CameraInfoManager>(ros::NodeHandle(nh, "rgb"), camera_ + "_rgb", url);
    // The polling thread reads the subscriber counts; the connect callbacks only need to exist.
    auto cb = [](const ros::SingleSubscriberPublisher&) {};
    cloud_pub_ = nh.advertise<InputCloud>("depth_registered/points", 2, cb, cb);
    rgb_pub_ = nh.advertise<sensor_msgs::Image>("rgb/image_raw", 2, cb, cb);
    rgb_info_pub_ = nh.advertise<sensor_msgs::CameraInfo>("rgb/camera_info", 2, cb, cb);
    depth_pub_ = nh.advertise<sensor_msgs::Image>("depth_registered/image_raw", 2, cb, cb);
    depth_info_pub_ = nh.advertise<sensor_msgs::CameraInfo>("depth_registered/camera_info", 2, cb, cb);
    if (publish_tf_)
      publishFrames();
    diag_.start(nh, pnh, getName(), "driver");
    diag_.set("device", "not open yet");
    if (backend_ != "openni2" && backend_ != "freenect")
    {
      NODELET_ERROR("backend must be openni2 or freenect, got '%s': publishing nothing", backend_.c_str());
      return;
    }
    running_ = true;
    thread_ = std::thread(&DriverNodelet::run, this);
  }

  // The camera's frames as openni2_launch gives a Kinect (rgbd_launch's kinect_frames): the colour
  // and depth cameras 4.5 and 2 cm to the right of <camera>_link, each with its optical frame
  // (z forward, x right, y down). Depth is registered to colour, so the clouds use the colour one.
  void publishFrames()
  {
    const auto transform = [&](const std::string& parent, const std::string& child, double y, bool optical) {
      geometry_msgs::TransformStamped t;
      t.header.stamp = ros::Time::now();
      t.header.frame_id = parent;
      t.child_frame_id = child;
      t.transform.translation.y = y;
      // roll -90 deg, yaw -90 deg: x right, y down, z forward
      t.transform.rotation.w = optical ? 0.5 : 1.0;
      t.transform.rotation.x = optical ? -0.5 : 0.0;
      t.transform.rotation.y = optical ? 0.5 : 0.0;
      t.transform.rotation.z = optical ? -0.5 : 0.0;
      return t;
    };
    tf_.sendTransform({ transform(camera_ + "_link", camera_ + "_rgb_frame", -0.045, false),
                        transform(camera_ + "_rgb_frame", camera_ + "_rgb_optical_frame", 0.0, true),
                        transform(camera_ + "_link", camera_ + "_depth_frame", -0.02, false),
                        transform(camera_ + "_depth_frame", camera_ + "_depth_optical_frame", 0.0, true) });
  }

  bool wanted() const
  {
    for (const ros::Publisher* p : { &cloud_pub_, &rgb_pub_, &rgb_info_pub_, &depth_pub_, &depth_info_pub_ })
      if (p->getNumSubscribers() > 0)
        return true;
    return false;
  }

  // Sleeps in small steps so that unloading never waits for a whole retry period.
  void pause(double seconds)
  {
    const auto until = ros::WallTime::now() + ros::WallDuration(seconds);
    while (running_ && ros::WallTime::now() < until)
      ros::WallDuration(0.05).sleep();
  }

  std::unique_ptr<RgbdDevice> open() const
  {
    if (backend_ == "freenect")
      return std::make_unique<FreenectDevice>(uri_, fakenect_library_);
    return std::make_unique<OpenNI2Device>(uri_);
  }

  void run()
  {
    std::unique_ptr<RgbdDevice> device;
    RgbdFrame frame;
    const std::string name = uri_.empty() ? "first " + backend_ + " device" : "'" + uri_ + "'";
    while (running_ && ros::ok())
    {
      try
      {
        if (!device)
        {
          device = open();
          NODELET_INFO("opened %s", device->description().c_str());
          diag_.set("device", device->description());
          diag_.setProblem("");
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
        {
          diag_.received();
          publish(frame);
        }
      }
      catch (const EndOfRecording& e)
      {
        NODELET_INFO("%s: publishing nothing more", e.what());
        diag_.set("device", e.what());
        break;
      }
      catch (const DeviceError& e)
      {
        NODELET_ERROR("%s; retrying %s in %.1f s", e.what(), name.c_str(), retry_period_);
        diag_.setProblem(e.what());
        device.reset();
        pause(retry_period_);
      }
    }
    device.reset();  // streams stopped and destroyed before the device closes, on this thread
  }

  // The colour camera's info: the calibration camera_info_manager loaded, if it fits the frame;
  // else the device's intrinsics without distortion.
  sensor_msgs::CameraInfo cameraInfo(const RgbdFrame& f)
  {
    sensor_msgs::CameraInfo info;
    if (info_manager_->isCalibrated())
    {
      info = info_manager_->getCameraInfo();
      if (info.width == std::uint32_t(f.width) && info.height == std::uint32_t(f.height))
        return info;
      NODELET_WARN_ONCE("the calibration is for %ux%u, the device delivers %dx%d: using the device's intrinsics",
                        info.width, info.height, f.width, f.height);
    }
    return pinholeCameraInfo(f.width, f.height, f.fx, f.fy, f.cx, f.cy);
  }

  void publish(const RgbdFrame& f)
  {
    if (f.default_intrinsics)
      NODELET_WARN_ONCE("the device reports no field of view: using Kinect v1 intrinsics (f = %.1f px at %dx%d)",
                        f.fx, f.width, f.height);
    std_msgs::Header header;
    header.stamp = ros::Time(clock_.stamp(f.timestamp_us, ros::Time::now().toSec()));
    // Whole microseconds, as a pcl cloud's header holds them: the images and the cloud of a frame
    // then carry the same stamp.
    header.stamp.fromNSec(header.stamp.toNSec() / 1000 * 1000);
    header.frame_id = frame_id_;
    sensor_msgs::CameraInfo info = cameraInfo(f);
    info.header = header;

    if (cloud_pub_.getNumSubscribers() > 0)
    {
      metres_.resize(f.depth_mm.size());
      for (std::size_t i = 0; i < f.depth_mm.size(); ++i)
        metres_[i] = f.depth_mm[i] * 0.001f;  // 0 = no reading, as depthToCloud takes it
      auto cloud = boost::make_shared<Cloud>();
      // Registered depth is in the colour camera: its projection P, as depth_image_proc uses it.
      depthToCloud(metres_.data(), f.rgb.data(), f.width, f.height, Intrinsics{ info.P[0], info.P[5], info.P[2], info.P[6] },
                   *cloud);
      cloud->header = pcl_conversions::toPCL(header);
      cloud_pub_.publish(InputCloud::of(cloud));
    }
    const auto image = [&](ros::Publisher& pub, const std::string& encoding, const void* data, int bytes_per_pixel) {
      if (pub.getNumSubscribers() == 0)
        return;
      auto m = boost::make_shared<sensor_msgs::Image>();
      m->header = header;
      m->width = f.width;
      m->height = f.height;
      m->encoding = encoding;
      m->step = f.width * bytes_per_pixel;
      m->data.resize(std::size_t(m->step) * f.height);
      std::memcpy(m->data.data(), data, m->data.size());
      pub.publish(m);
    };
    image(rgb_pub_, sensor_msgs::image_encodings::RGB8, f.rgb.data(), 3);
    image(depth_pub_, sensor_msgs::image_encodings::TYPE_16UC1, f.depth_mm.data(), 2);
    rgb_info_pub_.publish(info);
    depth_info_pub_.publish(info);
    diag_.published(header.stamp);
  }

  std::string backend_ = "openni2";
  std::string uri_;
  std::string fakenect_library_;
  std::string camera_ = "camera";
  std::string frame_id_;
  bool publish_tf_ = true;
  double retry_period_ = 3.0;
  std::unique_ptr<camera_info_manager::CameraInfoManager> info_manager_;
  tf2_ros::StaticTransformBroadcaster tf_;
  DeviceClock clock_;
  StageDiagnostics diag_;
  std::vector<float> metres_;
  ros::Publisher cloud_pub_, rgb_pub_, rgb_info_pub_, depth_pub_, depth_info_pub_;
  std::atomic<bool> running_{ false };
  std::thread thread_;
};

}  // namespace action_flow

PLUGINLIB_EXPORT_CLASS(action_flow::DriverNodelet, nodelet::Nodelet)
