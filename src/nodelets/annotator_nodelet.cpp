// Annotator: the colour image with each tracked person's box, track id and current label drawn on
// it, for image_view and rviz. Not part of the recognition: it only looks at the stages' outputs.
#include <action_flow/ros/input_checks.h>
#include <action_flow/ros/lazy_nodelet.h>
#include <action_flow/ros/stage_types.h>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <pcl_ros/point_cloud.h>
#include <pluginlib/class_list_macros.hpp>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>

namespace action_flow
{
namespace
{
/** Pinhole intrinsics of the image the boxes are drawn on. */
struct Intrinsics
{
  double fx = 0, fy = 0, cx = 0, cy = 0;
};

/** A person's box in pixels (inclusive corners), clipped to the image. */
struct Box
{
  int u0 = 0, v0 = 0, u1 = -1, v1 = -1;
  bool valid() const { return u1 >= u0 && v1 >= v0; }
};

/**
 * The image box of @p cloud's points (moved by @p to_camera into the image's optical frame) seen
 * with @p k in a @p width x @p height image; invalid when no point lies in front of the camera.
 */
Box projectExtent(const Cloud& cloud, const Eigen::Affine3f& to_camera, const Intrinsics& k, int width, int height)
{
  double u0 = INFINITY, v0 = INFINITY, u1 = -INFINITY, v1 = -INFINITY;
  for (const auto& p : cloud.points)
  {
    const Eigen::Vector3f c = to_camera * p.getVector3fMap();
    if (!std::isfinite(c.x()) || !std::isfinite(c.y()) || !(c.z() > 0.05f))
      continue;
    const double u = k.fx * c.x() / c.z() + k.cx, v = k.fy * c.y() / c.z() + k.cy;
    u0 = std::min(u0, u);
    u1 = std::max(u1, u);
    v0 = std::min(v0, v);
    v1 = std::max(v1, v);
  }
  Box b;
  if (!(u1 >= u0))
    return b;
  b.u0 = std::max(0, static_cast<int>(std::lround(u0)));
  b.v0 = std::max(0, static_cast<int>(std::lround(v0)));
  b.u1 = std::min(width - 1, static_cast<int>(std::lround(u1)));
  b.v1 = std::min(height - 1, static_cast<int>(std::lround(v1)));
  return b;
}

/**
 * Intrinsics of an organized cloud, fitted from its own points (u = fx x/z + cx per pixel column,
 * the same for rows): the cloud is its own camera model, whatever camera_info says or lacks.
 */
std::optional<Intrinsics> fitIntrinsics(const Cloud& cloud)
{
  if (cloud.height < 2 || cloud.width < 2 || cloud.points.size() != std::size_t(cloud.width) * cloud.height)
    return std::nullopt;
  // Least squares of u on x/z and of v on y/z over a sample of the finite points.
  double su[5] = { 0, 0, 0, 0, 0 }, sv[5] = { 0, 0, 0, 0, 0 };  // n, sum a, sum a^2, sum t, sum a t
  const std::size_t stride = std::max<std::size_t>(1, cloud.points.size() / 20000);
  for (std::size_t i = 0; i < cloud.points.size(); i += stride)
  {
    const auto& p = cloud.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !(p.z > 0.05f))
      continue;
    const double a = p.x / p.z, b = p.y / p.z, u = double(i % cloud.width), v = double(i / cloud.width);
    const double add_u[5] = { 1, a, a * a, u, a * u }, add_v[5] = { 1, b, b * b, v, b * v };
    for (int j = 0; j < 5; ++j)
    {
      su[j] += add_u[j];
      sv[j] += add_v[j];
    }
  }
  const auto solve = [](const double* s, double& f, double& c) {
    const double det = s[0] * s[2] - s[1] * s[1];
    if (s[0] < 100 || !(std::abs(det) > 1e-12 * s[0] * s[0]))
      return false;
    f = (s[0] * s[4] - s[1] * s[3]) / det;
    c = (s[3] - f * s[1]) / s[0];
    return std::isfinite(f) && f > 0;
  };
  Intrinsics k;
  if (!solve(su, k.fx, k.cx) || !solve(sv, k.fy, k.cy))
    return std::nullopt;
  return k;
}

/** A colour per track id (BGR), the same for an id in every frame. */
cv::Scalar trackColour(std::uint32_t id)
{
  static const cv::Scalar palette[] = { { 0, 255, 0 },   { 255, 128, 0 }, { 0, 128, 255 }, { 255, 0, 255 },
                                        { 0, 255, 255 }, { 255, 255, 0 }, { 128, 0, 255 }, { 0, 0, 255 } };
  return palette[id % (sizeof(palette) / sizeof(palette[0]))];
}
}  // namespace

/**
 * Subscribes `person_clouds` (PeopleClouds), `states` (ActionStates: each track's current label)
 * and, with image_source `image`, `rgb/image` (sensor_msgs/Image, rgb8 or bgr8) and
 * `rgb/camera_info`; publishes `annotated/image` (bgr8): the colour image of each people frame with
 * every tracked person's box (their cloud's points projected), "id: label" above it, and
 * `annotated/people_points` (an XYZRGB cloud: every tracked person's points in their track's box
 * colour, for rviz, which cannot show PeopleClouds).
 * With image_source `cloud` the image and the intrinsics come from the organized cloud the tracker
 * read (PeopleClouds::source, in the same manager only), for sensors that publish no image (the
 * driver). Images and people frames are matched by stamp (within `slop` s, small buffers of both).
 * Bad input gives a throttled error and is dropped; the next good frame is served. Subscribes only
 * while someone listens to an output.
 * Parameters (private): image_source (image|cloud), slop, queue_size, line_width.
 */
class AnnotatorNodelet : public LazyNodelet
{
  void onInit() override
  {
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    pnh.param("image_source", image_source_, image_source_);
    pnh.param("slop", slop_, slop_);
    pnh.param("queue_size", queue_size_, queue_size_);
    pnh.param("line_width", line_width_, line_width_);
    if (image_source_ != "image" && image_source_ != "cloud")
    {
      NODELET_ERROR("unknown image_source '%s' (image or cloud): using image", image_source_.c_str());
      image_source_ = "image";
    }
    queue_size_ = std::max(1, queue_size_);
    image_topic_ = getNodeHandle().resolveName("rgb/image");

    // LazyNodelet switches one subscription; the others follow it (subscribe() below holds them).
    setSubscribe([this] { return subscribe(); });
    image_pub_ = advertiseLazy<sensor_msgs::Image>("annotated/image", 5);
    points_pub_ = advertiseLazy<Cloud>("annotated/people_points", 5);
  }

  /** Subscribes every input; returns the person_clouds subscription, whose end ends the others. */
  ros::Subscriber subscribe()
  {
    ros::NodeHandle& nh = getNodeHandle();
    // The secondary subscriptions live in an object the people subscription's callback holds:
    // when LazyNodelet shuts that subscription down and drops it, roscpp drops the callback and
    // with it these subscriptions.
    auto extra = std::make_shared<std::vector<ros::Subscriber>>();
    extra->push_back(nh.subscribe("states", 10, &AnnotatorNodelet::onStates, this));
    if (image_source_ == "image")
    {
      extra->push_back(nh.subscribe("rgb/image", 5, &AnnotatorNodelet::onImage, this));
      extra->push_back(nh.subscribe("rgb/camera_info", 5, &AnnotatorNodelet::onInfo, this));
    }
    {
      std::lock_guard<std::mutex> lock(mutex_);
      images_.clear();
      people_.clear();
      labels_.clear();
    }
    return nh.subscribe<PeopleClouds>("person_clouds", 5,
                                      boost::function<void(const PeopleClouds::ConstPtr&)>(
                                          [this, extra](const PeopleClouds::ConstPtr& m) { onPeople(m); }));
  }

  void onStates(const ActionStates::ConstPtr& m)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& t : m->tracks)
      labels_[t.track_id] = t.label;
  }

  void onInfo(const sensor_msgs::CameraInfo::ConstPtr& m)
  {
    const std::string error = checkCameraInfo(*m);
    if (!error.empty())
    {
      NODELET_ERROR_THROTTLE(5, "ignored a camera_info on %s: it %s", getNodeHandle().resolveName("rgb/camera_info").c_str(),
                             error.c_str());
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    info_ = m;
  }

  void onImage(const sensor_msgs::Image::ConstPtr& m)
  {
    std::string error = checkImage(*m);
    if (error.empty() && m->encoding != "rgb8" && m->encoding != "bgr8")
      error = "has the encoding '" + m->encoding + "' (rgb8 or bgr8 expected)";
    if (!error.empty())
    {
      NODELET_ERROR_THROTTLE(5, "dropped a colour image on %s: it %s", image_topic_.c_str(), error.c_str());
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    images_.push_back(m);
    while (images_.size() > std::size_t(queue_size_))
      images_.pop_front();
    // People frames that came before their image.
    for (auto p = people_.begin(); p != people_.end(); ++p)
      if (std::abs(((*p)->header.stamp - m->header.stamp).toSec()) <= slop_)
      {
        const PeopleClouds::ConstPtr people = *p;
        people_.erase(people_.begin(), p + 1);
        annotateImage(m, people);
        return;
      }
  }

  void onPeople(const PeopleClouds::ConstPtr& m)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (m->reset)
      labels_.clear();
    for (std::uint32_t id : m->lost)
      labels_.erase(id);
    if (points_pub_.getNumSubscribers() > 0)
      publishPoints(*m);
    if (image_pub_.getNumSubscribers() == 0)
      return;
    if (image_source_ == "cloud")
    {
      annotateCloud(m);
      return;
    }
    // The image of the closest stamp within slop; older images are of frames already gone.
    auto best = images_.end();
    double best_dt = slop_;
    for (auto i = images_.begin(); i != images_.end(); ++i)
    {
      const double dt = std::abs(((*i)->header.stamp - m->header.stamp).toSec());
      if (dt <= best_dt)
      {
        best = i;
        best_dt = dt;
      }
    }
    if (best == images_.end())
    {
      people_.push_back(m);  // its image may still come
      while (people_.size() > std::size_t(queue_size_))
      {
        NODELET_WARN_THROTTLE(10, "no colour image on %s within %.3f s of people frame %.3f: not annotated",
                              image_topic_.c_str(), slop_, people_.front()->header.stamp.toSec());
        people_.pop_front();
      }
      return;
    }
    const sensor_msgs::Image::ConstPtr image = *best;
    images_.erase(images_.begin(), best + 1);
    annotateImage(image, m);
  }

  /** Annotates @p image with @p people (image_source image); called with mutex_ held. */
  void annotateImage(const sensor_msgs::Image::ConstPtr& image, const PeopleClouds::ConstPtr& people)
  {
    if (!info_)
    {
      // Usually the first frames after subscribing, before the first camera_info: a warning.
      NODELET_WARN_THROTTLE(5, "no good camera_info on %s yet: cannot place the people in the image",
                             getNodeHandle().resolveName("rgb/camera_info").c_str());
      return;
    }
    if (info_->width != image->width || info_->height != image->height)
    {
      NODELET_ERROR_THROTTLE(5, "dropped a colour image on %s: it is %ux%u, the camera_info says %ux%u",
                             image_topic_.c_str(), image->width, image->height, info_->width, info_->height);
      return;
    }
    auto out = newImage(image->header, image->width, image->height);
    const cv::Mat in(image->height, image->width, CV_8UC3, const_cast<std::uint8_t*>(image->data.data()), image->step);
    cv::Mat canvas(out->height, out->width, CV_8UC3, out->data.data(), out->step);
    if (image->encoding == "rgb8")
      cv::cvtColor(in, canvas, cv::COLOR_RGB2BGR);
    else
      in.copyTo(canvas);
    const Intrinsics k{ info_->P[0], info_->P[5], info_->P[2], info_->P[6] };  // P, as depth_image_proc projects
    draw(canvas, *people, image->header.frame_id, k);
    image_pub_.publish(out);
  }

  /** Annotates the tracker's own input cloud (image_source cloud); called with mutex_ held. */
  void annotateCloud(const PeopleClouds::ConstPtr& people)
  {
    const auto& cloud = people->source;
    if (!cloud)
    {
      NODELET_ERROR_THROTTLE(5, "image_source cloud: the people frame carries no input cloud (the tracker must run "
                                "in the same manager): not annotated");
      return;
    }
    const auto k = fitIntrinsics(*cloud);
    if (!k)
    {
      NODELET_ERROR_THROTTLE(5, "image_source cloud: the input cloud (%ux%u) is not an organized camera cloud: not "
                                "annotated",
                             cloud->width, cloud->height);
      return;
    }
    std_msgs::Header header = pcl_conversions::fromPCL(cloud->header);
    auto out = newImage(header, cloud->width, cloud->height);
    for (std::size_t i = 0; i < cloud->points.size(); ++i)
    {
      const auto& p = cloud->points[i];
      std::uint8_t* px = &out->data[3 * i];
      px[0] = p.b;
      px[1] = p.g;
      px[2] = p.r;
    }
    cv::Mat canvas(out->height, out->width, CV_8UC3, out->data.data(), out->step);
    draw(canvas, *people, header.frame_id, *k);
    image_pub_.publish(out);
  }

  /** All tracked people's points in one cloud (for rviz, which cannot show PeopleClouds), coloured by track. */
  void publishPoints(const PeopleClouds& people)
  {
    auto out = boost::make_shared<Cloud>();
    out->header = pcl_conversions::toPCL(people.header);
    for (const auto& p : people.people)
    {
      if (!p.cloud)
        continue;
      const cv::Scalar c = trackColour(p.info.id);
      for (PointT q : p.cloud->points)
      {
        q.b = static_cast<std::uint8_t>(c[0]);
        q.g = static_cast<std::uint8_t>(c[1]);
        q.r = static_cast<std::uint8_t>(c[2]);
        out->push_back(q);
      }
    }
    out->is_dense = false;
    points_pub_.publish(out);
  }

  static boost::shared_ptr<sensor_msgs::Image> newImage(const std_msgs::Header& header, std::uint32_t width,
                                                        std::uint32_t height)
  {
    auto out = boost::make_shared<sensor_msgs::Image>();
    out->header = header;
    out->width = width;
    out->height = height;
    out->encoding = "bgr8";
    out->step = 3 * width;
    out->data.resize(std::size_t(out->step) * height);
    return out;
  }

  /** Draws every person of @p people on @p canvas, an image in @p camera_frame seen with @p k. */
  void draw(cv::Mat& canvas, const PeopleClouds& people, const std::string& camera_frame, const Intrinsics& k)
  {
    Eigen::Affine3f to_camera = Eigen::Affine3f::Identity();
    if (!camera_frame.empty() && !people.header.frame_id.empty() && people.header.frame_id != camera_frame &&
        !people.people.empty())
    {
      if (!tf_buffer_)
      {
        tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
        tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_);
      }
      try
      {
        to_camera = tf2::transformToEigen(tf_buffer_->lookupTransform(camera_frame, people.header.frame_id,
                                                                      people.header.stamp, ros::Duration(0.05)))
                        .cast<float>();
      }
      catch (const tf2::TransformException& e)
      {
        NODELET_ERROR_THROTTLE(5, "no transform from the people's frame '%s' to the image's '%s' (%s): boxes not drawn",
                               people.header.frame_id.c_str(), camera_frame.c_str(), e.what());
        return;
      }
    }
    for (const auto& p : people.people)
    {
      if (!p.cloud)
        continue;
      const Box b = projectExtent(*p.cloud, to_camera, k, canvas.cols, canvas.rows);
      if (!b.valid())
        continue;
      const cv::Scalar colour = trackColour(p.info.id);
      cv::rectangle(canvas, cv::Point(b.u0, b.v0), cv::Point(b.u1, b.v1), colour, line_width_);
      const auto l = labels_.find(p.info.id);
      const std::string text =
          std::to_string(p.info.id) + ": " + (l == labels_.end() || l->second.empty() ? "?" : l->second);
      const double scale = std::max(0.4, canvas.rows / 960.0);
      int baseline = 0;
      const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &baseline);
      // Above the box, or inside its top when the box touches the top of the image.
      const int top = b.v0 - size.height - baseline - 4 >= 0 ? b.v0 - size.height - baseline - 4 : b.v0;
      cv::rectangle(canvas, cv::Point(b.u0, top), cv::Point(b.u0 + size.width + 4, top + size.height + baseline + 4),
                    colour, cv::FILLED);
      cv::putText(canvas, text, cv::Point(b.u0 + 2, top + size.height + 2), cv::FONT_HERSHEY_SIMPLEX, scale,
                  cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
  }

  std::string image_source_ = "image";
  double slop_ = 0.05;
  int queue_size_ = 10;
  int line_width_ = 2;
  std::string image_topic_;

  std::mutex mutex_;
  std::deque<sensor_msgs::Image::ConstPtr> images_;
  std::deque<PeopleClouds::ConstPtr> people_;
  std::map<std::uint32_t, std::string> labels_;
  sensor_msgs::CameraInfo::ConstPtr info_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::Publisher image_pub_, points_pub_;
};

}  // namespace action_flow

PLUGINLIB_EXPORT_CLASS(action_flow::AnnotatorNodelet, nodelet::Nodelet)
