// Image guard: lets only well-formed depth, colour and camera_info messages through to Debian's
// depth_image_proc, which runs in the same manager and dies on a malformed image (a 0x0 image, a
// step or data length that does not fit, a depth image larger than the colour one).
#include <action_flow/ros/input_checks.h>

#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>

#include <mutex>

namespace action_flow
{
/**
 * Subscribes `rgb/image_in`, `depth/image_in` and `rgb/camera_info_in`; publishes the very same
 * messages (the same pointers: no copy) on `rgb/image`, `depth/image` and `rgb/camera_info` when
 * they check out (checkImage, checkCameraInfo), the images also having the size of the last good
 * camera_info, colour in rgb8/bgr8/rgba8/bgra8/mono8 and depth in 16UC1/32FC1. Anything else is
 * dropped with a throttled error saying what was wrong. Subscribes only while someone listens.
 */
class ImageGuardNodelet : public nodelet::Nodelet
{
  void onInit() override
  {
    ros::NodeHandle& nh = getNodeHandle();
    const auto cb = [this](const ros::SingleSubscriberPublisher&) { update(); };
    // Resolved once: the callbacks must not read the subscribers, which update() may be assigning.
    rgb_topic_ = nh.resolveName("rgb/image_in");
    depth_topic_ = nh.resolveName("depth/image_in");
    info_topic_ = nh.resolveName("rgb/camera_info_in");
    std::lock_guard<std::mutex> lock(mutex_);
    rgb_pub_ = nh.advertise<sensor_msgs::Image>("rgb/image", 5, cb, cb);
    depth_pub_ = nh.advertise<sensor_msgs::Image>("depth/image", 5, cb, cb);
    info_pub_ = nh.advertise<sensor_msgs::CameraInfo>("rgb/camera_info", 5, cb, cb);
  }

  void update()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    const bool wanted =
        rgb_pub_.getNumSubscribers() > 0 || depth_pub_.getNumSubscribers() > 0 || info_pub_.getNumSubscribers() > 0;
    ros::NodeHandle& nh = getNodeHandle();
    if (wanted && !subscribed_)
    {
      rgb_sub_ = nh.subscribe<sensor_msgs::Image>("rgb/image_in", 5, [this](const sensor_msgs::Image::ConstPtr& m) {
        onImage(m, false);
      });
      depth_sub_ = nh.subscribe<sensor_msgs::Image>("depth/image_in", 5, [this](const sensor_msgs::Image::ConstPtr& m) {
        onImage(m, true);
      });
      info_sub_ = nh.subscribe("rgb/camera_info_in", 5, &ImageGuardNodelet::onInfo, this);
      subscribed_ = true;
    }
    else if (!wanted && subscribed_)
    {
      rgb_sub_.shutdown();
      depth_sub_.shutdown();
      info_sub_.shutdown();
      subscribed_ = false;
    }
  }

  void onInfo(const sensor_msgs::CameraInfo::ConstPtr& m)
  {
    std::string error = checkCameraInfo(*m);
    {
      // The image size is set once, by the first good camera_info: were it to change, a colour
      // image of the old size and a depth image of the new one with the same stamp could both pass
      // and depth_image_proc would pair them (it throws on a depth image taller than the colour).
      std::lock_guard<std::mutex> lock(size_mutex_);
      if (error.empty() && width_ != 0 && (m->width != width_ || m->height != height_))
        error = "is for " + std::to_string(m->width) + "x" + std::to_string(m->height) + " images, the camera's are " +
                std::to_string(width_) + "x" + std::to_string(height_) + " (a size change needs a restart)";
      if (error.empty())
      {
        width_ = m->width;
        height_ = m->height;
      }
    }
    if (!error.empty())
    {
      NODELET_ERROR_THROTTLE(5, "dropped a camera_info on %s: it %s", info_topic_.c_str(), error.c_str());
      return;
    }
    info_pub_.publish(m);
  }

  void onImage(const sensor_msgs::Image::ConstPtr& m, bool depth)
  {
    std::string error = checkImage(*m);
    if (error.empty())
    {
      const std::string& e = m->encoding;
      const bool fits = depth ? (e == "16UC1" || e == "32FC1")
                              : (e == "rgb8" || e == "bgr8" || e == "rgba8" || e == "bgra8" || e == "mono8");
      if (!fits)
        error = "has the encoding '" + e + "', which is not a " + (depth ? "depth" : "colour") + " encoding";
    }
    if (error.empty())
    {
      std::lock_guard<std::mutex> lock(size_mutex_);
      if (width_ == 0)
        error = "came before any good camera_info";
      else if (m->width != width_ || m->height != height_)
        error = "is " + std::to_string(m->width) + "x" + std::to_string(m->height) + ", the camera_info says " +
                std::to_string(width_) + "x" + std::to_string(height_);
    }
    if (!error.empty())
    {
      NODELET_ERROR_THROTTLE(5, "dropped a %s image on %s: it %s", depth ? "depth" : "colour",
                             (depth ? depth_topic_ : rgb_topic_).c_str(), error.c_str());
      return;
    }
    (depth ? depth_pub_ : rgb_pub_).publish(m);
  }

  std::mutex mutex_, size_mutex_;
  bool subscribed_ = false;
  std::uint32_t width_ = 0, height_ = 0;
  std::string rgb_topic_, depth_topic_, info_topic_;
  ros::Publisher rgb_pub_, depth_pub_, info_pub_;
  ros::Subscriber rgb_sub_, depth_sub_, info_sub_;
};

}  // namespace action_flow

PLUGINLIB_EXPORT_CLASS(action_flow::ImageGuardNodelet, nodelet::Nodelet)
