/**
 * @file openni2_device.h
 * @brief A thin wrapper of one OpenNI2 device (a sensor, an .oni recording or OpenNI2's Dummy
 *        test device): opens it, runs its depth and colour streams, reads synchronised frame
 *        pairs. No ROS; the driver nodelet owns one and turns frames into clouds.
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

/** @brief Raised when a device cannot be opened or its streams fail. */
class DeviceError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/** @brief One OpenNI2 device. Not thread-safe: use from one thread. */
class OpenNI2Device
{
public:
  /**
   * @param uri empty = the first device found, a path ending in .oni = playback of that file,
   *        "Dummy" = OpenNI2's built-in test device, anything else = a device URI
   * @throws DeviceError naming the URI and OpenNI2's own error if it cannot be opened
   */
  explicit OpenNI2Device(const std::string& uri);
  /** @brief Stops and destroys the streams before closing the device (Dummy crashes otherwise). */
  ~OpenNI2Device();
  OpenNI2Device(const OpenNI2Device&) = delete;
  OpenNI2Device& operator=(const OpenNI2Device&) = delete;

  /** @brief Starts depth and colour streams; @throws DeviceError. */
  void start();
  /** @brief Stops the streams (they can be started again). */
  void stop();
  bool streaming() const { return streaming_; }

  /**
   * @brief Waits up to @p timeout_ms for a depth frame and the latest colour frame.
   * @return false on timeout
   * @throws DeviceError if reading fails
   */
  bool read(RgbdFrame& frame, int timeout_ms);

  /** @brief What was opened: the device's URI and name. */
  const std::string& description() const { return description_; }
  bool isFile() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool streaming_ = false;
  std::string description_;
};

}  // namespace action_flow
