/**
 * @file freenect_device.h
 * @brief A Microsoft Kinect v1 through libfreenect (OpenKinect), or a dump of one replayed by
 *        libfreenect's fakenect library: opens it, runs depth and colour, reads frame pairs (an
 *        RgbdDevice). No ROS; the driver nodelet owns one with `backend: freenect`.
 *
 * libfreenect is loaded when a device is opened (dlopen), not linked: the real library
 * (libfreenect.so.0.5) for a sensor, fakenect's library of the same name for a dump. fakenect
 * 0.5.3 replays only 640x480 RGB and 11-bit raw depth, so a dump's depth is converted with
 * kinect_depth.h and taken as registered to colour (as `synth --fakenect` writes it); a sensor
 * runs in libfreenect's FREENECT_DEPTH_REGISTERED mode (millimetres, aligned to colour with the
 * device's own calibration).
 */
#pragma once

#include "rgbd_device.h"

#include <memory>
#include <string>

namespace action_flow
{
class FreenectDevice : public RgbdDevice
{
public:
  /**
   * @param which "" = the first Kinect, a number = the Kinect of that index, a folder = a fakenect
   *        dump (its INDEX.txt and every file it lists are checked before fakenect reads them:
   *        fakenect ends the process on a missing file)
   * @param fakenect_library the fakenect library to replay a dump with ("" = the one found when
   *        the package was built)
   * @throws DeviceError naming the device or dump and what is wrong
   */
  FreenectDevice(const std::string& which, const std::string& fakenect_library);
  ~FreenectDevice() override;
  FreenectDevice(const FreenectDevice&) = delete;
  FreenectDevice& operator=(const FreenectDevice&) = delete;

  void start() override;
  void stop() override;
  bool streaming() const override { return streaming_; }
  /** @throws EndOfRecording when a dump has no more frames (fakenect does not repeat) */
  bool read(RgbdFrame& frame, int timeout_ms) override;
  const std::string& description() const override { return description_; }

  /** @brief The fakenect library found when the package was built ("" if none was). */
  static std::string builtInFakenectLibrary();

private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  bool streaming_ = false;
  std::string description_;
};

}  // namespace action_flow
