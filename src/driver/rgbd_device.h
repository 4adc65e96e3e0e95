/**
 * @file rgbd_device.h
 * @brief What the driver nodelet needs of a depth+colour sensor, whichever library opens it:
 *        OpenNI2 (openni2_device.h: PrimeSense/Asus Xtion, .oni files, the Dummy device) or
 *        libfreenect (freenect_device.h: Microsoft Kinect v1, fakenect dumps). No ROS.
 */
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace action_flow
{
/** @brief One depth frame (millimetres, 0 = no reading) with the colour registered to it. */
struct RgbdFrame
{
  int width = 0, height = 0;
  std::vector<std::uint16_t> depth_mm;  ///< width*height
  std::vector<std::uint8_t> rgb;        ///< 3*width*height, resampled to the depth size if needed
  std::uint64_t timestamp_us = 0;       ///< the device's clock
  float fx = 0.0f, fy = 0.0f, cx = 0.0f, cy = 0.0f;  ///< depth intrinsics (pixels)
  bool default_intrinsics = false;      ///< the device reported no field of view: Kinect v1 values used
};

/** @brief Raised when a device cannot be opened or its streams fail (the driver retries). */
class DeviceError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/** @brief Raised when a recording has no more frames and does not repeat (the driver stops). */
class EndOfRecording : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/** @brief One open sensor or recording. Not thread-safe: use from one thread. */
class RgbdDevice
{
public:
  virtual ~RgbdDevice() = default;
  /** @brief Starts depth and colour streams; @throws DeviceError. */
  virtual void start() = 0;
  /** @brief Stops the streams (they can be started again). */
  virtual void stop() = 0;
  virtual bool streaming() const = 0;
  /**
   * @brief Waits up to @p timeout_ms for a depth frame and the latest colour frame.
   * @return false on timeout
   * @throws DeviceError if reading fails, EndOfRecording when a recording is over
   */
  virtual bool read(RgbdFrame& frame, int timeout_ms) = 0;
  /** @brief What was opened, for the log. */
  virtual const std::string& description() const = 0;
};

/** @brief Kinect v1 colour camera: f = 525 px at 640x480 (the value openni_launch uses), scaled. */
constexpr float kKinectV1Focal640 = 525.0f;

/** @brief Fills @p frame's intrinsics with Kinect v1 values for its size (default_intrinsics set). */
inline void setKinectV1Intrinsics(RgbdFrame& frame)
{
  frame.fx = frame.fy = kKinectV1Focal640 * frame.width / 640.0f;
  frame.cx = 0.5f * frame.width - 0.5f;
  frame.cy = 0.5f * frame.height - 0.5f;
  frame.default_intrinsics = true;
}

}  // namespace action_flow
