#include <action_flow/ros/input_checks.h>

#include <pcl_conversions/pcl_conversions.h>

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>

namespace action_flow
{
namespace
{
std::string number(std::uint64_t v)
{
  return std::to_string(v);
}

// Bytes of one value of a PointField datatype; 0 for an unknown one.
std::uint64_t datatypeSize(std::uint8_t datatype)
{
  switch (datatype)
  {
    case sensor_msgs::PointField::INT8:
    case sensor_msgs::PointField::UINT8: return 1;
    case sensor_msgs::PointField::INT16:
    case sensor_msgs::PointField::UINT16: return 2;
    case sensor_msgs::PointField::INT32:
    case sensor_msgs::PointField::UINT32:
    case sensor_msgs::PointField::FLOAT32: return 4;
    case sensor_msgs::PointField::FLOAT64: return 8;
    default: return 0;
  }
}

// Whether a field of @p m named @p name lies inside a point as one FLOAT32 (or, for colour, any
// 4-byte type); "" when fine or absent and not required.
std::string checkField(const sensor_msgs::PointCloud2& m, const std::string& name, bool required, bool colour)
{
  for (const auto& f : m.fields)
    if (f.name == name)
    {
      if (!colour && (f.datatype != sensor_msgs::PointField::FLOAT32 || f.count != 1))
        return "field '" + name + "' is not one FLOAT32";
      if (static_cast<std::uint64_t>(f.offset) + 4 > m.point_step)
        return "field '" + name + "' at offset " + number(f.offset) + " lies outside the point_step of " +
               number(m.point_step);
      return "";
    }
  return required ? "has no '" + name + "' field" : "";
}
}  // namespace

std::string checkPointCloud2(const sensor_msgs::PointCloud2& m)
{
  const std::uint64_t points = static_cast<std::uint64_t>(m.width) * m.height;
  if (points > kMaxCloudPoints)
    return "claims " + number(m.width) + "x" + number(m.height) + " points, more than the " + number(kMaxCloudPoints) +
           " a cloud may have";
  if (m.is_bigendian)
    return "is big-endian";
  if (m.point_step == 0 && points > 0)
    return "has point_step 0";
  if (static_cast<std::uint64_t>(m.row_step) != static_cast<std::uint64_t>(m.width) * m.point_step)
    return "row_step " + number(m.row_step) + " is not width " + number(m.width) + " x point_step " +
           number(m.point_step);
  const std::uint64_t bytes = static_cast<std::uint64_t>(m.row_step) * m.height;
  if (m.data.size() != bytes)
    return "carries " + number(m.data.size()) + " bytes of data, its header says " + number(bytes);
  // Every field inside the point, not only the ones looked for: a converter may take another field
  // of the same name (pcl::fromROSMsg takes the first of the right type).
  for (const auto& f : m.fields)
  {
    const std::uint64_t size = datatypeSize(f.datatype);
    if (size == 0)
      return "field '" + f.name + "' has the unknown datatype " + number(f.datatype);
    if (static_cast<std::uint64_t>(f.offset) + size * std::max<std::uint64_t>(f.count, 1) > m.point_step)
      return "field '" + f.name + "' at offset " + number(f.offset) + " (" + number(size * std::max<std::uint64_t>(f.count, 1)) +
             " bytes) lies outside the point_step of " + number(m.point_step);
  }
  for (const char* axis : { "x", "y", "z" })
  {
    const std::string e = checkField(m, axis, true, false);
    if (!e.empty())
      return e;
  }
  for (const char* colour : { "rgb", "rgba" })
  {
    const std::string e = checkField(m, colour, false, true);
    if (!e.empty())
      return e;
  }
  return "";
}

std::string checkImage(const sensor_msgs::Image& m)
{
  static const std::map<std::string, int> kBytes = { { "rgb8", 3 },  { "bgr8", 3 },   { "rgba8", 4 }, { "bgra8", 4 },
                                                     { "mono8", 1 }, { "mono16", 2 }, { "16UC1", 2 }, { "32FC1", 4 } };
  const auto it = kBytes.find(m.encoding);
  if (it == kBytes.end())
    return "has the encoding '" + m.encoding + "' (expected rgb8, bgr8, rgba8, bgra8, mono8, mono16, 16UC1 or 32FC1)";
  if (m.width == 0 || m.height == 0 || m.width > kMaxImageSide || m.height > kMaxImageSide)
    return "is " + number(m.width) + "x" + number(m.height) + " pixels (each side must be 1.." + number(kMaxImageSide) +
           ")";
  if (static_cast<std::uint64_t>(m.step) < static_cast<std::uint64_t>(m.width) * it->second)
    return "has step " + number(m.step) + ", less than width " + number(m.width) + " x " + number(it->second) +
           " bytes";
  if (static_cast<std::uint64_t>(m.step) > 4ull * m.width * it->second)
    return "has step " + number(m.step) + ", more than 4 times a row of pixels";
  const std::uint64_t bytes = static_cast<std::uint64_t>(m.step) * m.height;
  if (m.data.size() != bytes)
    return "carries " + number(m.data.size()) + " bytes of data, step x height is " + number(bytes);
  return "";
}

std::string checkCameraInfo(const sensor_msgs::CameraInfo& m)
{
  if (m.width == 0 || m.height == 0 || m.width > kMaxImageSide || m.height > kMaxImageSide)
    return "is for " + number(m.width) + "x" + number(m.height) + " images";
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(m.K[0]) || !positive(m.K[4]) || !std::isfinite(m.K[2]) || !std::isfinite(m.K[5]))
    return "has intrinsics K that are not finite with positive focal lengths";
  if (!positive(m.P[0]) || !positive(m.P[5]) || !std::isfinite(m.P[2]) || !std::isfinite(m.P[6]))
    return "has a projection P that is not finite with positive focal lengths";
  return "";
}

std::string checkPng(const std::vector<std::uint8_t>& data)
{
  static const std::uint8_t signature[8] = { 0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n' };
  if (data.size() < 8 || std::memcmp(data.data(), signature, 8) != 0)
    return "";
  const auto be32 = [&](std::size_t at) {
    return std::uint32_t(data[at]) << 24 | std::uint32_t(data[at + 1]) << 16 | std::uint32_t(data[at + 2]) << 8 |
           std::uint32_t(data[at + 3]);
  };
  for (std::size_t at = 8;;)
  {
    if (data.size() - at < 12)
      return "is a PNG cut short at byte " + number(at) + " (no IEND chunk)";
    const std::uint64_t length = be32(at);
    if (length > data.size() - at - 12)
      return "is a PNG whose chunk at byte " + number(at) + " claims " + number(length) + " bytes, past the end";
    const std::string type(reinterpret_cast<const char*>(&data[at + 4]), 4);
    if (at == 8 && type != "IHDR")
      return "is a PNG that does not start with an IHDR chunk";
    const auto crc = crc32(crc32(0L, Z_NULL, 0), &data[at + 4], static_cast<uInt>(length + 4));
    if (crc != be32(at + 8 + length))
      return "is a PNG with a CRC error in its chunk at byte " + number(at);
    if (type == "IEND")
      return "";
    at += 12 + length;
  }
}

InputCloud::ConstPtr InputCloud::of(boost::shared_ptr<const Cloud> cloud)
{
  auto in = boost::make_shared<InputCloud>();
  in->cloud = std::move(cloud);
  return in;
}

void InputCloud::fromWire(const sensor_msgs::PointCloud2& wire, InputCloud& out)
{
  out.cloud.reset();
  out.error = checkPointCloud2(wire);
  if (!out.error.empty())
    return;
  auto cloud = boost::make_shared<Cloud>();
  pcl::fromROSMsg(wire, *cloud);
  out.cloud = cloud;
}

}  // namespace action_flow

namespace ros
{
namespace serialization
{
sensor_msgs::PointCloud2 Serializer<action_flow::InputCloud>::wire(const action_flow::InputCloud& m)
{
  sensor_msgs::PointCloud2 w;
  if (m.cloud)
    pcl::toROSMsg(*m.cloud, w);
  return w;
}
}  // namespace serialization
}  // namespace ros
