// Loaders for the real RGB-D recordings in ../shared/data/real_rgbd (tests and the benchmark only:
// they use rosbag, the core does not).
#pragma once

#include <action_flow/depth_cloud.h>
#include <action_flow/types.h>

#include <pcl/io/pcd_io.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <dirent.h>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace action_flow
{
namespace test
{
/** The shared data folder passed in from CMake (../shared/data relative to the repository). */
inline std::string dataDir()
{
#ifdef ACTION_FLOW_DATA_DIR
  return ACTION_FLOW_DATA_DIR;
#else
  return "../shared/data";
#endif
}

inline bool fileExists(const std::string& path)
{
  FILE* f = std::fopen(path.c_str(), "rb");
  if (f)
    std::fclose(f);
  return f != nullptr;
}

/** Files in @p dir whose names start with @p prefix and end with @p suffix, sorted. */
inline std::vector<std::string> listFiles(const std::string& dir, const std::string& prefix, const std::string& suffix)
{
  std::vector<std::string> out;
  DIR* d = opendir(dir.c_str());
  if (!d)
    return out;
  while (dirent* e = readdir(d))
  {
    const std::string n = e->d_name;
    if (n.size() >= prefix.size() + suffix.size() && n.compare(0, prefix.size(), prefix) == 0 &&
        n.compare(n.size() - suffix.size(), suffix.size(), suffix) == 0)
      out.push_back(dir + "/" + n);
  }
  closedir(d);
  std::sort(out.begin(), out.end());
  return out;
}

/** Reads a PCD (XYZRGBA or XYZRGB) as our point type, keeping its organization. */
inline Cloud loadPcd(const std::string& path)
{
  Cloud c;
  if (pcl::io::loadPCDFile(path, c) != 0)
    throw std::runtime_error("cannot read " + path);
  return c;
}

/**
 * Builds the organized cloud of one tue_hsr_person bag: depth (32FC1, metres, registered to rgb),
 * rgb8 and camera_info, back-projected with the intrinsics K (optical frame: x right, y down, z ahead).
 */
inline Cloud loadTueBag(const std::string& path)
{
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  sensor_msgs::Image::ConstPtr depth, rgb;
  sensor_msgs::CameraInfo::ConstPtr info;
  for (const rosbag::MessageInstance& m : rosbag::View(bag))
  {
    if (auto i = m.instantiate<sensor_msgs::Image>())
    {
      if (i->encoding == "32FC1")
        depth = i;
      else if (i->encoding == "rgb8")
        rgb = i;
    }
    else if (auto ci = m.instantiate<sensor_msgs::CameraInfo>())
      info = ci;
  }
  if (!depth || !rgb || !info)
    throw std::runtime_error(path + ": needs a 32FC1 depth image, an rgb8 image and a camera_info");
  if (depth->width != rgb->width || depth->height != rgb->height)
    throw std::runtime_error(path + ": depth and rgb sizes differ");
  Intrinsics k;
  k.fx = info->K[0];
  k.fy = info->K[4];
  k.cx = info->K[2];
  k.cy = info->K[5];
  // Rows may be padded (step): copy them out contiguously for depthToCloud.
  const std::size_t w = depth->width, h = depth->height;
  std::vector<float> z(w * h);
  std::vector<std::uint8_t> colour(3 * w * h);
  for (std::size_t v = 0; v < h; ++v)
  {
    std::memcpy(&z[v * w], &depth->data[v * depth->step], 4 * w);
    std::memcpy(&colour[3 * v * w], &rgb->data[v * rgb->step], 3 * w);
  }
  Cloud c;
  depthToCloud(z.data(), colour.data(), static_cast<int>(w), static_cast<int>(h), k, c);
  return c;
}

}  // namespace test
}  // namespace action_flow
