/**
 * @file openni2_device.h
 * @brief A thin wrapper of one OpenNI2 device (a sensor, an .oni recording or OpenNI2's Dummy
 *        test device): opens it, runs its depth and colour streams, reads synchronised frame
 *        pairs (an RgbdDevice). No ROS; the driver nodelet owns one and turns frames into clouds.
 */
#pragma once

#include "rgbd_device.h"

#include <memory>
#include <string>

namespace action_flow
{
/** @brief One OpenNI2 device. Not thread-safe: use from one thread. */
class OpenNI2Device : public RgbdDevice
{
public:
  /**
   * @param uri empty = the first device found, a path ending in .oni = playback of that file,
   *        "Dummy" = OpenNI2's built-in test device, anything else = a device URI
   * @throws DeviceError naming the URI and OpenNI2's own error if it cannot be opened
   */
  explicit OpenNI2Device(const std::string& uri);
  /** @brief Stops and destroys the streams before closing the device (Dummy crashes otherwise). */
  ~OpenNI2Device() override;
  OpenNI2Device(const OpenNI2Device&) = delete;
  OpenNI2Device& operator=(const OpenNI2Device&) = delete;

  void start() override;
  void stop() override;
  bool streaming() const override { return streaming_; }

  bool read(RgbdFrame& frame, int timeout_ms) override;

  /** @brief What was opened: the device's URI and name. */
  const std::string& description() const override { return description_; }
  bool isFile() const;

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool streaming_ = false;
  std::string description_;
};

}  // namespace action_flow
