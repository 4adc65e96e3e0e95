/**
 * @file device_clock.h
 * @brief Stamps from a sensor's own frame times: when the device timed a frame, not when the
 *        driver got it. No ROS.
 */
#pragma once

#include <cmath>
#include <cstdint>

namespace action_flow
{
/**
 * @brief Maps a device's frame times (microseconds on its own clock) onto the host clock. The
 *        offset is fixed at the first frame and set again when the two clocks part by more than
 *        @p max_drift seconds or the device's time goes back (a device reset, a recording that
 *        loops), so stamps keep to the device's spacing and never run backwards or far from now.
 */
class DeviceClock
{
public:
  explicit DeviceClock(double max_drift = 0.1) : max_drift_(max_drift) {}

  /**
   * @param device_us the device's time of the frame; 0 = the device gives none
   * @param now the host time (s) the frame was received
   * @return the frame's stamp (s): @p now when the device gives no time
   */
  double stamp(std::uint64_t device_us, double now)
  {
    if (device_us == 0)
      return now;
    const double device = static_cast<double>(device_us) * 1e-6;
    if (!synced_ || std::fabs(device + offset_ - now) > max_drift_ || device + offset_ <= last_)
    {
      offset_ = now - device;
      synced_ = true;
    }
    last_ = device + offset_;
    return last_;
  }

private:
  double max_drift_;
  double offset_ = 0.0, last_ = 0.0;
  bool synced_ = false;
};

}  // namespace action_flow
