// Loaders for the real RGB-D recordings in ../shared/data/real_rgbd (tests and the benchmark only:
// they use rosbag, the core does not).
#pragma once

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
  const double fx = info->K[0], fy = info->K[4], cx = info->K[2], cy = info->K[5];
  Cloud c;
  c.width = depth->width;
  c.height = depth->height;
  c.is_dense = false;
  c.points.resize(static_cast<std::size_t>(c.width) * c.height);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::uint32_t v = 0; v < c.height; ++v)
    for (std::uint32_t u = 0; u < c.width; ++u)
    {
      float z;
      std::memcpy(&z, &depth->data[v * depth->step + 4 * u], sizeof z);
      PointT& p = c.at(u, v);
      const std::uint8_t* px = &rgb->data[v * rgb->step + 3 * u];
      p.r = px[0];
      p.g = px[1];
      p.b = px[2];
      if (!(std::isfinite(z) && z > 0.0f))
      {
        p.x = p.y = p.z = nan;
        continue;
      }
      p.x = static_cast<float>((u - cx) * z / fx);
      p.y = static_cast<float>((v - cy) * z / fy);
      p.z = z;
    }
  return c;
}

}  // namespace test
}  // namespace action_flow
