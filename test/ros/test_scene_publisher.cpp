// Test aid: publishes the hand-built scene of test_scene.h, or good and bad variants of it, as
// the pipeline's input (`cloud`) or directly as the tracker's output (`person_clouds`).
#include "../core/scene.h"

#include <action_flow/ros/input_checks.h>
#include <action_flow/ros/stage_types.h>

#include <nodelet/nodelet.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl_ros/point_cloud.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>

#include <cmath>
#include <limits>

namespace action_flow
{
/**
 * Parameters (private): output (cloud|person_clouds), scene (person|empty|nan|unorganized|
 * floorless), rate (Hz), frame_id, wave_hz, count (frames, 0 = forever), jump_back_after
 * (frames per loop: then the stamps start again from the first one; 0 = never), lose_after (frames per track: then the
 * track is reported lost and a new id starts; 0 = never), distance (m).
 */
class TestScenePublisher : public nodelet::Nodelet
{
  void onInit() override
  {
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    pnh.param("output", output_, output_);
    pnh.param("scene", scene_, scene_);
    pnh.param("frame_id", frame_id_, frame_id_);
    pnh.param("wave_hz", wave_hz_, wave_hz_);
    pnh.param("count", count_, count_);
    pnh.param("jump_back_after", jump_back_after_, jump_back_after_);
    pnh.param("lose_after", lose_after_, lose_after_);
    double distance = options_.distance;
    pnh.param("distance", distance, distance);
    options_.distance = static_cast<float>(distance);
    double rate = 15.0;
    pnh.param("rate", rate, rate);
    options_.floor = scene_ != "floorless";
    if (output_ == "cloud")
      pub_ = getNodeHandle().advertise<InputCloud>("cloud", 5);
    else
      pub_ = getNodeHandle().advertise<PeopleClouds>("person_clouds", 5);
    start_ = ros::Time::now();
    timer_ = getNodeHandle().createWallTimer(ros::WallDuration(1.0 / rate), &TestScenePublisher::tick, this);
    period_ = 1.0 / rate;
  }

  void tick(const ros::WallTimerEvent&)
  {
    if (count_ > 0 && frame_ >= count_)
      return;
    // Like a looping bag: every jump_back_after frames the stamps start again from the first one,
    // so a subscriber that starts late still sees time go back.
    if (jump_back_after_ > 0 && frame_ > 0 && frame_ % jump_back_after_ == 0)
      offset_ -= jump_back_after_ * period_;
    const double t = frame_ * period_;
    std_msgs::Header header;
    header.stamp = start_ + ros::Duration(t + offset_ + 10.0);  // +10: a stamp well above zero
    header.frame_id = frame_id_;
    const float angle = 0.3f + 0.9f * static_cast<float>(std::sin(2.0 * M_PI * wave_hz_ * t));
    if (output_ == "cloud")
      pub_.publish(InputCloud::of(sceneCloud(header, angle)));
    else
      pub_.publish(personClouds(header, angle));
    ++frame_;
  }

  boost::shared_ptr<Cloud> sceneCloud(const std_msgs::Header& header, float angle)
  {
    auto cloud = boost::make_shared<Cloud>();
    if (scene_ == "empty")
    {
    }
    else if (scene_ == "nan")
    {
      PointT p;
      p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
      cloud->points.assign(static_cast<std::size_t>(options_.width) * options_.height, p);
      cloud->width = options_.width;
      cloud->height = options_.height;
      cloud->is_dense = false;
    }
    else
    {
      *cloud = test::renderScene(options_, angle);
      if (scene_ == "unorganized")
      {
        Cloud finite;
        for (const auto& p : cloud->points)
          if (std::isfinite(p.z))
            finite.push_back(p);
        *cloud = finite;
      }
    }
    cloud->header = pcl_conversions::toPCL(header);
    return cloud;
  }

  boost::shared_ptr<PeopleClouds> personClouds(const std_msgs::Header& header, float angle)
  {
    auto out = boost::make_shared<PeopleClouds>();
    out->header = header;
    if (lose_after_ > 0 && frame_ > 0 && frame_ % lose_after_ == 0)
      out->lost.push_back(track_id_++);
    auto cloud = boost::make_shared<Cloud>();
    if (scene_ == "nan")
    {
      PointT p;
      p.x = p.y = p.z = std::numeric_limits<float>::quiet_NaN();
      cloud->points.assign(100, p);
      cloud->width = 100;
      cloud->height = 1;
    }
    else if (scene_ != "empty")
    {
      const Cloud full = test::renderPerson(options_, angle);
      pcl::VoxelGrid<PointT> grid;
      grid.setLeafSize(0.02f, 0.02f, 0.02f);
      grid.setInputCloud(full.makeShared());
      grid.filter(*cloud);
    }
    cloud->header = pcl_conversions::toPCL(header);
    PeopleClouds::Person p;
    p.info.id = track_id_;
    p.info.height = test::kPersonHeight;
    p.info.position = Eigen::Vector3f(0, options_.camera_height - 0.9f, options_.distance);
    const Eigen::Vector4f ground(0, -1, 0, options_.camera_height);
    p.info.frame = PersonFrame::fromGround(p.info.position, ground, p.info.height, p.info.position);
    p.cloud = cloud;
    out->people.push_back(p);
    return out;
  }

  std::string output_ = "cloud", scene_ = "person", frame_id_ = "camera_rgb_optical_frame";
  double wave_hz_ = 0.8, period_ = 1.0 / 15, offset_ = 0.0;
  int count_ = 0, jump_back_after_ = 0, lose_after_ = 0, frame_ = 0;
  std::uint32_t track_id_ = 1;
  test::SceneOptions options_;
  ros::Time start_;
  ros::Publisher pub_;
  ros::WallTimer timer_;
};

}  // namespace action_flow

PLUGINLIB_EXPORT_CLASS(action_flow::TestScenePublisher, nodelet::Nodelet)
