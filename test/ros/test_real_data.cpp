// Real recordings through the nodelets (skipped when ../shared/data is absent):
// each tue_hsr_person_*.bag's depth + rgb images through depth_image_proc/point_cloud_xyzrgb and
// the people tracker give exactly the one standing person; pcl_five_people.pcd gives 4 or 5 people.
#include "test_helpers.h"

#include <action_flow/TrackedPeople.h>

#include <gtest/gtest.h>
#include <pcl/common/io.h>
#include <pcl/io/pcd_io.h>
#include <pcl_conversions/pcl_conversions.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>

#include <boost/filesystem.hpp>

using namespace action_flow;
using action_flow::test::Collector;
using action_flow::test::waitFor;

namespace
{
std::string g_data;

/** The TrackedPeople message the tracker made from the input stamped @p stamp, if it came. */
boost::shared_ptr<const TrackedPeople> resultFor(const Collector<TrackedPeople>& people, const ros::Time& stamp)
{
  boost::shared_ptr<const TrackedPeople> found;
  waitFor(
      [&] {
        // pcl clouds keep stamps in microseconds: compare to within one.
        for (const auto& m : people.messages())
          if (std::abs((m->header.stamp - stamp).toSec()) < 2e-6)
            found = m;
        return static_cast<bool>(found);
      },
      20.0);
  return found;
}
}  // namespace

TEST(RealData, EachTueHsrBagGivesTheOneStandingPerson)
{
  std::vector<std::string> bags;
  const boost::filesystem::path dir = boost::filesystem::path(g_data) / "real_rgbd";
  if (boost::filesystem::is_directory(dir))
    for (const auto& e : boost::filesystem::directory_iterator(dir))
      if (e.path().filename().string().rfind("tue_hsr_person_", 0) == 0 && e.path().extension() == ".bag")
        bags.push_back(e.path().string());
  if (bags.empty())
    GTEST_SKIP() << "real data absent: no tue_hsr_person_*.bag in " << dir.string();
  std::sort(bags.begin(), bags.end());

  ros::NodeHandle nh;
  Collector<TrackedPeople> people(nh, "tue/people");
  ros::Publisher rgb_pub = nh.advertise<sensor_msgs::Image>("tue/rgb", 2);
  ros::Publisher depth_pub = nh.advertise<sensor_msgs::Image>("tue/depth", 2);
  ros::Publisher info_pub = nh.advertise<sensor_msgs::CameraInfo>("tue/camera_info", 2);
  ASSERT_TRUE(waitFor([&] { return rgb_pub.getNumSubscribers() && depth_pub.getNumSubscribers() && info_pub.getNumSubscribers(); }, 10.0))
      << "depth_image_proc did not subscribe to the images";

  for (const auto& path : bags)
  {
    SCOPED_TRACE(path);
    rosbag::Bag bag(path);
    sensor_msgs::Image::Ptr rgb, depth;
    sensor_msgs::CameraInfo::Ptr info;
    for (const auto& m : rosbag::View(bag))
    {
      if (m.getTopic() == "/hero/head_rgbd_sensor/rgb/image_raw" && !rgb)
        rgb = m.instantiate<sensor_msgs::Image>();
      else if (m.getTopic() == "/hero/head_rgbd_sensor/depth_registered/image" && !depth)
        depth = m.instantiate<sensor_msgs::Image>();
      else if (m.getTopic() == "/hero/head_rgbd_sensor/rgb/camera_info" && !info)
        info = m.instantiate<sensor_msgs::CameraInfo>();
    }
    ASSERT_TRUE(rgb && depth && info) << "the bag lacks one of its three topics";
    // The three recorded stamps differ, so depth_image_proc's synchronizer would never match
    // them: publish them with one fresh common stamp, a few times (the tracker confirms a track
    // after a few detections).
    ros::Time stamp;
    for (int k = 0; k < 3; ++k)
    {
      stamp = ros::Time::now();
      rgb->header.stamp = depth->header.stamp = info->header.stamp = stamp;
      info_pub.publish(info);
      rgb_pub.publish(rgb);
      depth_pub.publish(depth);
      ros::WallDuration(0.3).sleep();
    }
    const auto result = resultFor(people, stamp);
    ASSERT_TRUE(result) << "no tracker output for the last frame";
    EXPECT_EQ(result->people.size(), 1u) << "people tracked in the last frame";
    for (const auto& p : result->people)
    {
      EXPECT_GT(p.height, 1.5f);
      EXPECT_LT(p.height, 2.1f);
    }
    ros::WallDuration(0.7).sleep();  // longer than lost_after: the next bag starts afresh
  }
}

TEST(RealData, FivePeoplePcdGivesAtLeastFour)
{
  const std::string path = g_data + "/real_rgbd/pcl_five_people.pcd";
  if (!boost::filesystem::exists(path))
    GTEST_SKIP() << "real data absent: " << path;
  pcl::PointCloud<pcl::PointXYZRGBA> rgba;
  ASSERT_EQ(pcl::io::loadPCDFile(path, rgba), 0);
  pcl::PointCloud<pcl::PointXYZRGB> rgb;
  pcl::copyPointCloud(rgba, rgb);
  sensor_msgs::PointCloud2 msg;
  pcl::toROSMsg(rgb, msg);
  msg.header.frame_id = "camera_rgb_optical_frame";

  ros::NodeHandle nh;
  Collector<TrackedPeople> people(nh, "pcd/people");
  ros::Publisher pub = nh.advertise<sensor_msgs::PointCloud2>("pcd/cloud", 2);
  ASSERT_TRUE(waitFor([&] { return pub.getNumSubscribers() > 0; }, 10.0));
  for (int k = 0; k < 4; ++k)
  {
    msg.header.stamp = ros::Time::now();
    pub.publish(msg);
    ros::WallDuration(0.4).sleep();
  }
  const auto result = resultFor(people, msg.header.stamp);
  ASSERT_TRUE(result) << "no tracker output for the last frame";
  EXPECT_GE(result->people.size(), 4u);
  EXPECT_LE(result->people.size(), 5u) << "more people than there are";
  for (const auto& p : result->people)
  {
    EXPECT_GT(p.height, 1.4f);
    EXPECT_LT(p.height, 2.1f);
  }
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_real_data");
  ros::NodeHandle("~").getParam("data", g_data);
  ros::AsyncSpinner spinner(2);
  spinner.start();
  return RUN_ALL_TESTS();
}
