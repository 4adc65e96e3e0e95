// People tracker stage: ground, detection and tracking (core PeopleTracker); each tracked person's cloud.
#include <action_flow/TrackedPeople.h>
#include <action_flow/people_tracker.h>
#include <action_flow/ros/input_checks.h>
#include <action_flow/ros/lazy_nodelet.h>
#include <action_flow/ros/stage_diagnostics.h>
#include <action_flow/ros/params.h>
#include <action_flow/ros/stage_types.h>

#include <pcl/common/transforms.h>
#include <pcl_ros/point_cloud.h>
#include <pluginlib/class_list_macros.hpp>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_listener.h>

namespace action_flow
{
/**
 * Subscribes `cloud` (InputCloud: in-process the publisher's pcl::PointCloud<pcl::PointXYZRGB>
 * itself, from elsewhere a sensor_msgs/PointCloud2 that is checked before it is read); publishes `person_clouds`
 * (PeopleClouds) and `people` (TrackedPeople). Parameters (private): the TrackerParams members
 * (`ground` as a,b,c,d fixes the ground plane, `up_hint` as x,y,z), `fixed_frame` (empty: work in
 * the camera frame; else clouds are transformed into it with tf2, e.g. odom on a moving robot, and
 * up_hint defaults to +z there), `tf_timeout` (s), `ground_from_fixed_frame` (with fixed_frame: its
 * z = 0 plane is the floor, given to the tracker as its ground prior; default false).
 */
class PeopleTrackerNodelet : public LazyNodelet
{
  void onInit() override
  {
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    pnh.param("fixed_frame", fixed_frame_, fixed_frame_);
    try
    {
      TrackerParams params = readTrackerParams(pnh);
      // A fixed frame such as odom or map is z-up (REP 103), unlike the camera's optical frame.
      if (!fixed_frame_.empty() && !pnh.hasParam("up_hint"))
        params.up_hint = Eigen::Vector3f::UnitZ();
      // camera_height/camera_pitch describe the ground in the camera's optical frame; with a fixed
      // frame the clouds are not in it: the ground then comes from tf (ground_from_fixed_frame).
      if (!fixed_frame_.empty() && params.camera_height > 0.0f)
      {
        NODELET_WARN("camera_height/camera_pitch are ignored with a fixed_frame (use ground_from_fixed_frame)");
        params.camera_height = 0.0f;
      }
      if (params.hog_classifier_file == "default" && defaultHogClassifierFile().empty())
        NODELET_WARN("the default HOG classifier file is not found: no HOG confirmation (see docs/tracker.md)");
      tracker_ = std::make_unique<PeopleTracker>(params);
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR("bad tracker parameters (%s): using the defaults", e.what());
      tracker_ = std::make_unique<PeopleTracker>();
    }
    pnh.param("tf_timeout", tf_timeout_, tf_timeout_);
    pnh.param("ground_from_fixed_frame", ground_from_fixed_frame_, ground_from_fixed_frame_);
    if (!fixed_frame_.empty() && fixed_frame_[0] == '/')
      fixed_frame_.erase(0, 1);
    if (!fixed_frame_.empty())
    {
      tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
      tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, getNodeHandle());
      NODELET_INFO("tracking in the fixed frame '%s'", fixed_frame_.c_str());
    }
    diag_.start(getNodeHandle(), pnh, getName(), "people tracker");
    setSubscribe([this] { return getNodeHandle().subscribe("cloud", 5, &PeopleTrackerNodelet::onInput, this); });
    clouds_pub_ = advertiseLazy<PeopleClouds>("person_clouds", 10);
    people_pub_ = advertiseLazy<TrackedPeople>("people", 10);
  }

  void onInput(const InputCloud::ConstPtr& input)
  {
    diag_.received();
    if (!input->cloud)
    {
      NODELET_ERROR_THROTTLE(5, "dropped a malformed point cloud on %s: it %s", getNodeHandle().resolveName("cloud").c_str(),
                             input->error.c_str());
      return;
    }
    onCloud(input->cloud);
  }

  void onCloud(const boost::shared_ptr<const Cloud>& in)
  {
    std_msgs::Header header = pcl_conversions::fromPCL(in->header);
    if (header.frame_id.empty())
    {
      NODELET_ERROR_THROTTLE(5, "input cloud has no frame id: skipped");
      return;
    }
    if (header.frame_id[0] == '/')
      header.frame_id.erase(0, 1);
    if (in->empty())
      NODELET_WARN_THROTTLE(10, "input cloud is empty");

    boost::shared_ptr<const Cloud> cloud = in;
    Eigen::Vector3f camera = Eigen::Vector3f::Zero();
    if (tf_buffer_ && !toFixedFrame(header, cloud, camera))
      return;

    TrackerResult result;
    try
    {
      result = tracker_->update(*cloud, header.stamp.toSec(), camera);
    }
    catch (const std::exception& e)
    {
      NODELET_ERROR_THROTTLE(5, "tracker failed on a cloud of %zu points (%s): skipped", in->size(), e.what());
      return;
    }
    if (result.reset)
      NODELET_WARN_THROTTLE(5, "time went backwards: all tracks dropped");
    if (!result.ground_valid)
      NODELET_WARN_THROTTLE(10, "no ground plane found yet (frame '%s')", header.frame_id.c_str());

    publish(result, header, in);
  }

  /**
   * Moves @p cloud into the fixed frame (and @p header with it), setting @p camera to the sensor's
   * position there; false (logged) when tf has no transform for it.
   */
  bool toFixedFrame(std_msgs::Header& header, boost::shared_ptr<const Cloud>& cloud, Eigen::Vector3f& camera)
  {
    try
    {
      const auto t = tf_buffer_->lookupTransform(fixed_frame_, header.frame_id, header.stamp,
                                                 ros::Duration(tf_timeout_));
      const Eigen::Affine3f pose = tf2::transformToEigen(t).cast<float>();
      auto moved = boost::make_shared<Cloud>();
      pcl::transformPointCloud(*cloud, *moved, pose);
      cloud = moved;
      camera = pose.translation();
      header.frame_id = fixed_frame_;
      // The fixed frame's z = 0 is the floor (REP 105: base_footprint, odom, map of a ground
      // robot): the ground is known from tf, kept while the floor is hidden, refined where seen.
      if (ground_from_fixed_frame_ && !ground_prior_set_)
        ground_prior_set_ = tracker_->setGroundPrior(Eigen::Vector4f(0, 0, 1, 0), camera);
      return true;
    }
    catch (const tf2::TransformException& e)
    {
      NODELET_ERROR_THROTTLE(5, "no transform from '%s' to fixed_frame '%s' (%s): cloud skipped",
                             header.frame_id.c_str(), fixed_frame_.c_str(), e.what());
      return false;
    }
  }

  /// The people clouds (sharing @p in, the input cloud) and the tracked people of one frame.
  void publish(TrackerResult& result, const std_msgs::Header& header, const boost::shared_ptr<const Cloud>& in)
  {
    auto out = boost::make_shared<PeopleClouds>();
    out->header = header;
    out->lost = result.lost;
    out->reset = result.reset;
    out->source = in;
    auto people = boost::make_shared<TrackedPeople>();
    people->header = header;
    people->lost = result.lost;
    people->reset = result.reset;
    people->ground_valid = result.ground_valid;
    for (int i = 0; i < 4; ++i)
      people->ground[i] = result.ground[i];
    for (auto& person : result.people)
    {
      PeopleClouds::Person p;
      p.info.id = person.id;
      p.info.position = person.position;
      p.info.velocity = person.velocity;
      p.info.height = person.height;
      p.info.frame = person.frame;
      p.cloud = person.cloud;
      people->people.push_back(toMessage(p.info));
      out->people.push_back(std::move(p));
    }
    clouds_pub_.publish(out);
    people_pub_.publish(people);
    diag_.published(header.stamp);
    diag_.set("tracked people", std::to_string(result.people.size()));
  }

  std::unique_ptr<PeopleTracker> tracker_;
  std::string fixed_frame_;
  double tf_timeout_ = 0.1;
  bool ground_from_fixed_frame_ = false;
  bool ground_prior_set_ = false;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::Publisher clouds_pub_, people_pub_;
  StageDiagnostics diag_;
};

}  // namespace action_flow

PLUGINLIB_EXPORT_CLASS(action_flow::PeopleTrackerNodelet, nodelet::Nodelet)
