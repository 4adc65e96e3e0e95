/**
 * @file depth_cloud.h
 * @brief An organized XYZRGB cloud from a registered depth image and colour image (pinhole
 *        intrinsics), for tools that read depth+rgb recordings without a nodelet manager.
 *        Live, the pipeline uses depth_image_proc's point_cloud_xyzrgb nodelet instead.
 */
#pragma once

#include <action_flow/types.h>

#include <cstdint>

namespace action_flow
{
/** @brief Pinhole intrinsics of the depth-registered colour camera. */
struct Intrinsics
{
  double fx = 525.0, fy = 525.0, cx = 319.5, cy = 239.5;
};

/**
 * @brief Fills @p out (width x height, organized) from depth in metres (@p depth_m, row-major,
 *        NaN or <= 0 = no reading) and 8-bit RGB (@p rgb, row-major, 3 bytes per pixel).
 */
void depthToCloud(const float* depth_m, const std::uint8_t* rgb, int width, int height, const Intrinsics& k,
                  Cloud& out);

}  // namespace action_flow
