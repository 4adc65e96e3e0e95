/**
 * @file input_checks.h
 * @brief Checks of every message that enters the nodelet manager from outside, before anything
 *        reads or allocates by it: point clouds, images and camera_info. Each check is a header
 *        check (sizes, steps, fields, intrinsics against the data length), as cheap as that.
 *
 * Point clouds reach the people tracker as InputCloud: in-process publishers (the driver) hand it
 * the very cloud they made (no copy); from another process, or from a stage that publishes
 * sensor_msgs/PointCloud2 (depth_image_proc), the wire message is checked first and only a good
 * one is converted. A bad one becomes an InputCloud with an error and no cloud, which the tracker
 * logs (throttled) and drops; the next good cloud is served.
 */
#pragma once

#include <action_flow/types.h>

#include <boost/shared_ptr.hpp>
#include <ros/message_traits.h>
#include <ros/serialization.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>

#include <cstdint>
#include <string>
#include <vector>

namespace action_flow
{
/** Largest cloud a stage takes (points): 4 times a 640x480 frame is plenty for any RGB-D sensor. */
constexpr std::uint64_t kMaxCloudPoints = 4ull * 1280 * 960;
/** Largest image side (pixels). */
constexpr std::uint32_t kMaxImageSide = 8192;

/**
 * @brief What is wrong with @p m for the tracker, or "" when it can be converted to an XYZ(RGB)
 *        cloud: width x height points within kMaxCloudPoints, row_step = width x point_step,
 *        data = row_step x height bytes, FLOAT32 x, y and z (and rgb/rgba, if present) inside a
 *        point, little-endian.
 */
std::string checkPointCloud2(const sensor_msgs::PointCloud2& m);

/**
 * @brief What is wrong with @p m, or "": a known encoding (rgb8, bgr8, rgba8, bgra8, mono8, mono16,
 *        16UC1, 32FC1), sides within 1..kMaxImageSide, step >= width x bytes per pixel, data =
 *        step x height bytes.
 */
std::string checkImage(const sensor_msgs::Image& m);

/** @brief What is wrong with @p m, or "": positive size, finite positive focal lengths in K and P, finite centres. */
std::string checkCameraInfo(const sensor_msgs::CameraInfo& m);

/**
 * @brief What is wrong with the PNG file in @p data, or "" when it is whole: an IHDR chunk first,
 *        every chunk inside the data with its CRC right, an IEND chunk. Data that is not a PNG (no
 *        PNG signature: a JPEG, say) gives "". Checked before decoding, so that a damaged file is
 *        refused with this line instead of libpng's own messages on stderr.
 */
std::string checkPng(const std::vector<std::uint8_t>& data);

/** @brief The people tracker's input: a cloud, or why the message that should have been one was refused. */
struct InputCloud
{
  boost::shared_ptr<const Cloud> cloud;  ///< never modified after publishing; empty when refused
  std::string error;                     ///< what was wrong with the wire message, empty when good

  using Ptr = boost::shared_ptr<InputCloud>;
  using ConstPtr = boost::shared_ptr<const InputCloud>;

  /** @brief An InputCloud holding @p cloud (for in-process publishers). */
  static ConstPtr of(boost::shared_ptr<const Cloud> cloud);
  /** @brief The checked conversion of a wire message. */
  static void fromWire(const sensor_msgs::PointCloud2& wire, InputCloud& out);
};

}  // namespace action_flow

namespace ros
{
namespace message_traits
{
/** InputCloud goes on the wire as sensor_msgs/PointCloud2 (rviz, rosbag record and remote nodes see one). */
template <>
struct MD5Sum<action_flow::InputCloud>
{
  static const char* value() { return MD5Sum<sensor_msgs::PointCloud2>::value(); }
  static const char* value(const action_flow::InputCloud&) { return value(); }
};
template <>
struct DataType<action_flow::InputCloud>
{
  static const char* value() { return DataType<sensor_msgs::PointCloud2>::value(); }
  static const char* value(const action_flow::InputCloud&) { return value(); }
};
template <>
struct Definition<action_flow::InputCloud>
{
  static const char* value() { return Definition<sensor_msgs::PointCloud2>::value(); }
  static const char* value(const action_flow::InputCloud&) { return value(); }
};
}  // namespace message_traits

namespace serialization
{
/** Writes the cloud as a PointCloud2; reads a PointCloud2 and converts it only when it checks out. */
template <>
struct Serializer<action_flow::InputCloud>
{
  static sensor_msgs::PointCloud2 wire(const action_flow::InputCloud& m);

  template <typename Stream>
  inline static void write(Stream& stream, const action_flow::InputCloud& m)
  {
    stream.next(wire(m));
  }
  template <typename Stream>
  inline static void read(Stream& stream, action_flow::InputCloud& m)
  {
    sensor_msgs::PointCloud2 w;
    stream.next(w);  // roscpp's own reader: a length beyond the buffer throws, never reads past it
    action_flow::InputCloud::fromWire(w, m);
  }
  inline static uint32_t serializedLength(const action_flow::InputCloud& m) { return serializationLength(wire(m)); }
};
}  // namespace serialization
}  // namespace ros
