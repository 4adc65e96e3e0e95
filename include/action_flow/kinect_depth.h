/**
 * @file kinect_depth.h
 * @brief Kinect v1 raw depth: the 11-bit disparity values the sensor streams (libfreenect's
 *        FREENECT_DEPTH_11BIT, what fakenect records and replays) and metres.
 *
 * The conversion is Stéphane Magnenat's fit to the Kinect v1 (OpenKinect wiki, "Imaging
 * Information"): z = 0.1236 m * tan(raw / 2842.5 + 1.1863). It holds for a typical device to
 * about a centimetre within 4 m; a device's own calibration (libfreenect's
 * FREENECT_DEPTH_REGISTERED mode) is better and is what the driver uses with a real Kinect.
 * One raw step is about 3 mm at 1 m and 2.6 cm at 3 m, as the sensor's own quantisation.
 */
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

namespace action_flow
{
/** @brief The raw value that means "no reading". */
constexpr std::uint16_t kKinectRawNoReading = 2047;
/** @brief Readings beyond this (m) are not trusted (the fit diverges towards raw 1093). */
constexpr float kKinectRawMaxMetres = 10.0f;

/** @brief Metres for one raw 11-bit value; NaN for "no reading" or a value outside the fit. */
inline float kinectRawToMetres(std::uint16_t raw)
{
  if (raw >= kKinectRawNoReading)
    return std::numeric_limits<float>::quiet_NaN();
  const double z = 0.1236 * std::tan(raw / 2842.5 + 1.1863);
  return z > 0.0 && z <= kKinectRawMaxMetres ? static_cast<float>(z) : std::numeric_limits<float>::quiet_NaN();
}

/** @brief The raw 11-bit value nearest to @p metres; kKinectRawNoReading for NaN, <= 0.31 m or > 10 m. */
inline std::uint16_t metresToKinectRaw(float metres)
{
  if (!(metres > 0.0f) || metres > kKinectRawMaxMetres)
    return kKinectRawNoReading;
  const double raw = std::round((std::atan(metres / 0.1236) - 1.1863) * 2842.5);
  return raw < 0.0 ? kKinectRawNoReading : static_cast<std::uint16_t>(raw);
}

}  // namespace action_flow
