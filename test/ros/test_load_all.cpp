// Loads every nodelet class that nodelets.xml exports into an in-process manager, then unloads it.
#include <gtest/gtest.h>
#include <nodelet/loader.h>
#include <ros/ros.h>

#include <fstream>
#include <regex>
#include <sstream>

namespace
{
std::string g_xml;

std::vector<std::string> exportedClasses()
{
  std::ifstream in(g_xml);
  std::stringstream text;
  text << in.rdbuf();
  const std::string s = text.str();
  std::vector<std::string> names;
  const std::regex cls("<class\\s+name=\"([^\"]+)\"");
  for (auto it = std::sregex_iterator(s.begin(), s.end(), cls); it != std::sregex_iterator(); ++it)
    names.push_back((*it)[1]);
  return names;
}
}  // namespace

TEST(LoadAll, EveryExportedNodeletLoadsAndUnloads)
{
  const auto classes = exportedClasses();
  ASSERT_GE(classes.size(), 5u) << "nodelets.xml at " << g_xml << " lists too few classes";
  nodelet::Loader loader(false);  // no ROS services: a plain in-process manager
  const nodelet::M_string remappings;
  const nodelet::V_string argv;
  for (const auto& type : classes)
  {
    const std::string name = "/load_test_" + std::to_string(&type - &classes[0]);
    ros::param::set(name + "/device_uri", "/nonexistent/device.oni");  // the driver must not find hardware
    ros::param::set(name + "/retry_period", 0.2);
    EXPECT_TRUE(loader.load(name, type, remappings, argv)) << "cannot load nodelet " << type;
    ros::WallDuration(0.3).sleep();  // let the driver's thread try (and fail) to open its device
    EXPECT_TRUE(loader.unload(name)) << "cannot unload nodelet " << type;
  }
  // A second instance of each next to the first: no global state in the way.
  for (const auto& type : classes)
    EXPECT_TRUE(loader.load("/a_" + std::to_string(&type - &classes[0]), type, remappings, argv)) << type;
  for (const auto& type : classes)
    EXPECT_TRUE(loader.load("/b_" + std::to_string(&type - &classes[0]), type, remappings, argv)) << type;
  EXPECT_TRUE(loader.clear());
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "test_load_all");
  ros::NodeHandle pnh("~");
  pnh.getParam("nodelets_xml", g_xml);
  ros::AsyncSpinner spinner(1);
  spinner.start();
  return RUN_ALL_TESTS();
}
